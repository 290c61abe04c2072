//! Scenes of a few flat shapes (a room, a box of blocks): up to sixteen rays that need
//! not run together meet every shape at once, the rays in the lanes, one shape after
//! another. No tree: on such scenes scattered rays walk it slower than they test
//! everything, because which children a ray enters, in which order, and whether a leaf
//! holds its hit are branches the processor cannot foresee, where meeting every shape
//! is straight-line vector arithmetic.
//!
//! What the sweep keeps of a tree is one level of boxes over runs of neighbouring
//! shapes (a block's face, a wall's triangles): a batch passes over a run when none of
//! its rays enters the run's box, one test for all its lanes. A batch of scattered rays
//! rarely misses a whole block, but often misses each of its faces.
//!
//! Each lane repeats the single-ray shape test operation for operation, and keeps a
//! hit only when it is strictly nearer than the lane's best so far, so of equally near
//! shapes the first (the lowest index) stays: the answers of [`Bvh::closest`], bit for
//! bit. Shadow rays still walk the tree (`scattered`): most of a room's reach their
//! light, and meeting every shape cost them more than the walk (with the runs, and
//! the walls left out, the same as the walk).

use super::build::half_area;
use super::coherent::{PACKET_RAYS, Rays, lane_flag};
use super::leaf4::{Flat, Prim, padded_bounds};
use super::{Bvh, TINY_SCENE};
use crate::accel::Hit;
use crate::math::{Aabb, Ray};
use crate::scene::Shapes;

/// Scenes of at most this many shapes, all triangles or rectangles, are met this way.
/// Path-traced at 16 samples, against each ray walking the tree: a Cornell box with a
/// tessellated sphere of 100 to 400 triangles (136 to 436 shapes in all) takes
/// 0.79-0.83x the time, of 784 triangles 0.90x, and `CornellBox-Glossy` (1,112) 1.07x;
/// with 4 to 128 small cubes (84 to 1,572 shapes) 0.65-0.81x, with 512 cubes 1.20x.
/// The sweep's runs are one level of boxes, so past a few hundred shapes a batch tests
/// too many of them: the tree's levels pay where a dense mesh fills the view.
pub const FEW_SHAPES: usize = 512;

/// Every shape of a scene of [`FEW_SHAPES`] flat shapes at most, in index order, in
/// runs of neighbours.
pub(super) struct FewFlats {
    flats: Vec<Flat>,
    runs: Vec<Run>,
}

/// Consecutive shapes that lie together (a face of a block, a wall's two triangles),
/// with the box that holds every hit their tests report: when none of the rays enters
/// it before its best hit so far, the run is passed over, its hits no nearer. The runs
/// keep the shapes' order, so ties still go to the lowest index.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Run {
    /// One past the run's last shape; it starts where the run before it ends.
    end: u32,
    /// The union of the shapes' [`padded_bounds`], or `None` for a run that nearly
    /// every batch enters (a room's walls), met without its box test.
    bounds: Option<([f32; 3], [f32; 3])>,
}

/// A run's box test, in units of one shape's test against the same rays.
const RUN_TEST_COST: f32 = 0.5;
/// The rays a batch typically holds, for the odds that one of them enters a box.
const RAYS_PER_BATCH: i32 = 13;

/// The shapes cut into runs of consecutive indices at least cost: a run with a box
/// costs its box test plus its shapes' tests times the odds that some ray of a batch
/// enters the box, a ray entering it with the odds of its area over the scene's (as
/// the SAH has it); a run without one costs its shapes' tests. Scenes of
/// [`TINY_SCENE`] shapes or fewer stay one run, without a box.
fn runs(bounds: &[Aabb]) -> Vec<Run> {
    let n = bounds.len();
    let scene = bounds.iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
    let scene_area = half_area(&scene);
    if n <= TINY_SCENE || !(scene_area > 0.0 && scene_area.is_finite()) {
        return vec![Run {
            end: n as u32,
            bounds: None,
        }];
    }
    // best[j]: the least cost of the first j shapes, where its last run starts, and
    // whether that run has a box.
    let mut best = vec![(0.0f32, 0usize, false); n + 1];
    for j in 1..=n {
        best[j] = (f32::INFINITY, 0, false);
        let mut b = Aabb::EMPTY;
        for i in (0..j).rev() {
            b = b.union(bounds[i]);
            let odds = (half_area(&b) / scene_area).clamp(0.0, 1.0);
            let entered = 1.0 - (1.0 - odds).powi(RAYS_PER_BATCH);
            let shapes = (j - i) as f32;
            let boxed = RUN_TEST_COST + shapes * entered;
            let cost = best[i].0 + boxed.min(shapes);
            if cost < best[j].0 {
                best[j] = (cost, i, boxed < shapes);
            }
        }
    }
    let mut runs: Vec<Run> = Vec::new();
    let mut j = n;
    while j > 0 {
        let (_, i, boxed) = best[j];
        let b = bounds[i..j].iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
        match runs.last_mut() {
            // Neighbours without boxes are one run.
            Some(next) if !boxed && next.bounds.is_none() => {}
            _ => runs.push(Run {
                end: j as u32,
                bounds: boxed.then_some((b.min.to_array(), b.max.to_array())),
            }),
        }
        j = i;
    }
    runs.reverse();
    runs
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
        let bounds: Vec<Aabb> = (0..shapes.len())
            .map(|i| padded_bounds(&shapes.get(i)))
            .collect();
        Some(FewFlats {
            flats,
            runs: runs(&bounds),
        })
    }

    pub(super) fn memory_bytes(&self) -> usize {
        self.flats.capacity() * size_of::<Flat>() + self.runs.capacity() * size_of::<Run>()
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
        let mut first = 0;
        for run in &self.runs {
            let shapes = first..run.end;
            first = run.end;
            if let Some((lo, hi)) = run.bounds
                && !lanes.enter_any(lo, hi, &best_t)
            {
                continue;
            }
            for shape in shapes {
                let flat = &self.flats[shape as usize];
                // Each shape is met against `t_max` rather than the best so far, so
                // the shapes' tests do not wait on one another. A hit counts only
                // strictly before the best so far: a tie keeps the lower index. The
                // lanes are blended as bits, which the compiler keeps in vector
                // registers (as branches it made them one lane at a time).
                let (met, t) = lanes.meet_each(flat, &bound);
                for i in 0..N {
                    let keep = met[i] & lane_flag(t[i] < best_t[i]);
                    best_t[i] = f32::from_bits(t[i].to_bits() & keep | best_t[i].to_bits() & !keep);
                    best_shape[i] = shape & keep | best_shape[i] & !keep;
                }
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
