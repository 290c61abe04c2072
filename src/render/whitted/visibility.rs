//! Shadow rays of the whitted model: stopped by opaque surfaces, tinted by each
//! transparent one crossed (one traversal notes the glass spheres on the way, then a
//! walk through them, and the distances of the flat glass it crosses), let by where a
//! surface is clear to shadows, and an area light's samples from one point traced as
//! one packet.

use super::shadow_batch::ShadowBatch;
use super::{
    FLAT_CROSSINGS, LightSample, MAX_CLEAR_CROSSINGS, MAX_CROSSINGS, WALK_SPHERES, Whitted,
};
use crate::accel::Hit;
use crate::math::{Ray, Vec3, offset_origin, surface_epsilon};
use crate::render::{PixelSampler, RayCount};
use crate::scene::light::stratified::lanes::{LANES, SampleLanes};
use crate::scene::{Light, Shape, ShapeId, Surface};
use std::cell::Cell;
use std::mem::MaybeUninit;

/// The shadow ray of light sample `ls` seen from `from` (the point lifted onto its
/// surface, geometric normal `ng`), and the distance it must cover; `None` where the
/// sample is too close to need one (it is seen).
#[inline]
pub(super) fn shadow_ray(from: Vec3, ng: Vec3, ls: &LightSample) -> Option<(Ray, f32)> {
    let origin = offset_origin(from, ng, ls.dir);
    // Stop short of the light itself: an emissive mesh is geometry too.
    let t_max = if ls.dist.is_finite() {
        ls.dist * (1.0 - 1e-4) - surface_epsilon(origin)
    } else {
        f32::INFINITY
    };
    let ray = Ray {
        origin,
        dir: ls.dir,
    };
    // Written as the test it replaced: a NaN distance still traces.
    if t_max <= 0.0 {
        None
    } else {
        Some((ray, t_max))
    }
}

/// Where a shading point's shadow rays start: the point, the point lifted onto its
/// smooth surface, and the geometric normal on the side they leave from.
pub(super) struct Shadows {
    pub(super) p: Vec3,
    pub(super) shadow_from: Vec3,
    pub(super) ng: Vec3,
}

/// What a surface does to a shadow ray that meets it.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum ShadowRole {
    /// Stops it: opaque, nothing cut out.
    Blocks,
    /// Lets it by unchanged ([`Surface::is_clear_to_shadows`]).
    Clear,
    /// Tints it, or lets it through where an alpha map cuts the surface out.
    Crosses,
}

impl ShadowRole {
    pub(super) fn of(s: &Surface) -> ShadowRole {
        if s.is_clear_to_shadows() {
            ShadowRole::Clear
        } else if s.is_transmissive() || s.alpha_map.is_some() {
            ShadowRole::Crosses
        } else {
            ShadowRole::Blocks
        }
    }
}

