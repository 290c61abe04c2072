//! The 2014 material file (`.mtlx`).
//!
//! One material per line:
//!
//! ```text
//! newmtl NAME R G B ka kd ks shininess ior reflect refract transparent [texture [scale]]
//! ```
//!
//! - `R G B`: 0 to 255, stored divided by 255.
//! - `ka kd ks shininess reflect refract`: >= 0.
//! - `ior`: > 0. The one exception is found in the 2014 files themselves: their
//!   `lightsource` material says `ior 0` with refract weight 0. An index of a material
//!   that does not refract is never used, so `0` is accepted there and read as 1.
//! - `transparent`: exactly `0` or `1`.
//! - `texture`: an image file (PNG, JPEG, BMP, TGA or PNM), relative to the folder of
//!   the material file. With a texture the colour is ignored where the image shows.
//! - `scale`: how the image covers the surface. A number > 0 tiles it with one texel =
//!   `scale` world units; `0` stretches it over the shape; absent means tile at 1; a
//!   negative number is an error.
//!
//! **Extension (Prism's, backward compatible):** the scale field may also be one of the
//! words `stretch`, `fit` (whole image shown, uniformly scaled and centred; the rest of
//! the surface keeps the material colour), `crop` (uniformly scaled to cover the shape,
//! centred, the overflow cut) or `tile` (tile at scale 1). No 2014 file has a word there,
//! so every 2014 file reads as before.
//!
//! Comment lines start with `#`; blank lines are skipped; any other line is an error, as
//! is a name defined twice (also across several files read into one library).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::text::{At, data_lines, index_u32, read_text, shown};
use crate::error::Result;
use crate::math::Vec3;
use crate::scene::{FillMode, Material, Texture};

/// The fields of a material line, as the count error lists them.
const SYNTAX: &str =
    "newmtl NAME R G B ka kd ks shininess ior reflect refract transparent [texture [scale]]";

/// Materials and textures read from one or more material files, in file order, with
/// what is needed to reject duplicate names and to decode each image only once.
///
/// A file's images are decoded together once all its lines are read, in parallel (on
/// the current rayon pool): decoding is most of the time a textured scene takes to load.
/// Errors are the ones reading line by line would give, the first line's first.
#[derive(Debug, Default)]
pub struct MaterialLibrary {
    materials: Vec<Material>,
    textures: Vec<Texture>,
    /// Where each name was defined, for lookups and duplicate errors.
    names: HashMap<String, Definition>,
    /// Texture index per (canonical image path, fill mode).
    texture_of: HashMap<(PathBuf, FillKey), u32>,
    /// First texture decoded from each canonical image path: another fill mode of the
    /// same image copies its texels instead of decoding the file again.
    image_of: HashMap<PathBuf, u32>,
    /// Textures of the file being read, not decoded yet: they follow `textures`.
    pending: Vec<Pending>,
}

/// A texture a line asked for, decoded when the whole file has been read.
#[derive(Debug)]
struct Pending {
    /// The line that asked for it and the image path it gave, for errors.
    line: usize,
    file: PathBuf,
    fill: FillMode,
    source: Source,
}

#[derive(Debug)]
enum Source {
    /// Decode the image at this canonical path.
    Decode(PathBuf),
    /// The same image as an earlier texture, with another fill mode: copy its texels.
    SameAs(u32),
}

#[derive(Debug)]
struct Definition {
    index: u32,
    path: PathBuf,
    line: usize,
}

/// `FillMode` as a hashable key (its tile scale is an f32).
type FillKey = (u8, u32);

fn fill_key(fill: FillMode) -> FillKey {
    match fill {
        FillMode::Tile { scale } => (0, scale.to_bits()),
        FillMode::Stretch => (1, 0),
        FillMode::Fit => (2, 0),
        FillMode::Crop => (3, 0),
    }
}

impl MaterialLibrary {
    /// An empty library.
    pub fn new() -> MaterialLibrary {
        MaterialLibrary::default()
    }

    /// Index (into [`MaterialLibrary::materials`]) of the material called `name`.
    pub fn find(&self, name: &str) -> Option<u32> {
        self.names.get(name).map(|d| d.index)
    }

    /// The materials read so far, in file order; [`Material::texture`] indexes
    /// [`MaterialLibrary::textures`].
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The decoded textures, one per distinct image and fill mode.
    pub fn textures(&self) -> &[Texture] {
        &self.textures
    }

    /// The materials and the textures they index, to move into a `Scene`.
    pub fn into_parts(self) -> (Vec<Material>, Vec<Texture>) {
        (self.materials, self.textures)
    }

