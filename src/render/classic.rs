//! The classic shading model: how the 2014 program coloured a ray (SPEC 3.2, 3.3).
//!
//! Every contribution along a camera ray's tree is a (colour, weight) pair added to one
//! accumulator; the pixel is the weighted mean. Surface colour enters only through the
//! ambient term; diffuse and highlights are white, shadows black, and the weights shrink
//! with the ray's intensity, which each reflection or refraction scales by the material's
//! ratio. Light colours are not used.

use super::shadows::{KnownShadows, from_light, trace_ahead};
use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, highlight_pow, offset_origin, reflect};
use crate::scene::Scene;

/// Rays weaker than this are not traced.
pub const MIN_INTENSITY: f32 = 0.1;
/// Child rays deeper than this are not traced (camera rays have depth 0).
pub const MAX_DEPTH: u32 = 4;
/// Weight of the black of a shadow, per light, relative to the ray's intensity.
pub const SHADOW_WEIGHT: f32 = 3.0;
/// Floor of |N.L| in the highlight weight, which divides by it: a light grazing the
/// surface must not give an infinite weight.
const MIN_COS: f32 = 1e-6;

pub struct Classic<'a> {
    scene: &'a Scene,
    accel: &'a Accel<'a>,
    /// Refractive index of the medium camera rays start in.
    camera_ior: f32,
}

/// A ray of the classic model: geometry plus what R3 of the report adds.
#[derive(Clone, Copy, Debug)]
pub struct ClassicRay {
    pub ray: Ray,
    pub intensity: f32,
    /// Refractive index of the medium the ray travels in.
    pub ior: f32,
}

