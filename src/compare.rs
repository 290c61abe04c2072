//! Image comparison for golden-image tests and fidelity checks against reference crops.
//!
//! Images are 8-bit RGB, row-major, tightly packed (`width * height * 3` bytes), borrowed
//! through [`RgbImage`]. These are test/analysis helpers: misuse (mismatched sizes, a template
//! larger than the image, out-of-bounds crops, a data length that does not match the size)
//! panics via `assert!` with a descriptive message instead of returning an error.

/// A borrowed 8-bit RGB image: row-major, 3 bytes per pixel, no row padding.
#[derive(Clone, Copy, Debug)]
pub struct RgbImage<'a> {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 3` bytes, R G B per pixel, top row first.
    pub data: &'a [u8],
}

impl<'a> RgbImage<'a> {
    /// Wraps `data`. Panics if `data.len() != width * height * 3`.
    pub fn new(width: u32, height: u32, data: &'a [u8]) -> Self {
        let img = RgbImage {
            width,
            height,
            data,
        };
        img.dims();
        img
    }

    /// (width, height) as `usize`, after checking the data length.
    fn dims(&self) -> (usize, usize) {
        let (w, h) = (self.width as usize, self.height as usize);
        let len = self.data.len();
        assert!(
            len == w * h * 3,
            "RgbImage {w}x{h} needs {} bytes, got {len}",
            w * h * 3
        );
        (w, h)
    }

    /// Rec.601 luma, Y = 0.299 R + 0.587 G + 0.114 B, on the 0..=255 scale.
    fn luma(&self) -> Vec<f64> {
        let y =
            |p: &[u8]| 0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2]);
        self.data.chunks_exact(3).map(y).collect()
    }
}

fn assert_same_size(a: &RgbImage, b: &RgbImage) -> (usize, usize) {
    let (da, db) = (a.dims(), b.dims());
    assert!(
        da == db,
        "image size mismatch: {da:?} vs {db:?} (width, height)"
    );
    da
}

/// Per-channel absolute differences; panics if the sizes differ.
fn abs_diffs<'x>(a: &RgbImage<'x>, b: &RgbImage<'x>) -> impl Iterator<Item = u8> + 'x {
    assert_same_size(a, b);
    a.data.iter().zip(b.data).map(|(&x, &y)| x.abs_diff(y))
}

/// Peak signal-to-noise ratio in dB over all channels, peak 255. Identical images give
/// `f64::INFINITY`. Panics if the sizes differ.
pub fn psnr(a: &RgbImage, b: &RgbImage) -> f64 {
    let sse: f64 = abs_diffs(a, b).map(|d| f64::from(d).powi(2)).sum();
    if sse == 0.0 {
        return f64::INFINITY;
    }
    // Written so that an MSE of exactly 1 gives exactly 20 log10(255).
    20.0 * 255f64.log10() - 10.0 * (sse / a.data.len() as f64).log10()
}

/// Largest absolute per-channel difference. Panics if the sizes differ.
pub fn max_abs_diff(a: &RgbImage, b: &RgbImage) -> u8 {
    abs_diffs(a, b).max().unwrap_or(0)
}

/// Mean absolute per-channel difference (0 for empty images). Panics if the sizes differ.
pub fn mean_abs_diff(a: &RgbImage, b: &RgbImage) -> f64 {
    let total: u64 = abs_diffs(a, b).map(u64::from).sum();
    total as f64 / a.data.len().max(1) as f64
}

const WIN: usize = 11;

/// Normalised 1-D Gaussian, sigma 1.5; its outer product is the 11x11 SSIM window.
fn gaussian_kernel() -> [f64; WIN] {
    let k: [f64; WIN] = std::array::from_fn(|i| (-(i as f64 - 5.0).powi(2) / 4.5).exp());
    let s: f64 = k.iter().sum();
    k.map(|v| v / s)
}

/// Separable Gaussian filtering, 'valid' region only: output is (w-10) x (h-10).
fn blur_valid(src: &[f64], w: usize, h: usize, k: &[f64; WIN]) -> Vec<f64> {
    let (ow, oh) = (w + 1 - WIN, h + 1 - WIN);
    let dot = |s: &[f64]| s.iter().zip(k).map(|(a, b)| a * b).sum::<f64>();
    let tmp: Vec<f64> = src
        .chunks_exact(w)
        .flat_map(|r| r.windows(WIN).map(dot))
        .collect();
    let mut out = vec![0.0; ow * oh];
    for (y, orow) in out.chunks_exact_mut(ow).enumerate() {
        for (j, kv) in k.iter().enumerate() {
            let trow = &tmp[(y + j) * ow..][..ow];
            orow.iter_mut().zip(trow).for_each(|(o, t)| *o += kv * t);
        }
    }
    out
}

