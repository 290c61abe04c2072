//! Next-event estimation: at each vertex light is sampled from the lights and the
//! environment, weighed against the BSDF's own samples, and tested for shadow: every
//! sample with its own shadow ray, or one chosen among them (One Light). The light
//! tree's choice is in `tree.rs`.

use super::Path;
use crate::math::{Ray, Vec3, offset_origin, surface_epsilon};
use crate::render::bsdf::Bsdf;
use crate::render::cut_outs::MAX_CUT_OUTS;
use crate::render::{PixelSampler, RayCount};
use crate::scene::{Light, SurfacePoint};

/// How the light that both a light's samples and the BSDF's can find is shared between
/// the two estimates. Renders weigh by the power heuristic; the others exist so tests
/// can hold each strategy alone to the weighed sum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weighing {
    /// Veach's power heuristic: the lower variance of the two where each is good.
    PowerHeuristic,
    /// Light sampling alone (BSDF samples that meet a light add nothing).
    LightsOnly,
    /// BSDF sampling alone (light samples of lights with an extent add nothing).
    BsdfOnly,
}

impl Weighing {
    /// The weight of a sample one strategy drew with density `own` (`from_light`: the
    /// light's) that the other would draw with density `other`.
    #[inline]
    pub(super) fn of(self, own: f32, other: f32, from_light: bool) -> f32 {
        match self {
            Weighing::PowerHeuristic => power_heuristic(own, other),
            Weighing::LightsOnly => from_light as u8 as f32,
            Weighing::BsdfOnly => !from_light as u8 as f32,
        }
    }
}

impl Path<'_> {
    /// Light arriving at the hit straight from every light and the environment, each
    /// sampled once and weighed against the BSDF's own samples. Each sample is tested
    /// by a shadow ray, or with one shadow ray a vertex only the one [`OneOf`] chooses.
    /// At the `last` vertex the path goes no further, so no BSDF sample can find the
    /// light: the light's samples count in full.
    pub(super) fn direct(
        &self,
        bsdf: &Bsdf,
        sp: &SurfacePoint,
        ng: Vec3,
        last: bool,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Vec3 {
        let from = sp.shadow_origin(ng);
        let weighing = match self.weighing {
            Weighing::PowerHeuristic if last => Weighing::LightsOnly,
            weighing => weighing,
        };
        if let Some(tree) = &self.tree {
            let to = (tree, weighing);
            return self.direct_from_tree(to, bsdf, sp.p, from, ng, sampler, count);
        }
        let mut one = self.one_shadow_ray.then(|| OneOf::new(sampler.next_f32()));
        let mut l = Vec3::ZERO;
        let mut gather = |c: Vec3, dir: Vec3, dist: f32| match &mut one {
            Some(one) => one.offer(c, dir, dist),
            None => l += self.shadowed(c, from, ng, dir, dist, count),
        };
        for k in 0..self.scene.lights.len() {
            let u = sampler.next_2d();
            let Some(inc) = self.sample_incident(k, sp.p, u) else {
                continue;
            };
            gather(
                self.unshadowed(bsdf, weighing, inc.dir, inc.li, inc.pdf, 1.0),
                inc.dir,
                inc.dist,
            );
        }
        if let Some(env) = &self.environment {
            let u = sampler.next_2d();
            if let Some((dir, le, pdf)) = env.sample(self.scene, u) {
                let c = self.unshadowed(bsdf, weighing, dir, le, pdf, 1.0);
                gather(c, dir, f32::INFINITY);
            }
        }
        match one.and_then(OneOf::chosen) {
            Some((c, dir, dist)) => self.shadowed(c, from, ng, dir, dist, count),
            None => l,
        }
    }

    /// `c`, a light sample's unshadowed contribution along `dir`, where nothing blocks
    /// the `dist` from `from` to the light.
    #[inline]
    pub(super) fn shadowed(
        &self,
        c: Vec3,
        from: Vec3,
        ng: Vec3,
        dir: Vec3,
        dist: f32,
        count: &mut RayCount,
    ) -> Vec3 {
        if c.max_element() <= 0.0 || !self.visible(from, ng, dir, dist, count) {
            return Vec3::ZERO;
        }
        c
    }

    /// What one light sample adds where nothing blocks it: `f cos Li / pdf`, weighed
    /// by `weighing` unless the light has one direction (`pdf` 0), where `li` is its
    /// irradiance; over `pmf`, the odds the light was drawn with (1 where every light
    /// is sampled).
    #[inline]
    pub(super) fn unshadowed(
        &self,
        bsdf: &Bsdf,
        weighing: Weighing,
        dir: Vec3,
        li: Vec3,
        pdf: f32,
        pmf: f32,
    ) -> Vec3 {
        let (f, bsdf_pdf, cos) = bsdf.eval_pdf(dir);
        if f == Vec3::ZERO || li == Vec3::ZERO {
            return Vec3::ZERO;
        }
        if pdf > 0.0 {
            let pdf = pmf * pdf;
            f * li * (cos * weighing.of(pdf, bsdf_pdf, true) / pdf)
        } else {
            f * li * (cos / pmf)
        }
    }

    /// Whether nothing blocks the segment from `from` (geometric normal `ng`) along
    /// `dir` for `dist`; alpha cut-outs let it through, and lights that are not
    /// geometry stop it from their emitting side only.
    pub(super) fn visible(
        &self,
        from: Vec3,
        ng: Vec3,
        dir: Vec3,
        dist: f32,
        count: &mut RayCount,
    ) -> bool {
        count.rays += 1;
        let origin = offset_origin(from, ng, dir);
        // Stop short of the light itself: an emissive mesh is geometry too.
        let t_max = if dist.is_finite() {
            dist * (1.0 - 1e-4) - surface_epsilon(origin)
        } else {
            f32::INFINITY
        };
        // A NaN distance is seen, as a sample too close to need a ray.
        if t_max.is_nan() || t_max <= 0.0 {
            return true;
        }
        let mut ray = Ray { origin, dir };
        // A light that is not geometry stops shadow rays that meet its emitting side,
        // as it stops every other ray: light from behind it does not reach the point
        // by either strategy.
        if self.shaped_light_hit(&ray, t_max, true).is_some() {
            return false;
        }
        if !self.cuts_out {
            return !self.accel.occluded(&ray, t_max, |_| true);
        }
        let mut left = t_max;
        for _ in 0..MAX_CUT_OUTS {
            let Some(hit) = self.accel.closest(&ray, left) else {
                return true;
            };
            let s = self.surface(hit.id());
            if s.alpha_map.is_none() {
                return false;
            }
            let sp = self.scene.surface_point(hit.id(), &ray, hit.t, true);
            if !self.scene.cut_out(s, &sp) {
                return false;
            }
            left -= hit.t;
            ray.origin = offset_origin(sp.p, sp.ng, dir);
        }
        false
    }

    /// The nearest light that is not geometry `ray` meets before `t_max`. With
    /// `skip_hidden` (camera and shadow rays) the lights hidden from the camera are
    /// passed by: such a light is only its light, no object the camera sees or that
    /// casts a shadow, as Blender's lights are.
    pub(super) fn shaped_light_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        skip_hidden: bool,
    ) -> Option<(u32, &Light, f32, Vec3)> {
        let mut best = None;
        let mut t_best = t_max;
        for &k in &self.shaped_lights {
            let light = &self.scene.lights[k as usize];
            if skip_hidden && !light.camera_visible {
                continue;
            }
            let hit = match &self.flats[k as usize] {
                Some(flat) => flat.hit(ray, t_best),
                None => light.hit(ray, t_best),
            };
            if let Some((t, normal)) = hit {
                t_best = t;
                best = Some((k, light, t, normal));
            }
        }
        best
    }
}

