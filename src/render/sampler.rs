//! Random numbers for one pixel, seeded from the pixel itself so that the image does
//! not depend on which thread renders which pixel.
//!
//! A sample's stream ([`PixelSampler::for_sample`], the path model's) draws its first
//! pairs of dimensions from Owen-scrambled Sobol points (Burley's hash-based shuffle
//! and scramble, "Practical Hash-based Owen Scrambling", 2020): the samples of a pixel
//! are stratified in each pair (any power-of-two prefix of them is a (0, m, 2)-net)
//! while pairs, pixels and seeds stay independent; later dimensions and single numbers
//! come from PCG.

#[cfg(target_arch = "x86_64")]
use crate::accel::SimdLevel;
use crate::math::ONE_BELOW;
use rand_core::Rng;
use rand_pcg::Pcg32;

/// The random stream of one supersampled pixel of one frame.
pub struct PixelSampler {
    rng: Pcg32,
    /// The sample's scrambled Sobol points, drawn all at once when the stream is made
    /// (in vector lanes: one pair at a time they cost a tenth of a path's time).
    sobol: [(f32, f32); SOBOL_PAIRS as usize],
    /// The next of `sobol` to give; `SOBOL_PAIRS` when the stream has none left.
    next_pair: u32,
}

/// Pairs of dimensions a sample's stream draws from Sobol points: the pixel position,
/// the lens and the first few bounces' light and BSDF samples, where stratification
/// pays most.
const SOBOL_PAIRS: u32 = 8;

/// Pixel (`x`, `y`) as the one word its streams are keyed by.
#[inline]
fn pixel_word(x: u32, y: u32) -> u64 {
    (u64::from(y) << 32) | u64::from(x)
}

impl PixelSampler {
    /// Pixel coordinates are those of the full supersampled frame, so a region render
    /// draws exactly the numbers the full frame draws there.
    pub fn new(seed: u64, x: u32, y: u32) -> PixelSampler {
        PixelSampler::from_pcg(splitmix64(seed ^ splitmix64(pixel_word(x, y))))
    }

    /// The stream of sample `index` of the pixel: its numbers depend on the seed, the
    /// pixel and the index alone, so a pixel's samples may be taken in any order and
    /// split into passes without changing one of them (the path model's samples).
    pub fn for_sample(seed: u64, x: u32, y: u32, index: u32) -> PixelSampler {
        PixelStreams::new(seed, x, y).sample(index)
    }

    /// A stream that stands in a packet's unused places: made without hashing.
    #[inline]
    pub fn idle() -> PixelSampler {
        PixelSampler::from_pcg(0)
    }

    #[inline]
    fn from_pcg(state: u64) -> PixelSampler {
        PixelSampler {
            rng: Pcg32::new(state, 0xda3e_39cb_94b9_5bdb),
            sobol: [(0.0, 0.0); SOBOL_PAIRS as usize],
            next_pair: SOBOL_PAIRS,
        }
    }

