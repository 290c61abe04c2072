//! The physically based Whitted model (SPEC 4.3): linear radiance along each camera
//! ray, local lighting from every light (area lights by stratified shadow rays),
//! coloured shadows through transparent surfaces, mirror reflection, refraction with
//! exact Fresnel and Beer absorption, and the background where rays escape.
//!
//! ```text
//! L = Le + Ka La + sum_lights vis E (kd C max(0, N.L) + Ks s(N, L, V)) + R L_r + T L_t
//! ```

use super::bsdf::Bsdf;
use super::optics::{fresnel_dielectric, refract};
use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, offset_origin, reflect};
use crate::scene::light::LightSample;
use crate::scene::{Light, Scene, ShapeId, Surface, SurfacePoint};

mod casters;
mod shadow_batch;
mod visibility;

pub use casters::Casters;
use visibility::{ShadowRole, Shadows};

/// Surfaces a ray may pass through (alpha cut-outs) or a shadow ray may cross
/// (transparent ones) before the answer is taken as final: bounds the work of a ray
/// that meets a stack of leaves.
const MAX_CROSSINGS: u32 = 64;

/// Crossings of surfaces clear to shadows a shadow ray's walk may step through besides
/// its [`MAX_CROSSINGS`] tinting ones: clear glass changes nothing, so it does not use
/// up the tinting limit (the walk must answer as if it were not there, as the shadow
/// rays that let it by do), but a bound keeps every walk finite.
const MAX_CLEAR_CROSSINGS: u32 = 4096;

/// See-through spheres a shadow ray notes on its one traversal for the walk through
/// them; a ray passing more falls back to traversing the scene at every crossing.
const WALK_SPHERES: usize = 16;

/// Crossings of flat see-through shapes (a tinted glass mesh) a shadow ray gathers on
/// its one traversal; a ray meeting more walks the scene crossing by crossing. Fewer
/// than the walk's limit, so gathered crossings never reach it.
const FLAT_CROSSINGS: usize = 32;
const _: () = assert!(FLAT_CROSSINGS <= MAX_CROSSINGS as usize);

/// The physically based Whitted integrator over a scene, its intersector and its resolved
/// surfaces.
pub struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a Accel<'a>,
    surfaces: &'a [Surface],
    max_depth: u32,
    min_weight: f32,
    /// Whether any surface tints the light through it or cuts out: otherwise a shadow
    /// ray is a plain occlusion query (surfaces clear to shadows let it by).
    see_through: bool,
    /// What shadow rays are traced against: `accel`, or one over the scene's casters.
    shadow_accel: &'a Accel<'a>,
    /// The scene's index of each shape of `shadow_accel`, when it holds the casters.
    caster_index: Option<&'a [u32]>,
    /// What each surface does to a shadow ray, by material index.
    shadow_roles: Vec<ShadowRole>,
    /// Whether a shape of `shadow_accel` may be clear to shadows: otherwise each one a
    /// shadow ray meets blocks or tints it.
    shadows_meet_clear: bool,
    /// Whether any light is sampled (an area light): shading then draws from the
    /// pixel's sampler.
    samples_lights: bool,
    /// Whether an area light's shadow rays from one point go as one packet (the tests
    /// hold them to the rays one at a time).
    shadow_packets: bool,
    /// Shadow packets traced, for tests that hold the packets to being used.
    #[cfg(test)]
    packets_traced: std::sync::atomic::AtomicU32,
}