/// One of the light samples offered, chosen in proportion to its unshadowed
/// contribution and divided by the odds of the choice: its expectation is the sum of
/// the offers whatever the choice, so testing it alone for shadow is unbiased and
/// leaves the weights against the BSDF's samples as they are. The choice streams over
/// the offers with one random number (reservoir sampling), so nothing is allocated.
struct OneOf {
    /// The random number, rescaled after each offer onto the part of [0, 1) it fell
    /// in, so it stays uniform for the next.
    u: f32,
    total: f32,
    /// The chosen contribution, its size, direction and distance.
    chosen: Option<(Vec3, f32, Vec3, f32)>,
}

impl OneOf {
    fn new(u: f32) -> OneOf {
        OneOf {
            u,
            total: 0.0,
            chosen: None,
        }
    }

    /// A light sample of unshadowed contribution `c` along `dir` for `dist`, taken
    /// with probability its size over the sizes offered so far.
    #[inline]
    fn offer(&mut self, c: Vec3, dir: Vec3, dist: f32) {
        let w = c.x + c.y + c.z;
        if !(w > 0.0 && w.is_finite()) {
            return;
        }
        self.total += w;
        let p = w / self.total;
        if self.u < p {
            self.chosen = Some((c, w, dir, dist));
            self.u /= p;
        } else {
            self.u = (self.u - p) / (1.0 - p);
        }
        self.u = self.u.min(crate::math::ONE_BELOW);
    }

    /// The chosen sample's contribution over the odds of its choice, its direction and
    /// distance.
    fn chosen(self) -> Option<(Vec3, Vec3, f32)> {
        let (c, w, dir, dist) = self.chosen?;
        Some((c * (self.total / w), dir, dist))
    }
}

/// Veach's power heuristic for a sample drawn with density `a` that another strategy
/// would have drawn with density `b`.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    let w = a2 / (a2 + b2);
    if w.is_finite() { w } else { 0.0 }
}
