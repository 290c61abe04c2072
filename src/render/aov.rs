//! Passes for compositing and denoising (`--aov`): what each camera ray first meets,
//! its albedo, shading normal or distance, through the same camera samples and the
//! same resampling as the image, so a pass lines up with it pixel for pixel.

use super::cut_outs::first_uncut;
use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3};
use crate::options::Aov;
use crate::scene::{Scene, Surface};

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
        let Some((hit, sp)) = first_uncut(self.scene, self.accel, self.surfaces, ray, Some(hit))
        else {
            return Vec3::ZERO;
        };
        let (t, shape) = (hit.t, hit.shape);
        let s = &self.surfaces[self.scene.material_of[shape as usize] as usize];
        match self.aov {
            Aov::Albedo => self.scene.albedo(s, &sp, shape) * sp.color,
            Aov::Normal => {
                let mut sp = sp;
                if let Some(map) = &s.normal_map {
                    sp.n = self.scene.normal_mapped(&sp, shape, map, s.normal_scale);
                }
                if ray.dir.dot(sp.ng) < 0.0 {
                    sp.n
                } else {
                    -sp.n
                }
            }
            Aov::Depth => Vec3::splat(t),
        }
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
        _samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    ) {
        for (i, (ray, &hit)) in rays.iter().zip(hits).enumerate() {
            count.rays += 1;
            let acc = &mut accs[slot(accs, i)];
            acc.sum += self.value(ray, hit);
            acc.weight += 1.0;
        }
    }
}
