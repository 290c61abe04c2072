//! MaterialX documents (`.mtlx`, XML) that describe OpenPBR Surface materials: every
//! `<open_pbr_surface>` node's inputs, as constants or as `<image>` nodes, in the
//! document's colour space (`acescg`, `lin_rec709`, `srgb_texture`), and the
//! `<surfacematerial>` that names it.
//!
//! `.mtlx` is also the 2014 material file's extension: a MaterialX document is told
//! apart by its first character, `<` (`is_materialx`).

use super::image_file::{self, Encoding};
use crate::math::Vec3;
use crate::scene::material::linear_to_srgb;
use crate::scene::openpbr::{Channel, Color, OpenPbr, Scalar};
use crate::scene::{Albedo, ImageTexture, Material, Surface, TextureSlot};
use std::path::Path;

/// Largest MaterialX document read: materials are a few kilobytes.
const MAX_BYTES: u64 = 16 << 20;

/// Whether `bytes` are a MaterialX (XML) document rather than a 2014 material file.
pub fn is_materialx(bytes: &[u8]) -> bool {
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    text.iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(|&b| b == b'<')
}

/// One material of a document: its surface (with the images it reads, indexed from 0
/// in `images`), the 2014 terms alike, and the document's warnings.
#[derive(Debug)]
pub struct MaterialxMaterial {
    /// The 2014 terms: the material's name and base colour.
    pub material: Material,
    /// What is rendered; its texture slots index `images`.
    pub surface: Surface,
    /// The images the document's `<image>` nodes read, decoded.
    pub images: Vec<ImageTexture>,
    /// What was not read, by file and input.
    pub warnings: Vec<String>,
}

/// ACEScg (AP1, D60) to linear Rec. 709 (D65, Bradford): how constants in an `acescg`
/// document become Prism's linear RGB.
const ACESCG_TO_REC709: [[f32; 3]; 3] = [
    [1.705_051, -0.621_792, -0.083_259],
    [-0.130_256, 1.140_805, -0.010_548],
    [-0.024_003, -0.128_969, 1.152_972],
];

fn from_acescg(c: Vec3) -> Vec3 {
    let m = ACESCG_TO_REC709;
    Vec3::new(
        m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z,
        m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z,
        m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z,
    )
}

/// A colour in colour space `space`, as linear Rec. 709.
fn to_linear(c: Vec3, space: &str) -> Result<Vec3, String> {
    match space {
        "acescg" | "lin_ap1" => Ok(from_acescg(c)),
        "lin_rec709" | "" | "raw" => Ok(c),
        "srgb_texture" | "g22_rec709" => Ok(crate::scene::material::srgb_to_linear(c)),
        other => Err(format!(
            "colour space \"{other}\" is not read (expected acescg, lin_rec709 or srgb_texture)"
        )),
    }
}

/// The material named `name` (a `<surfacematerial>`'s or an `<open_pbr_surface>`'s
/// name), or the document's first, from the MaterialX file `path`.
pub fn load(path: &Path, name: Option<&str>) -> crate::Result<MaterialxMaterial> {
    let bytes = crate::util::file::read_regular(path, MAX_BYTES)
        .map_err(|e| crate::Error::file(path, format!("cannot read: {e}")))?;
    parse(crate::util::text::decode(&bytes, path)?, path, name)
}