impl<'a> Whitted<'a> {
    /// The integrator for `scene` with intersector `accel`; `surfaces[m]` shades material
    /// `m`. Hits at depth `max_depth` (camera rays are depth 0) spawn no children, nor do
    /// children whose path weight (largest channel) would fall below `min_weight`.
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel<'a>,
        surfaces: &'a [Surface],
        max_depth: u32,
        min_weight: f32,
    ) -> Whitted<'a> {
        let shadow_roles: Vec<ShadowRole> = surfaces.iter().map(ShadowRole::of).collect();
        let see_through = shadow_roles.contains(&ShadowRole::Crosses);
        let shadows_meet_clear = shadow_roles.contains(&ShadowRole::Clear);
        let samples_lights = scene.lights.iter().any(Light::is_area);
        Whitted {
            scene,
            accel,
            surfaces,
            max_depth,
            min_weight,
            see_through,
            shadow_accel: accel,
            caster_index: None,
            shadow_roles,
            shadows_meet_clear,
            samples_lights,
            shadow_packets: true,
            #[cfg(test)]
            packets_traced: Default::default(),
        }
    }

    /// Every shadow ray traced alone: the reference the packets are held to.
    #[cfg(test)]
    fn one_shadow_ray_at_a_time(mut self) -> Whitted<'a> {
        self.shadow_packets = false;
        self
    }

    /// Shadow rays traced against `accel`, built over the scene's [`Casters`]
    /// (`casters.scene_index()` gives each one's index in the scene): the same answers,
    /// without walking through the shapes that are clear to shadows.
    pub fn with_casters(mut self, accel: &'a Accel<'a>, casters: &'a Casters) -> Whitted<'a> {
        assert_eq!(accel.shape_count(), casters.scene_index().len());
        self.shadow_accel = accel;
        self.caster_index = Some(casters.scene_index());
        self.shadows_meet_clear = false;
        self
    }

    #[inline]
    fn surface(&self, shape: ShapeId) -> &Surface {
        &self.surfaces[self.scene.material_index(shape) as usize]
    }

    /// Radiance arriving along `ray`; `weight` is what the camera will multiply it by
    /// (for the bail-out), `depth` the number of bounces so far.
    pub fn radiance(
        &self,
        ray: &Ray,
        depth: u32,
        weight: Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Vec3 {
        let hit = self.accel.closest(ray, f32::INFINITY);
        self.radiance_from(ray, hit, depth, weight, sampler, count)
    }

    /// [`Whitted::radiance`] with the ray's closest hit already found (in a packet).
    fn radiance_from(
        &self,
        ray: &Ray,
        hit: Option<Hit>,
        depth: u32,
        weight: Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Vec3 {
        count.rays += 1;
        let Some((hit, sp)) =
            super::cut_outs::first_uncut(self.scene, self.accel, self.surfaces, ray, Some(hit))
        else {
            return self.scene.background(ray.dir);
        };
        let s = self.surface(hit.id());
        let d = ray.dir;
        // The normal map bends the base's normal; `sp.n` stays unbent for a coat.
        let mapped = match &s.normal_map {
            Some(slot) => self
                .scene
                .normal_mapped(&sp, hit.id(), slot, s.normal_scale),
            None => sp.n,
        };
        // Inside/outside from the geometric normal; shading normals turned to the ray.
        let entering = d.dot(sp.ng) < 0.0;
        let (ng, n) = if entering {
            (sp.ng, mapped)
        } else {
            (-sp.ng, -mapped)
        };
        // Beer: the ray crossed this surface's medium to get here from inside.
        let absorbed = if entering || s.absorption == Vec3::ZERO {
            Vec3::ONE
        } else {
            (-s.absorption * hit.t).exp()
        };
        let weight = weight * absorbed;

        // Emitters glow on the side their normal faces, as they light the scene.
        let mut l = if entering {
            s.emission * self.scene.map(&s.emission_map, &sp)
        } else {
            Vec3::ZERO
        };
        let albedo = self.scene.albedo(s, &sp, hit.id()) * sp.color;
        if !s.lit {
            return absorbed * (l + albedo);
        }
        l += s.ambient * self.scene.map(&s.ambient_map, &sp) * self.scene.ambient;
        let v = -d;
        let shadow_from = sp.shadow_origin(ng);
        let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
        // Light from lights is gathered through the surface's BSDF, the path model's.
        let bsdf = Bsdf::at(
            self.scene,
            s,
            &sp,
            hit.id(),
            albedo,
            v,
            n,
            ng,
            entering,
            None,
            false,
        );
        // What a sample lights at the point before its shadow ray, or `None` where it
        // lights nothing (and no shadow ray is traced).
        let shading = |ls: &LightSample| {
            let (f, cos) = bsdf.eval_cos(ls.dir);
            let shade = f * cos;
            (shade.max_element() > 0.0).then_some(shade)
        };
        for light in &self.scene.lights {
            if light.is_area() && self.shadow_packets {
                let from = Shadows {
                    p: sp.p,
                    shadow_from,
                    ng,
                };
                self.add_area_light(light, &from, &shading, &mut l, sampler, count);
                continue;
            }
            light.for_each_sample(self.scene, self.surfaces, sp.p, sampler, |ls| {
                let Some(shade) = shading(&ls) else {
                    return;
                };
                let vis = self.visibility(shadow_from, ng, &ls, count);
                l += vis * ls.e * shade;
            });
        }

        if depth >= self.max_depth {
            return absorbed * l;
        }
        // Reflection and refraction shares.
        let (eta_i, eta_t) = if entering { (1.0, s.ior) } else { (s.ior, 1.0) };
        let transmitted = if s.is_transmissive() {
            refract(d, n, eta_i, eta_t)
        } else {
            None
        };
        if let Bsdf::OpenPbr(framed) = &bsdf {
            // Its perfect mirror and refraction, as the path model follows them, and
            // its rough lobes' light from the scene gathered along the same two rays.
            let (kr, kt) = framed.deltas();
            let (gr, gt) = framed.glossy();
            let (kr, kt) = (kr + gr, kt + gt);
            if (weight * kr).max_element() >= self.min_weight {
                let dir = reflect(d, bsdf.normal());
                let child = Ray::new(offset_origin(sp.p, ng, dir), dir);
                l += kr * self.radiance(&child, depth + 1, weight * kr, sampler, count);
            }
            // Where the surface is only partly present, the rest passes straight on.
            let kp = Vec3::splat(framed.pass_through());
            if (weight * kp).max_element() >= self.min_weight {
                let child = Ray::new(offset_origin(sp.p, ng, d), d);
                l += kp * self.radiance(&child, depth + 1, weight * kp, sampler, count);
            }
            if let Some((kc, dir)) = framed.coat_reflection()
                && (weight * kc).max_element() >= self.min_weight
            {
                let child = Ray::new(offset_origin(sp.p, ng, dir), dir);
                l += kc * self.radiance(&child, depth + 1, weight * kc, sampler, count);
            }
            if let Some(dir) = framed.refracted()
                && (weight * kt).max_element() >= self.min_weight
            {
                let child = Ray::new(offset_origin(sp.p, ng, dir), dir);
                l += kt * self.radiance(&child, depth + 1, weight * kt, sampler, count);
            }
            return absorbed * l;
        }
        let (mut kr, mut kt) = if s.fresnel {
            let f = fresnel_dielectric(cos_i, eta_i, eta_t);
            (s.reflection * f, s.transmission * (1.0 - f))
        } else {
            (s.reflection, s.transmission)
        };
        if s.is_transmissive() && transmitted.is_none() {
            // Total internal reflection: what would have crossed is reflected.
            kr += kt;
            kt = Vec3::ZERO;
        }
        if (weight * kr).max_element() >= self.min_weight {
            let dir = reflect(d, n);
            let child = Ray::new(offset_origin(sp.p, ng, dir), dir);
            l += kr * self.radiance(&child, depth + 1, weight * kr, sampler, count);
        }
        if let Some(dir) = transmitted
            && (weight * kt).max_element() >= self.min_weight
        {
            let child = Ray::new(offset_origin(sp.p, ng, dir), dir);
            l += kt * self.radiance(&child, depth + 1, weight * kt, sampler, count);
        }
        absorbed * l
    }

    #[inline]
    fn cut_out(&self, shape: ShapeId, sp: &SurfacePoint) -> bool {
        self.scene.cut_out(self.surface(shape), sp)
    }
}

impl Integrator for Whitted<'_> {
    /// Point, spot and directional lights draw nothing from the sampler; area lights
    /// do, so with one in the scene a pixel's lens rays are shaded as they are made.
    fn lens_packets(&self) -> bool {
        !self.samples_lights
    }

    #[inline]
    fn trace_camera_ray(
        &self,
        ray: Ray,
        sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let l = self.radiance(&ray, 0, Vec3::ONE, sampler, count);
        add_camera_sample(acc, l);
    }

    /// Each hit is shaded alone. (Its shadow rays start where the hits lie, spread
    /// along a row; as a packet they measured slower than one at a time.)
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    ) {
        for (i, (ray, &hit)) in rays.iter().zip(hits).enumerate() {
            let sampler = &mut samplers[slot(samplers, i)];
            let l = self.radiance_from(ray, hit, 0, Vec3::ONE, sampler, count);
            add_camera_sample(&mut accs[slot(accs, i)], l);
        }
    }
}

/// Adds a camera ray's radiance to its pixel: every camera ray counts once, so the
/// pixel is the plain mean of its rays.
#[inline]
fn add_camera_sample(acc: &mut WeightedColor, l: Vec3) {
    let l = if l.is_finite() { l } else { Vec3::ZERO };
    acc.sum += l;
    acc.weight += 1.0;
}

#[cfg(test)]
mod tests;