/// Mean SSIM (Wang et al. 2004) on Rec.601 luma: 11x11 Gaussian window with sigma 1.5,
/// K1 = 0.01, K2 = 0.03, L = 255, averaged over the valid region (no padding).
/// Identical images give exactly 1. Panics if the sizes differ or either side is below 11 px.
pub fn ssim(a: &RgbImage, b: &RgbImage) -> f64 {
    let (w, h) = assert_same_size(a, b);
    assert!(
        w >= WIN && h >= WIN,
        "ssim needs images of at least 11x11, got {w}x{h}"
    );
    let (x, y, k) = (a.luma(), b.luma(), gaussian_kernel());
    let blur = |v: &[f64]| blur_valid(v, w, h, &k);
    let prod = |f: fn(f64, f64) -> f64| {
        blur(&x.iter().zip(&y).map(|(&p, &q)| f(p, q)).collect::<Vec<_>>())
    };
    let (mx, my) = (blur(&x), blur(&y));
    let (sxx, syy, sxy) = (prod(|p, _| p * p), prod(|_, q| q * q), prod(|p, q| p * q));
    let (c1, c2) = ((0.01f64 * 255.0).powi(2), (0.03f64 * 255.0).powi(2));
    let local = |i: usize| {
        let (ux, uy) = (mx[i], my[i]);
        let (vx, vy, cxy) = (sxx[i] - ux * ux, syy[i] - uy * uy, sxy[i] - ux * uy);
        ((2.0 * ux * uy + c1) * (2.0 * cxy + c2)) / ((ux * ux + uy * uy + c1) * (vx + vy + c2))
    };
    (0..mx.len()).map(local).sum::<f64>() / mx.len() as f64
}

/// Result of [`match_template`]: top-left offset of the template in the image and its
/// zero-mean normalised cross-correlation of luma, in [-1, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Match {
    /// Column of the template's left edge in the image, in pixels.
    pub x: u32,
    /// Row of the template's top edge in the image, in pixels.
    pub y: u32,
    /// Correlation at that offset, in [-1, 1]: 1 is an exact match up to gain and
    /// offset; 0 where the template or window is flat.
    pub ncc: f64,
}

/// A mean-subtracted luma plane with summed-area tables of values and squared values.
struct Plane {
    w: usize,
    h: usize,
    v: Vec<f64>,
    sum: Vec<f64>,
    sq: Vec<f64>,
}

impl Plane {
    fn new(w: usize, h: usize, mut v: Vec<f64>) -> Plane {
        // NCC is offset-invariant; centring keeps the summed-area tables well conditioned.
        let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
        v.iter_mut().for_each(|p| *p -= mean);
        let s = w + 1;
        let (mut sum, mut sq) = (vec![0.0; s * (h + 1)], vec![0.0; s * (h + 1)]);
        for (y, row) in v.chunks_exact(w).enumerate() {
            let (mut rs, mut rq) = (0.0, 0.0);
            for (x, p) in row.iter().enumerate() {
                (rs, rq) = (rs + p, rq + p * p);
                let i = (y + 1) * s + x + 1;
                (sum[i], sq[i]) = (sum[i - s] + rs, sq[i - s] + rq);
            }
        }
        Plane { w, h, v, sum, sq }
    }

    /// Box-averages f x f blocks (the remainder at the right/bottom edge is dropped).
    fn downsample(&self, f: usize) -> Plane {
        let (w, h) = (self.w / f, self.h / f);
        let block = |i: usize| self.rect(&self.sum, i % w * f, i / w * f, f, f);
        Plane::new(
            w,
            h,
            (0..w * h).map(|i| block(i) / (f * f) as f64).collect(),
        )
    }

    /// Sum of table `t` (`sum` or `sq`) over the rw x rh rectangle at (x, y).
    fn rect(&self, t: &[f64], x: usize, y: usize, rw: usize, rh: usize) -> f64 {
        let s = self.w + 1;
        t[(y + rh) * s + x + rw] - t[y * s + x + rw] - t[(y + rh) * s + x] + t[y * s + x]
    }

