//! Image files named by materials and backgrounds, decoded with a pixel limit read from
//! the header before any pixel is.

use super::source::{Source, regular_file};
use crate::Result;
use crate::scene::{ImageTexture, Texels};
use std::collections::HashMap;
use std::path::PathBuf;
use toml::Spanned;

/// Largest image accepted: 64 Mi pixels (8192 x 8192), 256 MiB as 8-bit RGBA.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;

/// The images read so far, each once per (file, encoding) however many materials name it.
#[derive(Default)]
pub struct ImageCache {
    loaded: HashMap<(PathBuf, bool), u32>,
}

impl ImageCache {
    /// The index in `images` of the image `at` names, relative to `source`'s folder.
    /// `srgb`: colour maps are sRGB-encoded; normal maps hold linear values.
    pub fn get(
        &mut self,
        source: &Source,
        at: &Spanned<String>,
        srgb: bool,
        images: &mut Vec<ImageTexture>,
    ) -> Result<u32> {
        let path = source.resolve(at.get_ref());
        let key = (path.canonicalize().unwrap_or(path.clone()), srgb);
        if let Some(&i) = self.loaded.get(&key) {
            return Ok(i);
        }
        let image = load(source, at, srgb)?;
        let index = images.len() as u32;
        images.push(image);
        self.loaded.insert(key, index);
        Ok(index)
    }
}

/// Reads an 8-bit image (PNG, JPEG, BMP, TGA, PNM) as RGBA.
pub fn load(source: &Source, at: &Spanned<String>, srgb: bool) -> Result<ImageTexture> {
    let path = source.resolve(at.get_ref());
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ext == "hdr" || ext == "exr" {
        return Err(source.error(
            at,
            format!(
                "{}: HDR and EXR images are not supported yet; use PNG, JPEG, BMP, TGA or PNM",
                path.display()
            ),
        ));
    }
    regular_file(source, at, &path)?;
    let fail = |m: String| source.error(at, format!("cannot load image {}: {m}", path.display()));
    let open = || {
        image::ImageReader::open(&path)
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| fail(e.to_string()))
    };
    let (width, height) = open()?.into_dimensions().map_err(|e| fail(e.to_string()))?;
    let pixels = u64::from(width) * u64::from(height);
    if pixels == 0 || pixels > MAX_IMAGE_PIXELS {
        return Err(fail(format!(
            "{width} x {height} pixels: expected between 1 and {MAX_IMAGE_PIXELS}"
        )));
    }
    let mut reader = open()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    // Room for the decoder's own buffer at 16 bits per channel plus our RGBA copy.
    limits.max_alloc = Some(pixels * 16);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| fail(e.to_string()))?;
    let rgba = decoded.to_rgba8();
    Ok(ImageTexture {
        name: path.display().to_string(),
        width,
        height,
        texels: Texels::Rgba8 {
            texels: rgba.pixels().map(|p| p.0).collect(),
            srgb,
        },
    })
}
