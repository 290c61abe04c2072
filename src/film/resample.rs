//! Anti-aliasing resampler: shrinks a supersampled frame by an integer factor `k` per axis.
//!
//! # Convention
//! Separable convolution with the tap rule of Pillow's `precompute_coeffs`, which
//! `fast_image_resize` implements too: this is what users of image tools know, and that
//! crate can serve as the test oracle. For output sample `o` of an axis with `k * n` input
//! samples:
//! - `centre = (o + 0.5) * k`, `support = radius * k` (the kernel is widened by `k`
//!   because we downscale);
//! - taps `x` in `max(0, floor(centre - support + 0.5)) .. min(in_len, floor(centre +
//!   support + 0.5))` with weight `f((x - centre + 0.5) / k)`;
//! - the weights are divided by their sum: near the frame borders the kernel is truncated
//!   and renormalised (no padding, no mirroring).
//!
//! Zero weights at either end of a tap list are dropped (as `fast_image_resize` does): the
//! result is unchanged, fewer input samples are needed, and a non-finite sample that gets
//! weight 0 cannot turn an output into NaN.
//!
//! Kernels `f` (radius in output pixels):
//! - `Area`: box, `f = 1` on `(-0.5, 0.5]` (Pillow's half-open side; for integer `k` no tap
//!   lands on ±0.5), radius 0.5. For integer `k` this is exactly the mean of the `k x k` block.
//! - `Bilinear`: triangle `1 - |x|`, radius 1.
//! - `Bicubic`: Catmull-Rom cubic (`a = -0.5`), radius 2.
//! - `Lanczos`: Lanczos-3, `sinc(x) sinc(x / 3)` on `[-3, 3)`, radius 3.
//! - `Nearest`: one tap at `floor((o + 0.5) * k)` (index `4o + 2` for `k = 4`), weight 1.
//!
//! `k == 1` is the identity for every filter by special case (one tap, weight 1). Pillow's
//! formula gives the identity for the box only; the other kernels vanish at non-zero
//! integers, so it gives the identity mathematically, but `sin(n * pi)` is not exactly 0
//! in floating point, and Lanczos would leave weights around 1e-17 on neighbours. (Pillow
//! and `fast_image_resize` skip the pass when sizes are equal, so users see the identity.)
//!
//! # Passes and windows
//! The weight tables cover the full frame ([`AxisWeights`]) and are built once. Any window
//! of output pixels can then be produced from the supersampled samples it needs
//! ([`AxisWeights::input_span`]): horizontal pass over the needed rows, then vertical pass.
//! Every output pixel is computed by the same operations in the same order whatever the
//! window, so a window (a region, or a horizontal band) is bit-for-bit the crop of a
//! full-frame resample. Results are not clamped: Bicubic and Lanczos have negative lobes,
//! and the caller clamps when quantising. Single-threaded and deterministic.

pub use crate::options::Filter;

impl Filter {
    /// Kernel radius in output pixels (`Nearest` is handled apart).
    fn radius(self) -> f64 {
        match self {
            Filter::Nearest | Filter::Area => 0.5,
            Filter::Bilinear => 1.0,
            Filter::Bicubic => 2.0,
            Filter::Lanczos => 3.0,
        }
    }

    /// The kernel at `x` output pixels from the centre (same formulas as Pillow).
    fn kernel(self, x: f64) -> f64 {
        fn sinc(x: f64) -> f64 {
            if x == 0.0 {
                1.0
            } else {
                let px = x * std::f64::consts::PI;
                px.sin() / px
            }
        }
        match self {
            Filter::Nearest | Filter::Area => f64::from(u8::from(x > -0.5 && x <= 0.5)),
            Filter::Bilinear => (1.0 - x.abs()).max(0.0),
            Filter::Bicubic => {
                const A: f64 = -0.5;
                let x = x.abs();
                if x < 1.0 {
                    ((A + 2.0) * x - (A + 3.0)) * x * x + 1.0
                } else if x < 2.0 {
                    (((x - 5.0) * x + 8.0) * x - 4.0) * A
                } else {
                    0.0
                }
            }
            Filter::Lanczos if (-3.0..3.0).contains(&x) => sinc(x) * sinc(x / 3.0),
            Filter::Lanczos => 0.0,
        }
    }
}

