//! The path model: unidirectional path tracing (Kajiya's rendering equation, as pbrt
//! and Mitsuba solve it). At every vertex light is gathered from each light by
//! next-event estimation and the path goes on in a direction the surface's BSDF draws;
//! where both strategies can find the same light (an area light, an emissive mesh, the
//! environment) their estimates are weighed by the power heuristic. Russian roulette
//! ends paths whose throughput has fallen, so depth is unlimited by default.
//!
//! Each camera sample draws from its own stream (seed, pixel, sample index), in a
//! fixed order of dimensions, so the image does not depend on threads or passes.

mod direct;
mod environment;
mod interior;
mod lanes;
mod subsurface;
#[cfg(test)]
mod tests;
mod tree;
mod wave;

pub use super::bsdf::{Bsdf, Highlight, PhongBsdf, Sampled, Terms};
use super::cut_outs::first_uncut;
use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, offset_origin};
use crate::options::LightSampling;
use crate::scene::light::sampling::{FlatEmitter, Incident};
use crate::scene::light::tree::LightTree;
use crate::scene::{Light, LightKind, Scene, ShapeId, Surface};
pub use direct::{Weighing, power_heuristic};
use environment::Environment;

/// Bounces after which Russian roulette may end a path (Mitsuba's default).
const ROULETTE_DEPTH: u32 = 5;
/// A path is continued with at most this probability, so that every path ends.
const MAX_CONTINUE: f32 = 0.95;
/// No emitter index.
const NONE: u32 = u32::MAX;

/// The path integrator over a scene, its intersector and its resolved surfaces.
pub struct Path<'a> {
    scene: &'a Scene,
    accel: &'a Accel<'a>,
    surfaces: &'a [Surface],
    max_depth: u32,
    /// The light each emissive triangle of the scene's own belongs to, by shape (empty
    /// without mesh lights): what a BSDF ray that meets one weighs itself against.
    light_of_shape: Vec<u32>,
    /// The mesh lights holding triangles each instance places:
    /// `placed_lights[placed_lights_from[i]..placed_lights_from[i + 1]]` for instance
    /// `i` (both empty when no light holds a placed triangle).
    placed_lights_from: Vec<u32>,
    placed_lights: Vec<u32>,
    /// Lights with an extent that are not geometry (quads, disks, spheres): a ray may
    /// meet them.
    shaped_lights: Vec<u32>,
    /// Each flat light's frame and area, by light (`None` for the others): worked out
    /// once, not at every sample and every ray that may meet it.
    flats: Vec<Option<FlatEmitter<'a>>>,
    /// Whether any surface cuts out: shadow rays then walk through the cut-outs.
    cuts_out: bool,
    /// What rays that leave the scene see, and how it is sampled.
    environment: Option<Environment>,
    /// How light that two strategies can find is weighed between them.
    weighing: Weighing,
    /// Whether a packet's samples may be traced side by side ([`Path::lanes_apply`]).
    lanes: Option<lanes::LaneScene>,
    /// The scattering medium inside each surface, by material (empty where none has
    /// one).
    interiors: Vec<Option<super::bsdf::medium::Medium>>,
    /// Whether a vertex traces one shadow ray, toward a light sample chosen by its
    /// contribution, instead of one toward each ([`LightSampling`]).
    one_shadow_ray: bool,
    /// Where a vertex draws its one light from a tree instead ([`LightSampling::Tree`]).
    tree: Option<LightTree>,
}

