//! `[[material]]` (and inline `material = { ... }`): the whitted terms of SPEC 4.3 as a
//! [`Surface`], and a classic [`Material`] that looks alike under `--integrator classic`.

use super::images::ImageCache;
use super::raw::{RawMaterial, RawTexture};
use super::source::Source;
use super::values::Color;
use crate::error::Result;
use crate::math::Vec3;
use crate::scene::material::linear_to_srgb;
use crate::scene::{Albedo, Highlight, Material, Surface, TextureSlot};
use toml::Spanned;

/// Albedo when a material gives no colour: a light grey, as [`Surface::default`].
pub const DEFAULT_COLOR: Vec3 = Vec3::splat(0.8);
/// Highlight exponent when `shininess` is not given: a moderately tight highlight.
pub const DEFAULT_SHININESS: f32 = 32.0;

/// Both readings of one material.
pub struct BuiltMaterial {
    pub material: Material,
    pub surface: Surface,
}

pub fn build(
    source: &Source,
    raw: &RawMaterial,
    name: String,
    images: &mut crate::scene::SceneBuilder,
    cache: &mut ImageCache,
) -> Result<BuiltMaterial> {
    if let Some(file) = &raw.file {
        return super::openpbr::from_materialx(source, raw, file, name, images);
    }
    match &raw.kind {
        Some(kind) if kind.get_ref() == "openpbr" => {
            return super::openpbr::build(source, raw, name, images, cache);
        }
        Some(kind) => {
            return Err(source.error(
                kind,
                format!(
                    "expected material type \"openpbr\" (or no type, for the Phong keys), found \"{}\"",
                    kind.get_ref()
                ),
            ));
        }
        None => super::openpbr::no_openpbr_keys(source, raw)?,
    }
    let color = raw.color.as_ref().map(|c| c.get_ref().rgb);
    let (albedo, base) = match &raw.texture {
        None => {
            let c = color.unwrap_or(DEFAULT_COLOR);
            (Albedo::Color(c), c)
        }
        Some(t) => match t.get_ref() {
            RawTexture::Image(file) => {
                let file = Spanned::new(t.span(), file.clone());
                let image = cache.get(source, &file, true, images)?;
                let tint = color.unwrap_or(Vec3::ONE);
                let slot = TextureSlot::new(image);
                (Albedo::Image { slot, tint }, tint * 0.5)
            }
            RawTexture::Checker(c) => {
                if let Some(color) = &raw.color {
                    return Err(source.error(
                        color,
                        "give `color` or a checker `texture`, not both: the checker has its colours",
                    ));
                }
                let scale = c.scale.map_or(1.0, |s| s.f32());
                if scale <= 0.0 {
                    return Err(
                        source.error(t, format!("expected a checker scale > 0, found {scale}"))
                    );
                }
                let (a, b) = (c.checker[0].rgb, c.checker[1].rgb);
                (Albedo::Checker { a, b, scale }, (a + b) * 0.5)
            }
        },
    };
    let non_negative = |v: &Option<Spanned<super::values::Num>>, what: &str, default: f32| match v {
        None => Ok(default),
        Some(n) if n.get_ref().0 >= 0.0 => Ok(n.get_ref().f32()),
        Some(n) => Err(source.error(n, format!("expected {what} >= 0, found {}", n.get_ref().0))),
    };
    let diffuse = non_negative(&raw.diffuse, "diffuse", 1.0)?;
    let shininess = non_negative(&raw.shininess, "shininess", DEFAULT_SHININESS)?;
    let ior = match &raw.ior {
        Some(n) if n.get_ref().0 <= 0.0 => {
            return Err(source.error(n, format!("expected ior > 0, found {}", n.get_ref().0)));
        }
        Some(n) => n.get_ref().f32(),
        None => 1.0,
    };
    let highlight = match &raw.highlight {
        None => Highlight::Phong,
        Some(h) => match h.get_ref().as_str() {
            "phong" => Highlight::Phong,
            "blinn" => Highlight::BlinnPhong,
            other => {
                return Err(source.error(
                    h,
                    format!("expected highlight \"phong\" or \"blinn\", found \"{other}\""),
                ));
            }
        },
    };
    let rgb = |c: &Option<Spanned<Color>>| c.as_ref().map(|c| c.get_ref().rgb);
    // A number is a factor of the material's colour, as POV-Ray's `ambient 0.1`.
    let ambient = match &raw.ambient {
        None => base,
        Some(a) if a.get_ref().number => base * a.get_ref().rgb.x,
        Some(a) => a.get_ref().rgb,
    };
    let fresnel = raw.fresnel.as_ref().is_some_and(|f| *f.get_ref());
    let reflection = rgb(&raw.reflection).unwrap_or(if fresnel { Vec3::ONE } else { Vec3::ZERO });
    let transmission = rgb(&raw.transmission).unwrap_or(Vec3::ZERO);
    let normal_map = match &raw.normal_map {
        None => None,
        Some(file) => Some(TextureSlot::new(cache.get(source, file, false, images)?)),
    };
    let surface = Surface {
        albedo,
        diffuse,
        ambient,
        specular: rgb(&raw.specular).unwrap_or(Vec3::ZERO),
        shininess,
        highlight,
        normalized: raw.normalized.as_ref().is_some_and(|n| *n.get_ref()),
        emission: rgb(&raw.emission).unwrap_or(Vec3::ZERO),
        reflection,
        transmission,
        ior,
        fresnel,
        absorption: rgb(&raw.absorption).unwrap_or(Vec3::ZERO),
        lit: raw.lit.as_ref().is_none_or(|l| *l.get_ref()),
        alpha_map: None,
        normal_map,
        specular_map: None,
        ambient_map: None,
        emission_map: None,
        ..Surface::default()
    };
    let material = classic(
        name,
        &surface,
        base,
        raw.ambient.as_ref().map(|a| *a.get_ref()),
    );
    Ok(BuiltMaterial { material, surface })
}

/// The 2014 terms closest to a whitted material: the colour in display (sRGB) values,
/// the factors as the largest channel of each colour term.
pub(super) fn classic(name: String, s: &Surface, base: Vec3, ambient: Option<Color>) -> Material {
    let unit = |v: f32| v.clamp(0.0, 1.0);
    Material {
        name,
        color: linear_to_srgb(base.clamp(Vec3::ZERO, Vec3::ONE)),
        ambient: match ambient {
            None => 1.0,
            Some(a) if a.number => unit(a.rgb.x),
            Some(a) => unit(a.rgb.max_element()),
        },
        diffuse: unit(s.diffuse),
        specular: unit(s.specular.max_element()),
        shininess: s.shininess,
        ior: s.ior,
        reflect: unit(s.reflection.max_element()),
        refract: unit(s.transmission.max_element()),
        transparent: s.is_transmissive(),
        texture: None,
    }
}