/// Per-output-sample taps along one axis of the full frame.
///
/// Output `o` reads input samples `first[o] ..` with weights
/// `weights[offsets[o] .. offsets[o + 1]]` (flat storage, no allocation per output).
#[derive(Clone, Debug, PartialEq)]
pub struct AxisWeights {
    first: Vec<u32>,
    offsets: Vec<u32>,
    weights: Vec<f32>,
}

impl AxisWeights {
    /// Taps for shrinking `k * out_len` input samples to `out_len`.
    ///
    /// # Panics
    /// If `k == 0` or `k * out_len` overflows `u32`.
    pub fn new(filter: Filter, k: u32, out_len: u32) -> AxisWeights {
        assert!(k >= 1, "resampling factor must be at least 1");
        let in_len = k.checked_mul(out_len).expect("input length overflows u32");
        let n = out_len as usize;
        let mut w = AxisWeights {
            first: Vec::with_capacity(n),
            offsets: Vec::with_capacity(n + 1),
            weights: Vec::new(),
        };
        w.offsets.push(0);
        let (mut taps, mut norm) = (Vec::<f64>::new(), Vec::<f32>::new());
        for o in 0..out_len {
            if k == 1 || filter == Filter::Nearest {
                // floor((o + 0.5) * k) in integers.
                let x = ((2 * u64::from(o) + 1) * u64::from(k) / 2) as u32;
                w.push(x, &[1.0]);
                continue;
            }
            let (kf, centre) = (f64::from(k), (f64::from(o) + 0.5) * f64::from(k));
            let support = filter.radius() * kf;
            let lo = (centre - support + 0.5).floor().max(0.0) as u32;
            let hi = ((centre + support + 0.5).floor() as u32).min(in_len);
            taps.clear();
            taps.extend((lo..hi).map(|x| filter.kernel((f64::from(x) - centre + 0.5) / kf)));
            let skip = taps.iter().take_while(|&&t| t == 0.0).count();
            let keep = taps.len() - taps.iter().rev().take_while(|&&t| t == 0.0).count();
            let taps = &taps[skip..keep.max(skip)];
            let sum: f64 = taps.iter().sum();
            assert!(sum != 0.0, "filter {filter} gives no weight to output {o}");
            norm.clear();
            norm.extend(taps.iter().map(|&t| (t / sum) as f32));
            w.push(lo + skip as u32, &norm);
        }
        w
    }

    fn push(&mut self, first: u32, weights: &[f32]) {
        self.first.push(first);
        self.weights.extend_from_slice(weights);
        self.offsets.push(self.weights.len() as u32);
    }

    /// Number of output samples.
    pub fn out_len(&self) -> u32 {
        self.first.len() as u32
    }

    /// First input index and weights of output `o`.
    pub fn taps(&self, o: u32) -> (u32, &[f32]) {
        let o = o as usize;
        let (a, b) = (self.offsets[o] as usize, self.offsets[o + 1] as usize);
        (self.first[o], &self.weights[a..b])
    }

    /// The input range `[lo, hi)` needed to produce outputs `[out_lo, out_hi)`;
    /// `(0, 0)` for an empty range.
    pub fn input_span(&self, out_lo: u32, out_hi: u32) -> (u32, u32) {
        assert!(
            out_lo <= out_hi && out_hi <= self.out_len(),
            "output range out of frame"
        );
        (out_lo..out_hi)
            .map(|o| {
                let (x, w) = self.taps(o);
                (x, x + w.len() as u32)
            })
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
            .unwrap_or((0, 0))
    }
}

