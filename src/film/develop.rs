//! Developing linear radiance into display values, as a photographer develops film:
//! exposure, then a tone map that brings unbounded radiance into 0..1, then the transfer
//! curve a display expects, then rounding to 8 or 16 bits.
//!
//! Each channel is developed on its own: `out = transfer(tonemap(2^exposure * radiance))`.
//! Negative radiance (a sharpening filter's lobe) and NaN develop to 0, +∞ to full white,
//! so a stray sample can never make an image fail to write.

use super::{Image, quantize};
pub use crate::options::{ToneMap, Transfer};
use rayon::prelude::*;

impl ToneMap {
    /// Maps exposed radiance `x` (finite or +∞, not negative) into 0..1.
    pub fn apply(self, x: f32) -> f32 {
        if x == f32::INFINITY {
            return 1.0;
        }
        match self {
            ToneMap::Clamp => x.min(1.0),
            ToneMap::Reinhard => x / (1.0 + x),
            ToneMap::Aces => aces_narkowicz(x),
        }
    }
}

/// Computed in f64: for large `x` both quadratics overflow f32 long before their ratio
/// settles at 2.51 / 2.43.
fn aces_narkowicz(x: f32) -> f32 {
    let x = f64::from(x);
    let y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    y.clamp(0.0, 1.0) as f32
}

impl Transfer {
    /// `v` in 0..1 to the stored value in 0..1.
    pub fn encode(self, v: f32) -> f32 {
        match self {
            Transfer::Classic => v,
            Transfer::Srgb => srgb_encode(v),
        }
    }
}

/// In f64, so that rounding to 16 bits sees the curve's true value.
fn srgb_encode(v: f32) -> f32 {
    let v = f64::from(v);
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    e as f32
}

/// Everything that turns radiance into stored display values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Develop {
    /// In stops: radiance is multiplied by `2^exposure` first.
    pub exposure: f32,
    /// Brings exposed radiance into 0..1, after exposure.
    pub tonemap: ToneMap,
    /// Curve from tone-mapped values to stored ones, last before rounding.
    pub transfer: Transfer,
}

impl Default for Develop {
    fn default() -> Develop {
        Develop::display()
    }
}

impl Develop {
    /// The 2014 program's output, bit for bit: clamp to 0..1, no curve, round.
    pub const fn classic() -> Develop {
        Develop {
            exposure: 0.0,
            tonemap: ToneMap::Clamp,
            transfer: Transfer::Classic,
        }
    }

    /// Radiance shown as is on an sRGB display: clamp to 0..1, sRGB curve.
    pub const fn display() -> Develop {
        Develop {
            exposure: 0.0,
            tonemap: ToneMap::Clamp,
            transfer: Transfer::Srgb,
        }
    }

    /// One channel of radiance to its stored value in 0..1.
    pub fn channel(&self, radiance: f32) -> f32 {
        let exposed = if self.exposure == 0.0 {
            radiance
        } else {
            radiance * self.exposure.exp2()
        };
        // NaN and negatives (and 0 × ∞ from an extreme exposure) develop to black.
        // Decided on the bits: `exposed > 0.0` may be compiled to a maximum with 0
        // (aarch64's `fmaxnm`), which makes a signalling NaN quiet instead of 0, and
        // the clamp then takes that NaN for 1.
        let positive = exposed.to_bits().wrapping_sub(1) < f32::INFINITY.to_bits();
        let exposed = if positive { exposed } else { 0.0 };
        self.transfer.encode(self.tonemap.apply(exposed))
    }

    /// 8-bit RGB, rounded to nearest.
    pub fn to_rgb8(&self, image: &Image) -> Vec<u8> {
        let developer = self.developer();
        develop(image, |pixels, out| developer.rgb8(pixels, out))
    }

    /// 16-bit RGB, rounded to nearest; rows in parallel.
    pub fn to_rgb16(&self, image: &Image) -> Vec<u16> {
        let developer = self.developer();
        develop(image, |pixels, out| developer.rgb16(pixels, out))
    }

    /// This development ready to run on pixels a few at a time (the rows of a band
    /// as the render finishes it), its 8-bit cut-offs found once.
    pub fn developer(&self) -> Developer {
        Developer {
            develop: *self,
            cuts: Cuts8::of(self),
        }
    }
}