fn parse(text: &str, path: &Path, name: Option<&str>) -> crate::Result<MaterialxMaterial> {
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| crate::Error::file(path, format!("invalid MaterialX XML: {e}")))?;
    let at = |node: roxmltree::Node, message: String| {
        let pos = doc.text_pos_at(node.range().start);
        crate::Error::parse_at(path, pos.row as usize, pos.col as usize, message)
    };
    let root = doc.root_element();
    if root.tag_name().name() != "materialx" {
        return Err(at(root, "expected a <materialx> document".into()));
    }
    let space = root.attribute("colorspace").unwrap_or("lin_rec709");
    let shaders: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("open_pbr_surface"))
        .collect();
    // A material's name, and the shader it uses.
    let materials: Vec<(&str, roxmltree::Node)> = root
        .children()
        .filter(|n| n.has_tag_name("surfacematerial"))
        .filter_map(|m| {
            let shader = m
                .children()
                .find(|i| i.has_tag_name("input") && i.attribute("name") == Some("surfaceshader"))?
                .attribute("nodename")?;
            let node = shaders
                .iter()
                .find(|s| s.attribute("name") == Some(shader))?;
            Some((m.attribute("name").unwrap_or(shader), *node))
        })
        .collect();
    let chosen = match name {
        None => materials.first().copied().or_else(|| {
            shaders
                .first()
                .map(|s| (s.attribute("name").unwrap_or("material"), *s))
        }),
        Some(want) => materials
            .iter()
            .copied()
            .find(|(n, _)| *n == want)
            .or_else(|| {
                shaders
                    .iter()
                    .find(|s| s.attribute("name") == Some(want))
                    .map(|s| (want, *s))
            }),
    };
    let Some((material_name, shader)) = chosen else {
        return Err(crate::Error::file(
            path,
            match name {
                Some(n) => format!("no material \"{n}\" with an <open_pbr_surface>"),
                None => "no <open_pbr_surface> material".into(),
            },
        ));
    };
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut p = OpenPbr::default();
    let mut images = Vec::new();
    let mut warnings = Vec::new();
    let mut base_color = Color::constant(crate::scene::openpbr::DEFAULT_BASE_COLOR);
    let (mut luminance, mut emission_color) = (0.0f32, Color::constant(Vec3::ONE));
    for input in shader.children().filter(|n| n.has_tag_name("input")) {
        let key = input.attribute("name").unwrap_or("");
        let kind = input.attribute("type").unwrap_or("");
        let input_space = input.attribute("colorspace").unwrap_or(space);
        let source = input.attribute("nodename");
        if input.attribute("nodegraph").is_some() || input.attribute("output").is_some() {
            warnings.push(format!(
                "{}: {material_name}.{key}: node graphs are not read; the default stands",
                path.display()
            ));
            continue;
        }
        // A texture: an <image> node's file, read at the hit's coordinates.
        let texture = match source {
            None => None,
            Some(node_name) => {
                let Some(image) = root
                    .children()
                    .find(|n| n.has_tag_name("image") && n.attribute("name") == Some(node_name))
                else {
                    warnings.push(format!(
                        "{}: {material_name}.{key}: node \"{node_name}\" is not an <image>; the default stands",
                        path.display()
                    ));
                    continue;
                };
                let file = image
                    .children()
                    .find(|i| i.attribute("name") == Some("file"))
                    .ok_or_else(|| at(image, "expected an image's `file` input".into()))?;
                let file_space = file
                    .attribute("colorspace")
                    .or(image.attribute("colorspace"))
                    .unwrap_or(if kind == "color3" {
                        "srgb_texture"
                    } else {
                        "raw"
                    });
                let encoding = match file_space {
                    "srgb_texture" | "g22_rec709" => Encoding::Srgb,
                    _ => Encoding::Linear,
                };
                let value = file.attribute("value").unwrap_or("");
                let texture = image_file::read_texture(&folder.join(value), encoding)
                    .map_err(|e| at(file, format!("{value}: {e}")))?;
                images.push(texture);
                Some(TextureSlot::new((images.len() - 1) as u32))
            }
        };
        let number = |v: &str| -> Result<f32, crate::Error> {
            v.trim()
                .parse::<f32>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| at(input, format!("{key}: expected a number, found \"{v}\"")))
        };
        let value = input.attribute("value");
        match kind {
            "float" => {
                let v = match value {
                    Some(v) => number(v)?,
                    None if texture.is_some() => 1.0,
                    None => continue,
                };
                let scalar = Scalar {
                    value: v,
                    texture: texture.map(|t| (t, Channel::R)),
                };
                match key {
                    "emission_luminance" => luminance = v.max(0.0),
                    _ => match p.scalar_mut(key) {
                        Some(s) => *s = scalar,
                        None => warnings.push(format!(
                            "{}: {material_name}.{key}: not an OpenPBR parameter Prism reads",
                            path.display()
                        )),
                    },
                }
            }
            "color3" => {
                let c = match value {
                    Some(v) => {
                        let parts: Vec<&str> = v.split(',').collect();
                        if parts.len() != 3 {
                            return Err(at(
                                input,
                                format!("{key}: expected three numbers, found \"{v}\""),
                            ));
                        }
                        let c = Vec3::new(number(parts[0])?, number(parts[1])?, number(parts[2])?);
                        to_linear(c, input_space).map_err(|e| at(input, format!("{key}: {e}")))?
                    }
                    None if texture.is_some() => Vec3::ONE,
                    None => continue,
                };
                let color = Color { value: c, texture };
                match key {
                    "base_color" => base_color = color,
                    "emission_color" => emission_color = color,
                    _ => match p.color_mut(key) {
                        Some(slot) => *slot = color,
                        None => warnings.push(format!(
                            "{}: {material_name}.{key}: not an OpenPBR parameter Prism reads",
                            path.display()
                        )),
                    },
                }
            }
            "boolean" if key == "geometry_thin_walled" => {
                p.geometry_thin_walled = value.is_some_and(|v| v.trim() == "true");
            }
            _ => warnings.push(format!(
                "{}: {material_name}.{key}: a {kind} input is not read",
                path.display()
            )),
        }
    }
    let albedo = match base_color.texture {
        None => Albedo::Color(base_color.value),
        Some(slot) => Albedo::Image {
            slot,
            tint: base_color.value,
        },
    };
    let absorption = p.absorption();
    let surface = Surface {
        albedo,
        emission: emission_color.value * luminance,
        emission_map: emission_color.texture,
        ior: p.specular_ior.value,
        absorption,
        openpbr: Some(Box::new(p)),
        ..Surface::default()
    };
    let material = Material {
        name: material_name.to_owned(),
        color: linear_to_srgb(base_color.value.clamp(Vec3::ZERO, Vec3::ONE)),
        ..Material::default_white()
    };
    Ok(MaterialxMaterial {
        material,
        surface,
        images,
        warnings,
    })
}

#[cfg(test)]
mod tests;