/// Resamples a window of the full frame. `input` holds rows `in_y0..in_y0 + in_h` and
/// columns `in_x0..in_x0 + in_w` of the supersampled frame, row-major (it must cover the
/// spans returned by [`AxisWeights::input_span`] for the requested outputs); produces output
/// pixels for columns `out_x0..out_x0 + out_w` and rows `out_y0..out_y0 + out_h` of the
/// final frame, row-major. The result equals that crop of [`resample`] bit for bit.
///
/// # Panics
/// If `input.len() != in_w * in_h`, or the input window does not cover the needed spans.
#[allow(clippy::too_many_arguments)]
pub fn resample_window(
    input: &[[f32; 3]],
    in_x0: u32,
    in_y0: u32,
    in_w: u32,
    in_h: u32,
    wx: &AxisWeights,
    wy: &AxisWeights,
    out_x0: u32,
    out_y0: u32,
    out_w: u32,
    out_h: u32,
) -> Vec<[f32; 3]> {
    let mut out = vec![[0.0f32; 3]; out_w as usize * out_h as usize];
    resample_window_into(
        input, in_x0, in_y0, in_w, in_h, wx, wy, out_x0, out_y0, out_w, out_h, &mut out,
    );
    out
}

/// [`resample_window`] into `out`, `out_w x out_h` pixels (a band of a frame being
/// written in place), every pixel overwritten.
#[allow(clippy::too_many_arguments)]
pub fn resample_window_into(
    input: &[[f32; 3]],
    in_x0: u32,
    in_y0: u32,
    in_w: u32,
    in_h: u32,
    wx: &AxisWeights,
    wy: &AxisWeights,
    out_x0: u32,
    out_y0: u32,
    out_w: u32,
    out_h: u32,
    out: &mut [[f32; 3]],
) {
    assert_eq!(input.len(), in_w as usize * in_h as usize, "input size");
    assert_eq!(out.len(), out_w as usize * out_h as usize, "output size");
    if out_w == 0 || out_h == 0 {
        return;
    }
    let (x_lo, x_hi) = wx.input_span(out_x0, out_x0 + out_w);
    let (y_lo, y_hi) = wy.input_span(out_y0, out_y0 + out_h);
    assert!(
        in_x0 <= x_lo && x_hi <= in_x0 + in_w && in_y0 <= y_lo && y_hi <= in_y0 + in_h,
        "input window {in_x0},{in_y0} {in_w}x{in_h} does not cover columns {x_lo}..{x_hi}, \
         rows {y_lo}..{y_hi}"
    );
    let (ow, iw) = (out_w as usize, in_w as usize);

    // Horizontal pass: input rows y_lo..y_hi into out_w columns.
    let mut tmp = vec![[0.0f32; 3]; ow * (y_hi - y_lo) as usize];
    for (r, tmp_row) in tmp.chunks_exact_mut(ow).enumerate() {
        let row_start = (y_lo - in_y0) as usize + r;
        let row = &input[row_start * iw..(row_start + 1) * iw];
        for (c, out) in tmp_row.iter_mut().enumerate() {
            let (x, ws) = wx.taps(out_x0 + c as u32);
            let src = &row[(x - in_x0) as usize..][..ws.len()];
            let mut acc = [0.0f32; 3];
            ws.iter().zip(src).for_each(|(&w, p)| madd(&mut acc, w, p));
            *out = acc;
        }
    }

    // Vertical pass: rows of tmp into output rows, accumulated a whole row at a time.
    for (r, out_row) in out.chunks_exact_mut(ow).enumerate() {
        out_row.fill([0.0; 3]);
        let (y, ws) = wy.taps(out_y0 + r as u32);
        for (t, &w) in ws.iter().enumerate() {
            let tr = (y - y_lo) as usize + t;
            for (acc, p) in out_row.iter_mut().zip(&tmp[tr * ow..(tr + 1) * ow]) {
                madd(acc, w, p);
            }
        }
    }
}

/// `acc += w * p`, per channel, in one fixed order.
#[inline]
fn madd(acc: &mut [f32; 3], w: f32, p: &[f32; 3]) {
    for ch in 0..3 {
        acc[ch] += w * p[ch];
    }
}

