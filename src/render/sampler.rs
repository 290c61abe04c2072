//! Random numbers for one pixel, seeded from the pixel itself so that the image does
//! not depend on which thread renders which pixel.

use rand_core::Rng;
use rand_pcg::Pcg32;

/// The random stream of one supersampled pixel of one frame.
pub struct PixelSampler {
    rng: Pcg32,
}

impl PixelSampler {
    /// Pixel coordinates are those of the full supersampled frame, so a region render
    /// draws exactly the numbers the full frame draws there.
    pub fn new(seed: u64, x: u32, y: u32) -> PixelSampler {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        PixelSampler {
            rng: Pcg32::new(splitmix64(seed ^ splitmix64(pixel)), 0xda3e_39cb_94b9_5bdb),
        }
    }

    /// The stream of sample `index` of the pixel: its numbers depend on the seed, the
    /// pixel and the index alone, so a pixel's samples may be taken in any order and
    /// split into passes without changing one of them (the path model's samples).
    pub fn for_sample(seed: u64, x: u32, y: u32, index: u32) -> PixelSampler {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let sample = splitmix64(SAMPLE_KEY ^ u64::from(index));
        PixelSampler {
            rng: Pcg32::new(
                splitmix64(seed ^ splitmix64(pixel) ^ sample),
                0xda3e_39cb_94b9_5bdb,
            ),
        }
    }

    /// Two uniform numbers in [0, 1).
    #[inline]
    pub fn next_2d(&mut self) -> (f32, f32) {
        let a = self.next_f32();
        (a, self.next_f32())
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        // 24 random bits: every value is exactly representable and below 1.
        (self.rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Sample `i` of `n` stratified points on the unit disk: a jittered spiral lattice
    /// (radius strata by area, golden-ratio angles), so any `n`, prime or not, covers the
    /// lens evenly without a per-pixel table.
    #[inline]
    pub fn disk_sample(&mut self, i: u32, n: u32) -> (f32, f32) {
        const GOLDEN: f32 = 0.618_034;
        let u = (i as f32 + self.next_f32()) / n as f32;
        let v = (i as f32 * GOLDEN + self.next_f32() / n as f32).fract();
        let r = u.sqrt();
        let (s, c) = crate::math::sin_cos(v * std::f32::consts::TAU);
        (r * c, r * s)
    }
}

impl PixelSampler {
    /// Sample `i` of `n` stratified points on the unit square, in the lattice pattern
    /// of [`PixelSampler::disk_sample`]: the first coordinate in equal strata, the
    /// second along golden-ratio steps.
    #[inline]
    pub fn square_sample(&mut self, i: u32, n: u32) -> (f32, f32) {
        const GOLDEN: f32 = 0.618_034;
        let u = (i as f32 + self.next_f32()) / n as f32;
        let v = (i as f32 * GOLDEN + self.next_f32() / n as f32).fract();
        (u.min(ONE_BELOW), v.min(ONE_BELOW))
    }
}

/// Mixed with a sample's index, so that sample streams differ from the pixel stream
/// [`PixelSampler::new`] gives.
const SAMPLE_KEY: u64 = 0x5a3c_96e1_0f2d_4b87;

/// The largest f32 below 1: strata computed in f32 can round up to 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// A strong 64-bit mixer: neighbouring pixels get unrelated seeds.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_pixel_same_numbers_other_pixel_other_numbers() {
        let draw = |s: &mut PixelSampler| (0..8).map(|_| s.next_f32()).collect::<Vec<_>>();
        let a = draw(&mut PixelSampler::new(7, 3, 4));
        assert_eq!(a, draw(&mut PixelSampler::new(7, 3, 4)));
        assert_ne!(a, draw(&mut PixelSampler::new(7, 4, 3)));
        assert_ne!(a, draw(&mut PixelSampler::new(8, 3, 4)));
        assert!(a.iter().all(|x| (0.0..1.0).contains(x)));
    }

    #[test]
    fn a_sample_stream_depends_on_seed_pixel_and_index_alone() {
        let draw = |s: &mut PixelSampler| (0..8).map(|_| s.next_f32()).collect::<Vec<_>>();
        let a = draw(&mut PixelSampler::for_sample(7, 3, 4, 5));
        assert_eq!(a, draw(&mut PixelSampler::for_sample(7, 3, 4, 5)));
        for other in [
            PixelSampler::for_sample(7, 3, 4, 6),
            PixelSampler::for_sample(7, 4, 3, 5),
            PixelSampler::for_sample(8, 3, 4, 5),
            PixelSampler::new(7, 3, 4),
        ] {
            assert_ne!(a, draw(&mut { other }));
        }
    }

    #[test]
    fn disk_samples_are_inside_and_cover_every_quadrant_and_ring() {
        let mut s = PixelSampler::new(1, 0, 0);
        let n = 127;
        let pts: Vec<_> = (0..n).map(|i| s.disk_sample(i, n)).collect();
        assert!(pts.iter().all(|(x, y)| x * x + y * y <= 1.0));
        for q in 0..4 {
            let count = pts
                .iter()
                .filter(|(x, y)| ((*x < 0.0) as i32 + 2 * (*y < 0.0) as i32) == q)
                .count();
            assert!((20..=44).contains(&count), "quadrant {q}: {count}");
        }
        // Equal-area rings hold equal shares: r^2 strata.
        let inner = pts.iter().filter(|(x, y)| x * x + y * y < 0.5).count();
        assert!((60..=67).contains(&inner), "{inner}");
    }
}
