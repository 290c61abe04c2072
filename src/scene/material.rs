//! Surface materials of the 2014 format (report section 5.2.2).

use super::OpenPbr;
use crate::math::Vec3;

/// A material of the 2014 format, as the classic model shades it: factors that weight the
/// surface colour, white diffuse light, highlights and child rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name the scene file gives the material, by which shapes refer to it.
    pub name: String,
    /// Base colour, 0..1 per channel (the file gives 0..255). Ignored under a texture.
    pub color: Vec3,
    /// Weight of the surface colour in a hit's classic mix (in the whitted reading, Ka's
    /// share of the colour).
    pub ambient: f32,
    /// Weight of the white diffuse term (in the whitted reading, kd).
    pub diffuse: f32,
    /// Strength of each light's highlight (ks).
    pub specular: f32,
    /// Phong exponent of the highlight, over `R.V`.
    pub shininess: f32,
    /// Refractive index of the medium inside the surface.
    pub ior: f32,
    /// Intensity factor of the mirror child ray.
    pub reflect: f32,
    /// Intensity factor of the refracted child ray.
    pub refract: f32,
    /// Transparent surfaces cast no shadows.
    pub transparent: bool,
    /// Index into `Scene::textures`.
    pub texture: Option<u32>,
}

impl Material {
    /// A plain matte white, for shapes that name no material.
    pub fn default_white() -> Material {
        Material {
            name: "default".into(),
            color: Vec3::ONE,
            ambient: 1.0,
            diffuse: 1.0,
            specular: 0.0,
            shininess: 1.0,
            ior: 1.0,
            reflect: 0.0,
            refract: 0.0,
            transparent: false,
            texture: None,
        }
    }
}

/// The physically based Whitted terms of a material (SPEC 4.3). Colours are linear RGB.
///
/// `Scene::surfaces[i]` belongs to `Scene::materials[i]`; a material without one (the
/// 2014 files) gets [`Surface::from_classic`] when rendered with the whitted model.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Where the albedo C comes from.
    pub albedo: Albedo,
    /// Scales the albedo in the diffuse term (kd).
    pub diffuse: f32,
    /// Ka: multiplied by the scene's ambient light.
    pub ambient: Vec3,
    /// Ks: the highlight colour.
    pub specular: Vec3,
    /// Ns: the highlight exponent.
    pub shininess: f32,
    /// Phong or Blinn-Phong form of the highlight term.
    pub highlight: Highlight,
    /// Scale the highlight so Ns changes its width, not the scene's brightness.
    pub normalized: bool,
    /// Le: radiance the surface emits (an emissive mesh is also an area light).
    pub emission: Vec3,
    /// R: mirror reflectance (with Fresnel off), or the tint of the Fresnel reflection.
    pub reflection: Vec3,
    /// T: transmission filter colour (Tf); zero for opaque surfaces.
    pub transmission: Vec3,
    /// Index of refraction of the medium inside.
    pub ior: f32,
    /// Reflect F(cos, ior) and transmit (1 - F) T instead of fixed R and T.
    pub fresnel: bool,
    /// Beer absorption per unit length inside the medium.
    pub absorption: Vec3,
    /// Whether lights shade it at all (`illum 0` shows the colour only).
    pub lit: bool,
    /// Alpha cut-out: rays pass where the map's value is below 1/2.
    pub alpha_map: Option<TextureSlot>,
    /// A tangent-space normal map (`norm`).
    pub normal_map: Option<TextureSlot>,
    /// Images multiplying `specular`, `ambient` and `emission` (MTL `map_Ks`,
    /// `map_Ka`, `map_Ke`; colour maps, decoded from sRGB).
    pub specular_map: Option<TextureSlot>,
    /// See `specular_map`: multiplies `ambient` (MTL `map_Ka`).
    pub ambient_map: Option<TextureSlot>,
    /// See `specular_map`: multiplies `emission` (MTL `map_Ke`).
    pub emission_map: Option<TextureSlot>,
    /// Where the alpha map cuts: rays pass where its value is below this.
    pub alpha_cutoff: f32,
    /// Scales the normal map's tangential components (glTF `normalTexture.scale`).
    pub normal_scale: f32,
    /// The OpenPBR Surface parameters of a physically based material: where present,
    /// its BSDF replaces the Phong terms (`diffuse`, `specular`, `shininess`,
    /// `highlight`, `reflection`, `transmission`, `ior`, `fresnel`, `absorption`);
    /// `albedo` is its `base_color`.
    pub openpbr: Option<Box<OpenPbr>>,
}