impl Whitted<'_> {
    /// What shape `s` of the scene does to a shadow ray.
    #[inline]
    pub(super) fn shadow_role(&self, s: ShapeId) -> ShadowRole {
        self.shadow_roles[self.scene.material_index(s) as usize]
    }

    /// Whether shape `s` of the shadow rays' intersector affects a shadow ray: stops it,
    /// or where surfaces tint shadow rays, may stop or tint it.
    #[inline]
    pub(super) fn shadow_blocks(&self, s: ShapeId) -> bool {
        !self.shadows_meet_clear || self.shadow_role(self.scene_shape(s)) != ShadowRole::Clear
    }

    /// The scene's index of shape `s` of the shadow rays' intersector.
    #[inline]
    pub(super) fn scene_shape(&self, s: ShapeId) -> ShapeId {
        match self.caster_index {
            Some(index) if s.is_world() => ShapeId::world(index[s.shape as usize]),
            _ => s,
        }
    }

    /// Adds to `l` the light of area light `light` at a shading point, whose samples
    /// (their shading factors from `shading`) send their shadow rays as one packet:
    /// they leave together from one point. Not inlined: the packet's buffers would
    /// otherwise sit in the frame of every level of the shading recursion.
    #[inline(never)]
    pub(super) fn add_area_light(
        &self,
        light: &Light,
        at: &Shadows,
        shading: &impl Fn(&LightSample) -> Option<Vec3>,
        l: &mut Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) {
        let mut batch = ShadowBatch::new();
        let meets = |shape| self.shadow_blocks(shape);
        let settle = |ls: &LightSample| {
            if self.see_through {
                self.visibility_of(at.shadow_from, at.ng, ls)
            } else {
                Vec3::ZERO
            }
        };
        // Where surfaces tint shadow rays, every ray a packet meets is traced again on
        // its own. So the first ray goes alone, and where it meets anything (the point
        // lies inside or behind glass, or in shadow) so do the rest.
        let (mut probe, mut alone) = (self.see_through, false);
        let n = light.samples.max(1);
        let mut lanes = SampleLanes::default();
        for first in (0..n).step_by(LANES) {
            let len = (n - first).min(LANES as u32) as usize;
            light.sample_lanes(
                self.scene,
                self.surfaces,
                at.p,
                sampler,
                first,
                len,
                &mut lanes,
            );
            for ls in lanes.lit() {
                let Some(shade) = shading(&ls) else {
                    continue;
                };
                count.rays += 1;
                if probe || alone {
                    let vis = self.visibility_of(at.shadow_from, at.ng, &ls);
                    *l += vis * ls.e * shade;
                    alone |= probe && vis != Vec3::ONE;
                    probe = false;
                    continue;
                }
                batch.push(shadow_ray(at.shadow_from, at.ng, &ls), ls, shade);
                if batch.is_full() {
                    self.count_packet(&batch);
                    batch.resolve(self.shadow_accel, meets, settle, |light| *l += light);
                }
            }
        }
        self.count_packet(&batch);
        batch.resolve(self.shadow_accel, meets, settle, |light| *l += light);
    }

    #[inline(always)]
    fn count_packet(&self, _batch: &ShadowBatch) {
        #[cfg(test)]
        if _batch.traces() {
            self.packets_traced
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// How many shadow packets were traced.
    #[cfg(test)]
    pub(super) fn packets_traced(&self) -> u32 {
        self.packets_traced
            .load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Fraction (per channel) of a light sample's light that reaches the point: zero
    /// behind an opaque surface, tinted by each transparent surface crossed.
    pub(super) fn visibility(
        &self,
        from: Vec3,
        ng: Vec3,
        ls: &LightSample,
        count: &mut RayCount,
    ) -> Vec3 {
        count.rays += 1;
        self.visibility_of(from, ng, ls)
    }

    /// [`Whitted::visibility`], uncounted.
    pub(super) fn visibility_of(&self, from: Vec3, ng: Vec3, ls: &LightSample) -> Vec3 {
        let Some((ray, t_max)) = shadow_ray(from, ng, ls) else {
            return Vec3::ONE;
        };
        if !self.see_through {
            let blocks = |shape| self.shadow_blocks(shape);
            return if self.shadow_accel.occluded(&ray, t_max, blocks) {
                Vec3::ZERO
            } else {
                Vec3::ONE
            };
        }
        // One traversal answers whether an opaque surface blocks the segment and, on
        // the way, notes the see-through spheres it passes and the flat see-through
        // shapes it crosses, so that no crossing needs a traversal of its own below.
        let mut spheres = [0u32; WALK_SPHERES];
        let noted = Cell::from_mut(&mut spheres[..]).as_slice_of_cells();
        let len = Cell::new(0usize);
        // Left uninitialised: clearing it would cost every shadow ray of a scene with
        // glass, and few meet a flat one.
        let mut flats = [const { MaybeUninit::<(f32, ShapeId)>::uninit() }; FLAT_CROSSINGS];
        let crossed = Cell::from_mut(&mut flats[..]).as_slice_of_cells();
        let flat_len = Cell::new(0usize);
        let whole_scene = Cell::new(false);
        let blocked = self.shadow_accel.occluded(&ray, t_max, |shape| {
            let shape = self.scene_shape(shape);
            match self.shadow_role(shape) {
                ShadowRole::Blocks => return true,
                // Crossing it multiplies by one: the walk below would change nothing
                // there (and a glass mesh would cost a traversal per crossing).
                ShadowRole::Clear => return false,
                ShadowRole::Crosses if whole_scene.get() => return false,
                ShadowRole::Crosses => {}
            }
            let geometry = &self.scene.shape_at(shape);
            if !matches!(geometry, Shape::Sphere(_)) {
                // A flat shape is crossed once: its distance is all the answer needs.
                if let Some(t) = geometry.intersect(&ray, t_max) {
                    let n = flat_len.get();
                    if n == crossed.len() {
                        whole_scene.set(true);
                    } else {
                        crossed[n].set(MaybeUninit::new((t, shape)));
                        flat_len.set(n + 1);
                    }
                }
                return false;
            }
            let n = len.get();
            // Spheres are the scene's own: an object holds triangles only.
            let shape = shape.shape;
            if noted[..n].iter().any(|c| c.get() == shape) {
                return false;
            }
            if n == noted.len() {
                whole_scene.set(true);
            } else {
                noted[n].set(shape);
                len.set(n + 1);
            }
            false
        });
        if blocked {
            return Vec3::ZERO;
        }
        let spheres = &spheres[..len.get()];
        // SAFETY: the first `flat_len` entries were written above, and a
        // `MaybeUninit<T>` has the layout of `T`.
        let flats = unsafe {
            std::slice::from_raw_parts_mut(
                flats.as_mut_ptr().cast::<(f32, ShapeId)>(),
                flat_len.get(),
            )
        };
        if whole_scene.get() || !(spheres.is_empty() || flats.is_empty()) {
            return self.walk_through(ray, t_max, |r, left| self.accel.closest(r, left));
        }
        if !flats.is_empty() {
            return self.cross_flats(&ray, flats);
        }
        if spheres.is_empty() {
            return Vec3::ONE;
        }
        // The nearest hit among the noted spheres, with the tie-break every intersector
        // uses: the hit `Accel::closest` would find, as long as the walk's rays (each
        // lifted a surface epsilon off the last crossing) meet no surface the traversal
        // did not pass, which only one within that epsilon of the segment could be.
        self.walk_through(ray, t_max, |r, left| {
            let mut best: Option<Hit> = None;
            for &shape in spheres {
                if let Some(t) = self
                    .scene
                    .shapes
                    .get(shape as usize)
                    .intersect(r, Hit::bound(&best, left))
                    && Hit::beats(t, shape, &best)
                {
                    best = Some(Hit::world(t, shape));
                }
            }
            best
        })
    }

    /// The light left after the flat see-through shapes `crossings` (distance along
    /// `ray`, scene index) the segment crosses: their transmissions multiplied nearest
    /// first. Hits closer along the ray than the surface epsilon to the last crossing
    /// count as that crossing: where the ray passes through an edge two triangles
    /// share, or through the octree's copies of one shape.
    ///
    /// The walk from crossing to crossing, which answers rays that also meet glass
    /// spheres or more flat crossings than a ray notes, lifts its ray a surface epsilon
    /// along each surface's normal instead. It can count a crossing through a box's
    /// edge twice, and pass a surface closer than an epsilon along that normal (panes a
    /// hair apart, crossed at a slant), so such rays can differ between the two.
    fn cross_flats(&self, ray: &Ray, crossings: &mut [(f32, ShapeId)]) -> Vec3 {
        crossings.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.order().cmp(&b.1.order())));
        let mut vis = Vec3::ONE;
        let mut last = f32::NEG_INFINITY;
        for &(t, shape) in crossings.iter() {
            let p = ray.at(t);
            if t - last <= surface_epsilon(p) {
                continue;
            }
            last = t;
            let s = self.surface(shape);
            if s.alpha_map.is_some() {
                let sp = self.scene.surface_point(shape, ray, t, true);
                if self.cut_out(shape, &sp) {
                    continue;
                }
            }
            vis *= s.transmission;
            if vis.max_element() <= 0.0 {
                return Vec3::ZERO;
            }
        }
        vis
    }

    /// The see-through surfaces along `ray` up to `t_max`, crossed one after another
    /// (each hit found by `closest` from just past the last), their transmissions
    /// multiplied in that order; cut-out parts let light by untouched. Surfaces clear to
    /// shadows are stepped through without counting against [`MAX_CROSSINGS`], so the
    /// answer is the one of shadow rays that let them by, but for a surface within a
    /// surface epsilon behind a clear one, which the ray lifted off the clear one
    /// passes (where `closest` sees clear shapes: the scene's intersector).
    #[inline]
    pub(super) fn walk_through(
        &self,
        ray: Ray,
        t_max: f32,
        closest: impl Fn(&Ray, f32) -> Option<Hit>,
    ) -> Vec3 {
        let mut vis = Vec3::ONE;
        let mut r = ray;
        let mut left = t_max;
        let (mut tinting, mut clear) = (0, 0);
        while tinting < MAX_CROSSINGS {
            let Some(hit) = closest(&r, left) else {
                return vis;
            };
            let s = self.surface(hit.id());
            if self.shadow_role(hit.id()) == ShadowRole::Clear {
                if clear == MAX_CLEAR_CROSSINGS {
                    return vis;
                }
                clear += 1;
            } else {
                tinting += 1;
            }
            let (p, ng) = if s.alpha_map.is_some() {
                let sp = self.scene.surface_point(hit.id(), &r, hit.t, true);
                if !self.cut_out(hit.id(), &sp) {
                    vis *= s.transmission;
                    if vis.max_element() <= 0.0 {
                        return Vec3::ZERO;
                    }
                }
                (sp.p, sp.ng)
            } else {
                vis *= s.transmission;
                if vis.max_element() <= 0.0 {
                    return Vec3::ZERO;
                }
                // What `surface_point` would give, without the texture coordinates
                // and mesh attributes nothing here reads.
                let p = r.at(hit.t);
                (p, self.scene.shape_at(hit.id()).normal(p))
            };
            let next = offset_origin(p, ng, r.dir);
            left -= (next - r.origin).length();
            if left <= 0.0 {
                return vis;
            }
            r.origin = next;
        }
        vis
    }
}
