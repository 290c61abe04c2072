//! The scene file as TOML says it, before meaning is given to it: every table denies
//! unknown keys, and every value the loader may complain about keeps its span.

use super::values::{Color, Num, Triple, Vector};
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use std::fmt;
use toml::Spanned;

type S<T> = Option<Spanned<T>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFile {
    #[serde(default)]
    pub include: Vec<Spanned<String>>,
    pub camera: S<RawCamera>,
    #[serde(default)]
    pub object: Vec<Spanned<RawObject>>,
    #[serde(default)]
    pub material: Vec<Spanned<RawMaterial>>,
    #[serde(default)]
    pub light: Vec<Spanned<RawLight>>,
    pub ambient: S<RawAmbient>,
    pub background: S<RawBackground>,
    pub render: S<RawRender>,
    /// Timing of `prism animate`: its types are checked here, its values read by
    /// `anim::file` with the tracks.
    #[allow(dead_code)]
    pub animation: S<RawAnimation>,
    #[serde(default)]
    pub track: Vec<Spanned<RawTrack>>,
}

/// `[animation]`: `frames` or `duration` (seconds), and `fps` (default 24).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
pub struct RawAnimation {
    pub frames: S<i64>,
    pub duration: S<f64>,
    pub fps: S<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawCamera {
    pub projection: S<String>,
    pub view_width: S<Num>,
    pub from: S<Vector>,
    pub at: S<Vector>,
    pub up: S<Vector>,
    pub fov: S<Num>,
    pub fov_axis: S<String>,
    pub aperture: S<Num>,
    pub focus_distance: S<Num>,
    pub focus_on: S<String>,
    /// Lens shift, right and up, in units of the side `fov_axis` names.
    pub shift: S<[Num; 2]>,
    /// Samples per pixel for depth of field; `lens_samples` is its older name.
    #[serde(alias = "lens_samples")]
    pub spp: S<u32>,
    pub cmr: S<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawObject {
    pub name: S<String>,
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    pub material: S<MaterialRef>,
    /// Shadow rays per shading point when the object glows (it is an area light).
    pub samples: S<u32>,
    pub file: S<String>,
    pub center: S<Vector>,
    pub radius: S<Num>,
    pub point: S<Vector>,
    pub normal: S<Vector>,
    pub corner: S<Vector>,
    pub edge1: S<Vector>,
    pub edge2: S<Vector>,
    pub vertices: S<[Vector; 3]>,
    pub min: S<Vector>,
    pub max: S<Vector>,
    pub base: S<Vector>,
    pub top: S<Vector>,
    pub axis: S<Vector>,
    pub height: S<Num>,
    pub capped: S<bool>,
    /// Mesh files: smooth vertex normals where the file has none.
    pub smooth: S<bool>,
    /// Mesh files: the axis the file has up, `"y"` (default) or `"z"` (Blender's).
    pub up_axis: S<String>,
    pub translate: S<Vector>,
    pub rotate: S<Rotations>,
    pub scale: S<Triple>,
    pub matrix: S<[[Num; 4]; 4]>,
    /// Instances: the name of the mesh object they place.
    pub of: S<String>,
    /// Instances: one placement each, a row-major affine 4 x 4 matrix applied before
    /// the object's own transform; or the name of matrices handed over in memory.
    pub transforms: S<Transforms>,
}

/// An instance object's placements: written out, or named (Python's arrays).
pub enum Transforms {
    Listed(Vec<[[Num; 4]; 4]>),
    Named(String),
}

impl<'de> Deserialize<'de> for Transforms {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Transforms;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a list of 4 x 4 matrices")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Transforms, E> {
                Ok(Transforms::Named(v.to_owned()))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Transforms, A::Error> {
                Deserialize::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(Transforms::Listed)
            }
        }
        d.deserialize_any(V)
    }
}

impl RawObject {
    /// The shape keys given, with where each starts: checked against the type's own.
    pub fn shape_keys(&self) -> Vec<(&'static str, std::ops::Range<usize>)> {
        let mut out = Vec::new();
        let mut add = |name, span: Option<std::ops::Range<usize>>| {
            if let Some(s) = span {
                out.push((name, s));
            }
        };
        add("file", self.file.as_ref().map(Spanned::span));
        add("of", self.of.as_ref().map(Spanned::span));
        add("transforms", self.transforms.as_ref().map(Spanned::span));
        add("center", self.center.as_ref().map(Spanned::span));
        add("radius", self.radius.as_ref().map(Spanned::span));
        add("point", self.point.as_ref().map(Spanned::span));
        add("normal", self.normal.as_ref().map(Spanned::span));
        add("corner", self.corner.as_ref().map(Spanned::span));
        add("edge1", self.edge1.as_ref().map(Spanned::span));
        add("edge2", self.edge2.as_ref().map(Spanned::span));
        add("vertices", self.vertices.as_ref().map(Spanned::span));
        add("min", self.min.as_ref().map(Spanned::span));
        add("max", self.max.as_ref().map(Spanned::span));
        add("base", self.base.as_ref().map(Spanned::span));
        add("top", self.top.as_ref().map(Spanned::span));
        add("axis", self.axis.as_ref().map(Spanned::span));
        add("height", self.height.as_ref().map(Spanned::span));
        add("capped", self.capped.as_ref().map(Spanned::span));
        add("smooth", self.smooth.as_ref().map(Spanned::span));
        add("up_axis", self.up_axis.as_ref().map(Spanned::span));
        out
    }
}