/// The albedo of a surface.
#[derive(Clone, Debug, PartialEq)]
pub enum Albedo {
    /// A constant colour, linear RGB.
    Color(Vec3),
    /// An image read at the hit's texture coordinates, times a tint.
    Image {
        /// The image and how texture coordinates map onto it.
        slot: TextureSlot,
        /// Linear RGB factor applied to the image's colour.
        tint: Vec3,
    },
    /// A solid checker in world space: cubes of side `scale` alternate `a` and `b`.
    Checker {
        /// Colour of the cells whose integer coordinates sum to an even number.
        a: Vec3,
        /// Colour of the other cells.
        b: Vec3,
        /// Side of a cell in world units.
        scale: f32,
    },
    /// The 2014 material colour or texture, with the 2014 mapping, decoded from sRGB.
    Classic,
}

/// An image (an index into `Scene::images`) with its texture-coordinate transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index into `Scene::images`.
    pub image: u32,
    /// `uv * scale + offset` is what is looked up (MTL `-s`, `-o`).
    pub scale: [f32; 2],
    /// Added to the scaled (or transformed) texture coordinates (MTL `-o`).
    pub offset: [f32; 2],
    /// Clamp to the edge instead of repeating (MTL `-clamp on`).
    pub clamp: bool,
    /// A full 2 x 2 matrix, rows `[[a, b], [c, d]]`, in place of `scale` where the
    /// transform rotates (glTF's KHR_texture_transform): `(a u + b v, c u + d v) +
    /// offset` is looked up.
    pub matrix: Option<[[f32; 2]; 2]>,
}

impl TextureSlot {
    /// Image `image` read as is: unit scale, no offset, repeating, no matrix.
    pub fn new(image: u32) -> TextureSlot {
        TextureSlot {
            image,
            scale: [1.0, 1.0],
            offset: [0.0, 0.0],
            clamp: false,
            matrix: None,
        }
    }
}

/// The form of the highlight term s(N, L, V).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Highlight {
    /// `max(0, R.V)^Ns`.
    #[default]
    Phong,
    /// `max(0, N.H)^Ns`.
    BlinnPhong,
}

impl Default for Surface {
    /// A matte white.
    fn default() -> Surface {
        Surface {
            albedo: Albedo::Color(Vec3::splat(0.8)),
            diffuse: 1.0,
            ambient: Vec3::ZERO,
            specular: Vec3::ZERO,
            shininess: 1.0,
            highlight: Highlight::Phong,
            normalized: false,
            emission: Vec3::ZERO,
            reflection: Vec3::ZERO,
            transmission: Vec3::ZERO,
            ior: 1.0,
            fresnel: false,
            absorption: Vec3::ZERO,
            lit: true,
            alpha_map: None,
            normal_map: None,
            specular_map: None,
            ambient_map: None,
            emission_map: None,
            alpha_cutoff: 0.5,
            normal_scale: 1.0,
            openpbr: None,
        }
    }
}

impl Surface {
    /// The physically based reading of a 2014 material: its colour (or texture) as the
    /// albedo with the diffuse factor, highlights of strength ks, and its reflect and
    /// refract ratios as mirror reflectance and transmission (no Fresnel: the 2014 files
    /// chose those ratios themselves). The 2014 ambient factor multiplies the colour.
    pub fn from_classic(m: &Material) -> Surface {
        let color = srgb_to_linear(m.color);
        Surface {
            albedo: Albedo::Classic,
            diffuse: m.diffuse.clamp(0.0, 1.0),
            ambient: color * m.ambient.clamp(0.0, 1.0),
            specular: Vec3::splat(m.specular.clamp(0.0, 1.0)),
            shininess: m.shininess.max(0.0),
            reflection: Vec3::splat(m.reflect.clamp(0.0, 1.0)),
            transmission: Vec3::splat(m.refract.clamp(0.0, 1.0)),
            ior: m.ior,
            ..Surface::default()
        }
    }