/// A [`Develop`] prepared by [`Develop::developer`].
pub struct Developer {
    develop: Develop,
    cuts: Option<Cuts8>,
}

impl Developer {
    /// `pixels` as 8-bit RGB into `out` (three values per pixel).
    pub fn rgb8(&self, pixels: &[[f32; 3]], out: &mut [u8]) {
        let out = out.iter_mut().zip(pixels.iter().flatten());
        match &self.cuts {
            Some(cuts) => out.for_each(|(o, &v)| *o = cuts.value(v)),
            None => out.for_each(|(o, &v)| *o = quantize(self.develop.channel(v))),
        }
    }

    /// `pixels` as 16-bit RGB into `out` (three values per pixel).
    pub fn rgb16(&self, pixels: &[[f32; 3]], out: &mut [u16]) {
        for (o, &v) in out.iter_mut().zip(pixels.iter().flatten()) {
            *o = quantize16(self.develop.channel(v));
        }
    }
}

/// `f` on every row of `image` and its share of the output, rows in parallel.
fn develop<T: Copy + Default + Send>(
    image: &Image,
    f: impl Fn(&[[f32; 3]], &mut [T]) + Sync,
) -> Vec<T> {
    let mut out = vec![T::default(); image.pixels.len() * 3];
    let row = (image.width as usize).max(1);
    out.par_chunks_mut(row * 3)
        .zip(image.pixels.par_chunks(row))
        .for_each(|(out, pixels)| f(pixels, out));
    out
}

/// Runs of `2^RUN_SHIFT` consecutive positive floats (those sharing their top bits) are
/// what [`Cuts8`] keeps a starting value for.
const RUN_SHIFT: u32 = 16;

/// An 8-bit development as cut-offs on radiance: the value of a channel is the number
/// of cut-offs at or below it, which a table read and a comparison or two find where
/// the formula takes an f64 `powf` and a rounding.
///
/// Exact where the developed value never falls as radiance grows, which holds for the
/// clamp: an exposure multiplies by a constant and the clamp takes a minimum (both
/// rounded monotonically), the sRGB curve's `powf` of two neighbouring f32 values
/// differs by some 10^8 times its f64 error, and the rounding to 8 bits keeps order.
/// (A test checks `Cuts8` against the formula for every f32 in 0..=1.)
/// Reinhard's `x / (1 + x)` in f32 can fall by an ulp where `1 + x` rounds up, so the
/// other tone maps keep the formula.
struct Cuts8 {
    /// `cut[k]`: the bits of the least positive radiance that develops above `k`
    /// (bits order positive floats as their values do); `u32::MAX` where none does.
    cut: [u32; 255],
    /// The value of the first float of every run, indexed by `bits >> RUN_SHIFT`.
    start: Vec<u8>,
    /// The value of zero, which NaN and negative radiance develop as.
    zero: u8,
}