    /// Two uniform numbers in [0, 1): the sample's next pair of Sobol dimensions while
    /// there are any, then two from PCG.
    #[inline]
    pub fn next_2d(&mut self) -> (f32, f32) {
        if let Some(&point) = self.sobol.get(self.next_pair as usize) {
            self.next_pair += 1;
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

/// The registers a packet's pixel streams are made in: sixteen lanes where the work
/// they are drawn for runs on sixteen (the path model's lanes on AVX-512), eight
/// otherwise. On the Cornell box the sixteen-lane streams take 0.97x the time of the
/// render and the eight-lane ones 0.99x; made in sixteen lanes where the rest runs on
/// eight (the Blender showcase's OpenPBR surfaces), they slowed the processor's clock
/// for all of it (1.06x the time).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum StreamLanes {
    /// AVX2's registers.
    Eight,
    /// AVX-512's, where the processor has them and they are wanted.
    Sixteen,
}

/// Samples whose Sobol points are worked out together.
const BATCH_SAMPLES: usize = 16;

/// The Sobol pairs of a sample, as an index.
const PAIRS: usize = SOBOL_PAIRS as usize;

/// Lanes of a row of [`PixelStreams::sobol_batch`]: two samples' pairs.
const ROW: usize = 2 * PAIRS;

/// Mixed with a sample's index, so that sample streams differ from the pixel stream
/// [`PixelSampler::new`] gives.
const SAMPLE_KEY: u64 = 0x5a3c_96e1_0f2d_4b87;

/// What the streams of one pixel's samples share: the pixel's PCG key and the
/// scrambles of its Sobol pairs. A packet of a pixel's samples hashes them once.
pub struct PixelStreams {
    /// Mixed with a sample's index into the seed of its PCG stream.
    pcg_key: u64,
    /// Per pair: the seed of the index shuffle, and of each coordinate's scramble.
    shuffle: [u32; SOBOL_PAIRS as usize],
    scramble_x: [u32; SOBOL_PAIRS as usize],
    scramble_y: [u32; SOBOL_PAIRS as usize],
}

impl PixelStreams {
    /// The streams of pixel (`x`, `y`) of the frame drawn with `seed`.
    pub fn new(seed: u64, x: u32, y: u32) -> PixelStreams {
        let pixel = pixel_word(x, y);
        let pixel_key = splitmix64(seed ^ splitmix64(pixel ^ SAMPLE_KEY));
        let key = (pixel_key ^ (pixel_key >> 32)) as u32;
        let shuffle: [u32; SOBOL_PAIRS as usize] =
            std::array::from_fn(|pair| mix32(key ^ (pair as u32).wrapping_mul(0x9e37_79b9)));
        PixelStreams {
            pcg_key: seed ^ splitmix64(pixel),
            shuffle,
            scramble_x: shuffle.map(|s| mix32(s ^ 0x68e3_1da4)),
            scramble_y: shuffle.map(|s| mix32(s ^ 0xb529_7a4d)),
        }
    }

    /// The stream of sample `index` ([`PixelSampler::for_sample`]): a batch of one.
    pub fn sample(&self, index: u32) -> PixelSampler {
        let mut one = [PixelSampler::idle()];
        self.samples_into(index, &mut one, StreamLanes::Eight);
        let [stream] = one;
        stream
    }

    /// The streams of samples `first..first + out.len()`, into `out`, made in the
    /// registers `lanes` asks for where the processor has them.
    pub fn samples_into(&self, first: u32, out: &mut [PixelSampler], lanes: StreamLanes) {
        #[cfg(target_arch = "x86_64")]
        if SimdLevel::current() == SimdLevel::Avx2 {
            let gfni = std::arch::is_x86_feature_detected!("gfni");
            if gfni && lanes == StreamLanes::Sixteen && crate::accel::simd::avx512_wanted() {
                // SAFETY: the processor runs AVX-512 F, VL, DQ and BW, and GFNI.
                return unsafe { self.samples_into_avx512(first, out) };
            }
            if gfni {
                // SAFETY: the processor runs AVX2 and GFNI.
                return unsafe { self.samples_into_gfni(first, out) };
            }
            // SAFETY: as in `sample`.
            return unsafe { self.samples_into_avx2(first, out) };
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = lanes;
        self.samples_into_in(first, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn samples_into_avx2(&self, first: u32, out: &mut [PixelSampler]) {
        self.samples_into_in(first, out);
    }

    /// With the bits reversed by GFNI's affine byte transform.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,gfni")]
    unsafe fn samples_into_gfni(&self, first: u32, out: &mut [PixelSampler]) {
        self.samples_into_in(first, out);
    }

    /// [`PixelStreams::samples_into_gfni`] in sixteen-lane registers.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,gfni")]
    unsafe fn samples_into_avx512(&self, first: u32, out: &mut [PixelSampler]) {
        self.samples_into_in(first, out);
    }

    // The streams drawn in a loop, not in a closure: that would be compiled without
    // the caller's target features.
    #[inline(always)]
    fn samples_into_in(&self, first: u32, out: &mut [PixelSampler]) {
        for (c, chunk) in out.chunks_mut(BATCH_SAMPLES).enumerate() {
            let first = first.wrapping_add((c * BATCH_SAMPLES) as u32);
            let points = self.sobol_batch(first, chunk.len());
            for (k, stream) in chunk.iter_mut().enumerate() {
                *stream = self.stream(first.wrapping_add(k as u32));
                stream.sobol = points[k];
            }
        }
    }

    /// Sample `index`'s stream, its Sobol points still to be filled in.
    #[inline(always)]
    fn stream(&self, index: u32) -> PixelSampler {
        let sample = splitmix64(SAMPLE_KEY ^ u64::from(index));
        let mut stream = PixelSampler::from_pcg(splitmix64(self.pcg_key ^ sample));
        stream.next_pair = 0;
        stream
    }

    /// Point `index` of the two-dimensional Sobol sequence (its first two dimensions:
    /// a (0, 2)-sequence) for every pair, the index shuffled and each coordinate
    /// Owen-scrambled by the pair's seeds, for each sample `index` of `first..first +
    /// n` (`n` at most [`BATCH_SAMPLES`]). Written on bit-reversed words, where the
    /// scramble works, and without tables, so that the pairs fill vector lanes; worked
    /// out step by step over all the samples' pairs at once, since one sample's steps
    /// wait on one another (the scramble's four multiplications each) while the
    /// samples' do not, so the processor overlaps them.
    #[inline(always)]
    fn sobol_batch(&self, first: u32, n: usize) -> [[(f32, f32); PAIRS]; BATCH_SAMPLES] {
        debug_assert!(n <= BATCH_SAMPLES);
        // Two samples' pairs to a row of sixteen lanes, the pairs' seeds repeated.
        let twice =
            |seeds: &[u32; PAIRS]| -> [u32; ROW] { std::array::from_fn(|j| seeds[j % PAIRS]) };
        let (shuffle, scramble_x, scramble_y) = (
            twice(&self.shuffle),
            twice(&self.scramble_x),
            twice(&self.scramble_y),
        );
        let rows = n.div_ceil(2);
        let mut x = [[0u32; ROW]; BATCH_SAMPLES / 2];
        let mut y = [[0u32; ROW]; BATCH_SAMPLES / 2];
        for r in 0..rows {
            for j in 0..ROW {
                let index = first.wrapping_add((2 * r + j / PAIRS) as u32);
                // The shuffled index (Owen-scrambled like a fraction, on its reversed
                // bits). The first dimension is its bits reversed (van der Corput); the
                // second the XOR of reversed direction numbers over its bits.
                let shuffled = laine_karras(index.reverse_bits(), shuffle[j]).reverse_bits();
                x[r][j] = shuffled;
                y[r][j] = sobol_second_reversed(shuffled);
            }
        }
        for r in 0..rows {
            for j in 0..ROW {
                x[r][j] = laine_karras(x[r][j], scramble_x[j]).reverse_bits();
                y[r][j] = laine_karras(y[r][j], scramble_y[j]).reverse_bits();
            }
        }
        let mut points = [[(0.0, 0.0); PAIRS]; BATCH_SAMPLES];
        for (k, sample) in points.iter_mut().enumerate().take(n) {
            for (pair, point) in sample.iter_mut().enumerate() {
                let j = (k % 2) * PAIRS + pair;
                *point = (unit(x[k / 2][j]), unit(y[k / 2][j]));
            }
        }
        points
    }
}

/// The second dimension of the Sobol sequence with its bits reversed: direction
/// numbers `v_k = v_(k-1) ^ (v_(k-1) >> 1)` from `v_0 = 1/2`, reversed: `w_k = w_(k-1)
/// ^ (w_(k-1) << 1)` from 1, so bit `j` of `w_k` is binomial(k, j) mod 2, set exactly
/// where the bits of `j` are among those of `k` (Lucas). Bit `j` of the XOR of `w_k`
/// over the set bits `k` of `i` is then the parity of the bits of `i` at the supersets
/// of `j`: five shift-and-XOR steps, one per bit of a bit position.
#[inline(always)]
fn sobol_second_reversed(i: u32) -> u32 {
    let mut y = i;
    y ^= (y >> 1) & 0x5555_5555;
    y ^= (y >> 2) & 0x3333_3333;
    y ^= (y >> 4) & 0x0f0f_0f0f;
    y ^= (y >> 8) & 0x00ff_00ff;
    y ^ ((y >> 16) & 0x0000_ffff)
}

/// Laine and Karras's permutation with Burley's constants: on a bit-reversed fraction,
/// each bit flipped by a hash of the bits below it, i.e. Owen's nested uniform
/// scramble of the fraction.
#[inline(always)]
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// A 32-bit fraction's top 24 bits as a float in [0, 1).
#[inline(always)]
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

    /// One pair as the sampler once drew it, a pair at a time with a table of direction
    /// numbers per byte of the index: the reference the lanes must equal bit for bit.
    fn sobol_2d_one_at_a_time(index: u32, seed: u32) -> (f32, f32) {
        let mut w = [0u32; 32];
        w[0] = 1;
        for k in 1..32 {
            w[k] = w[k - 1] ^ (w[k - 1] << 1);
        }
        let second = |i: u32| (0..32).filter(|k| i >> k & 1 == 1).fold(0, |y, k| y ^ w[k]);
        let (s0, s1, s2) = (seed, mix32(seed ^ 0x68e3_1da4), mix32(seed ^ 0xb529_7a4d));
        let r = laine_karras(index.reverse_bits(), s0);
        let x = laine_karras(r.reverse_bits(), s1).reverse_bits();
        let y = laine_karras(second(r.reverse_bits()), s2).reverse_bits();
        (unit(x), unit(y))
    }

    /// Every way a batch of streams is drawn, on this processor.
    fn batch_draws(streams: &PixelStreams, first: u32, out: &mut [PixelSampler]) {
        streams.samples_into_in(first, out);
        #[cfg(target_arch = "x86_64")]
        {
            let check = |drawn: &[PixelSampler], out: &[PixelSampler]| {
                for (a, b) in drawn.iter().zip(out) {
                    assert_eq!(
                        a.sobol.map(|(u, v)| (u.to_bits(), v.to_bits())),
                        b.sobol.map(|(u, v)| (u.to_bits(), v.to_bits()))
                    );
                }
            };
            let mut other: Vec<_> = (0..out.len()).map(|_| PixelSampler::idle()).collect();
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor runs AVX2.
                unsafe { streams.samples_into_avx2(first, &mut other) };
                check(&other, out);
            }
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("gfni")
            {
                // SAFETY: the processor runs AVX2 and GFNI.
                unsafe { streams.samples_into_gfni(first, &mut other) };
                check(&other, out);
            }
            if crate::accel::simd::avx512_supported() && std::arch::is_x86_feature_detected!("gfni")
            {
                // SAFETY: the processor runs AVX-512 F, VL, DQ and BW, and GFNI.
                unsafe { streams.samples_into_avx512(first, &mut other) };
                check(&other, out);
            }
        }
    }

    #[test]
    fn a_batch_of_streams_is_each_sample_s_own_stream() {
        let mut rng = Pcg32::new(4, 2);
        for len in 0..=37 {
            let (seed, x, y) = (rng.next_u64(), rng.next_u32() % 5000, rng.next_u32() % 5000);
            let first = if len % 3 == 0 {
                rng.next_u32()
            } else {
                len as u32 * 16
            };
            let streams = PixelStreams::new(seed, x, y);
            let mut out: Vec<_> = (0..=len).map(|_| PixelSampler::idle()).collect();
            batch_draws(&streams, first, &mut out[..len]);
            assert_eq!(
                out[len].next_pair, SOBOL_PAIRS,
                "the stream past the batch is left"
            );
            for (k, drawn) in out[..len].iter_mut().enumerate() {
                let mut want = PixelSampler::for_sample(seed, x, y, first.wrapping_add(k as u32));
                for _ in 0..SOBOL_PAIRS + 2 {
                    let (a, b) = (drawn.next_2d(), want.next_2d());
                    assert_eq!(
                        (a.0.to_bits(), a.1.to_bits()),
                        (b.0.to_bits(), b.1.to_bits()),
                        "len {len}, sample {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_sobol_lanes_draw_the_pairs_one_at_a_time_drew() {
        let mut rng = Pcg32::new(9, 1);
        for case in 0..2_000 {
            let (seed, x, y) = (rng.next_u64(), rng.next_u32() % 5000, rng.next_u32() % 5000);
            let index = if case % 2 == 0 { case } else { rng.next_u32() };
            let pixel = (u64::from(y) << 32) | u64::from(x);
            let pixel_key = splitmix64(seed ^ splitmix64(pixel ^ SAMPLE_KEY));
            let key = (pixel_key ^ (pixel_key >> 32)) as u32;
            let streams = PixelStreams::new(seed, x, y);
            let mut one = PixelSampler::for_sample(seed, x, y, index);
            let mut scalar = [PixelSampler::idle()];
            streams.samples_into_in(index, &mut scalar);
            let [mut scalar] = scalar;
            let mut packed = [PixelSampler::idle(), PixelSampler::idle()];
            streams.samples_into(index, &mut packed[..1], StreamLanes::Sixteen);
            let [mut packed, idle] = packed;
            assert_eq!(idle.next_pair, SOBOL_PAIRS);
            for pair in 0..SOBOL_PAIRS {
                let want =
                    sobol_2d_one_at_a_time(index, mix32(key ^ pair.wrapping_mul(0x9e37_79b9)));
                let bits = |(u, v): (f32, f32)| (u.to_bits(), v.to_bits());
                let want = bits(want);
                assert_eq!(bits(one.next_2d()), want, "case {case}, pair {pair}");
                assert_eq!(bits(scalar.next_2d()), want, "case {case}, pair {pair}");
                assert_eq!(bits(packed.next_2d()), want, "case {case}, pair {pair}");
            }
            // And on from the same PCG stream.
            let after = one.next_f32();
            assert_eq!(after, scalar.next_f32());
            assert_eq!(after, packed.next_f32());
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
