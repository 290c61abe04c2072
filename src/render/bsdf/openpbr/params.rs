//! An OpenPBR material's parameters at one hit, its textures read and its ranges
//! enforced, and the indices of refraction its dispersion and specular weight give.

use crate::math::Vec3;
use crate::scene::openpbr::{Channel, Color, Scalar};
use crate::scene::{OpenPbr, Scene, SurfacePoint};

/// An OpenPBR material's parameters at a hit, textures read and ranges enforced. Each
/// field is the specification's parameter of that name.
#[allow(missing_docs)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub base_weight: f32,
    pub base_color: Vec3,
    pub base_metalness: f32,
    pub base_diffuse_roughness: f32,
    pub specular_weight: f32,
    pub specular_color: Vec3,
    pub specular_roughness: f32,
    pub specular_roughness_anisotropy: f32,
    pub specular_ior: f32,
    pub transmission_weight: f32,
    /// The tint of light crossing the surface (white where a volume colours it).
    pub transmission_tint: Vec3,
    pub subsurface_weight: f32,
    pub subsurface_color: Vec3,
    /// The mean free path per channel: `subsurface_radius × subsurface_radius_scale`.
    pub subsurface_radius: Vec3,
    pub subsurface_scatter_anisotropy: f32,
    /// Whether the subsurface is a medium light is walked through (the path model)
    /// rather than a diffuse lobe of its colour. Set by the model, not the material.
    pub subsurface_walk: bool,
    pub coat_weight: f32,
    pub coat_color: Vec3,
    pub coat_roughness: f32,
    pub coat_roughness_anisotropy: f32,
    pub coat_ior: f32,
    pub coat_darkening: f32,
    pub fuzz_weight: f32,
    pub fuzz_color: Vec3,
    pub fuzz_roughness: f32,
    pub thin_film_weight: f32,
    /// In micrometres.
    pub thin_film_thickness: f32,
    pub thin_film_ior: f32,
    pub thin_walled: bool,
    pub opacity: f32,
}

impl Params {
    /// The specification's default material with base colour `base_color`.
    pub fn of(m: &OpenPbr, base_color: Vec3) -> Params {
        Params::read(m, base_color, |s| s.value, |c| c.value)
    }

    /// `m`'s parameters at hit `sp`: each texture read at its coordinates.
    pub fn at(scene: &Scene, m: &OpenPbr, base_color: Vec3, sp: &SurfacePoint) -> Params {
        let scalar = |s: &Scalar| match &s.texture {
            None => s.value,
            Some((slot, channel)) => {
                let c = scene.images[slot.image as usize].sample_slot(slot, sp.uv);
                s.value
                    * match channel {
                        Channel::R => c.x,
                        Channel::G => c.y,
                        Channel::B => c.z,
                        Channel::A => c.w,
                    }
            }
        };
        let color = |c: &Color| match &c.texture {
            None => c.value,
            Some(slot) => {
                let t = scene.images[slot.image as usize].sample_slot(slot, sp.uv);
                c.value * Vec3::new(t.x, t.y, t.z)
            }
        };
        Params::read(m, base_color, scalar, color)
    }

