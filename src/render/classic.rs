//! The classic shading model: how the 2014 program coloured a ray (SPEC 3.2, 3.3).
//!
//! Every contribution along a camera ray's tree is a (colour, weight) pair added to one
//! accumulator; the pixel is the weighted mean. Surface colour enters only through the
//! ambient term; diffuse and highlights are white, shadows black, and the weights shrink
//! with the ray's intensity, which each reflection or refraction scales by the material's
//! ratio. Light colours are not used.

use super::{Integrator, PixelSampler, RayCount, WeightedColor};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, offset_origin, reflect, surface_epsilon};
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
        self.shade(r, hit, depth, acc, count);
    }

    /// Adds the contributions of `r`, whose closest hit is `hit`, and its children.
    fn shade(
        &self,
        r: ClassicRay,
        hit: Option<Hit>,
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
        self.add_lights(r.ray.dir, p, n, i, m.specular, m.shininess, acc, count);

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

    /// Shadow (black, weight 3 I) or highlight (white) of each light at `p`. Shadow rays
    /// go from the light toward the point and pass through transparent shapes.
    #[allow(clippy::too_many_arguments)]
    fn add_lights(
        &self,
        view_dir: Vec3,
        p: Vec3,
        n: Vec3,
        i: f32,
        specular: f32,
        shininess: f32,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        for light in &self.scene.lights {
            let to_point = p - light.position;
            let dist = to_point.length();
            if dist == 0.0 {
                continue;
            }
            let l = to_point / dist;
            count.rays += 1;
            let shadow = Ray {
                origin: light.position,
                dir: l,
            };
            let blocks = |s: u32| !self.scene.material(s).transparent;
            if self
                .accel
                .occluded(&shadow, dist - surface_epsilon(p), blocks)
            {
                acc.add(Vec3::ZERO, SHADOW_WEIGHT * i);
                continue;
            }
            let r = reflect(l, n);
            let r_dot_v = -r.dot(view_dir);
            if r_dot_v >= 0.0 && specular != 0.0 {
                let w = specular * r_dot_v.powf(shininess) / n.dot(l).abs().max(MIN_COS);
                acc.add(Vec3::ONE, i * w);
            }
        }
    }
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

    #[inline]
    fn trace_camera_hit(
        &self,
        ray: Ray,
        hit: Option<Hit>,
        _sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        let r = ClassicRay {
            ray,
            intensity: 1.0,
            ior: self.camera_ior,
        };
        // What `trace` does at depth 0, with the closest hit already found.
        count.rays += 1;
        self.shade(r, hit, 0, acc, count);
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