impl<'a> Path<'a> {
    /// The integrator for `scene` with intersector `accel`; `surfaces[m]` shades material
    /// `m`. A path scatters at most `max_depth` times (0: direct light only).
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel<'a>,
        surfaces: &'a [Surface],
        max_depth: u32,
    ) -> Path<'a> {
        let mut light_of_shape = Vec::new();
        let mut shaped_lights = Vec::new();
        let mut placed = Vec::new();
        for (k, light) in scene.lights.iter().enumerate() {
            match &light.kind {
                LightKind::Mesh { shapes, .. } => {
                    for &s in shapes {
                        if !s.is_world() {
                            // Placed shapes come sorted: one entry per instance.
                            if placed.last() != Some(&(s.instance, k as u32)) {
                                placed.push((s.instance, k as u32));
                            }
                            continue;
                        }
                        if light_of_shape.is_empty() {
                            light_of_shape = vec![NONE; scene.shapes.len()];
                        }
                        light_of_shape[s.shape as usize] = k as u32;
                    }
                }
                LightKind::Quad { .. } | LightKind::Disk { .. } | LightKind::Sphere { .. } => {
                    shaped_lights.push(k as u32)
                }
                _ => {}
            }
        }
        let (placed_lights_from, placed_lights) = by_instance(placed, scene.instances.len());
        Path {
            scene,
            accel,
            surfaces,
            max_depth,
            light_of_shape,
            placed_lights_from,
            placed_lights,
            shaped_lights,
            flats: scene.lights.iter().map(Light::flat).collect(),
            cuts_out: surfaces.iter().any(|s| s.alpha_map.is_some()),
            environment: Environment::of(scene),
            weighing: Weighing::PowerHeuristic,
            lanes: Path::lanes_apply(scene, surfaces),
            interiors: interior::interiors(surfaces),
            one_shadow_ray: false,
            tree: None,
        }
        .light_sampling(LightSampling::default())
    }

    /// The same integrator tracing the shadow rays `how` says. One shadow ray a vertex
    /// is the path at a time's alone: the vectorised lanes trace one toward each light.
    pub fn light_sampling(mut self, how: LightSampling) -> Path<'a> {
        let lights = self.scene.lights.len();
        self.one_shadow_ray = how.traces_one(lights);
        if self.one_shadow_ray {
            self.lanes = None;
        }
        self.tree = how
            .draws_from_tree(lights)
            .then(|| LightTree::new(self.scene, self.surfaces, self.environment.is_some()));
        self
    }

    /// The same integrator weighing the two strategies by `weighing`.
    pub fn weighing(mut self, weighing: Weighing) -> Path<'a> {
        self.weighing = weighing;
        self
    }

    #[inline]
    /// Whether the paths of a packet step through the scene in vector lanes.
    #[cfg(test)]
    pub(crate) fn steps_in_lanes(&self) -> bool {
        self.lanes.is_some()
    }

    fn surface(&self, shape: ShapeId) -> &Surface {
        &self.surfaces[self.scene.material_index(shape) as usize]
    }

    /// [`Light::sample_incident`] of light `k`, a flat one's from its frame kept.
    #[inline]
    fn sample_incident(&self, k: usize, p: Vec3, u: (f32, f32)) -> Option<Incident> {
        match &self.flats[k] {
            Some(flat) => flat.sample_incident(self.scene, self.surfaces, p, u),
            None => self.scene.lights[k].sample_incident(self.scene, self.surfaces, p, u),
        }
    }

    /// The light whose triangle `shape` is, if any, and its index.
    #[inline]
    fn light_of(&self, shape: ShapeId) -> Option<(u32, &Light)> {
        if shape.is_world() {
            let k = *self.light_of_shape.get(shape.shape as usize)?;
            return Some((k, self.scene.lights.get(k as usize)?));
        }
        let i = shape.instance as usize;
        let from = *self.placed_lights_from.get(i)? as usize;
        let to = *self.placed_lights_from.get(i + 1)? as usize;
        self.placed_lights[from..to]
            .iter()
            .map(|&k| (k, &self.scene.lights[k as usize]))
            .find(|(_, light)| light.emits_from(shape))
    }

    /// Radiance arriving along camera ray `ray` whose closest hit is `hit`.
    pub fn radiance(
        &self,
        ray: Ray,
        hit: Option<Hit>,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Vec3 {
        let mut path = PathState::new(ray);
        let mut hit = hit;
        while self.vertex(&mut path, hit, sampler, count) {
            hit = self.accel.closest(&path.ray, f32::INFINITY);
        }
        path.radiance()
    }

    /// One step of `path`: what its ray meets (`hit`, the ray's closest hit) adds to
    /// its radiance, and where it scatters next. False once the path has ended.
    #[inline]
    fn vertex(
        &self,
        path: &mut PathState,
        hit: Option<Hit>,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> bool {
        count.rays += 1;
        // Without cut-outs the closest hit is the surface, and its shading point is
        // made in place below: passed through an `Option` it was copied, two hundred
        // bytes a vertex.
        let (hit, mut cut_point) = if self.cuts_out {
            match first_uncut(self.scene, self.accel, self.surfaces, &path.ray, Some(hit)) {
                Some((hit, sp)) => (Some(hit), Some(sp)),
                None => (None, None),
            }
        } else {
            (hit, None)
        };
        // A ray that meets a solid from inside crossed its medium, and where that
        // scatters the ray may not get there.
        let mut crossed = false;
        if let Some(h) = hit
            && let Some(medium) = self.interior(h.id())
        {
            let sp = cut_point.take().unwrap_or_else(|| {
                let s = self.surface(h.id());
                let ray = &path.ray;
                self.scene
                    .surface_point(h.id(), ray, h.t, s.reads_texture_coords())
            });
            if path.ray.dir.dot(sp.ng) >= 0.0 {
                match self.cross(path, medium, h.t, sampler) {
                    interior::Crossing::Scattered(goes_on) => return goes_on,
                    interior::Crossing::Reached => crossed = true,
                }
            }
            cut_point = Some(sp);
        }
        let PathState {
            ray,
            l,
            beta,
            last,
            channel,
            depth,
            ..
        } = path;
        let t_scene = hit.map_or(f32::INFINITY, |h| h.t);
        if let Some((k, light, t, normal)) = self.shaped_light_hit(ray, t_scene, *depth == 0) {
            let le = light.color * light.intensity;
            let w = last.map_or(1.0, |(p, n, pdf)| {
                let light_pdf = self.light_pmf(p, n, k) * light.pdf_incident(p, ray.at(t), normal);
                self.weighing.of(pdf, light_pdf, false)
            });
            *l += *beta * le * w;
            return false;
        }
        let Some(hit) = hit else {
            if let Some(env) = &self.environment {
                let le = env.radiance(self.scene, ray.dir);
                let w = last.map_or(1.0, |(_, _, pdf)| {
                    let env_pdf = self.environment_pmf() * env.pdf(ray.dir);
                    self.weighing.of(pdf, env_pdf, false)
                });
                *l += *beta * le * w;
            }
            return false;
        };
        let s = self.surface(hit.id());
        let sp = match cut_point {
            Some(sp) => sp,
            None => self
                .scene
                .surface_point(hit.id(), ray, hit.t, s.reads_texture_coords()),
        };
        // The normal map bends the base's normal; `sp.n` stays unbent for a coat.
        let mapped = match &s.normal_map {
            Some(slot) => self
                .scene
                .normal_mapped(&sp, hit.id(), slot, s.normal_scale),
            None => sp.n,
        };
        let sp = &sp;
        let entering = ray.dir.dot(sp.ng) < 0.0;
        let (ng, n) = if entering {
            (sp.ng, mapped)
        } else {
            (-sp.ng, -mapped)
        };
        if !entering && !crossed && s.absorption != Vec3::ZERO {
            *beta *= (-s.absorption * hit.t).exp();
        }
        if entering && s.emission != Vec3::ZERO {
            let light = self.light_of(hit.id());
            let le = s.emission
                * self.scene.map(&s.emission_map, sp)
                * light.map_or(1.0, |(_, light)| light.intensity);
            let w = match (*last, light) {
                (Some((p, n, pdf)), Some((k, light))) => {
                    let light_pdf = self.light_pmf(p, n, k) * light.pdf_incident(p, sp.p, sp.ng);
                    self.weighing.of(pdf, light_pdf, false)
                }
                _ => 1.0,
            };
            *l += *beta * le * w;
        }
        let albedo = self.scene.albedo(s, sp, hit.id()) * sp.color;
        if !s.lit {
            *l += *beta * albedo;
            return false;
        }
        // A dispersive surface splits light by colour: the path goes on as one
        // channel, drawn once, carrying three times its share.
        if channel.is_none() && s.openpbr.as_ref().is_some_and(|m| m.disperses()) {
            let c = ((sampler.next_f32() * 3.0) as usize).min(2);
            let mut only = [0.0; 3];
            only[c] = 3.0 * beta[c];
            *beta = Vec3::from_array(only);
            *channel = Some(c);
        }
        let wo = -ray.dir;
        let bsdf = Bsdf::at(
            self.scene,
            s,
            sp,
            hit.id(),
            albedo,
            wo,
            n,
            ng,
            entering,
            *channel,
            true,
        );
        if bsdf.has_smooth() {
            let last = *depth >= self.max_depth;
            *l += *beta * self.direct(&bsdf, sp, ng, last, sampler, count);
        }
        self.scatter(path, &bsdf, sp.p, ng, sampler, count)
    }

    /// The path goes on from `p` (geometric normal `ng` on its side) in a direction
    /// `bsdf` draws, through the subsurface medium where the draw enters it; false
    /// where it ends (the depth reached, absorbed, or ended by Russian roulette).
    #[inline]
    fn scatter(
        &self,
        path: &mut PathState,
        bsdf: &Bsdf,
        p: Vec3,
        ng: Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> bool {
        if path.depth >= self.max_depth {
            return false;
        }
        let pick = sampler.next_f32();
        let Some(scattered) = bsdf.sample(pick, sampler.next_2d()) else {
            return false;
        };
        path.beta *= scattered.weight;
        if scattered.subsurface
            && let Some(medium) = bsdf.medium()
        {
            return self.through_medium(path, &medium, p, ng, scattered.wi, sampler, count);
        }
        path.last = (scattered.pdf > 0.0).then_some((p, ng, scattered.pdf));
        path.ray = Ray::new(offset_origin(p, ng, scattered.wi), scattered.wi);
        self.bounced(path, sampler)
    }

    /// A scattering counted: Russian roulette from [`ROULETTE_DEPTH`] on, and the
    /// path ends where its throughput is spent or overflowed.
    #[inline]
    fn bounced(&self, path: &mut PathState, sampler: &mut PixelSampler) -> bool {
        path.depth += 1;
        if path.depth >= ROULETTE_DEPTH {
            let q = path.beta.max_element().min(MAX_CONTINUE);
            if sampler.next_f32() >= q {
                return false;
            }
            path.beta /= q;
        }
        path.beta.is_finite() && path.beta.max_element() > 0.0
    }
}

/// A path between its vertices: the ray it goes on along and what it carries.
struct PathState {
    ray: Ray,
    /// Radiance gathered so far.
    l: Vec3,
    /// Throughput: what the path's next radiance is weighed by.
    beta: Vec3,
    /// Where the last scattering was, the geometric normal there and the density its
    /// direction was drawn with; `None` for the camera and after a mirror or refraction
    /// (nothing else could have found what the ray meets, so it counts in full).
    last: Option<(Vec3, Vec3, f32)>,
    /// The colour channel the path carries alone once it crossed a dispersive surface.
    channel: Option<usize>,
    /// Scatterings so far.
    depth: u32,
    /// Scatterings inside media so far (not counted in `depth`).
    flights: u32,
}

impl PathState {
    fn new(ray: Ray) -> PathState {
        PathState {
            ray,
            l: Vec3::ZERO,
            beta: Vec3::ONE,
            last: None,
            channel: None,
            depth: 0,
            flights: 0,
        }
    }

    /// The path's radiance; a path whose arithmetic overflowed adds nothing.
    fn radiance(&self) -> Vec3 {
        if self.l.is_finite() {
            self.l
        } else {
            Vec3::ZERO
        }
    }
}

impl Integrator for Path<'_> {
    /// Every sample draws from the sampler while it is shaded.
    fn lens_packets(&self) -> bool {
        false
    }

    fn spreads_samples(&self) -> bool {
        true
    }

    fn sixteen_lanes(&self) -> bool {
        self.lanes.is_some() && crate::accel::simd::avx512_wanted()
    }

    #[inline]
    fn trace_camera_ray(
        &self,
        ray: Ray,
        sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let hit = self.accel.closest(&ray, f32::INFINITY);
        let l = self.radiance(ray, hit, sampler, count);
        acc.sum += l;
        acc.weight += 1.0;
    }

    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    ) {
        if let Some(lights) = &self.lanes
            && self.weighing == Weighing::PowerHeuristic
            && samplers.len() == rays.len()
        {
            for (rays, hits, samplers, first) in chunks_of_lanes(rays, hits, samplers) {
                let mut l = [Vec3::ZERO; lanes::LANES];
                self.radiance_lanes(lights, rays, hits, samplers, count, &mut l);
                for (k, l) in l.iter().take(rays.len()).enumerate() {
                    let acc = &mut accs[slot(accs, first + k)];
                    acc.sum += *l;
                    acc.weight += 1.0;
                }
            }
            return;
        }
        if samplers.len() == rays.len() {
            for (rays, hits, samplers, first) in chunks_of_lanes(rays, hits, samplers) {
                let mut l = [Vec3::ZERO; lanes::LANES];
                self.radiance_wave(rays, hits, samplers, count, &mut l);
                for (k, l) in l.iter().take(rays.len()).enumerate() {
                    let acc = &mut accs[slot(accs, first + k)];
                    acc.sum += *l;
                    acc.weight += 1.0;
                }
            }
            return;
        }
        for (i, (ray, &hit)) in rays.iter().zip(hits).enumerate() {
            let l = self.radiance(*ray, hit, &mut samplers[slot(samplers, i)], count);
            let acc = &mut accs[slot(accs, i)];
            acc.sum += l;
            acc.weight += 1.0;
        }
    }
}

