//! Shadow rays that need not run together (one toward a light from each of a pixel's
//! paths), each walking the tree alone, but past the root together: the root's eight
//! boxes are tested against all of them at once, the rays in the lanes, and each ray
//! starts its own walk from the children it enters. In a small tree the root is most of
//! a ray's walk (a room's shadow ray visits 1.3 nodes), and its test and the set-up of
//! a ray's box test were a third of the walk's time: a ray whose root children are all
//! leaves now needs neither.
//!
//! Each ray's answer is the one [`Bvh::occluded`] gives it: the root's boxes are
//! tested by the slab test of the packets ([`Rays`]), which culls no box a hit lies in,
//! and below the root every ray walks as a single ray does.

use super::boxes::Boxes4;
#[cfg(target_arch = "x86_64")]
use super::boxes::Boxes8;
use super::coherent::{PACKET_RAYS, Rays, shadow_bounds};
use super::leaf4::RayLanes;
use super::stack::Stack;
use super::{Bvh, WIDTH};
use crate::math::Ray;

impl Bvh<'_> {
    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) meet a shape with
    /// `0 < t < t_max[i]`: [`Bvh::occluded`] for each ray, every shape blocking, for
    /// rays that need not run together.
    pub fn occluded_many(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        assert!(rays.len() <= PACKET_RAYS && t_max.len() == rays.len());
        if self.root.count > 0 || rays.len() < 2 {
            // One leaf, or one ray: nothing to share.
            return (0..rays.len())
                .map(|i| u32::from(self.occluded(&rays[i], t_max[i], |_| true)) << i)
                .sum();
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == super::SimdLevel::Avx2 {
            if crate::accel::simd::avx512_wanted() {
                // SAFETY: the processor runs AVX-512 F, VL, DQ and BW.
                return unsafe { self.occluded_many_avx512(rays, t_max) };
            }
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.occluded_many_avx2(rays, t_max) };
        }
        self.occluded_many_in::<false>(rays, t_max)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
    unsafe fn occluded_many_avx512(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        self.occluded_many_in::<true>(rays, t_max)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn occluded_many_avx2(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        self.occluded_many_in::<true>(rays, t_max)
    }

    /// `WIDE` where the caller is compiled for AVX2 and FMA (the box test below the
    /// root is then [`Boxes8`]).
    #[inline(always)]
    fn occluded_many_in<const WIDE: bool>(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        let lanes = Rays::<PACKET_RAYS>::new(rays);
        let bound = shadow_bounds(t_max);
        let all = u32::MAX >> (32 - rays.len());
        let Some(indoors) = &self.indoors else {
            return self.walk_many::<WIDE>(&lanes, rays, &bound, all);
        };
        // The rays that keep off the walls walk the tree without them.
        let (origin, dir) = lanes.axes();
        let clear = indoors.clear_lanes(origin, dir, &bound) & all;
        let mut blocked = 0;
        if clear != 0 {
            blocked |= indoors
                .tree()
                .walk_many::<WIDE>(&lanes, rays, &bound, clear);
        }
        if clear != all {
            blocked |= self.walk_many::<WIDE>(&lanes, rays, &bound, all & !clear);
        }
        blocked
    }

    /// Which of the rays in `which` (bit `i` for ray `i`) meet a shape before their
    /// `bound`: the root's boxes tested against them all at once in `lanes`, then
    /// each ray's own walk.
    #[inline(always)]
    fn walk_many<const WIDE: bool>(
        &self,
        lanes: &Rays<PACKET_RAYS>,
        rays: &[Ray],
        bound: &[f32; PACKET_RAYS],
        which: u32,
    ) -> u32 {
        if self.shape_count == 0 {
            return 0;
        }
        let mut blocked = 0;
        if self.root.count > 0 {
            for i in (0..rays.len()).filter(|&i| which >> i & 1 == 1) {
                let hit =
                    self.leaf_blocks(self.root, &RayLanes::new(&rays[i]), bound[i], &|_| true);
                blocked |= u32::from(hit) << i;
            }
            return blocked;
        }
        let root = self.node(self.root);
        let mut entered = [0u32; WIDTH];
        for (lane, rays_in) in entered.iter_mut().enumerate() {
            *rays_in = lanes.enter(root, lane, bound).0 & which;
        }
        let mut stack = Stack::empty();
        for (i, ray) in rays.iter().enumerate() {
            // The root's children this ray enters, stacked as the single ray's walk
            // stacks them.
            stack.len = 0;
            let mut inner = false;
            for (lane, &rays_in) in entered.iter().enumerate() {
                if rays_in >> i & 1 == 1 {
                    let child = root.entry(lane, 0.0);
                    inner |= child.count == 0;
                    stack.push(child);
                }
            }
            if stack.len == 0 {
                continue;
            }
            let ray_lanes = RayLanes::new(ray);
            let t = bound[i];
            let hit = if inner {
                self.occluded_below_root::<WIDE>(&mut stack, ray, &ray_lanes, t)
            } else {
                // Leaves alone, in the order the walk pops them: no box test to set up.
                let mut hit = false;
                while let Some(leaf) = stack.pop() {
                    if self.leaf_blocks(leaf, &ray_lanes, t, &|_| true) {
                        hit = true;
                        break;
                    }
                }
                hit
            };
            blocked |= u32::from(hit) << i;
        }
        blocked
    }

    /// The walk below the root with the box test for `ray`.
    #[inline(always)]
    fn occluded_below_root<const WIDE: bool>(
        &self,
        stack: &mut Stack,
        ray: &Ray,
        lanes: &RayLanes,
        t_max: f32,
    ) -> bool {
        let blocks = |_| true;
        #[cfg(target_arch = "x86_64")]
        if WIDE && let Some(boxes) = Boxes8::new(ray) {
            return self.occluded_below(stack, &boxes, lanes, t_max, &blocks);
        }
        self.occluded_below(stack, &Boxes4::<false>::new(ray), lanes, t_max, &blocks)
    }
}

#[cfg(test)]
mod tests;