impl<'a> Classic<'a> {
    pub fn new(scene: &'a Scene, accel: &'a Accel<'a>, camera_ior: f32) -> Classic<'a> {
        Classic {
            scene,
            accel,
            camera_ior,
        }
    }

    /// Adds the contributions of `r` and its children to `acc`.
    pub fn trace(&self, r: ClassicRay, depth: u32, acc: &mut WeightedColor, count: &mut RayCount) {
        if depth > MAX_DEPTH || r.intensity < MIN_INTENSITY {
            return;
        }
        count.rays += 1;
        let hit = self.accel.closest(&r.ray, f32::INFINITY);
        self.shade(r, hit, KnownShadows::NONE, depth, acc, count);
    }

    /// Adds the contributions of `r`, whose closest hit is `hit`, and its children;
    /// `known` holds the answers of shadow rays already traced from the hit.
    fn shade(
        &self,
        r: ClassicRay,
        hit: Option<Hit>,
        known: KnownShadows,
        depth: u32,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let Some(hit) = hit else {
            return;
        };
        let p = r.ray.at(hit.t);
        let shape = &self.scene.shapes.get(hit.shape as usize);
        let m = self.scene.material(hit.shape);
        let n = shape.normal(p);
        let i = r.intensity;

        acc.add(self.scene.surface_color(hit.shape, p), i * m.ambient);
        acc.add(Vec3::ONE, i * m.diffuse);
        let shading = Highlight {
            view_dir: r.ray.dir,
            n,
            specular: m.specular,
            shininess: m.shininess,
        };
        self.add_lights(p, &shading, i, known, acc, count);

        let d = r.ray.dir;
        if m.reflect != 0.0 {
            let dir = reflect(d, n);
            let child = ClassicRay {
                ray: Ray::new(offset_origin(p, n, dir), dir),
                intensity: i * m.reflect,
                ior: r.ior,
            };
            self.trace(child, depth + 1, acc, count);
        }
        if m.refract != 0.0 {
            let child = match refract(d, n, r.ior, m.ior) {
                Some((dir, ior)) => ClassicRay {
                    ray: Ray::new(offset_origin(p, n, dir), dir),
                    intensity: i * m.refract,
                    ior,
                },
                // Total internal reflection: the refracted share is reflected instead.
                None => {
                    let dir = reflect(d, n);
                    ClassicRay {
                        ray: Ray::new(offset_origin(p, n, dir), dir),
                        intensity: i * m.refract,
                        ior: r.ior,
                    }
                }
            };
            self.trace(child, depth + 1, acc, count);
        }
    }

    /// Shadow (black, weight 3 I) or highlight (white) of each light at `p`.
    fn add_lights(
        &self,
        p: Vec3,
        h: &Highlight,
        i: f32,
        known: KnownShadows,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        for (j, light) in self.scene.lights.iter().enumerate() {
            let Some((shadow, t_max)) = from_light(light.position, p) else {
                continue;
            };
            count.rays += 1;
            let blocked = match known.blocked(j) {
                Some(blocked) => blocked,
                None => self.accel.occluded(&shadow, t_max, |s| self.blocks(s)),
            };
            if blocked {
                acc.add(Vec3::ZERO, SHADOW_WEIGHT * i);
                continue;
            }
            let l = shadow.dir;
            let r = reflect(l, h.n);
            let r_dot_v = -r.dot(h.view_dir);
            if r_dot_v >= 0.0 && h.specular != 0.0 {
                let w = h.specular * highlight_pow(r_dot_v, h.shininess)
                    / h.n.dot(l).abs().max(MIN_COS);
                acc.add(Vec3::ONE, i * w);
            }
        }
    }

    /// Whether shape `s` stops light: transparent shapes let it through.
    #[inline]
    fn blocks(&self, s: u32) -> bool {
        !self.scene.material(s).transparent
    }
}

/// What the highlight of a light at a hit depends on besides the light.
struct Highlight {
    view_dir: Vec3,
    n: Vec3,
    specular: f32,
    shininess: f32,
}

/// Refraction across a surface with geometric normal `n` (SPEC 3.3). A ray going along
/// the normal (`d.n > 0`) enters the material, whose index is `material_ior`; against it,
/// it leaves into index 1. Returns the new direction and medium index, or `None` on total
/// internal reflection.
pub fn refract(d: Vec3, n: Vec3, ray_ior: f32, material_ior: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(d);
    let (n, target) = if cos_i < 0.0 {
        cos_i = -cos_i;
        (-n, 1.0)
    } else {
        (n, material_ior)
    };
    let eta = target / ray_ior;
    let cos_t2 = 1.0 - (1.0 - cos_i * cos_i) / (eta * eta);
    if cos_t2 < 0.0 {
        return None;
    }
    let dir = d / eta - (cos_i / eta - cos_t2.sqrt()) * n;
    Some((dir.normalize(), target))
}

impl Integrator for Classic<'_> {
    /// Shading draws nothing from the sampler: camera rays may be traced ahead.
    fn lens_packets(&self) -> bool {
        true
    }

    /// The shadow rays of the hits go toward each light as one packet: they share the
    /// light as origin, and their directions differ little.
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    ) {
        let n = rays.len();
        let mut known = [KnownShadows::NONE; super::PACKET_RAYS];
        trace_ahead(
            self.accel,
            self.scene.lights.len(),
            &mut known[..n],
            |i, j| {
                let hit = hits[i]?;
                from_light(self.scene.lights[j].position, rays[i].at(hit.t))
            },
            |s| self.blocks(s),
        );
        for i in 0..n {
            let r = ClassicRay {
                ray: rays[i],
                intensity: 1.0,
                ior: self.camera_ior,
            };
            // What `trace` does at depth 0, with the closest hit already found.
            count.rays += 1;
            let k = slot(samplers, i);
            self.shade(r, hits[i], known[i], 0, &mut accs[k], count);
        }
    }

    #[inline]
    fn trace_camera_ray(
        &self,
        ray: Ray,
        _sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let r = ClassicRay {
            ray,
            intensity: 1.0,
            ior: self.camera_ior,
        };
        self.trace(r, 0, acc, count);
    }
}

#[cfg(test)]
mod tests;
