//! Image files read as textures for texture coordinates: 8-bit images (PNG, JPEG, BMP,
//! TGA, PPM) and linear HDR images (Radiance `.hdr`, OpenEXR), refused from their
//! header when they are too large, never read unless they are regular files.

use crate::film::hdr_io::read_linear_image;
use crate::scene::{ImageTexture, Texels};
use std::path::Path;

/// Pixels a texture may have: 8192 x 8192 (256 MiB as RGBA8). Checked from the
/// header, before anything is decoded, so a small file claiming a huge image costs
/// nothing.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 26;

/// How the channels of an 8-bit image are meant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// A colour map: sRGB-encoded colour, linear alpha.
    Srgb,
    /// Data: alpha, heights, normals.
    Linear,
    /// A cut-out mask: the alpha channel where the image has one, else the first
    /// channel (a grey mask), stored in alpha.
    Mask,
}

/// Reads `path` as a texture. The error says why, without the path (callers name the
/// file and the line that asked for it).
pub fn read_texture(path: &Path, encoding: Encoding) -> Result<ImageTexture, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("not a regular file".into());
    }
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if ext == "hdr" || ext == "exr" {
        let image = read_linear_image(path).map_err(|e| e.to_string())?;
        let texels = image
            .pixels
            .iter()
            .map(|&[r, g, b]| [r, g, b, 1.0])
            .collect();
        return Ok(ImageTexture {
            name,
            width: image.width,
            height: image.height,
            texels: Texels::RgbaF32(texels),
        });
    }
    let decoded = read_image(path)?;
    let has_alpha = decoded.color().has_alpha();
    let rgba = decoded.to_rgba8();
    let (width, height) = rgba.dimensions();
    let mut texels: Vec<[u8; 4]> = rgba.pixels().map(|p| p.0).collect();
    if encoding == Encoding::Mask && !has_alpha {
        for t in &mut texels {
            t[3] = t[0];
        }
    }
    Ok(ImageTexture {
        name,
        width,
        height,
        texels: Texels::Rgba8 {
            texels,
            srgb: encoding == Encoding::Srgb,
        },
    })
}

/// Largest image file read: far beyond any texture within the pixel limit.
pub const MAX_IMAGE_FILE_BYTES: u64 = 1 << 30;

/// Reads and decodes an 8-bit image file (the format from its content), refusing it
/// from its header when it has more than [`MAX_TEXTURE_PIXELS`].
pub fn read_image(path: &Path) -> Result<image::DynamicImage, String> {
    let bytes = super::file::read_regular(path, MAX_IMAGE_FILE_BYTES)?;
    let open = || {
        image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    let (width, height) = open()?
        .into_dimensions()
        .map_err(|e| format!("cannot read the image header: {e}"))?;
    check_size(width, height)?;
    let mut reader = open()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    limits.max_alloc = Some(MAX_TEXTURE_PIXELS * 16);
    reader.limits(limits);
    reader.decode().map_err(|e| e.to_string())
}

fn check_size(width: u32, height: u32) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err("the image is empty".into());
    }
    let pixels = u64::from(width) * u64::from(height);
    if pixels > MAX_TEXTURE_PIXELS {
        return Err(format!(
            "the image is {width}x{height} ({pixels} pixels); textures may have at most \
             {MAX_TEXTURE_PIXELS} pixels"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_maps_decode_srgb_and_masks_take_grey_into_alpha() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("grey.png");
        image::GrayImage::from_raw(2, 1, vec![0, 200])
            .unwrap()
            .save(&path)
            .unwrap();
        let colour = read_texture(&path, Encoding::Srgb).unwrap();
        assert_eq!((colour.width, colour.height), (2, 1));
        assert_eq!(colour.texel(1, 0).w, 1.0);
        assert!((colour.texel(1, 0).x - 0.577_580).abs() < 1e-5);
        let mask = read_texture(&path, Encoding::Mask).unwrap();
        assert_eq!(mask.texel(0, 0).w, 0.0);
        assert!((mask.texel(1, 0).w - 200.0 / 255.0).abs() < 1e-6);
    }

    #[test]
    fn a_huge_header_is_refused_before_decoding() {
        // A PNG header claiming 60000 x 60000 pixels, with no image data at all.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.png");
        let mut png = Vec::new();
        png.extend_from_slice(b"\x89PNG\r\n\x1a\n");
        let mut ihdr = Vec::new();
        ihdr.extend_from_slice(&60000u32.to_be_bytes());
        ihdr.extend_from_slice(&60000u32.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
        png.extend_from_slice(&13u32.to_be_bytes());
        png.extend_from_slice(b"IHDR");
        png.extend_from_slice(&ihdr);
        let crc = crc32(b"IHDR", &ihdr);
        png.extend_from_slice(&crc.to_be_bytes());
        for kind in [b"IDAT", b"IEND"] {
            png.extend_from_slice(&0u32.to_be_bytes());
            png.extend_from_slice(kind);
            png.extend_from_slice(&crc32(kind, &[]).to_be_bytes());
        }
        assert!(png.len() < 100);
        std::fs::write(&path, png).unwrap();
        let e = read_texture(&path, Encoding::Srgb).unwrap_err();
        assert!(e.contains("60000x60000"), "{e}");
    }

    #[test]
    fn directories_and_missing_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            read_texture(dir.path(), Encoding::Srgb).unwrap_err(),
            "not a regular file"
        );
        assert!(read_texture(&dir.path().join("none.png"), Encoding::Srgb).is_err());
    }

    /// The CRC-32 of a PNG chunk's type and data.
    fn crc32(kind: &[u8], data: &[u8]) -> u32 {
        let mut crc = 0xffff_ffffu32;
        for &b in kind.iter().chain(data) {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xedb8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }
}