/// `rays`, their hits and samplers in runs of at most [`lanes::LANES`], each with the
/// index of its first ray.
fn chunks_of_lanes<'r, 's>(
    rays: &'r [Ray],
    hits: &'r [Option<Hit>],
    samplers: &'s mut [PixelSampler],
) -> impl Iterator<Item = (&'r [Ray], &'r [Option<Hit>], &'s mut [PixelSampler], usize)> {
    rays.chunks(lanes::LANES)
        .zip(hits.chunks(lanes::LANES))
        .zip(samplers.chunks_mut(lanes::LANES))
        .enumerate()
        .map(|(k, ((r, h), s))| (r, h, s, k * lanes::LANES))
}

/// Pairs of (instance, light) as a table of each instance's lights: where each
/// instance's run starts in the second vector (`instances + 1` entries), and the runs.
fn by_instance(mut pairs: Vec<(u32, u32)>, instances: usize) -> (Vec<u32>, Vec<u32>) {
    if pairs.is_empty() {
        return (Vec::new(), Vec::new());
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut from = Vec::with_capacity(instances + 1);
    let mut at = 0;
    for i in 0..=instances as u32 {
        while at < pairs.len() && pairs[at].0 < i {
            at += 1;
        }
        from.push(at as u32);
    }
    (from, pairs.into_iter().map(|(_, k)| k).collect())
}
