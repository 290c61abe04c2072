//! Image files read as textures for texture coordinates: 8-bit images (PNG, JPEG, BMP,
//! TGA, PPM) and linear HDR images (Radiance `.hdr`, OpenEXR), refused from their
//! header when they are too large, never read unless they are regular files.

use crate::error::Error;
use crate::scene::{ImageTexture, Texels};
use crate::util::hdr::decode_linear_image;
use std::io::Cursor;
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
    let bytes = crate::util::file::read_regular(path, MAX_IMAGE_FILE_BYTES)?;
    let name = path.display().to_string();
    decode_texture(&bytes, &name, encoding, MAX_TEXTURE_PIXELS)
}

/// Decodes the bytes of the image file `name` as a texture, as [`read_texture`] does:
/// `.hdr` and `.exr` names as linear floats, others as 8-bit images of the format their
/// content shows. Images of more than `max_pixels` are refused from their header;
/// `read_texture` passes [`MAX_TEXTURE_PIXELS`]. The error says why, without the name.
pub fn decode_texture(
    bytes: &[u8],
    name: &str,
    encoding: Encoding,
    max_pixels: u64,
) -> Result<ImageTexture, String> {
    let ext = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if ext == "hdr" || ext == "exr" {
        let image =
            decode_linear_image(Cursor::new(bytes), Path::new(name), max_pixels).map_err(|e| {
                match e {
                    Error::File { message, .. } => message,
                    e => e.to_string(),
                }
            })?;
        let texels = image
            .pixels
            .iter()
            .map(|&[r, g, b]| [r, g, b, 1.0])
            .collect();
        return Ok(ImageTexture {
            name: name.to_owned(),
            width: image.width,
            height: image.height,
            texels: Texels::RgbaF32(texels),
        });
    }
    let decoded = decode_image(bytes, name, max_pixels)?;
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
        name: name.to_owned(),
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

/// Reads and decodes an 8-bit image file (the format from its content, else from its
/// extension), refusing it from its header when it has more than [`MAX_TEXTURE_PIXELS`].
pub fn read_image(path: &Path) -> Result<image::DynamicImage, String> {
    let bytes = crate::util::file::read_regular(path, MAX_IMAGE_FILE_BYTES)?;
    decode_image(&bytes, &path.display().to_string(), MAX_TEXTURE_PIXELS)
}

/// Decodes the bytes of the 8-bit image file `name` (the format from its content, else
/// from the name's extension), refusing it from its header when it has more than
/// `max_pixels`.
pub fn decode_image(
    bytes: &[u8],
    name: &str,
    max_pixels: u64,
) -> Result<image::DynamicImage, String> {
    check_png_palette(bytes)?;
    let open = || {
        let mut reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        // TGA has no signature: only its extension tells what it is.
        if reader.format().is_none()
            && let Ok(format) = image::ImageFormat::from_path(name)
        {
            reader.set_format(format);
        }
        Ok::<_, String>(reader)
    };
    let (width, height) = open()?
        .into_dimensions()
        .map_err(|e| format!("cannot read the image header: {e}"))?;
    check_size(width, height, max_pixels)?;
    let mut reader = open()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    // The widest pixel a decoder produces: four f32 channels.
    limits.max_alloc = Some(max_pixels.saturating_mul(16));
    reader.limits(limits);
    reader.decode().map_err(|e| e.to_string())
}

/// Refuses a PNG whose palette is not whole RGB entries: png 0.18.1 accepts a PLTE chunk
/// of any length from 3 to 768 bytes and then panics expanding one of, say, 16
/// (image-rs/image-png#694). Only the chunk headers are read.
fn check_png_palette(bytes: &[u8]) -> Result<(), String> {
    let Some(mut rest) = bytes.strip_prefix(b"\x89PNG\r\n\x1a\n".as_slice()) else {
        return Ok(());
    };
    while let Some((head, _)) = rest.split_first_chunk::<8>() {
        let len = u32::from_be_bytes([head[0], head[1], head[2], head[3]]) as usize;
        if &head[4..] == b"PLTE" && !len.is_multiple_of(3) {
            return Err(format!(
                "invalid PNG: its palette (PLTE) has {len} bytes, not a whole number of RGB \
                 entries"
            ));
        }
        // Length, type, data and CRC; past the end is the end.
        let next = len.saturating_add(12);
        rest = rest.get(next..).unwrap_or_default();
    }
    Ok(())
}

fn check_size(width: u32, height: u32, max_pixels: u64) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err("the image is empty".into());
    }
    let pixels = u64::from(width) * u64::from(height);
    if pixels > max_pixels {
        return Err(format!(
            "the image is {width}x{height} ({pixels} pixels); textures may have at most \
             {max_pixels} pixels"
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

    #[test]
    fn bytes_decode_as_the_file_does_and_truncated_bytes_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rgb.png");
        image::RgbImage::from_raw(2, 2, (0..12).map(|i| i * 20).collect())
            .unwrap()
            .save(&path)
            .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let file = read_texture(&path, Encoding::Linear).unwrap();
        let decoded = decode_texture(&bytes, "rgb.png", Encoding::Linear, 4).unwrap();
        assert_eq!(decoded.name, "rgb.png");
        assert_eq!((decoded.width, decoded.height), (file.width, file.height));
        assert_eq!(decoded.texel(1, 1), file.texel(1, 1));

        let e = decode_texture(&bytes, "rgb.png", Encoding::Linear, 3).unwrap_err();
        assert!(
            e.contains("2x2 (4 pixels)") && e.contains("at most 3"),
            "{e}"
        );
        for cut in [0, 8, 30, bytes.len() - 13] {
            let e = decode_texture(&bytes[..cut], "rgb.png", Encoding::Linear, 4).unwrap_err();
            assert!(
                !e.contains("rgb.png"),
                "{cut}: the caller names the file: {e}"
            );
        }
    }

    #[test]
    fn linear_textures_have_the_texture_limit() {
        // 8193 x 8192 is within what `film::read_linear_image` reads, but not a texture.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sky.hdr");
        std::fs::write(
            &path,
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 8193\n",
        )
        .unwrap();
        let e = read_texture(&path, Encoding::Linear).unwrap_err();
        assert!(
            e.contains("8193x8192") && e.contains(&MAX_TEXTURE_PIXELS.to_string()),
            "{e}"
        );
        assert!(!e.contains("sky.hdr"), "the caller names the file: {e}");
    }

    #[test]
    fn an_empty_radiance_image_is_refused() {
        // fuzz/findings/texture-radiance-height-0.hdr: the header says 8x0, and sampling a
        // texture without rows would panic.
        let bytes = b"#?RADIANCE\n\n-Y 0 +X 8";
        let e = decode_texture(bytes, "t.hdr", Encoding::Linear, MAX_TEXTURE_PIXELS).unwrap_err();
        assert_eq!(e, "the image is empty (8x0)");
    }

    #[test]
    fn a_png_palette_of_partial_entries_is_refused() {
        // fuzz/findings/texture-png-palette-of-16-bytes.png: png 0.18.1 panics expanding a
        // palette whose length is not a multiple of 3.
        let png = |palette: &[u8]| {
            let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
            // 2x2, 8-bit indices 0 1 / 1 0, in a stored (uncompressed) zlib stream.
            let rows = [0u8, 0, 1, 0, 1, 0];
            let mut idat = vec![0x78, 0x01, 0x01, 6, 0, !6, 0xff];
            idat.extend_from_slice(&rows);
            let (a, b) = rows.iter().fold((1u32, 0u32), |(a, b), &x| {
                let a = (a + u32::from(x)) % 65521;
                (a, (b + a) % 65521)
            });
            idat.extend_from_slice(&(b << 16 | a).to_be_bytes());
            let ihdr = [0, 0, 0, 2, 0, 0, 0, 2, 8, 3, 0, 0, 0];
            for (kind, data) in [
                (b"IHDR", &ihdr[..]),
                (b"PLTE", palette),
                (b"IDAT", &idat),
                (b"IEND", &[]),
            ] {
                png.extend_from_slice(&(data.len() as u32).to_be_bytes());
                png.extend_from_slice(kind);
                png.extend_from_slice(data);
                png.extend_from_slice(&crc32(kind, data).to_be_bytes());
            }
            png
        };
        let whole = decode_texture(&png(&[255, 0, 0, 0, 0, 255]), "p.png", Encoding::Linear, 4);
        assert_eq!(
            whole.unwrap().texel(1, 0),
            glam::Vec4::new(0.0, 0.0, 1.0, 1.0)
        );
        for len in [4, 16, 767] {
            let e = decode_texture(&png(&vec![9; len]), "p.png", Encoding::Linear, 4).unwrap_err();
            assert!(
                e.contains(&format!("palette (PLTE) has {len} bytes")),
                "{e}"
            );
        }
    }

    #[test]
    fn tga_files_load_by_their_extension() {
        // TGA has no signature, so its content alone does not name the format.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.tga");
        image::RgbImage::from_raw(2, 1, vec![255, 0, 0, 0, 0, 255])
            .unwrap()
            .save(&path)
            .unwrap();
        let texture = read_texture(&path, Encoding::Linear).unwrap();
        assert_eq!((texture.width, texture.height), (2, 1));
        assert_eq!(texture.texel(1, 0), glam::Vec4::new(0.0, 0.0, 1.0, 1.0));
        let bytes = std::fs::read(&path).unwrap();
        assert!(decode_texture(&bytes, "a.png", Encoding::Linear, 2).is_err());
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
