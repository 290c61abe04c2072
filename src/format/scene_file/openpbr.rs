//! `[[material]] type = "openpbr"`: an OpenPBR Surface material, its parameters named
//! as the specification names them (docs/materials.md), each a number or colour or
//! `{ texture = "file.png", channel = "g", factor = 0.5 }`.

use super::images::ImageCache;
use super::materials::{BuiltMaterial, classic};
use super::raw::RawMaterial;
use super::source::Source;
use super::values::Color as TomlColor;
use crate::error::Result;
use crate::math::Vec3;
use crate::scene::openpbr::{Channel, Color, OpenPbr, Scalar};
use crate::scene::{Albedo, Surface, TextureSlot};
use serde::Deserialize;
use toml::{Spanned, Value};

/// Calls `$with!` with the raw material's OpenPBR fields: scalars with their range,
/// then colours. The one list the reader, the check against mixing and the docs follow.
macro_rules! openpbr_fields {
    ($with:ident) => {
        $with!(
            [
                (base_weight, UNIT),
                (base_diffuse_roughness, UNIT),
                (base_metalness, UNIT),
                (specular_weight, NON_NEGATIVE),
                (specular_roughness, UNIT),
                (specular_roughness_anisotropy, UNIT),
                (specular_ior, IOR),
                (transmission_weight, UNIT),
                (transmission_depth, NON_NEGATIVE),
                (transmission_scatter_anisotropy, SIGNED_UNIT),
                (transmission_dispersion_scale, NON_NEGATIVE),
                (transmission_dispersion_abbe_number, POSITIVE),
                (subsurface_weight, UNIT),
                (subsurface_radius, NON_NEGATIVE),
                (subsurface_scatter_anisotropy, SIGNED_UNIT),
                (coat_weight, UNIT),
                (coat_roughness, UNIT),
                (coat_roughness_anisotropy, UNIT),
                (coat_ior, IOR),
                (coat_darkening, UNIT),
                (fuzz_weight, UNIT),
                (fuzz_roughness, UNIT),
                (thin_film_weight, UNIT),
                (thin_film_thickness, NON_NEGATIVE),
                (thin_film_ior, IOR)
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

/// Allowed ranges, inclusive, and how they read in messages.
type Range = (f32, f32, &'static str);
const UNIT: Range = (0.0, 1.0, "from 0 to 1");
const SIGNED_UNIT: Range = (-1.0, 1.0, "from -1 to 1");
const NON_NEGATIVE: Range = (0.0, f32::MAX, ">= 0");
const POSITIVE: Range = (f32::MIN_POSITIVE, f32::MAX, "> 0");
const IOR: Range = (f32::MIN_POSITIVE, f32::MAX, "> 0");

/// The Phong keys, which an OpenPBR material may not mix in.
fn phong_keys(raw: &RawMaterial) -> [(&'static str, Option<std::ops::Range<usize>>); 15] {
    let at = |s: Option<std::ops::Range<usize>>| s;
    [
        ("color", at(raw.color.as_ref().map(Spanned::span))),
        ("texture", at(raw.texture.as_ref().map(Spanned::span))),
        ("ambient", at(raw.ambient.as_ref().map(Spanned::span))),
        ("diffuse", at(raw.diffuse.as_ref().map(Spanned::span))),
        ("specular", at(raw.specular.as_ref().map(Spanned::span))),
        ("shininess", at(raw.shininess.as_ref().map(Spanned::span))),
        ("highlight", at(raw.highlight.as_ref().map(Spanned::span))),
        ("normalized", at(raw.normalized.as_ref().map(Spanned::span))),
        ("reflection", at(raw.reflection.as_ref().map(Spanned::span))),
        (
            "transmission",
            at(raw.transmission.as_ref().map(Spanned::span)),
        ),
        ("ior", at(raw.ior.as_ref().map(Spanned::span))),
        ("fresnel", at(raw.fresnel.as_ref().map(Spanned::span))),
        ("absorption", at(raw.absorption.as_ref().map(Spanned::span))),
        ("emission", at(raw.emission.as_ref().map(Spanned::span))),
        ("normal_map", at(raw.normal_map.as_ref().map(Spanned::span))),
    ]
}

/// Every OpenPBR key the material gives, with its place.
fn openpbr_keys(raw: &RawMaterial) -> Vec<(&'static str, std::ops::Range<usize>)> {
    let mut keys = Vec::new();
    macro_rules! note {
        ([$(($s:ident, $r:ident)),*], [$($c:ident),*]) => {
            $(if let Some(v) = &raw.$s { keys.push((stringify!($s), v.span())); })*
            $(if let Some(v) = &raw.$c { keys.push((stringify!($c), v.span())); })*
        };
    }
    openpbr_fields!(note);
    for (key, v) in [
        ("base_color", &raw.base_color),
        ("emission_luminance", &raw.emission_luminance),
        ("emission_color", &raw.emission_color),
        ("geometry_opacity", &raw.geometry_opacity),
    ] {
        if let Some(v) = v {
            keys.push((key, v.span()));
        }
    }
    for (key, v) in [
        (
            "geometry_normal",
            raw.geometry_normal.as_ref().map(Spanned::span),
        ),
        (
            "geometry_coat_normal",
            raw.geometry_coat_normal.as_ref().map(Spanned::span),
        ),
        (
            "geometry_thin_walled",
            raw.geometry_thin_walled.as_ref().map(Spanned::span),
        ),
    ] {
        if let Some(span) = v {
            keys.push((key, span));
        }
    }
    keys
}

/// A material without `type` may not use OpenPBR's keys: it says which to add.
pub fn no_openpbr_keys(source: &Source, raw: &RawMaterial) -> Result<()> {
    match openpbr_keys(raw).first() {
        None => Ok(()),
        Some((key, span)) => Err(source.error_at(
            span.clone(),
            format!("`{key}` is an OpenPBR parameter: give the material type = \"openpbr\""),
        )),
    }
}

/// Reads images and checks values for one material.
struct Reader<'a> {
    source: &'a Source,
    images: &'a mut crate::scene::SceneBuilder,
    cache: &'a mut ImageCache,
}

impl Reader<'_> {
    /// An image named at `at` (the table holding `texture = "..."`).
    fn image(&mut self, table: &toml::Table, at: &Spanned<Value>, srgb: bool) -> Result<u32> {
        let Some(Value::String(file)) = table.get("texture") else {
            return Err(self.source.error(
                at,
                "expected a number, a colour, or a table { texture = \"file\", ... }",
            ));
        };
        let file = Spanned::new(at.span(), file.clone());
        self.cache.get(self.source, &file, srgb, self.images)
    }

    fn factor(&self, table: &toml::Table, at: &Spanned<Value>) -> Result<Option<f32>> {
        match table.get("factor") {
            None => Ok(None),
            Some(Value::Float(f)) => Ok(Some(*f as f32)),
            Some(Value::Integer(i)) => Ok(Some(*i as f32)),
            Some(_) => Err(self.source.error(at, "expected `factor` to be a number")),
        }
    }

    fn keys(&self, table: &toml::Table, at: &Spanned<Value>, allowed: &[&str]) -> Result<()> {
        match table.keys().find(|k| !allowed.contains(&k.as_str())) {
            None => Ok(()),
            Some(k) => Err(self.source.error(
                at,
                format!(
                    "unknown key `{k}` in a texture (expected {})",
                    allowed.join(", ")
                ),
            )),
        }
    }

    /// A scalar parameter called `name` in `range`.
    fn scalar(&mut self, name: &str, v: &Spanned<Value>, range: Range) -> Result<Scalar> {
        let check = |x: f32| {
            if x.is_finite() && x >= range.0 && x <= range.1 {
                Ok(x)
            } else {
                Err(self
                    .source
                    .error(v, format!("expected {name} {}, found {x}", range.2)))
            }
        };
        match v.get_ref() {
            Value::Float(f) => Ok(Scalar::constant(check(*f as f32)?)),
            Value::Integer(i) => Ok(Scalar::constant(check(*i as f32)?)),
            Value::Table(t) => {
                self.keys(t, v, &["texture", "channel", "factor"])?;
                let channel = match t.get("channel").map(|c| c.as_str()) {
                    None | Some(Some("r")) => Channel::R,
                    Some(Some("g")) => Channel::G,
                    Some(Some("b")) => Channel::B,
                    Some(Some("a")) => Channel::A,
                    Some(_) => {
                        return Err(self
                            .source
                            .error(v, "expected `channel` \"r\", \"g\", \"b\" or \"a\""));
                    }
                };
                let value = check(self.factor(t, v)?.unwrap_or(1.0))?;
                let image = self.image(t, v, false)?;
                Ok(Scalar {
                    value,
                    texture: Some((TextureSlot::new(image), channel)),
                })
            }
            _ => Err(self.source.error(
                v,
                format!("expected {name} as a number or {{ texture = \"file\", channel = \"r\" }}"),
            )),
        }
    }

    /// A colour parameter: any colour the scene file reads, or a texture table.
    fn color(&mut self, v: &Spanned<Value>) -> Result<Color> {
        match v.get_ref() {
            Value::Table(t) => {
                self.keys(t, v, &["texture", "factor"])?;
                let factor = match t.get("factor") {
                    None => Vec3::ONE,
                    Some(f) => self.plain_color(f, v)?,
                };
                let image = self.image(t, v, true)?;
                Ok(Color {
                    value: factor,
                    texture: Some(TextureSlot::new(image)),
                })
            }
            other => Ok(Color::constant(self.plain_color(other, v)?)),
        }
    }

    fn plain_color(&self, value: &Value, at: &Spanned<Value>) -> Result<Vec3> {
        TomlColor::deserialize(value.clone())
            .map(|c| c.rgb)
            .map_err(|e| self.source.error(at, e.to_string()))
    }
}

/// Builds an OpenPBR material: its `Surface` (base colour as the albedo, emission,
/// cut-out, normal map, the lobes' parameters) and the classic terms alike.
pub fn build(
    source: &Source,
    raw: &RawMaterial,
    name: String,
    images: &mut crate::scene::SceneBuilder,
    cache: &mut ImageCache,
) -> Result<BuiltMaterial> {
    if let Some((key, Some(span))) = phong_keys(raw).into_iter().find(|(_, s)| s.is_some()) {
        return Err(source.error_at(
            span,
            format!(
                "`{key}` is not an OpenPBR parameter (an OpenPBR material names the specification's, e.g. base_color, specular_roughness)"
            ),
        ));
    }
    let mut r = Reader {
        source,
        images,
        cache,
    };
    let mut p = OpenPbr::default();
    macro_rules! read {
        ([$(($s:ident, $range:ident)),*], [$($c:ident),*]) => {
            $(if let Some(v) = &raw.$s {
                p.$s = r.scalar(stringify!($s), v, $range)?;
            })*
            $(if let Some(v) = &raw.$c {
                p.$c = r.color(v)?;
            })*
        };
    }
    openpbr_fields!(read);
    p.geometry_thin_walled = raw
        .geometry_thin_walled
        .as_ref()
        .is_some_and(|b| *b.get_ref());
    if let Some(file) = &raw.geometry_coat_normal {
        p.geometry_coat_normal = Some((
            TextureSlot::new(r.cache.get(source, file, false, r.images)?),
            1.0,
        ));
    }
    let base = match &raw.base_color {
        None => Color::constant(crate::scene::openpbr::DEFAULT_BASE_COLOR),
        Some(v) => r.color(v)?,
    };
    let albedo = match base.texture {
        None => Albedo::Color(base.value),
        Some(slot) => Albedo::Image {
            slot,
            tint: base.value,
        },
    };
    let luminance = match &raw.emission_luminance {
        None => 0.0,
        Some(v) => {
            let s = r.scalar("emission_luminance", v, NON_NEGATIVE)?;
            if s.texture.is_some() {
                return Err(source.error(v, "expected emission_luminance as a number"));
            }
            s.value
        }
    };
    let emission_color = match &raw.emission_color {
        None => Color::constant(Vec3::ONE),
        Some(v) => r.color(v)?,
    };
    // A presence below 1 lets the rest of the light straight through (a map too).
    if let Some(v) = &raw.geometry_opacity {
        p.geometry_opacity = r.scalar("geometry_opacity", v, UNIT)?;
    }
    let normal_map = match &raw.geometry_normal {
        None => None,
        Some(file) => Some(TextureSlot::new(
            r.cache.get(source, file, false, r.images)?,
        )),
    };
    let absorption = p.absorption();
    let surface = Surface {
        albedo,
        ambient: Vec3::ZERO,
        emission: emission_color.value * luminance,
        emission_map: emission_color.texture,
        ior: p.specular_ior.value,
        absorption,
        normal_map,
        openpbr: Some(Box::new(p)),
        ..Surface::default()
    };
    let material = classic(name, &surface, base.value, None);
    Ok(BuiltMaterial { material, surface })
}

/// `[[material]] file = "x.mtlx"`: the MaterialX document's material of this name, or
/// its first; nothing else may be said of it.
pub fn from_materialx(
    source: &Source,
    raw: &RawMaterial,
    file: &Spanned<String>,
    name: String,
    images: &mut crate::scene::SceneBuilder,
) -> Result<BuiltMaterial> {
    let said = phong_keys(raw)
        .into_iter()
        .filter_map(|(k, s)| Some((k, s?)))
        .chain(openpbr_keys(raw))
        .chain(raw.kind.as_ref().map(|k| ("type", k.span())))
        .next();
    if let Some((key, span)) = said {
        return Err(source.error_at(
            span,
            format!(
                "`{key}` goes with a material of its own, not with `file` (a MaterialX document)"
            ),
        ));
    }
    let path = source.resolve(file.get_ref());
    let bytes = crate::util::file::read_regular(&path, 1 << 24)
        .map_err(|e| source.error(file, format!("cannot read {}: {e}", path.display())))?;
    if !crate::format::materialx::is_materialx(&bytes) {
        return Err(source.error(file, "expected a MaterialX document (XML)"));
    }
    let wanted = crate::format::materialx::load(&path, Some(&name))
        .or_else(|_| crate::format::materialx::load(&path, None))?;
    let base = images.image_count();
    for image in wanted.images {
        images.add_image(image);
    }
    let mut surface = wanted.surface;
    for slot in surface.image_slots_mut() {
        slot.image += base;
    }
    let material = crate::scene::Material {
        name,
        ..wanted.material
    };
    Ok(BuiltMaterial { material, surface })
}
