//! Image files named by materials and backgrounds, decoded with a pixel limit read from
//! the header before any pixel is.

use super::source::{Source, regular_file};
use crate::error::Result;
use crate::format::image_file::{Encoding, read_texture};
use crate::scene::ImageTexture;
use std::collections::HashMap;
use std::path::PathBuf;
use toml::Spanned;

/// Largest image accepted: 64 Mi pixels (8192 x 8192), 256 MiB as 8-bit RGBA.
pub const MAX_IMAGE_PIXELS: u64 = crate::format::image_file::MAX_TEXTURE_PIXELS;

/// The images read so far, each once per (file, encoding) however many materials name it.
#[derive(Default)]
pub struct ImageCache {
    loaded: HashMap<(PathBuf, bool), u32>,
}

impl ImageCache {
    /// The index among `images`' images of the image `at` names, relative to `source`'s folder.
    /// `srgb`: colour maps are sRGB-encoded; normal maps hold linear values.
    pub fn get(
        &mut self,
        source: &Source,
        at: &Spanned<String>,
        srgb: bool,
        images: &mut crate::scene::SceneBuilder,
    ) -> Result<u32> {
        let path = source.resolve(at.get_ref());
        let key = (path.canonicalize().unwrap_or(path.clone()), srgb);
        if let Some(&i) = self.loaded.get(&key) {
            return Ok(i);
        }
        let image = load(source, at, srgb)?;
        let index = images.add_image(image);
        self.loaded.insert(key, index);
        Ok(index)
    }
}

/// Reads an image: 8-bit files (PNG, JPEG, BMP, TGA, PNM) as RGBA, HDR and EXR as
/// linear floats (environment maps), through `format::image_file` and its limits.
pub fn load(source: &Source, at: &Spanned<String>, srgb: bool) -> Result<ImageTexture> {
    let path = source.resolve(at.get_ref());
    regular_file(source, at, &path)?;
    let encoding = if srgb {
        Encoding::Srgb
    } else {
        Encoding::Linear
    };
    read_texture(&path, encoding)
        .map_err(|m| source.error(at, format!("cannot load image {}: {m}", path.display())))
}
