//! Linear radiance files: OpenEXR and Radiance HDR (RGBE). They store the image as
//! rendered, with no exposure, tone map or curve, so that it can be developed later.
//!
//! Neither file ever holds NaN or an infinity: a non-finite channel is written as 0.
//! EXR keeps negative values; half precision saturates at ±65504 (half's largest finite
//! value) instead of becoming infinite. RGBE cannot hold negatives, which are written as
//! 0, nor values beyond 2^126 (saturated) or pixels whose brightest channel is below
//! 2^-120 (written as black): its shared exponent has 8 bits.

use super::image::Image;
use super::limits::MAX_LINEAR_PIXELS;
use crate::error::{Error, Result};
use exr::prelude::{self as exr_img, ReadChannels, ReadLayers, WritableImage};
use std::fmt;
use std::io::{BufRead, BufReader, Read, Seek, Write};
use std::path::Path;
use std::str::FromStr;

/// Sample type of an OpenEXR file's channels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrPrecision {
    /// 16-bit float: 11 significant bits (relative error ≤ 2^-11), half the size of
    /// float; what renderers and compositors exchange by default.
    #[default]
    Half,
    /// 32-bit float: the renderer's own values, bit for bit.
    Float,
}

impl ExrPrecision {
    /// The name front ends accept and print (`half`, `float`); parsed back by `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            ExrPrecision::Half => "half",
            ExrPrecision::Float => "float",
        }
    }
}

impl fmt::Display for ExrPrecision {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ExrPrecision {
    type Err = String;