    fn read(
        m: &OpenPbr,
        base_color: Vec3,
        scalar: impl Fn(&Scalar) -> f32,
        color: impl Fn(&Color) -> Vec3,
    ) -> Params {
        let unit = |s: &Scalar| finite_or(scalar(s), 0.0).clamp(0.0, 1.0);
        let ior = |s: &Scalar| finite_or(scalar(s), 1.5).clamp(1.0 / 3.0, 3.0);
        let rgb = |c: &Color| {
            let v = color(c);
            if v.is_finite() {
                v.clamp(Vec3::ZERO, Vec3::ONE)
            } else {
                Vec3::ZERO
            }
        };
        let depth = finite_or(scalar(&m.transmission_depth), 0.0);
        Params {
            base_weight: unit(&m.base_weight),
            base_color: base_color.clamp(Vec3::ZERO, Vec3::ONE),
            base_metalness: unit(&m.base_metalness),
            base_diffuse_roughness: unit(&m.base_diffuse_roughness),
            specular_weight: finite_or(scalar(&m.specular_weight), 1.0).max(0.0),
            specular_color: rgb(&m.specular_color),
            specular_roughness: unit(&m.specular_roughness),
            specular_roughness_anisotropy: unit(&m.specular_roughness_anisotropy),
            specular_ior: ior(&m.specular_ior),
            transmission_weight: unit(&m.transmission_weight),
            transmission_tint: if depth > 0.0 {
                Vec3::ONE
            } else {
                rgb(&m.transmission_color)
            },
            subsurface_weight: unit(&m.subsurface_weight),
            subsurface_color: rgb(&m.subsurface_color),
            subsurface_radius: {
                let r = finite_or(scalar(&m.subsurface_radius), 0.0).max(0.0)
                    * color(&m.subsurface_radius_scale);
                if r.is_finite() {
                    r.max(Vec3::ZERO)
                } else {
                    Vec3::ZERO
                }
            },
            subsurface_scatter_anisotropy: finite_or(scalar(&m.subsurface_scatter_anisotropy), 0.0)
                .clamp(-1.0, 1.0),
            subsurface_walk: false,
            coat_weight: unit(&m.coat_weight),
            coat_color: rgb(&m.coat_color),
            coat_roughness: unit(&m.coat_roughness),
            coat_roughness_anisotropy: unit(&m.coat_roughness_anisotropy),
            coat_ior: ior(&m.coat_ior),
            coat_darkening: unit(&m.coat_darkening),
            fuzz_weight: unit(&m.fuzz_weight),
            fuzz_color: rgb(&m.fuzz_color),
            fuzz_roughness: unit(&m.fuzz_roughness),
            thin_film_weight: unit(&m.thin_film_weight),
            thin_film_thickness: finite_or(scalar(&m.thin_film_thickness), 0.0).clamp(0.0, 100.0),
            thin_film_ior: ior(&m.thin_film_ior),
            thin_walled: m.geometry_thin_walled,
            opacity: unit(&m.geometry_opacity),
        }
    }
}

/// The dielectric's index at wavelength `nm` where OpenPBR's dispersion is on: Cauchy's
/// `A + B / λ²` through `n_d` at the d line (587.6 nm) with Abbe number
/// `abbe / scale` (the specification's parametrisation); `n_d` where `scale` is 0.
pub fn dispersed_ior(n_d: f32, abbe: f32, scale: f32, nm: f32) -> f32 {
    // The Fraunhofer C, d and F lines.
    const LAMBDA_C: f32 = 656.3;
    const LAMBDA_D: f32 = 587.6;
    const LAMBDA_F: f32 = 486.1;
    if scale.is_nan() || scale <= 0.0 || !abbe.is_finite() {
        return n_d;
    }
    // Below an Abbe number of 1 no real dielectric disperses: the bound keeps B finite.
    let v = (abbe / scale).max(1.0);
    let b = (n_d - 1.0) / (v * (1.0 / (LAMBDA_F * LAMBDA_F) - 1.0 / (LAMBDA_C * LAMBDA_C)));
    let a = n_d - b / (LAMBDA_D * LAMBDA_D);
    a + b / (nm * nm)
}

impl Params {
    /// These parameters for light of one colour channel (red, green or blue, at the
    /// thin film's wavelengths) where `m` disperses: `specular_ior` that channel's.
    pub fn for_channel(mut self, m: &OpenPbr, channel: usize) -> Params {
        let nm = crate::render::bsdf::thin_film::WAVELENGTHS[channel.min(2)];
        self.specular_ior = dispersed_ior(
            self.specular_ior,
            m.transmission_dispersion_abbe_number.value,
            m.transmission_dispersion_scale.value,
            nm,
        )
        .clamp(1.0 / 3.0, 3.0);
        self
    }
}

fn finite_or(v: f32, or: f32) -> f32 {
    if v.is_finite() { v } else { or }
}

/// The index of a dielectric whose reflectance at normal incidence is `weight` times
/// that of index `eta` (OpenPBR's `specular_weight`): above 1 it brightens, 0 removes
/// the reflection (and the index contrast) altogether.
pub fn weighted_ior(eta: f32, weight: f32) -> f32 {
    if weight == 1.0 {
        return eta;
    }
    let inside = eta < 1.0;
    let e = if inside { 1.0 / eta } else { eta };
    let f0 = ((e - 1.0) / (e + 1.0)).powi(2);
    let s = (weight * f0).clamp(0.0, 0.99999).sqrt();
    let e = (1.0 + s) / (1.0 - s);
    if inside { 1.0 / e } else { e }
}