    /// Sum of squared deviations from the mean over the rw x rh rectangle at (x, y).
    fn var_sum(&self, x: usize, y: usize, rw: usize, rh: usize) -> f64 {
        let s = self.rect(&self.sum, x, y, rw, rh);
        self.rect(&self.sq, x, y, rw, rh) - s * s / (rw * rh) as f64
    }
}

/// Zero-mean NCC of the (already zero-mean) template `t` at offset (x, y) of `img`.
/// Flat (near zero-variance) windows or templates score 0.
fn ncc_at(img: &Plane, t: &Plane, x: usize, y: usize) -> f64 {
    let n = (t.w * t.h) as f64;
    let (vi, vt) = (img.var_sum(x, y, t.w, t.h), t.var_sum(0, 0, t.w, t.h));
    if vi <= 1e-6 * n || vt <= 1e-6 * n {
        return 0.0;
    }
    let row = |(j, tr): (usize, &[f64])| {
        let ir = &img.v[(y + j) * img.w + x..][..t.w];
        ir.iter().zip(tr).map(|(a, b)| a * b).sum::<f64>()
    };
    let cross: f64 = t.v.chunks_exact(t.w).enumerate().map(row).sum();
    (cross / (vi * vt).sqrt()).clamp(-1.0, 1.0)
}

/// Highest NCC; ties go to the earliest candidate.
fn pick(ms: impl Iterator<Item = Match>) -> Match {
    ms.reduce(|best, m| if m.ncc > best.ncc { m } else { best })
        .expect("no candidate offsets")
}

/// Scores every offset in the inclusive ranges, in row-major order.
fn scan(
    img: &Plane,
    t: &Plane,
    xs: (usize, usize),
    ys: (usize, usize),
) -> impl Iterator<Item = Match> {
    let at = move |(x, y)| Match {
        x: x as u32,
        y: y as u32,
        ncc: ncc_at(img, t, x, y),
    };
    (ys.0..=ys.1).flat_map(move |y| (xs.0..=xs.1).map(move |x| at((x, y))))
}

/// Up to `k` best offsets over the whole plane, dropping any within 2 px of a better one.
fn peaks(img: &Plane, t: &Plane, k: usize) -> Vec<Match> {
    let mut all: Vec<Match> = scan(img, t, (0, img.w - t.w), (0, img.h - t.h)).collect();
    all.sort_by(|a, b| b.ncc.total_cmp(&a.ncc));
    let mut peaks: Vec<Match> = Vec::with_capacity(k);
    for m in all {
        if peaks.len() < k
            && peaks
                .iter()
                .all(|p| p.x.abs_diff(m.x) > 2 || p.y.abs_diff(m.y) > 2)
        {
            peaks.push(m);
        }
    }
    peaks
}

/// Finds where `template` sits inside `image`: the top-left offset maximising zero-mean
/// normalised cross-correlation of luma over every offset. Coarse-to-fine: an exhaustive
/// search on box-downsampled luma (4x, or 2x for small templates), then the best 6 separated
/// coarse peaks are each refined over ±(factor+1) pixels at full resolution. Templates under
/// 16 px on a side are searched exhaustively at full resolution. A flat template scores 0
/// everywhere. Panics if the template is empty or larger than the image in either dimension.
pub fn match_template(image: &RgbImage, template: &RgbImage) -> Match {
    let ((iw, ih), (tw, th)) = (image.dims(), template.dims());
    assert!(
        tw > 0 && th > 0 && tw <= iw && th <= ih,
        "template {tw}x{th} must be non-empty and fit inside the {iw}x{ih} image"
    );
    let (img, tpl) = (
        Plane::new(iw, ih, image.luma()),
        Plane::new(tw, th, template.luma()),
    );
    let (mx, my) = (iw - tw, ih - th);
    let Some(f) = [4, 2].into_iter().find(|&f| tw / f >= 8 && th / f >= 8) else {
        return pick(scan(&img, &tpl, (0, mx), (0, my)));
    };
    let refine = |c: Match| {
        let (x, y) = ((c.x as usize * f).min(mx), (c.y as usize * f).min(my));
        let span = |v: usize, max: usize| (v.saturating_sub(f + 1), (v + f + 1).min(max));
        pick(scan(&img, &tpl, span(x, mx), span(y, my)))
    };
    pick(
        peaks(&img.downsample(f), &tpl.downsample(f), 6)
            .into_iter()
            .map(refine),
    )
}