/// Resamples a whole `in_w x in_h` frame by `k` (both multiples of `k`).
pub fn resample(input: &[[f32; 3]], in_w: u32, in_h: u32, k: u32, filter: Filter) -> Vec<[f32; 3]> {
    assert!(
        k >= 1 && in_w.is_multiple_of(k) && in_h.is_multiple_of(k),
        "frame size not a multiple of {k}"
    );
    let (out_w, out_h) = (in_w / k, in_h / k);
    let wx = AxisWeights::new(filter, k, out_w);
    let wy = AxisWeights::new(filter, k, out_h);
    resample_window(input, 0, 0, in_w, in_h, &wx, &wy, 0, 0, out_w, out_h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fast_image_resize::{FilterType as T, ResizeAlg};
    use proptest::prelude::*;

    type Px = [f32; 3];

    /// Deterministic pseudo-random image in [0, 1) (xorshift64*).
    fn image(w: u32, h: u32, seed: u64) -> Vec<Px> {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = || {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            (s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..w * h).map(|_| [next(), next(), next()]).collect()
    }

    #[test]
    fn names_parse_and_default() {
        for f in Filter::ALL {
            assert_eq!(f.name().parse::<Filter>(), Ok(f));
            assert_eq!(f.to_string(), f.name());
        }
        assert_eq!(Filter::default(), Filter::Area);
        let err = "gaussian".parse::<Filter>().unwrap_err();
        assert!(err.contains("`gaussian`") && err.contains("bilinear, area, bicubic or lanczos"));
    }

    #[test]
    fn area_k2_gives_block_means() {
        let input: Vec<Px> = (0..16u8).map(f32::from).map(|x| [x, 2.0 * x, -x]).collect();
        let means = [2.5f32, 4.5, 10.5, 12.5]; // (0+1+4+5)/4, (2+3+6+7)/4, ...
        let expect: Vec<Px> = means.iter().map(|&m| [m, 2.0 * m, -m]).collect();
        assert_eq!(resample(&input, 4, 4, 2, Filter::Area), expect);
        let ws = AxisWeights::new(Filter::Area, 2, 2);
        assert_eq!(ws.taps(1), (2, &[0.5f32, 0.5][..]));
    }

    #[test]
    fn k1_is_identity_for_every_filter() {
        let input = image(7, 5, 1);
        for f in Filter::ALL {
            assert_eq!(resample(&input, 7, 5, 1, f), input, "{f}");
        }
    }

    #[test]
    fn nearest_k4_picks_centre_sample() {
        let w4 = AxisWeights::new(Filter::Nearest, 4, 5);
        for o in 0..5 {
            assert_eq!(w4.taps(o), (4 * o + 2, &[1.0f32][..]));
        }
        let w3 = AxisWeights::new(Filter::Nearest, 3, 2); // floor(1.5 * 3) = 4
        assert_eq!(w3.taps(1), (4, &[1.0f32][..]));
        let input = image(16, 8, 2);
        let out = resample(&input, 16, 8, 4, Filter::Nearest);
        for (oy, ox) in [(0, 0), (0, 3), (1, 2)] {
            assert_eq!(out[oy * 4 + ox], input[(4 * oy + 2) * 16 + 4 * ox + 2]);
        }
    }

    #[test]
    fn bilinear_k2_interior_weights() {
        // centre 2o+1, support 2: taps 2o-1..2o+3 at (x - 2o - 0.5)/2 = -0.75, -0.25, 0.25,
        // 0.75 -> 1/4, 3/4, 3/4, 1/4, sum 2.
        let ws = AxisWeights::new(Filter::Bilinear, 2, 8);
        assert_eq!(ws.taps(3), (5, &[0.125f32, 0.375, 0.375, 0.125][..]));
    }

    #[test]
    fn bicubic_k2_interior_weights() {
        // Taps 2o-3..2o+5. Catmull-Rom at ±0.25, ±0.75, ±1.25, ±1.75: 0.8671875, 0.2265625,
        // -0.0703125, -0.0234375; the sum is 2, so all halve exactly.
        let ws = AxisWeights::new(Filter::Bicubic, 2, 8);
        let half = [-0.01171875f32, -0.03515625, 0.11328125, 0.43359375];
        let expect: Vec<f32> = half.iter().chain(half.iter().rev()).copied().collect();
        assert_eq!(ws.taps(4), (5, &expect[..]));
    }

    #[test]
    fn lanczos_k2_interior_weights() {
        // Taps 2o-5..2o+7 at ±0.25, ±0.75, ..., ±2.75 output pixels from the centre.
        let ws = AxisWeights::new(Filter::Lanczos, 2, 10);
        let (x, w) = ws.taps(5);
        assert_eq!((x, w.len()), (5, 12));
        let pi = std::f64::consts::PI;
        let l = |t: f64| 3.0 * (pi * t).sin() * (pi * t / 3.0).sin() / (pi * pi * t * t);
        assert!((l(0.25) - 0.890_067_05).abs() < 1e-7); // sinc(1/4) sinc(1/12)
        let raw: Vec<f64> = (0..12).map(|i| l(-2.75 + 0.5 * f64::from(i))).collect();
        let sum: f64 = raw.iter().sum();
        for (got, r) in w.iter().zip(&raw) {
            assert!((f64::from(*got) - r / sum).abs() < 1e-7, "{got}");
        }
        assert!(w[..6].iter().eq(w[6..].iter().rev()), "symmetric");
    }

    #[test]
    fn weights_sum_to_one_and_stay_in_frame() {
        for (f, k, n) in Filter::ALL
            .iter()
            .flat_map(|&f| (1..=5).map(move |k| (f, k)))
            .flat_map(|(f, k)| [1, 2, 3, 7].map(|n| (f, k, n)))
        {
            let ws = AxisWeights::new(f, k, n);
            for o in 0..n {
                let (x, w) = ws.taps(o);
                let sum: f32 = w.iter().sum();
                assert!((sum - 1.0).abs() < 1e-6, "{f} k={k} n={n} o={o}: {sum}");
                assert!(!w.is_empty() && x + w.len() as u32 <= k * n);
                assert!(
                    w[0] != 0.0 && w[w.len() - 1] != 0.0,
                    "no zero taps at the ends"
                );
            }
        }
        // Borders truncate: Lanczos k=2 output 0 has taps 0..7 (not -5..7).
        let span = |f, k, n, a, b| AxisWeights::new(f, k, n).input_span(a, b);
        assert_eq!(span(Filter::Lanczos, 2, 10, 0, 1), (0, 7));
        assert_eq!(span(Filter::Lanczos, 2, 10, 0, 2), (0, 9));
        assert_eq!(span(Filter::Bicubic, 2, 10, 9, 10), (15, 20));
        assert_eq!(span(Filter::Area, 4, 10, 3, 5), (12, 20));
        assert_eq!(span(Filter::Area, 4, 10, 3, 3), (0, 0));
    }

    #[test]
    fn constant_image_stays_constant() {
        let c = [0.3f32, 1.0, 7.5];
        for (f, k) in Filter::ALL
            .iter()
            .flat_map(|&f| (1..=5).map(move |k| (f, k)))
        {
            for p in resample(&vec![c; (28 * k * k) as usize], 7 * k, 4 * k, k, f) {
                let ok = p.iter().zip(c).all(|(a, b)| (a - b).abs() <= 1e-6 * b);
                assert!(ok, "{f} k={k}: {p:?}");
            }
        }
    }

    #[test]
    fn results_are_not_clamped() {
        // A bright column next to black: Lanczos' negative lobe goes below 0.
        let mut input = vec![[0.0f32; 3]; 24 * 2];
        (input[12], input[36]) = ([1.0; 3], [1.0; 3]);
        let out = resample(&input, 24, 2, 2, Filter::Lanczos);
        assert!(out.iter().any(|p| p[0] < 0.0));
    }

    /// Outputs `[ox, ox+ow) x [oy, oy+oh)` from the full input cropped to their spans.
    fn window(full: &[Px], k: u32, (w, h): (u32, u32), f: Filter, win: [u32; 4]) -> Vec<Px> {
        let [ox, oy, ow, oh] = win;
        let (wx, wy) = (AxisWeights::new(f, k, w), AxisWeights::new(f, k, h));
        let ((x0, x1), (y0, y1)) = (wx.input_span(ox, ox + ow), wy.input_span(oy, oy + oh));
        let row = |y: u32| &full[(y * k * w + x0) as usize..(y * k * w + x1) as usize];
        let crop: Vec<Px> = (y0..y1).flat_map(row).copied().collect();
        resample_window(&crop, x0, y0, x1 - x0, y1 - y0, &wx, &wy, ox, oy, ow, oh)
    }

    proptest! {
        #[test]
        fn window_equals_crop_of_full(k in 1u32..=5, w in 1u32..10, h in 1u32..10,
                                      a in 0u32..100, b in 0u32..100, c in 0u32..100,
                                      d in 0u32..100, seed in any::<u64>()) {
            let (ox, oy) = (a % w, b % h);
            let (ow, oh) = (1 + c % (w - ox), 1 + d % (h - oy));
            let input = image(k * w, k * h, seed);
            for f in Filter::ALL {
                let full = resample(&input, k * w, k * h, k, f);
                let row = |y: u32| &full[(y * w + ox) as usize..(y * w + ox + ow) as usize];
                let crop: Vec<Px> = (oy..oy + oh).flat_map(row).copied().collect();
                let got = window(&input, k, (w, h), f, [ox, oy, ow, oh]);
                let bits = |v: &[Px]| v.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
                prop_assert_eq!(bits(&got), bits(&crop), "{} window {:?}", f, (ox, oy, ow, oh));
            }
        }
    }

    #[test]
    #[should_panic(expected = "does not cover")]
    fn short_input_window_panics() {
        let wx = AxisWeights::new(Filter::Bilinear, 2, 4);
        let input = vec![[0.0f32; 3]; 4 * 8];
        resample_window(&input, 2, 0, 4, 8, &wx, &wx, 1, 0, 2, 4);
    }

    /// Oracle: fast_image_resize (Pillow's scheme, f64 weights and sums, f32 between passes).
    fn oracle(input: &[Px], w: u32, h: u32, k: u32, alg: ResizeAlg) -> Vec<Px> {
        use fast_image_resize::{ResizeOptions, Resizer, images::TypedImage, pixels::F32x3};
        let pixels = input.iter().map(|&p| F32x3::new(p)).collect();
        let src = TypedImage::<F32x3>::from_pixels(w, h, pixels).unwrap();
        let mut dst = TypedImage::<F32x3>::new(w / k, h / k);
        let options = ResizeOptions::new().resize_alg(alg);
        Resizer::new()
            .resize_typed(&src, &mut dst, &options)
            .unwrap();
        dst.pixels().iter().map(|p| p.0).collect()
    }

    #[test]
    fn matches_fast_image_resize() {
        let cases = [
            (Filter::Nearest, ResizeAlg::Nearest),
            (Filter::Area, ResizeAlg::Convolution(T::Box)),
            (Filter::Bilinear, ResizeAlg::Convolution(T::Bilinear)),
            (Filter::Bicubic, ResizeAlg::Convolution(T::CatmullRom)),
            (Filter::Lanczos, ResizeAlg::Convolution(T::Lanczos3)),
        ];
        // The brief's 48x32 -> 12x8, an odd k, and a kernel wider than the frame.
        for (w, h, k) in [(48, 32, 4), (45, 33, 3), (15, 10, 5)] {
            let input = image(w, h, u64::from(w * h));
            for (f, alg) in cases {
                let (ours, theirs) = (resample(&input, w, h, k, f), oracle(&input, w, h, k, alg));
                let diffs = ours
                    .iter()
                    .zip(&theirs)
                    .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()));
                let d = diffs.fold(0.0f32, f32::max);
                eprintln!("{w}x{h} k={k} {f}: max |diff| = {d:e}");
                assert!(d < 1e-5 && ours.len() == theirs.len(), "{f}: {d}");
            }
        }
    }
}
