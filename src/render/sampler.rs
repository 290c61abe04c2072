//! Random numbers for one pixel, seeded from the pixel itself so that the image does
//! not depend on which thread renders which pixel.
//!
//! A sample's stream ([`PixelSampler::for_sample`], the path model's) draws its first
//! pairs of dimensions from Owen-scrambled Sobol points (Burley's hash-based shuffle
//! and scramble, "Practical Hash-based Owen Scrambling", 2020): the samples of a pixel
//! are stratified in each pair (any power-of-two prefix of them is a (0, m, 2)-net)
//! while pairs, pixels and seeds stay independent; later dimensions and single numbers
//! come from PCG.

use crate::math::ONE_BELOW;
use rand_core::Rng;
use rand_pcg::Pcg32;

/// The random stream of one supersampled pixel of one frame.
pub struct PixelSampler {
    rng: Pcg32,
    /// The sample's place among the pixel's samples, the key of its pixel, and the
    /// next pair of dimensions, when pairs come from scrambled Sobol points.
    sobol: Option<(u32, u32, u32)>,
}

/// Pairs of dimensions a sample's stream draws from Sobol points: the pixel position,
/// the lens and the first few bounces' light and BSDF samples, where stratification
/// pays most.
const SOBOL_PAIRS: u32 = 8;

impl PixelSampler {
    /// Pixel coordinates are those of the full supersampled frame, so a region render
    /// draws exactly the numbers the full frame draws there.
    pub fn new(seed: u64, x: u32, y: u32) -> PixelSampler {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        PixelSampler {
            rng: Pcg32::new(splitmix64(seed ^ splitmix64(pixel)), 0xda3e_39cb_94b9_5bdb),
            sobol: None,
        }
    }

    /// The stream of sample `index` of the pixel: its numbers depend on the seed, the
    /// pixel and the index alone, so a pixel's samples may be taken in any order and
    /// split into passes without changing one of them (the path model's samples).
    pub fn for_sample(seed: u64, x: u32, y: u32, index: u32) -> PixelSampler {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let sample = splitmix64(SAMPLE_KEY ^ u64::from(index));
        let pixel_key = splitmix64(seed ^ splitmix64(pixel ^ SAMPLE_KEY));
        PixelSampler {
            rng: Pcg32::new(
                splitmix64(seed ^ splitmix64(pixel) ^ sample),
                0xda3e_39cb_94b9_5bdb,
            ),
            sobol: Some((index, (pixel_key ^ (pixel_key >> 32)) as u32, 0)),
        }
    }

    /// A stream that stands in a packet's unused places: made without hashing.
    #[inline]
    pub fn idle() -> PixelSampler {
        PixelSampler {
            rng: Pcg32::new(0, 0xda3e_39cb_94b9_5bdb),
            sobol: None,
        }
    }

