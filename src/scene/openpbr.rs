//! OpenPBR Surface 1.1 (Academy Software Foundation): the parameters of Prism's one
//! physically based material, named as the specification names them, with its
//! defaults. Every reader that describes a physical surface (glTF, the scene file's
//! `type = "openpbr"`, MaterialX) fills one; the BSDF is resolved from it at each hit
//! (`render::bsdf`).
//!
//! Three of the specification's parameters live on the [`Surface`](super::Surface)
//! that carries these, because every model reads them: `base_color` is the surface's
//! albedo (constant, image or checker, times vertex colours), the emission
//! (`emission_luminance × emission_color`) its `emission`, a cut-out (glTF's alpha
//! mask) its alpha map and `geometry_normal` its normal map. A fractional presence is
//! `geometry_opacity` here: the BSDF lets the rest of the light straight through.

use super::TextureSlot;
use crate::math::Vec3;

/// Which of a texel's channels a scalar parameter reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
    /// Alpha.
    A,
}

/// A scalar parameter: a constant, times a texture's channel where one is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scalar {
    /// The value, or the texture's factor.
    pub value: f32,
    /// An image and the channel of it that multiplies `value`.
    pub texture: Option<(TextureSlot, Channel)>,
}

impl Scalar {
    /// A constant.
    pub const fn constant(value: f32) -> Scalar {
        Scalar {
            value,
            texture: None,
        }
    }
}

/// A colour parameter (linear RGB): a constant, times a texture's RGB where one is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color {
    /// The value, or the texture's factor.
    pub value: Vec3,
    /// An image whose RGB multiplies `value`.
    pub texture: Option<TextureSlot>,
}

impl Color {
    /// A constant.
    pub const fn constant(value: Vec3) -> Color {
        Color {
            value,
            texture: None,
        }
    }
}

/// The OpenPBR Surface parameters that shape the BSDF (the specification's names; its
/// ranges are enforced when the BSDF is resolved, so a texture cannot leave them).
#[derive(Clone, Debug, PartialEq)]
pub struct OpenPbr {
    /// Weight of the base's diffuse (and subsurface) albedo.
    pub base_weight: Scalar,
    /// Oren-Nayar roughness of the diffuse base, 0 (Lambert) to 1.
    pub base_diffuse_roughness: Scalar,
    /// Mix from the dielectric base (0) to a metal (1).
    pub base_metalness: Scalar,
    /// Scales the dielectric's Fresnel reflectance (and the metal's).
    pub specular_weight: Scalar,
    /// Tint of the dielectric's reflection; a metal's edge colour (F82).
    pub specular_color: Color,
    /// Perceptual roughness of the specular layer, 0 (mirror) to 1.
    pub specular_roughness: Scalar,
    /// Anisotropy of that roughness along the tangent, 0 to 1.
    pub specular_roughness_anisotropy: Scalar,
    /// Index of refraction of the dielectric base.
    pub specular_ior: Scalar,
    /// Share of the dielectric base that transmits instead of scattering diffusely.
    pub transmission_weight: Scalar,
    /// Colour the transmitted light takes: at the surface, or at `transmission_depth`
    /// inside a volume.
    pub transmission_color: Color,
    /// Distance at which light inside has taken `transmission_color` (0: the colour
    /// tints the surface, no volume).
    pub transmission_depth: Scalar,
    /// Single-scattering albedo of the volume inside (read, not yet scattered: Prism's
    /// volumes absorb).
    pub transmission_scatter: Color,
    /// Phase-function anisotropy of that scattering.
    pub transmission_scatter_anisotropy: Scalar,
    /// Dispersion: 0 none, 1 the Abbe number as given.
    pub transmission_dispersion_scale: Scalar,
    /// Abbe number of the dielectric.
    pub transmission_dispersion_abbe_number: Scalar,
    /// Share of the dielectric base that scatters below the surface.
    pub subsurface_weight: Scalar,
    /// Albedo of that scattering.
    pub subsurface_color: Color,
    /// Mean free path, scaled per channel by `subsurface_radius_scale`.
    pub subsurface_radius: Scalar,
    /// Per-channel factor of `subsurface_radius`.
    pub subsurface_radius_scale: Color,
    /// Phase-function anisotropy below the surface.
    pub subsurface_scatter_anisotropy: Scalar,
    /// Presence of the clear coat, 0 to 1.
    pub coat_weight: Scalar,
    /// Colour the coat absorbs toward (white: clear).
    pub coat_color: Color,
    /// Perceptual roughness of the coat.
    pub coat_roughness: Scalar,
    /// Anisotropy of the coat's roughness.
    pub coat_roughness_anisotropy: Scalar,
    /// Index of refraction of the coat.
    pub coat_ior: Scalar,
    /// How much the coat darkens the base by trapping light in it, 0 to 1.
    pub coat_darkening: Scalar,
    /// Presence of the fuzz (sheen) layer.
    pub fuzz_weight: Scalar,
    /// Colour of the fuzz.
    pub fuzz_color: Color,
    /// Roughness of the fuzz's fibres.
    pub fuzz_roughness: Scalar,
    /// Presence of the thin film on the specular layer.
    pub thin_film_weight: Scalar,
    /// Thickness of the thin film in micrometres.
    pub thin_film_thickness: Scalar,
    /// Index of refraction of the thin film.
    pub thin_film_ior: Scalar,
    /// A thin shell (a leaf, a bubble) instead of the boundary of a solid.
    pub geometry_thin_walled: bool,
    /// Presence of the surface, 0 to 1: where below 1, light passes straight through
    /// the rest of the time.
    pub geometry_opacity: Scalar,
    /// A tangent-space normal map of the coat, and its scale.
    pub geometry_coat_normal: Option<(TextureSlot, f32)>,
    /// Rotation of the anisotropy's tangent about the normal, in turns (0 to 1): the
    /// direction the specification's `geometry_tangent` gives, as glTF gives it.
    pub tangent_rotation: f32,
}