    /// Adds a material that no `usemtl` can name (the default white of faces that come
    /// before any `usemtl`), so it cannot clash with a file's `default`.
    pub(super) fn push_unnamed(&mut self, at: At, material: Material) -> Result<u32> {
        let index = index_u32(at, self.materials.len(), "materials")?;
        self.materials.push(material);
        Ok(index)
    }

    /// Rejects a second definition of `name`, saying where the first one is.
    fn check_new_name(&self, at: At, name: &str) -> Result<()> {
        match self.names.get(name) {
            Some(first) => Err(at.error(format!(
                "material {} is already defined at {}:{}",
                shown(name),
                first.path.display(),
                first.line
            ))),
            None => Ok(()),
        }
    }

    fn push_named(&mut self, at: At, material: Material) -> Result<()> {
        self.check_new_name(at, &material.name)?;
        let index = self.push_unnamed(at, material.clone())?;
        let definition = Definition {
            index,
            path: at.path.to_path_buf(),
            line: at.line,
        };
        self.names.insert(material.name, definition);
        Ok(())
    }

    /// Index of the texture for image `file` (already resolved) with `fill`. The image
    /// is decoded by [`MaterialLibrary::decode_pending`], unless the same file was
    /// asked for before.
    fn texture(&mut self, at: At, file: &Path, fill: FillMode) -> Result<u32> {
        let canonical = std::fs::canonicalize(file).map_err(|e| cannot_load(at, file, &e))?;
        let key = (canonical, fill_key(fill));
        if let Some(&index) = self.texture_of.get(&key) {
            return Ok(index);
        }
        let index = index_u32(at, self.textures.len() + self.pending.len(), "textures")?;
        let source = match self.image_of.get(&key.0) {
            Some(&same_image) => Source::SameAs(same_image),
            None => Source::Decode(key.0.clone()),
        };
        self.pending.push(Pending {
            line: at.line,
            file: file.to_path_buf(),
            fill,
            source,
        });
        self.image_of.entry(key.0.clone()).or_insert(index);
        self.texture_of.insert(key, index);
        Ok(index)
    }

    /// Decodes the images the lines of material file `path` asked for, all at once in
    /// parallel, and appends their textures in line order. The first failure in line
    /// order is the error.
    fn decode_pending(&mut self, path: &Path) -> Result<()> {
        let pending = std::mem::take(&mut self.pending);
        // Largest file first, each image one task taken in that order by whichever
        // thread is free: the big images do not end up last, on one thread.
        let mut order: Vec<(u64, usize)> = pending
            .iter()
            .enumerate()
            .filter_map(|(i, p)| match &p.source {
                Source::Decode(canonical) => {
                    let bytes = std::fs::metadata(canonical).map_or(0, |m| m.len());
                    Some((bytes, i))
                }
                Source::SameAs(_) => None,
            })
            .collect();
        order.sort_by(|a, b| b.cmp(a));
        let decoded: Vec<OnceLock<std::result::Result<Texture, String>>> =
            pending.iter().map(|_| OnceLock::new()).collect();
        rayon::scope_fifo(|scope| {
            for &(_, i) in &order {
                let (p, slot) = (&pending[i], &decoded[i]);
                if let Source::Decode(canonical) = &p.source {
                    scope.spawn_fifo(move |_| {
                        let _ = slot.set(decode_image(canonical, p.fill));
                    });
                }
            }
        });
        for (p, texture) in pending.into_iter().zip(decoded) {
            let texture = texture.into_inner();
            let at = At { path, line: p.line };
            let texture = match (texture, p.source) {
                (Some(Ok(texture)), _) => texture,
                (Some(Err(why)), _) => return Err(cannot_load(at, &p.file, &why)),
                (None, Source::SameAs(same_image)) => Texture {
                    fill: p.fill,
                    ..self.textures[same_image as usize].clone()
                },
                (None, Source::Decode(_)) => unreachable!("every image to decode was decoded"),
            };
            self.textures.push(texture);
        }
        Ok(())
    }
}

fn cannot_load(at: At, file: &Path, why: &dyn std::fmt::Display) -> crate::error::Error {
    at.error(format!("cannot load texture {}: {why}", file.display()))
}

/// Decodes an image file into an 8-bit RGB texture. The format is taken from the
/// content when it can be, so a PNG named `.jpg` still loads.
fn decode_image(path: &Path, fill: FillMode) -> std::result::Result<Texture, String> {
    // `into_rgb8` keeps an RGB image's buffer (most JPEGs) instead of copying it.
    let image = super::image_file::read_image(path)?.into_rgb8();
    let (width, height) = image.dimensions();
    let texels = image
        .as_raw()
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    Ok(Texture::new(width, height, texels, fill))
}