    /// Two uniform numbers in [0, 1): the sample's next pair of Sobol dimensions while
    /// there are any, then two from PCG.
    #[inline]
    pub fn next_2d(&mut self) -> (f32, f32) {
        if let Some((index, key, pair)) = &mut self.sobol
            && *pair < SOBOL_PAIRS
        {
            let point = sobol_2d(*index, mix32(*key ^ pair.wrapping_mul(0x9e37_79b9)));
            *pair += 1;
            return point;
        }
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

/// A light's stratified samples draw from the pixel's stream: squares and disks in the
/// lattice patterns above.
impl crate::scene::light::Strata for PixelSampler {
    #[inline]
    fn square(&mut self, i: u32, n: u32) -> (f32, f32) {
        self.square_sample(i, n)
    }

    #[inline]
    fn disk(&mut self, i: u32, n: u32) -> (f32, f32) {
        self.disk_sample(i, n)
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

/// Point `index` of the two-dimensional Sobol sequence (its first two dimensions: a
/// (0, 2)-sequence), the index shuffled and each coordinate Owen-scrambled by `seed`.
/// Written on bit-reversed words, where the scramble works, to reverse as few as can be.
#[inline]
fn sobol_2d(index: u32, seed: u32) -> (f32, f32) {
    let (s0, s1, s2) = (seed, mix32(seed ^ 0x68e3_1da4), mix32(seed ^ 0xb529_7a4d));
    // The shuffled index, reversed: Owen-scrambled like a fraction.
    let r = laine_karras(index.reverse_bits(), s0);
    // First dimension: the index's bits reversed (van der Corput), scrambled.
    let x = laine_karras(r.reverse_bits(), s1).reverse_bits();
    // Second: the XOR of reversed direction numbers over the index's bits, scrambled.
    let y = laine_karras(sobol_second_reversed(r.reverse_bits()), s2).reverse_bits();
    (unit(x), unit(y))
}

/// The second dimension of the Sobol sequence with its bits reversed: direction
/// numbers `v_k = v_(k-1) ^ (v_(k-1) >> 1)` from `v_0 = 1/2`, reversed (`w_k = w_(k-1)
/// ^ (w_(k-1) << 1)` from 1), XORed over the set bits of `i`, a byte at a time.
#[inline]
fn sobol_second_reversed(i: u32) -> u32 {
    let t = &SOBOL_SECOND_REVERSED;
    t[0][(i & 0xff) as usize]
        ^ t[1][((i >> 8) & 0xff) as usize]
        ^ t[2][((i >> 16) & 0xff) as usize]
        ^ t[3][(i >> 24) as usize]
}

/// For each byte of an index, the XOR of the reversed direction numbers of its set
/// bits: four lookups instead of a loop over 32 bits.
const SOBOL_SECOND_REVERSED: [[u32; 256]; 4] = {
    let mut w = [0u32; 32];
    w[0] = 1;
    let mut k = 1;
    while k < 32 {
        w[k] = w[k - 1] ^ (w[k - 1] << 1);
        k += 1;
    }
    let mut t = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut v = 0;
        while v < 256 {
            let mut r = 0u32;
            let mut bit = 0;
            while bit < 8 {
                if v & (1 << bit) != 0 {
                    r ^= w[byte * 8 + bit];
                }
                bit += 1;
            }
            t[byte][v] = r;
            v += 1;
        }
        byte += 1;
    }
    t
};

/// Laine and Karras's permutation with Burley's constants: on a bit-reversed fraction,
/// each bit flipped by a hash of the bits below it, i.e. Owen's nested uniform
/// scramble of the fraction.
#[inline]
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// A 32-bit fraction's top 24 bits as a float in [0, 1).
#[inline]
fn unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// A 32-bit mixer (Wellons's lowbias32): every input bit reaches every output bit.
#[inline]
fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

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
    fn the_sobol_pairs_of_a_pixel_s_samples_are_stratified_in_every_elementary_interval() {
        for (seed, x, y) in [(0, 0, 0), (7, 31, 4), (99, 1000, 2000)] {
            let m = 6;
            let n = 1u32 << m;
            let mut streams: Vec<_> = (0..n)
                .map(|i| PixelSampler::for_sample(seed, x, y, i))
                .collect();
            for pair in 0..SOBOL_PAIRS {
                let points: Vec<(f32, f32)> = streams.iter_mut().map(|s| s.next_2d()).collect();
                // Every box of 2^a x 2^(m - a) cells holds exactly one point.
                for a in 0..=m {
                    let (cx, cy) = (1u32 << a, 1u32 << (m - a));
                    let mut seen = vec![false; n as usize];
                    for &(u, v) in &points {
                        let cell = (u * cx as f32) as u32 * cy + (v * cy as f32) as u32;
                        assert!(
                            !seen[cell as usize],
                            "pair {pair}, {cx}x{cy}: two in a cell"
                        );
                        seen[cell as usize] = true;
                    }
                }
            }
            // Past the Sobol pairs the stream goes on from PCG, in [0, 1).
            let (u, v) = streams[3].next_2d();
            assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
        }
    }

    #[test]
    fn the_second_sobol_dimension_is_the_known_sequence() {
        // 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8 (direction numbers in binary order).
        let want = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
        for (i, w) in want.iter().enumerate() {
            let y = sobol_second_reversed(i as u32).reverse_bits();
            assert_eq!(y as f64 / 2f64.powi(32), *w, "{i}");
        }
        // Every bit's direction number, against the recurrence.
        let mut v = 1u32 << 31;
        for k in 0..32 {
            assert_eq!(sobol_second_reversed(1 << k).reverse_bits(), v, "bit {k}");
            v ^= v >> 1;
        }
    }

    #[test]
    fn pixels_and_pairs_get_different_scrambles() {
        let first = |x, pair| {
            let mut s = PixelSampler::for_sample(1, x, 0, 0);
            (0..pair).for_each(|_| {
                s.next_2d();
            });
            s.next_2d()
        };
        assert_ne!(first(0, 0), first(1, 0));
        assert_ne!(first(0, 0), first(0, 1));
        assert_eq!(first(5, 2), first(5, 2));
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