    fn from_str(s: &str) -> Result<ExrPrecision, String> {
        match s {
            "half" => Ok(ExrPrecision::Half),
            "float" => Ok(ExrPrecision::Float),
            _ => Err(format!(
                "unknown EXR precision {}: expected half or float",
                super::text::shown(s)
            )),
        }
    }
}

/// A channel as the linear files store it: non-finite values become 0.
fn finite_or_zero(v: f32) -> f32 {
    if v.is_finite() { v } else { 0.0 }
}

/// Writes `image` as a single-part scan-line OpenEXR file with R, G and B channels,
/// ZIP-compressed (lossless, readable by every OpenEXR reader).
pub fn write_exr(
    image: &Image,
    precision: ExrPrecision,
    out: impl Write + Seek,
) -> Result<(), exr::error::Error> {
    let size = (image.width as usize, image.height as usize);
    let at = |exr_img::Vec2(x, y): exr_img::Vec2<usize>| {
        image.pixels[y * size.0 + x].map(finite_or_zero)
    };
    let encoding = exr_img::Encoding::SMALL_LOSSLESS;
    let attributes = exr_img::LayerAttributes::default();
    match precision {
        ExrPrecision::Float => {
            let channels = exr_img::SpecificChannels::rgb(|pos| {
                let [r, g, b] = at(pos);
                (r, g, b)
            });
            let layer = exr_img::Layer::new(size, attributes, encoding, channels);
            exr_img::Image::from_layer(layer).write().to_buffered(out)
        }
        ExrPrecision::Half => {
            let channels = exr_img::SpecificChannels::rgb(|pos| {
                let [r, g, b] = at(pos).map(to_half);
                (r, g, b)
            });
            let layer = exr_img::Layer::new(size, attributes, encoding, channels);
            exr_img::Image::from_layer(layer).write().to_buffered(out)
        }
    }
}

/// Writes `image` with more layers beside it, each named and with its own channels
/// taken from the first channels of its image (a depth layer's one channel "Z"): one
/// file of several parts, as compositors read render passes. The image is the first
/// part, "image" (R, G, B): a reader that takes the first part sees it.
pub fn write_exr_layers(
    image: &Image,
    layers: &[(&str, &[&str], &Image)],
    precision: ExrPrecision,
    out: impl Write + Seek,
) -> Result<(), exr::error::Error> {
    use exr_img::{AnyChannel, AnyChannels, FlatSamples, Layer, LayerAttributes, Text};
    let size = (image.width as usize, image.height as usize);
    let layer = |name: &str, channels: &[&str], img: &Image| {
        let channels = channels
            .iter()
            .enumerate()
            .map(|(c, &n)| {
                let values = img.pixels.iter().map(|p| finite_or_zero(p[c.min(2)]));
                let samples = match precision {
                    ExrPrecision::Float => FlatSamples::F32(values.collect()),
                    ExrPrecision::Half => FlatSamples::F16(values.map(to_half).collect()),
                };
                AnyChannel::new(n, samples)
            })
            .collect();
        let attributes = LayerAttributes {
            layer_name: Some(Text::from(name)),
            ..LayerAttributes::default()
        };
        Layer::new(
            size,
            attributes,
            exr_img::Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(channels),
        )
    };
    let mut parts = vec![layer("image", &["R", "G", "B"], image)];
    for (name, channels, img) in layers {
        parts.push(layer(name, channels, img));
    }
    let attributes = exr_img::ImageAttributes::new(exr_img::IntegerBounds::from_dimensions(size));
    exr_img::Image::from_layers(attributes, parts)
        .write()
        .to_buffered(out)
}

/// Rounds to half, saturating: a finite radiance never becomes an infinity in the file.
fn to_half(v: f32) -> exr_img::f16 {
    let max = exr_img::f16::MAX.to_f32();
    exr_img::f16::from_f32(v.clamp(-max, max))
}

/// RGBE's exponent byte holds 2^-128..2^127; these bounds keep every pixel well inside.
const RGBE_MAX: f32 = (1u128 << 126) as f32;
const RGBE_MIN: f32 = 1.0 / (1u128 << 120) as f32;

/// Writes `image` as a Radiance RGBE file (run-length encoded where the format allows).
pub fn write_hdr(image: &Image, out: impl Write) -> image::ImageResult<()> {
    let pixels: Vec<image::Rgb<f32>> = image.pixels.iter().map(|&p| rgbe_safe(p)).collect();
    let (w, h) = (image.width as usize, image.height as usize);
    image::codecs::hdr::HdrEncoder::new(out).encode(&pixels, w, h)
}

fn rgbe_safe(p: [f32; 3]) -> image::Rgb<f32> {
    let p = p.map(|v| finite_or_zero(v).clamp(0.0, RGBE_MAX));
    let brightest = p[0].max(p[1]).max(p[2]);
    image::Rgb(if brightest < RGBE_MIN { [0.0; 3] } else { p })
}

const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Reads an OpenEXR or Radiance HDR file (told apart by their signatures, whatever the
/// extension) as linear RGB. Only regular files are read; images above
/// [`MAX_LINEAR_PIXELS`] are refused from their header. Non-finite values read as 0, as
/// they are written. Of an EXR file, the first part with R, G and B channels is read, at
/// its largest resolution level; its data window becomes the image.
pub fn read_linear_image(path: &Path) -> Result<Image> {
    let cannot_read = |e: &dyn fmt::Display| Error::file(path, format!("cannot read: {e}"));
    let file = super::file::open_regular(path).map_err(|e| cannot_read(&e))?;
    decode_linear_image(BufReader::new(file), path, MAX_LINEAR_PIXELS)
}

/// Decodes an OpenEXR or Radiance HDR image from `reader`, as [`read_linear_image`]
/// does, refusing it from its header when it has more than `max_pixels`. `path` names
/// the file in errors. Textures decode their files' bytes through here, with their own
/// limit.
pub fn decode_linear_image(
    mut reader: impl BufRead + Seek,
    path: &Path,
    max_pixels: u64,
) -> Result<Image> {
    let cannot_read = |e: &dyn fmt::Display| Error::file(path, format!("cannot read: {e}"));
    let mut signature = [0u8; 10];
    let n = read_up_to(&mut reader, &mut signature).map_err(|e| cannot_read(&e))?;
    reader.rewind().map_err(|e| cannot_read(&e))?;
    let signature = &signature[..n];
    let mut image = if signature.starts_with(&EXR_MAGIC) {
        read_exr(reader, path, max_pixels)?
    } else if signature.starts_with(b"#?RADIANCE") || signature.starts_with(b"#?RGBE") {
        read_hdr(reader, path, max_pixels)?
    } else {
        return Err(Error::file(
            path,
            "expected an OpenEXR or Radiance HDR file, found neither signature",
        ));
    };
    image
        .pixels
        .iter_mut()
        .for_each(|p| *p = p.map(finite_or_zero));
    Ok(image)
}

/// Fills as much of `buf` as the reader has.
fn read_up_to(reader: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match reader.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

/// Refuses empty images, and `width × height` images above `max` pixels with both
/// numbers in the message.
fn check_size(path: &Path, width: u64, height: u64, max: u64) -> Result<()> {
    // Radiance headers may say `-Y 0`; an image without texels cannot be sampled.
    if width == 0 || height == 0 {
        return Err(Error::file(
            path,
            format!("the image is empty ({width}x{height})"),
        ));
    }
    if width.saturating_mul(height) > max {
        return Err(too_large(
            path,
            format!("image of {width}x{height} pixels"),
            max,
        ));
    }
    Ok(())
}

fn too_large(path: &Path, what: String, max: u64) -> Error {
    Error::file(
        path,
        format!("{what} is too large: expected at most {max} pixels"),
    )
}

fn read_exr(mut reader: impl BufRead + Seek, path: &Path, max_pixels: u64) -> Result<Image> {
    let invalid = |e: exr::error::Error| Error::file(path, format!("invalid OpenEXR file: {e}"));
    let meta = exr_img::MetaData::read_from_buffered(&mut reader, false).map_err(invalid)?;
    // Every part counts: the reader may hold chunks of all of them.
    let sizes = meta.headers.iter().map(|h| h.layer_size);
    let sizes: Vec<(u64, u64)> = sizes.map(|s| (s.0 as u64, s.1 as u64)).collect();
    match sizes[..] {
        [(w, h)] => check_size(path, w, h, max_pixels)?,
        _ => {
            for &(w, h) in &sizes {
                check_size(path, w, h, max_pixels)?;
            }
            let total = sizes
                .iter()
                .fold(0u64, |t, &(w, h)| t.saturating_add(w.saturating_mul(h)));
            if total > max_pixels {
                let what = format!("OpenEXR file of {} parts and {total} pixels", sizes.len());
                return Err(too_large(path, what, max_pixels));
            }
        }
    }
    reader
        .rewind()
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))?;

    let exr_image = exr_img::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![[0.0f32; 3]; size.area()]),
            |(w, pixels): &mut (usize, Vec<[f32; 3]>), pos, (r, g, b): (f32, f32, f32)| {
                pixels[pos.y() * *w + pos.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(reader)
        .map_err(|e| match e {
            exr::error::Error::Invalid(m) if m.contains("no layer in the image matched") => {
                Error::file(
                    path,
                    "expected an OpenEXR part with R, G and B channels, found none",
                )
            }
            e => invalid(e),
        })?;
    let layer = exr_image.layer_data;
    let exr_img::Vec2(w, h) = layer.size;
    let (_, pixels) = layer.channel_data.pixels;
    // Both fit in u32: neither is 0, and their product is within the limit (2^28 at most).
    Ok(Image::new(w as u32, h as u32, pixels))
}

fn read_hdr(reader: impl BufRead + Seek, path: &Path, max_pixels: u64) -> Result<Image> {
    use image::ImageDecoder;
    let invalid =
        |e: image::ImageError| Error::file(path, format!("invalid Radiance HDR file: {e}"));
    let decoder = image::codecs::hdr::HdrDecoder::new(reader).map_err(invalid)?;
    let (width, height) = decoder.dimensions();
    check_size(path, width.into(), height.into(), max_pixels)?;
    let mut pixels = vec![[0.0f32; 3]; width as usize * height as usize];
    // The decoder writes native-endian f32 RGB, which is the layout of `[f32; 3]`.
    decoder
        .read_image(bytemuck::cast_slice_mut(&mut pixels))
        .map_err(invalid)?;
    Ok(Image::new(width, height, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn precision_names_parse() {
        for p in [ExrPrecision::Half, ExrPrecision::Float] {
            assert_eq!(p.name().parse::<ExrPrecision>(), Ok(p));
            assert_eq!(p.to_string(), p.name());
        }
        assert_eq!(ExrPrecision::default(), ExrPrecision::Half);
        let e = "double".parse::<ExrPrecision>().unwrap_err();
        assert_eq!(e, "unknown EXR precision `double`: expected half or float");
    }

    #[test]
    fn half_saturates_instead_of_overflowing() {
        assert_eq!(to_half(1e9).to_f32(), 65504.0);
        assert_eq!(to_half(-1e9).to_f32(), -65504.0);
        assert_eq!(to_half(0.5).to_f32(), 0.5);
    }

    #[test]
    fn rgbe_inputs_stay_in_range() {
        let safe = |p| rgbe_safe(p).0;
        assert_eq!(safe([f32::NAN, f32::INFINITY, -1.0]), [0.0; 3]);
        assert_eq!(safe([1e-37, 1e-38, 0.0]), [0.0; 3]);
        assert_eq!(safe([f32::MAX, 1.0, 0.0]), [RGBE_MAX, 1.0, 0.0]);
        assert_eq!(safe([0.25, -0.5, 3.0]), [0.25, 0.0, 3.0]);
    }

    #[test]
    fn size_limit_names_both_numbers() {
        let p = Path::new("big.exr");
        assert!(check_size(p, 16384, 16384, MAX_LINEAR_PIXELS).is_ok());
        let e = check_size(p, 16385, 16384, MAX_LINEAR_PIXELS)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("16385x16384") && e.contains("at most 268435456"),
            "{e}"
        );
        assert!(check_size(p, u64::MAX, u64::MAX, MAX_LINEAR_PIXELS).is_err());
        for (w, h) in [(8, 0), (0, 8), (0, 0)] {
            let e = check_size(p, w, h, MAX_LINEAR_PIXELS)
                .unwrap_err()
                .to_string();
            assert!(e.contains(&format!("empty ({w}x{h})")), "{e}");
        }
    }

    use crate::film::{OutputOptions, write_image};

    /// Radiance as the physically based model makes it: dim, bright, saturated, negative.
    fn radiance() -> Image {
        let values = [0.0, 0.18, 1.0, 3.5, 1234.5, 0.001, 7e-5, 42.0, 0.75, 2.0e4];
        let pixels = (0..15).map(|i| {
            let v = |k: usize| values[(i * 7 + k * 3) % 10] * (1.0 + i as f32 / 16.0);
            [v(0), v(1), v(2)]
        });
        Image::new(5, 3, pixels.collect())
    }

    fn round_trip(image: &Image, name: &str, precision: ExrPrecision) -> Image {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join(name);
        let options = OutputOptions {
            exr_precision: precision,
            ..OutputOptions::default()
        };
        write_image(image, &p, &options).unwrap();
        read_linear_image(&p).unwrap()
    }

    #[test]
    fn exr_float_round_trip_is_exact() {
        let mut image = radiance();
        image.pixels[0] = [-0.5, f32::MAX, f32::MIN_POSITIVE];
        let back = round_trip(&image, "a.exr", ExrPrecision::Float);
        let bits = |i: &Image| {
            i.pixels
                .iter()
                .map(|p| p.map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!((back.width, back.height), (5, 3));
        assert_eq!(bits(&back), bits(&image));
    }

    #[test]
    fn exr_half_round_trip_within_half_precision() {
        let image = radiance();
        let back = round_trip(&image, "a.exr", ExrPrecision::Half);
        assert_eq!((back.width, back.height), (5, 3));
        for (a, b) in image
            .pixels
            .iter()
            .flatten()
            .zip(back.pixels.iter().flatten())
        {
            // Half's normal range starts at 2^-14; below it the step is absolute, 2^-24.
            let tolerance = (a.abs() * 2f32.powi(-11)).max(2f32.powi(-25));
            assert!((a - b).abs() <= tolerance, "{a} -> {b}");
        }
    }

    #[test]
    fn hdr_round_trip_within_rgbe_precision() {
        let image = radiance();
        let back = round_trip(&image, "a.hdr", ExrPrecision::Half);
        assert_eq!((back.width, back.height), (5, 3));
        for (p, q) in image.pixels.iter().zip(&back.pixels) {
            // The three channels share the brightest one's exponent.
            let brightest = p[0].max(p[1]).max(p[2]);
            for (a, b) in p.iter().zip(q) {
                assert!((a - b).abs() <= brightest / 128.0, "{p:?} -> {q:?}");
            }
        }
        // Wide enough for run-length encoded scan lines too.
        let wide = Image::new(40, 2, vec![[0.5, 8.0, 100.0]; 80]);
        let back = round_trip(&wide, "wide.hdr", ExrPrecision::Half);
        assert!(
            back.pixels.iter().all(|&p| p == [0.5, 8.0, 100.0]),
            "{:?}",
            back.pixels[0]
        );
    }

    #[test]
    fn linear_files_hold_no_nan_and_ignore_development() {
        let image = Image::new(
            2,
            1,
            vec![
                [f32::NAN, f32::INFINITY, f32::NEG_INFINITY],
                [1e9, -2.0, 0.5],
            ],
        );
        let bright = OutputOptions {
            develop: crate::film::Develop {
                exposure: 3.0,
                ..crate::film::Develop::display()
            },
            ..OutputOptions::default()
        };
        let dir = tempfile::tempdir().unwrap();
        let expect = [
            (
                "half.exr",
                ExrPrecision::Half,
                [[0.0; 3], [65504.0, -2.0, 0.5]],
            ),
            (
                "float.exr",
                ExrPrecision::Float,
                [[0.0; 3], [1e9, -2.0, 0.5]],
            ),
            ("a.hdr", ExrPrecision::Half, [[0.0; 3], [1e9, 0.0, 0.0]]),
        ];
        for (name, precision, want) in expect {
            let p = dir.path().join(name);
            let options = OutputOptions {
                exr_precision: precision,
                ..bright
            };
            write_image(&image, &p, &options).unwrap();
            let back = read_linear_image(&p).unwrap().pixels;
            assert_eq!(back[0], want[0], "{name}");
            // RGBE keeps 8 bits of the brightest channel; 0.5 is below its last step.
            let close = back[1]
                .iter()
                .zip(want[1])
                .all(|(a, b)| (a - b).abs() <= 1e9 / 128.0);
            assert!(
                close && (name == "a.hdr" || back[1] == want[1]),
                "{name}: {:?}",
                back[1]
            );
        }
    }

    #[test]
    fn reader_refuses_what_it_should() {
        let dir = tempfile::tempdir().unwrap();
        let err = |p: &Path| read_linear_image(p).unwrap_err().to_string();
        assert!(err(dir.path()).contains("not a regular file"));
        assert!(err(&dir.path().join("none.exr")).contains("cannot read"));

        let png = dir.path().join("a.png");
        crate::film::write_image(&radiance(), &png, &OutputOptions::classic()).unwrap();
        assert!(err(&png).contains("expected an OpenEXR or Radiance HDR file, found neither"));

        // A Radiance header announcing 20000 x 20000 pixels, and no pixels.
        let big = dir.path().join("big.hdr");
        std::fs::write(
            &big,
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 20000\n",
        )
        .unwrap();
        assert!(
            err(&big).contains("image of 20000x20000 pixels is too large"),
            "{}",
            err(&big)
        );

        // A real EXR whose data window is widened to 20000 x 20000 in the header.
        let exr = dir.path().join("a.exr");
        write_image(&radiance(), &exr, &OutputOptions::default()).unwrap();
        let mut bytes = std::fs::read(&exr).unwrap();
        let key = b"dataWindow\0box2i\0";
        let at = bytes.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
        bytes[at + 8..at + 16]
            .copy_from_slice(&[&19999i32.to_le_bytes()[..], &19999i32.to_le_bytes()].concat());
        let big = dir.path().join("big.exr");
        std::fs::write(&big, &bytes).unwrap();
        assert!(
            err(&big).contains("image of 20000x20000 pixels is too large"),
            "{}",
            err(&big)
        );

        // Truncated files are errors, not panics.
        let good = std::fs::read(&exr).unwrap();
        for cut in [4, 20, good.len() / 2, good.len() - 1] {
            std::fs::write(&big, &good[..cut]).unwrap();
            assert!(
                err(&big).contains("invalid OpenEXR file"),
                "{cut}: {}",
                err(&big)
            );
        }
        let hdr = dir.path().join("a.hdr");
        write_image(&radiance(), &hdr, &OutputOptions::default()).unwrap();
        let good = std::fs::read(&hdr).unwrap();
        std::fs::write(&hdr, &good[..good.len() - 3]).unwrap();
        assert!(
            err(&hdr).contains("invalid Radiance HDR file"),
            "{}",
            err(&hdr)
        );
    }
}
