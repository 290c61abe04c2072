//! Scenes of a few flat shapes (a room, a box of blocks): up to sixteen rays that need
//! not run together meet every shape at once, the rays in the lanes, one shape after
//! another. No tree: on such scenes scattered rays walk it slower than they test
//! everything, because which children a ray enters, in which order, and whether a leaf
//! holds its hit are branches the processor cannot foresee, where meeting every shape
//! is straight-line vector arithmetic.
//!
//! Each lane repeats the single-ray shape test operation for operation, and keeps a
//! hit only when it is strictly nearer than the lane's best so far, so of equally near
//! shapes the first (the lowest index) stays: the answers of [`Bvh::closest`], bit for
//! bit. Shadow rays still walk the tree (`scattered`): most of a room's reach their
//! light, and meeting every shape cost them more than the walk.

use super::Bvh;
use super::coherent::{PACKET_RAYS, Rays, lane_flag};
use super::leaf4::{Flat, Prim};
use crate::accel::Hit;
use crate::math::Ray;
use crate::scene::Shapes;

/// Scenes of at most this many shapes, all triangles or rectangles, are met this way.
/// Path-traced, the Cornell box (36 triangles) takes 17 % less time so, and with two
/// more cubes (60) still 5 % less.
pub const FEW_SHAPES: usize = 64;

/// Every shape of a scene of [`FEW_SHAPES`] flat shapes at most, in index order.
pub(super) struct FewFlats {
    flats: Vec<Flat>,
}

impl FewFlats {
    /// The shapes of `shapes` if there are few enough, all flat.
    pub(super) fn of(shapes: &Shapes) -> Option<FewFlats> {
        if shapes.is_empty() || shapes.len() > FEW_SHAPES {
            return None;
        }
        let flats = (0..shapes.len() as u32)
            .map(|i| match Prim::of(shapes, i) {
                Prim::Flat(f) => Some(f),
                Prim::Sphere(_) => None,
            })
            .collect::<Option<Vec<_>>>()?;
        Some(FewFlats { flats })
    }

    pub(super) fn memory_bytes(&self) -> usize {
        self.flats.capacity() * size_of::<Flat>()
    }

    /// The closest hit of each ray with `0 < t < t_max` into `hits`, the rays in the
    /// fewest lanes of four, eight or sixteen that hold them: on a processor that
    /// splits a wide register's work in two halves, a half-empty one costs double.
    #[inline(always)]
    fn closest(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        match rays.len() {
            0..=4 => self.closest_in::<4>(rays, t_max, hits),
            5..=8 => self.closest_in::<8>(rays, t_max, hits),
            _ => self.closest_in::<PACKET_RAYS>(rays, t_max, hits),
        }
    }

    #[inline(always)]
    fn closest_in<const N: usize>(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        let lanes = Rays::<N>::new(rays);
        // Lanes without a ray get -inf: nothing meets them.
        let mut bound = [f32::NEG_INFINITY; N];
        bound[..rays.len()].fill(t_max);
        let mut best_t = bound;
        let mut best_shape = [u32::MAX; N];
        for (shape, flat) in self.flats.iter().enumerate() {
            // Each shape is met against `t_max` rather than the best so far, so the
            // shapes' tests do not wait on one another. A hit counts only strictly
            // before the best so far: a tie keeps the lower index. The lanes are
            // blended as bits, which the compiler keeps in vector registers (as
            // branches it made them one lane at a time).
            let (met, t) = lanes.meet_each(flat, &bound);
            for i in 0..N {
                let keep = met[i] & lane_flag(t[i] < best_t[i]);
                best_t[i] = f32::from_bits(t[i].to_bits() & keep | best_t[i].to_bits() & !keep);
                best_shape[i] = shape as u32 & keep | best_shape[i] & !keep;
            }
        }
        for (i, hit) in hits.iter_mut().enumerate() {
            *hit = (best_shape[i] != u32::MAX).then_some(Hit::world(best_t[i], best_shape[i]));
        }
    }
}

impl Bvh<'_> {
    /// Whether [`Bvh::closest_many`] meets every shape at once rather than walking the
    /// tree one ray at a time.
    #[cfg(test)]
    fn meets_all_at_once(&self) -> bool {
        self.few.is_some()
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays that need not run
    /// together, into `hits`: what [`Bvh::closest`] gives each.
    pub fn closest_many(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        assert!(rays.len() <= PACKET_RAYS && hits.len() == rays.len());
        let Some(few) = &self.few else {
            for (hit, ray) in hits.iter_mut().zip(rays) {
                *hit = self.closest(ray, t_max);
            }
            return;
        };
        if rays.is_empty() {
            return;
        }
        if rays.len() == 1 {
            // A packet's last path: a walk tests a leaf or two, where the sweep's
            // narrowest lanes would meet every shape for it alone (the Cornell box's
            // path render 0.96x the time; two rays walked gain nothing more).
            hits[0] = self.closest(&rays[0], t_max);
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == super::SimdLevel::Avx2 {
            if crate::accel::simd::avx512_wanted() {
                // SAFETY: the processor runs AVX-512 F, VL, DQ and BW.
                return unsafe { closest_avx512(few, rays, t_max, hits) };
            }
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { closest_avx2(few, rays, t_max, hits) };
        }
        few.closest(rays, t_max, hits);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
unsafe fn closest_avx512(few: &FewFlats, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
    few.closest(rays, t_max, hits);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn closest_avx2(few: &FewFlats, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
    few.closest(rays, t_max, hits);
}

#[cfg(test)]
mod tests;