impl Default for OpenPbr {
    /// The specification's defaults: a grey plastic of roughness 0.3 and IOR 1.5.
    fn default() -> OpenPbr {
        let s = Scalar::constant;
        let c = |v: f32| Color::constant(Vec3::splat(v));
        OpenPbr {
            base_weight: s(1.0),
            base_diffuse_roughness: s(0.0),
            base_metalness: s(0.0),
            specular_weight: s(1.0),
            specular_color: c(1.0),
            specular_roughness: s(0.3),
            specular_roughness_anisotropy: s(0.0),
            specular_ior: s(1.5),
            transmission_weight: s(0.0),
            transmission_color: c(1.0),
            transmission_depth: s(0.0),
            transmission_scatter: c(0.0),
            transmission_scatter_anisotropy: s(0.0),
            transmission_dispersion_scale: s(0.0),
            transmission_dispersion_abbe_number: s(20.0),
            subsurface_weight: s(0.0),
            subsurface_color: c(0.8),
            subsurface_radius: s(1.0),
            subsurface_radius_scale: Color::constant(Vec3::new(1.0, 0.5, 0.25)),
            subsurface_scatter_anisotropy: s(0.0),
            coat_weight: s(0.0),
            coat_color: c(1.0),
            coat_roughness: s(0.0),
            coat_roughness_anisotropy: s(0.0),
            coat_ior: s(1.6),
            coat_darkening: s(1.0),
            fuzz_weight: s(0.0),
            fuzz_color: c(1.0),
            fuzz_roughness: s(0.5),
            thin_film_weight: s(0.0),
            thin_film_thickness: s(0.5),
            thin_film_ior: s(1.4),
            geometry_thin_walled: false,
            geometry_opacity: s(1.0),
            geometry_coat_normal: None,
            tangent_rotation: 0.0,
        }
    }
}

/// The specification's default base colour (`base_color`), a light grey.
pub const DEFAULT_BASE_COLOR: Vec3 = Vec3::splat(0.8);