/// Copies the `w` x `h` region at (x, y) into an owned, tightly packed RGB buffer.
/// Panics if the region does not fit inside the image.
pub fn crop(image: &RgbImage, x: u32, y: u32, w: u32, h: u32) -> Vec<u8> {
    let (iw, ih) = image.dims();
    let (x, y, w, h) = (x as usize, y as usize, w as usize, h as usize);
    assert!(
        x + w <= iw && y + h <= ih,
        "crop {w}x{h} at ({x}, {y}) does not fit in {iw}x{ih}"
    );
    if w * h == 0 {
        return Vec::new();
    }
    let rows = image.data.chunks_exact(iw * 3).skip(y).take(h);
    rows.flat_map(|r| &r[x * 3..(x + w) * 3]).copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Non-periodic texture: sines, a radial chirp and a checker, clamped to 0..=255.
    fn synth(w: u32, h: u32) -> Vec<u8> {
        let px = |i: u32| {
            let (x, y) = (i % w, i / w);
            let (fx, fy) = (f64::from(x), f64::from(y));
            let chirp = 35.0 * ((fx - 120.0).powi(2) * 0.0009 + (fy - 70.0).powi(2) * 0.0013).sin();
            let checker = 25.0 - 50.0 * f64::from((x / 7 + y / 5) % 2);
            let r = 128.0 + 40.0 * (0.21 * fx + 0.05 * fy).sin() + chirp + checker;
            let g = 128.0 + 30.0 * (0.11 * fy - 0.03 * fx).sin() + chirp - checker / 2.0;
            let b = 100.0 + 60.0 * ((fx + 2.0 * fy) * 0.045).sin();
            [r, g, b].map(|c| c.round().clamp(0.0, 255.0) as u8)
        };
        (0..w * h).flat_map(px).collect()
    }

    /// Adds deterministic uniform noise in [-amp, amp] (64-bit LCG).
    fn noisy(data: &[u8], amp: u64, seed: u64) -> Vec<u8> {
        let mut s = seed;
        let mut noise = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
            ((s >> 33) % (2 * amp + 1)) as i64 - amp as i64
        };
        let add = |v: &u8| (i64::from(*v) + noise()).clamp(0, 255) as u8;
        data.iter().map(add).collect()
    }

    #[test]
    fn psnr_known_values() {
        let d = synth(30, 20);
        let (a, one_off) = (
            RgbImage::new(30, 20, &d),
            d.iter().map(|v| v ^ 1).collect::<Vec<_>>(),
        );
        assert_eq!(psnr(&a, &a), f64::INFINITY);
        let p = psnr(&a, &RgbImage::new(30, 20, &one_off));
        assert_eq!(p, 20.0 * 255f64.log10());
        assert!((p - 48.130_803_608_679).abs() < 1e-9);
        // One channel of one pixel off by 3: MSE = 9 / 3 = 3; PSNR = 48.1308036 - 4.7712125.
        let p = psnr(
            &RgbImage::new(1, 1, &[0, 0, 0]),
            &RgbImage::new(1, 1, &[3, 0, 0]),
        );
        assert!((p - 43.359_591_061_482).abs() < 1e-9, "{p}");
    }

    #[test]
    fn abs_diffs_hand_case() {
        let (a, b) = ([10u8, 20, 30, 40, 50, 60], [12u8, 20, 25, 40, 50, 255]);
        let (a, b) = (RgbImage::new(2, 1, &a), RgbImage::new(2, 1, &b));
        assert_eq!(
            (max_abs_diff(&a, &b), mean_abs_diff(&a, &b)),
            (195, 202.0 / 6.0)
        );
        assert_eq!((max_abs_diff(&a, &a), mean_abs_diff(&a, &a)), (0, 0.0));
    }

    #[test]
    #[should_panic(expected = "image size mismatch")]
    fn mismatched_sizes_panic() {
        let d = [0u8; 12];
        psnr(&RgbImage::new(2, 2, &d), &RgbImage::new(4, 1, &d));
    }

    /// SSIM of a 64x48 texture against a per-channel remapping of itself, both ways round.
    fn ssim_vs(f: impl Fn(u8) -> u8) -> (f64, f64) {
        let d = synth(64, 48);
        let e: Vec<u8> = d.iter().map(|&v| f(v)).collect();
        let (a, b) = (RgbImage::new(64, 48, &d), RgbImage::new(64, 48, &e));
        (ssim(&a, &b), ssim(&b, &a))
    }

    #[test]
    fn ssim_identical_is_one() {
        assert!((ssim_vs(|v| v).0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn ssim_is_symmetric() {
        let (ab, ba) = ssim_vs(|v| v / 2 + 40);
        assert_eq!(ab, ba);
        assert!(ab < 0.9, "{ab}");
    }

    #[test]
    fn ssim_inverse_is_negative() {
        assert!(ssim_vs(|v| 255 - v).0 < 0.0);
    }

    #[test]
    fn ssim_brightness_shift_reduces_it() {
        let (s10, s60) = (
            ssim_vs(|v| v.saturating_add(10)).0,
            ssim_vs(|v| v.saturating_add(60)).0,
        );
        assert!(s60 < s10 && s10 < 1.0, "{s10} {s60}");
    }

    #[test]
    fn ssim_flat_images_hand_case() {
        // Zero variance: SSIM = (2 mx my + C1) / (mx^2 + my^2 + C1) with C1 = 6.5025.
        let (a, b) = (vec![100u8; 16 * 16 * 3], vec![110u8; 16 * 16 * 3]);
        let s = ssim(&RgbImage::new(16, 16, &a), &RgbImage::new(16, 16, &b));
        assert!((s - 22006.5025 / 22106.5025).abs() < 1e-9, "{s}");
    }

    /// Crops a `tw` x `th` template (plus noise) at corners, edges and inside a 300x200 texture.
    fn check_match(tw: u32, th: u32, noise: u64) {
        let (w, h, d) = (300, 200, synth(300, 200));
        let img = RgbImage::new(w, h, &d);
        let (ex, ey) = (w - tw, h - th);
        let offsets = [
            (0, 0),
            (ex, ey),
            (0, ey),
            (ex, 0),
            (1, 1),
            (123, 77),
            (ex - 1, 3),
        ];
        for (k, &(x, y)) in offsets.iter().enumerate() {
            let t = noisy(&crop(&img, x, y, tw, th), noise, k as u64 + 1);
            let m = match_template(&img, &RgbImage::new(tw, th, &t));
            assert_eq!((m.x, m.y), (x, y), "{tw}x{th}, noise {noise}: {m:?}");
            assert!(m.ncc > if noise == 0 { 1.0 - 1e-9 } else { 0.9 }, "{m:?}");
        }
    }

    #[test]
    fn match_exact_crops() {
        check_match(80, 60, 0); // 4x coarse search
        check_match(40, 30, 0); // 2x coarse search
        check_match(12, 14, 0); // exhaustive
    }

    #[test]
    fn match_with_noisy_template() {
        check_match(80, 60, 12);
        check_match(40, 30, 8);
        check_match(12, 14, 4);
    }

    #[test]
    fn match_agrees_with_brute_force() {
        let (d, t) = (synth(300, 200), noisy(&synth(48, 36), 40, 9));
        let (img, tpl) = (RgbImage::new(300, 200, &d), RgbImage::new(48, 36, &t));
        let (pi, pt) = (
            Plane::new(300, 200, img.luma()),
            Plane::new(48, 36, tpl.luma()),
        );
        let brute = pick(scan(&pi, &pt, (0, 300 - 48), (0, 200 - 36)));
        assert_eq!(match_template(&img, &tpl), brute);
    }

    #[test]
    fn match_whole_image() {
        let d = synth(50, 40);
        let m = match_template(&RgbImage::new(50, 40, &d), &RgbImage::new(50, 40, &d));
        assert_eq!((m.x, m.y), (0, 0));
    }

    #[test]
    #[should_panic(expected = "must be non-empty and fit")]
    fn oversized_template_panics() {
        let (d, t) = (synth(20, 20), synth(21, 5));
        match_template(&RgbImage::new(20, 20, &d), &RgbImage::new(21, 5, &t));
    }

    #[test]
    fn crop_copies_rows() {
        let d: Vec<u8> = (0..4 * 3 * 3).collect();
        let c = crop(&RgbImage::new(4, 3, &d), 1, 1, 2, 2);
        assert_eq!(c, [15, 16, 17, 18, 19, 20, 27, 28, 29, 30, 31, 32]);
        assert!(crop(&RgbImage::new(4, 3, &d), 4, 3, 0, 0).is_empty());
    }

    #[test]
    fn match_finds_a_noisy_crop_in_a_frame_sized_image() {
        let d = synth(1000, 560);
        let img = RgbImage::new(1000, 560, &d);
        let t = noisy(&crop(&img, 517, 301, 400, 210), 5, 3);
        let m = match_template(&img, &RgbImage::new(400, 210, &t));
        assert_eq!((m.x, m.y), (517, 301));
    }
}