    /// Every image slot the surface reads (its albedo, maps and OpenPBR textures): what
    /// a reader that moves a scene's images into another's rebases, in one place.
    pub fn image_slots_mut(&mut self) -> impl Iterator<Item = &mut TextureSlot> {
        let albedo = match &mut self.albedo {
            Albedo::Image { slot, .. } => Some(slot),
            _ => None,
        };
        [
            albedo,
            self.alpha_map.as_mut(),
            self.normal_map.as_mut(),
            self.specular_map.as_mut(),
            self.ambient_map.as_mut(),
            self.emission_map.as_mut(),
        ]
        .into_iter()
        .flatten()
        .chain(self.openpbr.iter_mut().flat_map(|p| p.texture_slots_mut()))
    }

    /// The surface as the integrators take it: an OpenPBR material's `transmission` and
    /// `ior` are what it lets through to shadow rays (its transmission weight times its
    /// colour, white where a volume colours the light instead) and its
    /// `specular_ior`, so that shadow rays, the albedo pass and the lanes' test read
    /// every surface alike.
    pub fn resolved(&self) -> Surface {
        let mut s = self.clone();
        if let Some(p) = &self.openpbr {
            let tint = if p.transmission_depth.value > 0.0 {
                Vec3::ONE
            } else {
                p.transmission_color.value
            };
            // Light passes where the surface is absent, or present and transmitting.
            let present = p.geometry_opacity.value.clamp(0.0, 1.0);
            s.transmission = tint * (p.transmission_weight.value.clamp(0.0, 1.0) * present)
                + Vec3::splat(1.0 - present);
            s.ior = p.specular_ior.value;
        }
        s
    }

    /// Whether light passes through: such surfaces tint shadows instead of casting them.
    pub fn is_transmissive(&self) -> bool {
        self.transmission.max_element() > 0.0
    }

    /// Whether a shadow ray crosses it unchanged: it lets all light through (white
    /// transmission) and cuts nothing out, so shadow rays need not find it at all.
    pub fn is_clear_to_shadows(&self) -> bool {
        self.transmission == Vec3::ONE && self.alpha_map.is_none()
    }

    /// Whether shading reads a hit's texture coordinates (an image albedo or any map):
    /// hits on other surfaces skip computing them.
    pub fn reads_texture_coords(&self) -> bool {
        matches!(self.albedo, Albedo::Image { .. })
            || self.alpha_map.is_some()
            || self.normal_map.is_some()
            || self.specular_map.is_some()
            || self.ambient_map.is_some()
            || self.emission_map.is_some()
            || self.openpbr.as_ref().is_some_and(|m| m.reads_textures())
    }
}

/// The sRGB transfer curve undone (IEC 61966-2-1), per channel.
pub fn srgb_to_linear(c: Vec3) -> Vec3 {
    Vec3::from_array(c.to_array().map(srgb_channel_to_linear))
}

/// The sRGB curve (IEC 61966-2-1), per channel, for 0..1 values.
pub fn linear_to_srgb(c: Vec3) -> Vec3 {
    Vec3::from_array(c.to_array().map(|v| {
        if v <= 0.003_130_8 {
            v * 12.92
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    }))
}

/// One channel of [`srgb_to_linear`].
pub fn srgb_channel_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_coordinates_are_read_by_an_image_albedo_and_by_every_map() {
        assert!(!Surface::default().reads_texture_coords());
        let checker = Surface {
            albedo: Albedo::Checker {
                a: Vec3::ZERO,
                b: Vec3::ONE,
                scale: 1.0,
            },
            ..Surface::default()
        };
        assert!(!checker.reads_texture_coords());
        let slot = Some(TextureSlot::new(0));
        let image = Surface {
            albedo: Albedo::Image {
                slot: TextureSlot::new(0),
                tint: Vec3::ONE,
            },
            ..Surface::default()
        };
        assert!(image.reads_texture_coords());
        for set in [
            |s: &mut Surface, m| s.alpha_map = m,
            |s: &mut Surface, m| s.normal_map = m,
            |s: &mut Surface, m| s.specular_map = m,
            |s: &mut Surface, m| s.ambient_map = m,
            |s: &mut Surface, m| s.emission_map = m,
        ] {
            let mut s = Surface::default();
            set(&mut s, slot);
            assert!(s.reads_texture_coords());
        }
    }
}