/// `material = "NAME"` or `material = { color = ..., ... }`.
pub enum MaterialRef {
    Name(String),
    Inline(Box<RawMaterial>),
}

impl<'de> Deserialize<'de> for MaterialRef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<MaterialRef, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = MaterialRef;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a material name or an inline table of material terms")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<MaterialRef, E> {
                Ok(MaterialRef::Name(v.to_owned()))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<MaterialRef, A::Error> {
                let m = RawMaterial::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(MaterialRef::Inline(Box::new(m)))
            }
        }
        d.deserialize_any(V)
    }
}

/// `rotate = [ax, ay, az, degrees]` or a list of them, applied in order.
pub struct Rotations(pub Vec<[f64; 4]>);

impl<'de> Deserialize<'de> for Rotations {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Rotations, D::Error> {
        /// An element of the outer array: a number (one rotation written flat) or a
        /// whole `[ax, ay, az, degrees]`.
        enum Item {
            Number(f64),
            Rotation([f64; 4]),
        }
        impl<'de> Deserialize<'de> for Item {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Item, D::Error> {
                struct V;
                impl<'de> Visitor<'de> for V {
                    type Value = Item;
                    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                        f.write_str("a number or [ax, ay, az, degrees]")
                    }
                    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Item, E> {
                        self.visit_f64(v as f64)
                    }
                    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Item, E> {
                        Num::deserialize(de::value::F64Deserializer::<E>::new(v))
                            .map(|n| Item::Number(n.0))
                    }
                    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Item, A::Error> {
                        let r =
                            <[Num; 4]>::deserialize(de::value::SeqAccessDeserializer::new(seq))?;
                        Ok(Item::Rotation(r.map(|n| n.0)))
                    }
                }
                d.deserialize_any(V)
            }
        }
        let items = Vec::<Item>::deserialize(d)?;
        let numbers: Vec<f64> = items
            .iter()
            .filter_map(|i| match i {
                Item::Number(n) => Some(*n),
                Item::Rotation(_) => None,
            })
            .collect();
        if numbers.len() == items.len() {
            return match numbers[..] {
                [x, y, z, deg] => Ok(Rotations(vec![[x, y, z, deg]])),
                _ => Err(de::Error::custom(format!(
                    "expected rotate = [ax, ay, az, degrees], found {} numbers",
                    numbers.len()
                ))),
            };
        }
        if !numbers.is_empty() {
            return Err(de::Error::custom(
                "expected [ax, ay, az, degrees] or a list of them, found a mix of numbers and lists",
            ));
        }
        Ok(Rotations(
            items
                .into_iter()
                .filter_map(|i| match i {
                    Item::Rotation(r) => Some(r),
                    Item::Number(_) => None,
                })
                .collect(),
        ))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMaterial {
    pub name: S<String>,
    pub color: S<Color>,
    pub texture: S<RawTexture>,
    pub ambient: S<Color>,
    pub diffuse: S<Num>,
    pub specular: S<Color>,
    pub shininess: S<Num>,
    pub highlight: S<String>,
    pub normalized: S<bool>,
    pub reflection: S<Color>,
    pub transmission: S<Color>,
    pub ior: S<Num>,
    pub fresnel: S<bool>,
    pub absorption: S<Color>,
    pub emission: S<Color>,
    pub normal_map: S<String>,
    pub lit: S<bool>,
    /// `"openpbr"` for an OpenPBR Surface material, whose keys follow.
    #[serde(rename = "type")]
    pub kind: S<String>,
    /// A MaterialX document whose material (the one of this name, else its first) this is.
    pub file: S<String>,
    pub base_weight: S<toml::Value>,
    pub base_diffuse_roughness: S<toml::Value>,
    pub base_metalness: S<toml::Value>,
    pub specular_weight: S<toml::Value>,
    pub specular_roughness: S<toml::Value>,
    pub specular_roughness_anisotropy: S<toml::Value>,
    pub specular_ior: S<toml::Value>,
    pub transmission_weight: S<toml::Value>,
    pub transmission_depth: S<toml::Value>,
    pub transmission_scatter_anisotropy: S<toml::Value>,
    pub transmission_dispersion_scale: S<toml::Value>,
    pub transmission_dispersion_abbe_number: S<toml::Value>,
    pub subsurface_weight: S<toml::Value>,
    pub subsurface_radius: S<toml::Value>,
    pub subsurface_scatter_anisotropy: S<toml::Value>,
    pub coat_weight: S<toml::Value>,
    pub coat_roughness: S<toml::Value>,
    pub coat_roughness_anisotropy: S<toml::Value>,
    pub coat_ior: S<toml::Value>,
    pub coat_darkening: S<toml::Value>,
    pub fuzz_weight: S<toml::Value>,
    pub fuzz_roughness: S<toml::Value>,
    pub thin_film_weight: S<toml::Value>,
    pub thin_film_thickness: S<toml::Value>,
    pub thin_film_ior: S<toml::Value>,
    pub emission_luminance: S<toml::Value>,
    pub geometry_opacity: S<toml::Value>,
    pub base_color: S<toml::Value>,
    pub specular_color: S<toml::Value>,
    pub transmission_color: S<toml::Value>,
    pub transmission_scatter: S<toml::Value>,
    pub subsurface_color: S<toml::Value>,
    pub subsurface_radius_scale: S<toml::Value>,
    pub coat_color: S<toml::Value>,
    pub fuzz_color: S<toml::Value>,
    pub emission_color: S<toml::Value>,
    pub geometry_thin_walled: S<bool>,
    pub geometry_normal: S<String>,
    pub geometry_coat_normal: S<String>,
}

/// `texture = "image.png"` or `texture = { checker = [c1, c2], scale = s }`.
pub enum RawTexture {
    Image(String),
    Checker(RawChecker),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawChecker {
    pub checker: [Color; 2],
    pub scale: Option<Num>,
}

impl<'de> Deserialize<'de> for RawTexture {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<RawTexture, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawTexture;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an image file name or { checker = [c1, c2], scale = s }")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RawTexture, E> {
                Ok(RawTexture::Image(v.to_owned()))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RawTexture, A::Error> {
                RawChecker::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(RawTexture::Checker)
            }
        }
        d.deserialize_any(V)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawLight {
    pub name: S<String>,
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    pub color: S<Color>,
    pub intensity: S<Num>,
    pub falloff: S<String>,
    pub samples: S<u32>,
    pub camera_visible: S<bool>,
    pub position: S<Vector>,
    pub direction: S<Vector>,
    pub at: S<Vector>,
    pub angle: S<Num>,
    pub inner_angle: S<Num>,
    pub falloff_angle: S<Num>,
    pub edge: S<String>,
    pub corner: S<Vector>,
    pub center: S<Vector>,
    pub edge1: S<Vector>,
    pub edge2: S<Vector>,
    pub normal: S<Vector>,
    pub radius: S<Num>,
}

impl RawLight {
    /// The placement keys given, with where each starts: checked against the type's own.
    pub fn shape_keys(&self) -> Vec<(&'static str, std::ops::Range<usize>)> {
        let mut out = Vec::new();
        let mut add = |name, span: Option<std::ops::Range<usize>>| {
            if let Some(s) = span {
                out.push((name, s));
            }
        };
        add("falloff", self.falloff.as_ref().map(Spanned::span));
        add("samples", self.samples.as_ref().map(Spanned::span));
        add(
            "camera_visible",
            self.camera_visible.as_ref().map(Spanned::span),
        );
        add("position", self.position.as_ref().map(Spanned::span));
        add("direction", self.direction.as_ref().map(Spanned::span));
        add("at", self.at.as_ref().map(Spanned::span));
        add("angle", self.angle.as_ref().map(Spanned::span));
        add("inner_angle", self.inner_angle.as_ref().map(Spanned::span));
        add(
            "falloff_angle",
            self.falloff_angle.as_ref().map(Spanned::span),
        );
        add("edge", self.edge.as_ref().map(Spanned::span));
        add("corner", self.corner.as_ref().map(Spanned::span));
        add("center", self.center.as_ref().map(Spanned::span));
        add("edge1", self.edge1.as_ref().map(Spanned::span));
        add("edge2", self.edge2.as_ref().map(Spanned::span));
        add("normal", self.normal.as_ref().map(Spanned::span));
        add("radius", self.radius.as_ref().map(Spanned::span));
        out
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawAmbient {
    pub color: Spanned<Color>,
    pub intensity: S<Num>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBackground {
    pub color: S<Color>,
    pub image: S<String>,
    pub up: S<Vector>,
    pub forward: S<Vector>,
    pub intensity: S<Num>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRender {
    pub width: S<u32>,
    pub height: S<u32>,
    pub aa: S<u32>,
    pub filter: S<String>,
    pub spp: S<u32>,
    pub max_depth: S<u32>,
    pub min_weight: S<Num>,
    pub light_sampling: S<String>,
    pub seed: S<u64>,
    pub integrator: S<String>,
    pub exposure: S<Num>,
    pub tonemap: S<String>,
    pub denoise: S<bool>,
}

/// An animation track (docs/animation.md); its keys are checked by the animation
/// reader, the scene file checks what it names (the other fields are accepted here
/// and not yet read).
#[allow(dead_code)]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTrack {
    pub target: Spanned<String>,
    pub motion: Spanned<String>,
    pub interpolation: S<toml::Value>,
    pub axis: S<toml::Value>,
    pub center: S<toml::Value>,
    pub keep_orientation: S<toml::Value>,
    pub at: S<toml::Value>,
    pub focus: S<toml::Value>,
    pub keys: S<toml::Value>,
}