/// Calls `$with` with the scalar parameters' names, then the colour parameters': the
/// one list every walk over the textures reads, so a new parameter cannot be missed.
macro_rules! textured_fields {
    ($with:ident) => {
        $with!(
            [
                base_weight,
                base_diffuse_roughness,
                base_metalness,
                specular_weight,
                specular_roughness,
                specular_roughness_anisotropy,
                specular_ior,
                transmission_weight,
                transmission_depth,
                transmission_scatter_anisotropy,
                transmission_dispersion_scale,
                transmission_dispersion_abbe_number,
                subsurface_weight,
                subsurface_radius,
                subsurface_scatter_anisotropy,
                coat_weight,
                coat_roughness,
                coat_roughness_anisotropy,
                coat_ior,
                coat_darkening,
                fuzz_weight,
                fuzz_roughness,
                thin_film_weight,
                thin_film_thickness,
                thin_film_ior,
                geometry_opacity
            ],
            [
                specular_color,
                transmission_color,
                transmission_scatter,
                subsurface_color,
                subsurface_radius_scale,
                coat_color,
                fuzz_color
            ]
        )
    };
}

impl OpenPbr {
    /// Every texture slot the parameters read, for readers that move a scene's images
    /// (a scene file's merge).
    pub fn texture_slots_mut(&mut self) -> impl Iterator<Item = &mut TextureSlot> {
        macro_rules! slots {
            ([$($s:ident),*], [$($c:ident),*]) => {
                [$(self.$s.texture.as_mut().map(|(slot, _)| slot)),*]
                    .into_iter()
                    .chain([$(self.$c.texture.as_mut()),*])
                    .chain([self.geometry_coat_normal.as_mut().map(|(slot, _)| slot)])
                    .flatten()
            };
        }
        textured_fields!(slots)
    }

    /// The scalar parameter the specification calls `name`.
    pub fn scalar_mut(&mut self, name: &str) -> Option<&mut Scalar> {
        macro_rules! find {
            ([$($s:ident),*], [$($c:ident),*]) => {
                match name {
                    $(stringify!($s) => Some(&mut self.$s),)*
                    _ => None,
                }
            };
        }
        textured_fields!(find)
    }

    /// The colour parameter the specification calls `name`.
    pub fn color_mut(&mut self, name: &str) -> Option<&mut Color> {
        macro_rules! find {
            ([$($s:ident),*], [$($c:ident),*]) => {
                match name {
                    $(stringify!($c) => Some(&mut self.$c),)*
                    _ => None,
                }
            };
        }
        textured_fields!(find)
    }

    /// Whether light crossing it splits by colour (`transmission_dispersion_scale`
    /// above 0 on a surface that transmits).
    pub fn disperses(&self) -> bool {
        self.transmission_dispersion_scale.value > 0.0
            && (self.transmission_weight.value > 0.0 || self.transmission_weight.texture.is_some())
    }

    /// Beer's absorption per unit length inside the volume (`Surface::absorption`):
    /// `transmission_color` is what remains after `transmission_depth`. Zero without a
    /// depth or with a textured colour (a volume has one colour).
    pub fn absorption(&self) -> Vec3 {
        let depth = self.transmission_depth.value;
        if !(depth > 0.0 && depth.is_finite()) || self.transmission_color.texture.is_some() {
            return Vec3::ZERO;
        }
        let c = self.transmission_color.value.max(Vec3::splat(1e-6));
        -Vec3::new(c.x.ln(), c.y.ln(), c.z.ln()) / depth
    }

    /// Whether any parameter reads a texture: a hit on it needs texture coordinates.
    pub fn reads_textures(&self) -> bool {
        macro_rules! any {
            ([$($s:ident),*], [$($c:ident),*]) => {
                false $(|| self.$s.texture.is_some())* $(|| self.$c.texture.is_some())*
                    || self.geometry_coat_normal.is_some()
            };
        }
        textured_fields!(any)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_texture_is_found_for_rebasing() {
        let mut m = OpenPbr::default();
        assert!(!m.reads_textures());
        m.coat_roughness.texture = Some((TextureSlot::new(3), Channel::G));
        m.fuzz_color.texture = Some(TextureSlot::new(4));
        m.geometry_coat_normal = Some((TextureSlot::new(5), 1.0));
        assert!(m.reads_textures());
        for slot in m.texture_slots_mut() {
            slot.image += 10;
        }
        assert_eq!(m.coat_roughness.texture.unwrap().0.image, 13);
        assert_eq!(m.fuzz_color.texture.unwrap().image, 14);
        assert_eq!(m.geometry_coat_normal.unwrap().0.image, 15);
    }
}