/// Reads a material file into `library`.
pub fn load(path: &Path, library: &mut MaterialLibrary) -> Result<()> {
    parse(&read_text(path)?, path, library)
}

/// Parses the text of a material file at `path` into `library`. `path` names the file
/// in errors, and its folder is where texture paths are resolved.
pub fn parse(text: &str, path: &Path, library: &mut MaterialLibrary) -> Result<()> {
    let folder = path.parent().unwrap_or(Path::new(""));
    for line in data_lines(text) {
        let at = At {
            path,
            line: line.number,
        };
        if let Err(e) = parse_line(at, &line.tokens, folder, library) {
            // An image of an earlier line that does not decode is the first error.
            library.decode_pending(path)?;
            return Err(e);
        }
    }
    library.decode_pending(path)
}

fn parse_line(at: At, tokens: &[&str], folder: &Path, library: &mut MaterialLibrary) -> Result<()> {
    if tokens[0] != "newmtl" {
        return Err(at.error(format!(
            "unknown keyword {}: expected newmtl (a material file holds one `{SYNTAX}` per line)",
            shown(tokens[0])
        )));
    }
    let values = tokens.len() - 1;
    if !(12..=14).contains(&values) {
        return Err(at.error(format!(
            "expected `{SYNTAX}`: 12 to 14 values after newmtl, found {values}"
        )));
    }
    let name = tokens[1];
    // Before the texture is decoded, which is the slow part.
    library.check_new_name(at, name)?;
    let component = |i: usize, what: &str| -> Result<f32> {
        let value = at.number(tokens[i], what)?;
        if !(0.0..=255.0).contains(&value) {
            return Err(at.error(format!(
                "expected {what} from 0 to 255, found {}",
                shown(tokens[i])
            )));
        }
        Ok(value as f32)
    };
    let non_negative = |i: usize, what: &str| -> Result<f32> {
        Ok(at.number_above(tokens[i], what, 0.0, false)? as f32)
    };

    let color = Vec3::new(
        component(2, "the red component")?,
        component(3, "the green component")?,
        component(4, "the blue component")?,
    ) / 255.0;
    let ambient = non_negative(5, "the ambient coefficient ka")?;
    let diffuse = non_negative(6, "the diffuse coefficient kd")?;
    let specular = non_negative(7, "the specular coefficient ks")?;
    let shininess = non_negative(8, "the shininess")?;
    let reflect = non_negative(10, "the reflection weight")?;
    let refract = non_negative(11, "the refraction weight")?;
    let ior = if refract > 0.0 {
        at.number_above(tokens[9], "the refractive index", 0.0, true)? as f32
    } else {
        // Never used without refraction; the 2014 light-source material says 0.
        let ior = non_negative(9, "the refractive index")?;
        if ior == 0.0 { 1.0 } else { ior }
    };
    let transparent = match tokens[12] {
        "0" => false,
        "1" => true,
        other => {
            return Err(at.error(format!(
                "expected 0 or 1 for the transparent flag, found {}",
                shown(other)
            )));
        }
    };
    let texture = match tokens.get(13) {
        None => None,
        Some(file) => {
            let fill = fill_mode(at, tokens.get(14).copied())?;
            Some(library.texture(at, &folder.join(file), fill)?)
        }
    };
    let material = Material {
        name: name.to_string(),
        color,
        ambient,
        diffuse,
        specular,
        shininess,
        ior,
        reflect,
        refract,
        transparent,
        texture,
    };
    library.push_named(at, material)
}

/// The fill mode of the optional scale field (see the module doc).
fn fill_mode(at: At, token: Option<&str>) -> Result<FillMode> {
    let Some(token) = token else {
        return Ok(FillMode::Tile { scale: 1.0 });
    };
    Ok(match token {
        "stretch" => FillMode::Stretch,
        "fit" => FillMode::Fit,
        "crop" => FillMode::Crop,
        "tile" => FillMode::Tile { scale: 1.0 },
        _ => {
            let what = "the texture scale (a number >= 0, or stretch, fit, crop or tile)";
            let scale = at.number_above(token, what, 0.0, false)?;
            if scale == 0.0 {
                FillMode::Stretch
            } else if scale as f32 > 0.0 {
                FillMode::Tile {
                    scale: scale as f32,
                }
            } else {
                // Positive but below f32 precision: it would tile by zero.
                return Err(at.error(format!(
                    "expected a texture scale of at least {:e}, found {}",
                    f32::MIN_POSITIVE,
                    shown(token)
                )));
            }
        }
    })
}

#[cfg(test)]
mod tests;
