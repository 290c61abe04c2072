//! Passes for compositing and denoising (`--aov`): what each camera ray first meets,
//! its albedo, shading normal or distance, through the same camera samples and the
//! same resampling as the image, so a pass lines up with it pixel for pixel.

use super::cut_outs::first_uncut;
use super::{Integrator, PixelSampler, RayCount, WeightedColor, slot};
use crate::accel::{Accel, Hit};
use crate::math::{Ray, Vec3, offset_origin, reflect};
use crate::options::Aov;
use crate::scene::{Scene, Surface, SurfacePoint};

use super::optics::refract;

/// Mirrors and panes of glass the albedo pass looks through, at most, before it
/// takes the surface it stands on.
const MAX_SPECULAR_BOUNCES: u32 = 8;

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
            return match self.aov {
                Aov::Background => self.scene.background(ray.dir),
                _ => Vec3::ZERO,
            };
        };
        let (t, shape) = (hit.t, hit.id());
        let s = &self.surfaces[self.scene.material_index(shape) as usize];
        match self.aov {
            Aov::Albedo => self.albedo_seen(*ray, hit, sp),
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
            Aov::Alpha => Vec3::ONE,
            Aov::Background => Vec3::ZERO,
        }
    }
}

impl AovTracer<'_> {
    /// The albedo of the first surface along `ray` that is not a mirror or a pane of
    /// glass without a diffuse lobe (which have no colour of their own to show a
    /// denoiser), tinted by those it is seen through: what Open Image Denoise asks of
    /// its albedo pass.
    /// Glass is looked through where light can cross it, else into. `hit` and `sp` are
    /// the ray's first surface.
    fn albedo_seen(&self, mut ray: Ray, mut hit: Hit, mut sp: SurfacePoint) -> Vec3 {
        let mut tint = Vec3::ONE;
        for bounce in 0..=MAX_SPECULAR_BOUNCES {
            let s = &self.surfaces[self.scene.material_index(hit.id()) as usize];
            let albedo = self.scene.albedo(s, &sp, hit.id()) * sp.color;
            if !looks_through(s, albedo) || bounce == MAX_SPECULAR_BOUNCES {
                return (tint * albedo).clamp(Vec3::ZERO, Vec3::ONE);
            }
            let entering = ray.dir.dot(sp.ng) < 0.0;
            let n = if entering { sp.n } else { -sp.n };
            let (eta_i, eta_t) = if entering { (1.0, s.ior) } else { (s.ior, 1.0) };
            let crossing = (s.transmission != Vec3::ZERO)
                .then(|| refract(ray.dir, n, eta_i, eta_t))
                .flatten();
            let dir = match crossing {
                Some(dir) => {
                    tint *= s.transmission;
                    dir
                }
                None => {
                    // A mirror, or glass reflecting all it receives.
                    tint *= if s.reflection != Vec3::ZERO {
                        s.reflection
                    } else {
                        s.transmission
                    };
                    reflect(ray.dir, n)
                }
            };
            ray = Ray::new(offset_origin(sp.p, sp.ng, dir), dir);
            let Some(next) = first_uncut(self.scene, self.accel, self.surfaces, &ray, None) else {
                return Vec3::ZERO;
            };
            (hit, sp) = next;
        }
        Vec3::ZERO
    }
}

/// Whether the albedo pass looks through a surface of albedo `albedo` at a hit: one
/// with no diffuse lobe that mirrors or refracts, and so shows what it reflects or lets
/// through rather than a colour of its own (a highlight it may have is a light's
/// reflection, not a colour either).
fn looks_through(s: &Surface, albedo: Vec3) -> bool {
    if let Some(m) = &s.openpbr {
        // A smooth metal or clear glass: mirrors or refracts all that is not absorbed.
        let smooth = m.specular_roughness.value < 0.05 && m.specular_roughness.texture.is_none();
        let whole = |p: &crate::scene::openpbr::Scalar| p.value >= 1.0 && p.texture.is_none();
        return s.lit && smooth && (whole(&m.base_metalness) || whole(&m.transmission_weight));
    }
    s.lit
        && (s.diffuse <= 0.0 || albedo == Vec3::ZERO)
        && (s.reflection != Vec3::ZERO || s.transmission != Vec3::ZERO)
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
