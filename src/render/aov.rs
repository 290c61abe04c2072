//! Passes for compositing and denoising (`--aov`): what each camera ray first meets,
//! its albedo, shading normal or distance, through the same camera samples and the
//! same resampling as the image, so a pass lines up with it pixel for pixel.

use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, offset_origin};
use crate::options::Aov;
use crate::scene::{Scene, Surface, SurfacePoint};

/// Alpha cut-outs a camera ray passes through before the next surface counts.
const MAX_CUT_OUTS: u32 = 64;

/// An integrator whose "radiance" is one pass's value at the first surface.
pub struct AovTracer<'a> {
    scene: &'a Scene,
    accel: &'a Accel<'a>,
    surfaces: &'a [Surface],
    aov: Aov,
    /// Whether samples spread over the pixel, as the image's model takes them.
    spread: bool,
}

impl<'a> AovTracer<'a> {
    /// Pass `aov` of `scene`; `spread` as the image's model's
    /// [`Integrator::spreads_samples`].
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel<'a>,
        surfaces: &'a [Surface],
        aov: Aov,
        spread: bool,
    ) -> AovTracer<'a> {
        AovTracer {
            scene,
            accel,
            surfaces,
            aov,
            spread,
        }
    }

    /// The pass's value along `ray` whose closest hit is `hit`.
    fn value(&self, ray: &Ray, hit: Option<Hit>) -> Vec3 {
        let Some((t, shape, sp)) = self.first_surface(ray, hit) else {
            return Vec3::ZERO;
        };
        let s = &self.surfaces[self.scene.material_of[shape as usize] as usize];
        match self.aov {
            Aov::Albedo => self.scene.albedo(s, &sp, shape) * sp.color,
            Aov::Normal => {
                let sp = match &s.normal_map {
                    Some(map) => self.scene.normal_mapped(sp, shape, map, s.normal_scale),
                    None => sp,
                };
                if ray.dir.dot(sp.ng) < 0.0 {
                    sp.n
                } else {
                    -sp.n
                }
            }
            Aov::Depth => Vec3::splat(t),
        }
    }

    /// The first surface along `ray` not cut out: its distance, shape and point.
    fn first_surface(&self, ray: &Ray, hit: Option<Hit>) -> Option<(f32, u32, SurfacePoint)> {
        let mut r = *ray;
        let mut travelled = 0.0;
        let mut known = Some(hit);
        for _ in 0..MAX_CUT_OUTS {
            let hit = match known.take() {
                Some(hit) => hit,
                None => self.accel.closest(&r, f32::INFINITY),
            }?;
            let s = &self.surfaces[self.scene.material_of[hit.shape as usize] as usize];
            let sp = self
                .scene
                .surface_point(hit.shape, &r, hit.t, s.reads_texture_coords());
            if !self.scene.cut_out(s, &sp) {
                return Some((travelled + hit.t, hit.shape, sp));
            }
            travelled += hit.t;
            r.origin = offset_origin(sp.p, sp.ng, r.dir);
        }
        None
    }
}

impl Integrator for AovTracer<'_> {
    /// Draws nothing while shading.
    fn lens_packets(&self) -> bool {
        true
    }

    fn spreads_samples(&self) -> bool {
        self.spread
    }

    fn trace_camera_ray(
        &self,
        ray: Ray,
        _sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    ) {
        count.rays += 1;
        let hit = self.accel.closest(&ray, f32::INFINITY);
        acc.sum += self.value(&ray, hit);
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
        for (i, (ray, &hit)) in rays.iter().zip(hits).enumerate() {
            count.rays += 1;
            let k = slot(samplers, i);
            accs[k].sum += self.value(ray, hit);
            accs[k].weight += 1.0;
        }
    }
}