impl Cuts8 {
    fn of(d: &Develop) -> Option<Cuts8> {
        if d.tonemap != ToneMap::Clamp {
            return None;
        }
        let value = |bits: u32| quantize(d.channel(f32::from_bits(bits)));
        let top = f32::INFINITY.to_bits();
        let mut cut = [u32::MAX; 255];
        // Each cut-off is found by bisection above the one before it.
        let mut lo = 1;
        for k in 0..=254u8 {
            if value(top) <= k {
                break;
            }
            let mut hi = top;
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if value(mid) > k {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            cut[usize::from(k)] = lo;
        }
        let start = (0..=top >> RUN_SHIFT)
            .map(|run| cut.partition_point(|&c| c <= run << RUN_SHIFT) as u8)
            .collect();
        Some(Cuts8 {
            cut,
            start,
            zero: value(0),
        })
    }

    #[inline]
    fn value(&self, radiance: f32) -> u8 {
        if radiance > 0.0 {
            let bits = radiance.to_bits();
            let mut k = self.start[(bits >> RUN_SHIFT) as usize];
            while k < 255 && self.cut[usize::from(k)] <= bits {
                k += 1;
            }
            k
        } else {
            self.zero
        }
    }
}

/// 0..1 to 0..65535, rounded; NaN and out-of-range values are clamped.
pub fn quantize16(v: f32) -> u16 {
    if v.is_nan() {
        return 0;
    }
    (v.clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// Parses an exposure in stops for the command line: finite, within ±64 stops (beyond
/// that every pixel is black or white).
pub fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(ev) if ev.is_finite() && ev.abs() <= 64.0 => Ok(ev),
        _ => Err(format!(
            "expected an exposure in stops between -64 and 64, found {}",
            crate::util::text::shown(s)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gray(v: f32) -> Image {
        Image::new(1, 1, vec![[v; 3]])
    }

    /// Rows are developed in parallel: on one thread or three, every channel is what
    /// the formula gives it, in place.
    #[test]
    fn rows_develop_in_place_on_any_number_of_threads() {
        let (w, h) = (37, 23);
        let pixels = (0..w * h)
            .map(|i| {
                let v = i as f32 / (w * h) as f32;
                [v * 1.3, 1.0 - v, (i % 7) as f32 * 0.2 - 0.1]
            })
            .collect();
        let image = Image::new(w, h, pixels);
        let d = Develop {
            exposure: 0.5,
            ..Develop::display()
        };
        let flat: Vec<f32> = image.pixels.iter().flatten().copied().collect();
        let want16: Vec<u16> = flat.iter().map(|&v| quantize16(d.channel(v))).collect();
        let want8: Vec<u8> = flat.iter().map(|&v| quantize(d.channel(v))).collect();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| d.to_rgb16(&image)), want16, "{threads}");
            assert_eq!(pool.install(|| d.to_rgb8(&image)), want8, "{threads}");
        }
    }

    fn rgb8(d: Develop, v: f32) -> u8 {
        d.to_rgb8(&gray(v))[0]
    }

    fn rgb16(d: Develop, v: f32) -> u16 {
        d.to_rgb16(&gray(v))[0]
    }

    #[test]
    fn srgb_curve_exact_values() {
        let d = Develop::display();
        assert_eq!((rgb8(d, 0.0), rgb16(d, 0.0)), (0, 0));
        assert_eq!((rgb8(d, 1.0), rgb16(d, 1.0)), (255, 65535));
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735356983...: 187.516 -> 188, 48191.62 -> 48192.
        assert_eq!(rgb8(d, 0.5), 188);
        assert_eq!(rgb16(d, 0.5), 48192);
        // The linear segment ends at 0.0031308 -> 12.92 * 0.0031308 = 0.04044994:
        // 10.31 in 8 bits, 2650.87 in 16.
        assert_eq!(rgb8(d, 0.003_130_8), 10);
        assert_eq!(rgb16(d, 0.003_130_8), 2651);
        assert_eq!(rgb16(d, 0.001), 847); // 0.01292 * 65535 = 846.7
        // The two pieces meet: no jump across the boundary.
        let below = Transfer::Srgb.encode(0.003_130_8);
        let above = Transfer::Srgb.encode(0.003_130_8f32.next_up());
        assert!((above - below).abs() < 1e-6, "{below} {above}");
    }

    #[test]
    fn exposure_is_in_stops() {
        let plus1 = Develop {
            exposure: 1.0,
            ..Develop::classic()
        };
        let minus2 = Develop {
            exposure: -2.0,
            ..Develop::classic()
        };
        assert_eq!(plus1.channel(0.25), 0.5);
        assert_eq!(plus1.channel(0.3), 0.6);
        assert_eq!(minus2.channel(0.8), 0.2);
        assert_eq!(rgb8(plus1, 0.25), rgb8(Develop::classic(), 0.5));
    }

    #[test]
    fn reinhard_and_aces_at_known_inputs() {
        let r = ToneMap::Reinhard;
        assert_eq!(
            [
                r.apply(0.0),
                r.apply(1.0),
                r.apply(3.0),
                r.apply(f32::INFINITY)
            ],
            [0.0, 0.5, 0.75, 1.0]
        );
        let a = ToneMap::Aces;
        assert_eq!(a.apply(0.0), 0.0);
        // 1 * 2.54 / 3.16 = 0.80379746...
        assert_eq!(a.apply(1.0), (2.54f64 / 3.16) as f32);
        // 0.18 (middle grey): 0.18 * 0.4818 / (0.18 * 1.0274 + 0.14) = 0.266899...
        assert!(
            (a.apply(0.18) - 0.266_899).abs() < 1e-6,
            "{}",
            a.apply(0.18)
        );
        // Saturates at 1 (the fit's limit is 2.51 / 2.43 > 1), from x = 7.24 (0.08 x² = 0.56 x + 0.14), also far out and at +inf.
        assert!(a.apply(7.2) < 1.0 && a.apply(7.3) == 1.0);
        assert_eq!(
            [a.apply(1e6), a.apply(f32::MAX), a.apply(f32::INFINITY)],
            [1.0; 3]
        );
        assert_eq!(ToneMap::Clamp.apply(7.0), 1.0);
        // Through a Develop: Reinhard of 1 is 0.5, no curve -> 128 (127.5 rounds up).
        let d = Develop {
            tonemap: ToneMap::Reinhard,
            ..Develop::classic()
        };
        assert_eq!(rgb8(d, 1.0), 128);
    }

    #[test]
    fn non_finite_and_negative_radiance() {
        for d in [Develop::classic(), Develop::display()] {
            for t in ToneMap::ALL {
                let d = Develop { tonemap: t, ..d };
                let img = Image::new(
                    4,
                    1,
                    vec![
                        [f32::NAN; 3],
                        [f32::INFINITY; 3],
                        [f32::NEG_INFINITY; 3],
                        [-2.0; 3],
                    ],
                );
                assert_eq!(d.to_rgb8(&img), [0, 0, 0, 255, 255, 255, 0, 0, 0, 0, 0, 0]);
                assert_eq!(d.to_rgb16(&img)[3..6], [65535; 3]);
            }
        }
        // An exposure so large that 2^EV overflows: 0 stays black, not NaN.
        let huge = Develop {
            exposure: 200.0,
            ..Develop::display()
        };
        assert_eq!(
            huge.to_rgb8(&Image::new(2, 1, vec![[0.0; 3], [1e-30; 3]])),
            [0, 0, 0, 255, 255, 255]
        );
    }

    #[test]
    fn classic_matches_quantize_bit_for_bit() {
        // Every 1/16 of an 8-bit step over -0.1..1.1, around every rounding boundary, and
        // the special values: classic development must equal `Image::to_rgb8`.
        let mut values: Vec<f32> = (-400..=4500).map(|i| i as f32 / (255.0 * 16.0)).collect();
        for k in 0..=255 {
            let edge = (k as f32 + 0.5) / 255.0;
            values.extend([edge, edge.next_down(), edge.next_up()]);
        }
        values.extend([
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            f32::MAX,
            1e-40,
        ]);
        let pixels: Vec<[f32; 3]> = values.iter().map(|&v| [v, 1.0 - v, v * 0.5]).collect();
        let img = Image::new(pixels.len() as u32, 1, pixels);
        assert_eq!(Develop::classic().to_rgb8(&img), img.to_rgb8());
    }

    /// Developments the cut-offs must reproduce: both curves, exposures that scale,
    /// overflow and underflow, and the tone maps that keep the formula.
    fn developments() -> Vec<Develop> {
        let mut all = Vec::new();
        for transfer in [Transfer::Srgb, Transfer::Classic] {
            for tonemap in ToneMap::ALL {
                for exposure in [0.0, 1.0, -2.0, 0.37, 7.5, -7.5, 64.0, -64.0, 200.0, -200.0] {
                    all.push(Develop {
                        exposure,
                        tonemap,
                        transfer,
                    });
                }
            }
        }
        all
    }

    /// What `to_rgb8` gave before the cut-offs: the formula, channel by channel.
    fn by_formula(d: &Develop, values: &[f32]) -> Vec<u8> {
        values.iter().map(|&v| quantize(d.channel(v))).collect()
    }

    /// `values` as an image 61 pixels wide (rows developed in parallel), padded with 0.
    fn image_of(values: &[f32]) -> (Image, Vec<f32>) {
        let mut values = values.to_vec();
        while !values.len().is_multiple_of(3 * 61) {
            values.push(0.0);
        }
        let pixels: Vec<[f32; 3]> = values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let h = pixels.len() as u32 / 61;
        (Image::new(61, h, pixels), values)
    }

    /// Every NaN develops to black, signalling ones too, on every machine.
    #[test]
    fn nan_develops_to_black() {
        let nans = [
            0x7fc0_0000,
            0xffc0_0000,
            0x7fc0_1234,
            0x7f80_0001,
            0xff80_0001,
            0x7fbf_ffff,
        ];
        for d in developments() {
            for bits in nans {
                let v = std::hint::black_box(f32::from_bits(bits));
                assert_eq!(quantize(d.channel(v)), 0, "{d:?} {bits:08x}");
            }
        }
    }

    #[test]
    fn cut_offs_develop_every_value_as_the_formula_does() {
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(0xc0ffee, 3);
        let mut values: Vec<f32> = (-400..=20_000).map(|i| i as f32 / (255.0 * 16.0)).collect();
        values.extend((0..100_000).map(|_| f32::from_bits(rng.next_u32())));
        values.extend((0..100_000).map(|_| (rng.next_u32() >> 8) as f32 / (1u32 << 23) as f32));
        values.extend([
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7fc0_1234),
            f32::from_bits(0x7f80_0001),
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x007f_ffff),
            -f32::from_bits(1),
            f32::MAX,
            f32::MIN,
            1.0,
            1.0f32.next_up(),
            1.0f32.next_down(),
            0.003_130_8,
            0.003_130_8f32.next_up(),
            0.003_130_8f32.next_down(),
        ]);
        for d in developments() {
            let mut all = values.clone();
            // Around every cut-off, and every 8-bit boundary of the curve's output.
            if let Some(cuts) = Cuts8::of(&d) {
                for &c in cuts.cut.iter().filter(|&&c| c != u32::MAX) {
                    all.extend((c.saturating_sub(300)..c.saturating_add(300)).map(f32::from_bits));
                }
            }
            for k in 0..=255 {
                let edge = (k as f32 + 0.5) / 255.0;
                all.extend([edge, edge.next_down(), edge.next_up()]);
            }
            let (img, all) = image_of(&all);
            assert!(
                d.to_rgb8(&img) == by_formula(&d, &all),
                "{d:?}: {:?}",
                all.iter()
                    .zip(d.to_rgb8(&img))
                    .find(|&(&v, q)| q != quantize(d.channel(v)))
            );
        }
    }

    /// Every f32 from 0 to 1 through the cut-offs of the clamp with both curves: the
    /// check behind their exactness for all radiance (some seconds on two cores).
    #[test]
    fn cut_offs_match_the_formula_for_every_f32_up_to_1() {
        for d in [Develop::display(), Develop::classic()] {
            let cuts = Cuts8::of(&d).unwrap();
            let bad = (0..=1.0f32.to_bits())
                .into_par_iter()
                .map(f32::from_bits)
                .find_any(|&v| cuts.value(v) != quantize(d.channel(v)));
            assert_eq!(bad, None, "{d:?}");
        }
    }

    #[test]
    fn quantize16_rounds_and_clamps() {
        assert_eq!(quantize16(0.5), 32768); // 32767.5 rounds away from zero
        assert_eq!(quantize16(0.49 / 65535.0), 0);
        assert_eq!(quantize16(0.51 / 65535.0), 1);
        assert_eq!(
            [quantize16(-1.0), quantize16(2.0), quantize16(f32::NAN)],
            [0, 65535, 0]
        );
    }

    #[test]
    fn names_parse() {
        for t in ToneMap::ALL {
            assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
            assert_eq!(t.to_string(), t.name());
        }
        assert_eq!(ToneMap::default(), ToneMap::Clamp);
        let e = "filmic".parse::<ToneMap>().unwrap_err();
        assert_eq!(
            e,
            "unknown tone map `filmic`: expected clamp, reinhard or aces"
        );
    }

    #[test]
    fn exposure_parses_in_range() {
        assert_eq!(parse_exposure("-1.5"), Ok(-1.5));
        assert_eq!(parse_exposure("64"), Ok(64.0));
        for bad in ["inf", "NaN", "65", "two"] {
            let e = parse_exposure(bad).unwrap_err();
            assert!(e.contains("between -64 and 64") && e.contains(bad), "{e}");
        }
    }

    #[test]
    fn default_is_display() {
        assert_eq!(Develop::default(), Develop::display());
        assert_eq!(Develop::display().transfer, Transfer::Srgb);
    }
}
