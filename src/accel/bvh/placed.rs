//! The tree of an object placed by an instance, met by a world ray.
//!
//! The nodes stay in the object's space and the ray is taken there to cull them, with
//! boxes grown by a bound on every rounding between the two spaces, so no box holding a
//! hit is skipped. The leaves are met in world space: each triangle's corners placed
//! as [`Instance::place_corners`] places them for the flattened twin, then the same
//! four-lane test. So a placed triangle gives the flattened one's distance bit for bit.

#[cfg(target_arch = "x86_64")]
use super::Boxes8;
use super::leaf4::{Leaf4, RayLanes};
use super::{BoxTest, Boxes4, Bvh, Entry, STORED, Stack};
use crate::accel::Hit;
#[cfg(target_arch = "x86_64")]
use crate::accel::simd::SimdLevel;
use crate::math::Ray;
use crate::scene::{Instance, ShapeId};
use glam::Affine3A;

/// The ray of a world-space query, as one placed object meets it.
pub struct PlacedRay<'a> {
    /// The ray in world space: what the leaves are met with.
    pub world: &'a Ray,
    /// The ray in the object's space (its direction not renormalised, so a distance
    /// along it is the world distance): what the nodes are culled with.
    pub local: Ray,
    /// How far, in the object's space, the boxes are grown.
    pub pad: f32,
    /// The instance and its index.
    pub instance: &'a Instance,
    /// Its object-to-world transform, unpacked once for every leaf the ray meets.
    pub to_world: Affine3A,
    pub index: u32,
}

impl Bvh<'_> {
    /// Updates `best` with the nearest hit before `t_max` on the object placed as `ray`
    /// says.
    #[inline]
    pub fn closest_placed(&self, ray: &PlacedRay, t_max: f32, best: &mut Option<Hit>) {
        if self.shape_count == 0 {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.closest_placed_avx2(ray, t_max, best) };
        }
        self.closest_placed_sse2(ray, t_max, best)
    }

    /// [`Bvh::closest_placed`] on four lanes, not inlined (see [`Bvh::closest_sse2`]).
    #[inline(never)]
    fn closest_placed_sse2(&self, ray: &PlacedRay, t_max: f32, best: &mut Option<Hit>) {
        let boxes = Boxes4::<true>::padded(&ray.local, ray.pad);
        self.closest_placed_in(boxes, ray, t_max, best)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn closest_placed_avx2(&self, ray: &PlacedRay, t_max: f32, best: &mut Option<Hit>) {
        match Boxes8::padded(&ray.local, ray.pad) {
            Some(boxes) => self.closest_placed_in(boxes, ray, t_max, best),
            None => self.closest_placed_sse2(ray, t_max, best),
        }
    }

    #[inline(always)]
    fn closest_placed_in(
        &self,
        boxes: impl BoxTest,
        ray: &PlacedRay,
        t_max: f32,
        best: &mut Option<Hit>,
    ) {
        let lanes = RayLanes::new(ray.world);
        let mut stack = Stack::new(self.root);
        let mut next: Option<Entry> = None;
        while let Some(entry) = next.take().or_else(|| stack.pop()) {
            let bound = Hit::bound(best, t_max);
            if entry.t > bound * super::BOX_SLACK {
                continue;
            }
            if entry.count > 0 {
                self.placed_leaf_closest(entry, &lanes, ray, t_max, best);
                continue;
            }
            let node = self.node(entry);
            let (mask, t_near) = boxes.hit(node, bound);
            next = node.only_child(mask, &t_near);
            if next.is_some() {
                continue;
            }
            stack.push_children(node, mask, &t_near);
        }
    }

    /// Whether a shape of the placed object for which `blocks` holds meets the ray
    /// before `t_max`.
    #[inline]
    pub fn occluded_placed(
        &self,
        ray: &PlacedRay,
        t_max: f32,
        blocks: &impl Fn(ShapeId) -> bool,
    ) -> bool {
        if self.shape_count == 0 {
            return false;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.occluded_placed_avx2(ray, t_max, blocks) };
        }
        self.occluded_placed_sse2(ray, t_max, blocks)
    }

    /// [`Bvh::occluded_placed`] on four lanes, not inlined.
    #[inline(never)]
    fn occluded_placed_sse2(
        &self,
        ray: &PlacedRay,
        t_max: f32,
        blocks: &impl Fn(ShapeId) -> bool,
    ) -> bool {
        let boxes = Boxes4::<true>::padded(&ray.local, ray.pad);
        self.occluded_placed_in(boxes, ray, t_max, blocks)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn occluded_placed_avx2(
        &self,
        ray: &PlacedRay,
        t_max: f32,
        blocks: &impl Fn(ShapeId) -> bool,
    ) -> bool {
        match Boxes8::padded(&ray.local, ray.pad) {
            Some(boxes) => self.occluded_placed_in(boxes, ray, t_max, blocks),
            None => self.occluded_placed_sse2(ray, t_max, blocks),
        }
    }

    #[inline(always)]
    fn occluded_placed_in(
        &self,
        boxes: impl BoxTest,
        ray: &PlacedRay,
        t_max: f32,
        blocks: &impl Fn(ShapeId) -> bool,
    ) -> bool {
        let lanes = RayLanes::new(ray.world);
        let mut stack = Stack::new(self.root);
        let mut next: Option<Entry> = None;
        while let Some(entry) = next.take().or_else(|| stack.pop()) {
            if entry.count > 0 {
                if self.placed_leaf_blocks(entry, &lanes, ray, t_max, blocks) {
                    return true;
                }
                continue;
            }
            let node = self.node(entry);
            let (mut mask, t_near) = boxes.hit(node, t_max);
            next = node.only_child(mask, &t_near);
            if next.is_some() {
                continue;
            }
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                stack.push(node.entry(lane, 0.0));
            }
        }
        false
    }

    #[inline(always)]
    fn placed_leaf_closest(
        &self,
        entry: Entry,
        lanes: &RayLanes,
        ray: &PlacedRay,
        t_max: f32,
        best: &mut Option<Hit>,
    ) {
        debug_assert!(entry.count & STORED == 0);
        let first = entry.child as usize;
        for four in self.prims[first..first + entry.count as usize].chunks(4) {
            let leaf = Leaf4::placed(self.shapes, four, &ray.to_world, ray.instance.flip());
            let (mut mask, t) = leaf.intersect_flat(lanes, Hit::bound(best, t_max));
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let id = ShapeId {
                    instance: ray.index,
                    shape: leaf.shape(lane),
                };
                if Hit::beats_id(t[lane], id, best) {
                    *best = Some(Hit {
                        t: t[lane],
                        shape: id.shape,
                        instance: id.instance,
                    });
                }
            }
        }
    }

    #[inline(always)]
    fn placed_leaf_blocks(
        &self,
        entry: Entry,
        lanes: &RayLanes,
        ray: &PlacedRay,
        t_max: f32,
        blocks: &impl Fn(ShapeId) -> bool,
    ) -> bool {
        // Loops, not iterator closures: a closure would not inherit the caller's
        // instruction set. An object holds triangles only, so no leaf is stored.
        debug_assert!(entry.count & STORED == 0);
        let first = entry.child as usize;
        for four in self.prims[first..first + entry.count as usize].chunks(4) {
            let leaf = Leaf4::placed(self.shapes, four, &ray.to_world, ray.instance.flip());
            let mut mask = leaf.intersect_flat(lanes, t_max).0;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let id = ShapeId {
                    instance: ray.index,
                    shape: leaf.shape(lane),
                };
                if blocks(id) {
                    return true;
                }
            }
        }
        false
    }
}
