//! Image files by extension, written atomically: a temporary file beside the target,
//! renamed over it only once complete, so a failed run never leaves a partial image.

use super::Image;
use super::develop::Develop;
use super::stream::PngStream;
use crate::error::{Error, Result};
use crate::util::hdr::{ExrPrecision, write_exr, write_hdr};
use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use image::{ExtendedColorType, ImageEncoder, ImageFormat};
use rayon::prelude::*;
use std::fmt;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// An image file format, chosen by the output path's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// PNG: developed RGB, 8 or 16 bits per channel ([`PngBits`]); compressed band by
    /// band while the render runs.
    Png,
    /// BMP: developed 8-bit RGB.
    Bmp,
    /// JPEG: developed 8-bit RGB, lossy.
    Jpeg,
    /// Binary PPM (`P6`): developed 8-bit RGB.
    Ppm,
    /// TGA: developed 8-bit RGB.
    Tga,
    /// OpenEXR: linear radiance, half or float.
    Exr,
    /// Radiance RGBE: linear radiance, 8-bit mantissas sharing an exponent.
    Hdr,
}

impl OutputFormat {
    /// The extensions [`OutputFormat::from_path`] knows, listed for messages.
    pub const EXTENSIONS: &'static str = "png, bmp, jpg/jpeg, ppm, tga, exr, hdr";

    /// The format named by `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<OutputFormat> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        Ok(match ext.as_str() {
            "png" => OutputFormat::Png,
            "bmp" => OutputFormat::Bmp,
            "jpg" | "jpeg" => OutputFormat::Jpeg,
            "ppm" => OutputFormat::Ppm,
            "tga" => OutputFormat::Tga,
            "exr" => OutputFormat::Exr,
            "hdr" => OutputFormat::Hdr,
            _ => {
                return Err(Error::file(
                    path,
                    format!(
                        "unknown image extension `{ext}`: expected one of {}",
                        Self::EXTENSIONS
                    ),
                ));
            }
        })
    }

    /// Whether the file stores radiance as is rather than developed display values.
    pub fn is_linear(self) -> bool {
        matches!(self, OutputFormat::Exr | OutputFormat::Hdr)
    }
}

/// Bits per channel of a PNG file; the other display formats always have 8.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PngBits {
    /// 256 levels, as every viewer reads.
    #[default]
    Eight,
    /// 65536 levels: no banding in smooth gradients, and room for later grading.
    Sixteen,
}

impl fmt::Display for PngBits {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            PngBits::Eight => "8",
            PngBits::Sixteen => "16",
        })
    }
}

impl FromStr for PngBits {
    type Err = String;

    fn from_str(s: &str) -> Result<PngBits, String> {
        match s {
            "8" => Ok(PngBits::Eight),
            "16" => Ok(PngBits::Sixteen),
            _ => Err(format!(
                "unknown PNG depth {}: expected 8 or 16",
                crate::util::text::shown(s)
            )),
        }
    }
}

/// How an image becomes a file: display formats are developed, linear ones
/// (`OutputFormat::is_linear`) ignore `develop` and store radiance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OutputOptions {
    /// Exposure, tone map and transfer curve from radiance to display values.
    pub develop: Develop,
    /// Bits per channel of a PNG file.
    pub png_bits: PngBits,
    /// Sample type of an OpenEXR file's channels.
    pub exr_precision: ExrPrecision,
}

impl OutputOptions {
    /// The 2014 program's output: classic development, 8-bit PNG.
    pub fn classic() -> OutputOptions {
        OutputOptions {
            develop: Develop::classic(),
            ..OutputOptions::default()
        }
    }
}

/// The folder `path` will be written into; it must exist.
fn target_dir(path: &Path) -> Result<&Path> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(Error::file(
            path,
            format!("output folder `{}` does not exist", dir.display()),
        ));
    }
    Ok(dir)
}

/// Checks, before any rendering, that `path` can be written: known extension, existing
/// folder.
pub fn check_output_path(path: &Path) -> Result<OutputFormat> {
    let format = OutputFormat::from_path(path)?;
    let dir = target_dir(path)?;
    // A folder that cannot take the file is found now, not after the render: the
    // temporary file the writer would make, made and dropped at once.
    tempfile::Builder::new()
        .prefix(".prism-")
        .suffix(".part")
        .tempfile_in(dir)
        .map_err(|e| Error::file(path, format!("cannot write into `{}`: {e}", dir.display())))?;
    Ok(format)
}

/// Rows of a finished image developed as one task when it is written as a PNG.
const STREAM_ROWS: usize = 32;

/// Writes `image` to `path` in the format its extension names, developed as `options`
/// say for display formats (a job's [`crate::job::Job::output`] says it for a render;
/// [`OutputOptions::classic`] keeps a classic render's exact values).
pub fn write_image(image: &Image, path: &Path, options: &OutputOptions) -> Result<()> {
    let format = check_output_path(path)?;
    let cannot_encode =
        |e: &dyn fmt::Display| Error::file(path, format!("cannot encode image: {e}"));
    let (w, h) = (image.width, image.height);
    if format == OutputFormat::Png {
        // The writer a render streams into, given the image in bands: a PNG has the
        // same bytes whether its render streamed it or not.
        let stream = PngStream::new(path, w, h, options)?;
        image
            .pixels
            .par_chunks((w as usize).max(1) * STREAM_ROWS)
            .enumerate()
            .for_each(|(i, band)| stream.rows((i * STREAM_ROWS) as u32, band));
        return stream.finish();
    }
    write_atomically(path, |out| match format {
        OutputFormat::Exr => {
            write_exr(image, options.exr_precision, out).map_err(|e| cannot_encode(&e))
        }
        OutputFormat::Hdr => write_hdr(image, out).map_err(|e| cannot_encode(&e)),
        // Binary PPM (`P6`), which every tool reads, rather than the image crate's
        // default for PNM output, PAM (`P7`).
        OutputFormat::Ppm => PnmEncoder::new(out)
            .with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary))
            .write_image(
                &options.develop.to_rgb8(image),
                w,
                h,
                ExtendedColorType::Rgb8,
            )
            .map_err(|e| cannot_encode(&e)),
        OutputFormat::Png => unreachable!("PNG files are written above"),
        OutputFormat::Bmp | OutputFormat::Jpeg | OutputFormat::Tga => {
            let image_format = match format {
                OutputFormat::Bmp => ImageFormat::Bmp,
                OutputFormat::Jpeg => ImageFormat::Jpeg,
                _ => ImageFormat::Tga,
            };
            let rgb8 = options.develop.to_rgb8(image);
            image::write_buffer_with_format(out, &rgb8, w, h, ExtendedColorType::Rgb8, image_format)
                .map_err(|e| cannot_encode(&e))
        }
    })
}

/// Writes `image` to `path` as OpenEXR with each pass of `passes` as a layer named
/// after it ([`crate::options::Aov`]); a path of another format is refused.
pub fn write_exr_with_passes(
    image: &Image,
    passes: &[(crate::options::Aov, Image)],
    path: &Path,
    options: &OutputOptions,
) -> Result<()> {
    if check_output_path(path)? != OutputFormat::Exr {
        return Err(Error::Settings(format!(
            "passes (--aov) are written as layers of an OpenEXR file: {} is not .exr",
            crate::util::text::shown(&path.display().to_string())
        )));
    }
    let layers: Vec<(&str, &[&str], &Image)> = passes
        .iter()
        .map(|(aov, img)| (aov.name(), aov.channels(), img))
        .collect();
    write_atomically(path, |out| {
        crate::util::hdr::write_exr_layers(image, &layers, options.exr_precision, out)
            .map_err(|e| Error::file(path, format!("cannot encode image: {e}")))
    })
}

/// The bytes of the file `image` would be written as with extension `ext`: written
/// in a private temporary folder by [`write_image`] and read back, so they are the
/// bytes a file of that name gets.
pub fn file_bytes(image: &Image, ext: &str, options: &OutputOptions) -> Result<Vec<u8>> {
    let dir = tempfile::tempdir().map_err(|e| Error::file(Path::new("."), e))?;
    let path = dir.path().join(format!("image.{ext}"));
    write_image(image, &path, options)?;
    std::fs::read(&path).map_err(|e| Error::file(&path, e))
}

/// An image file a render writes as it goes: a PNG is developed and compressed band by
/// band while the render runs ([`PngStream`]), any other format is written from the
/// finished image. Nothing is on disk before [`OutputFile::finish`].
pub struct OutputFile {
    path: PathBuf,
    options: OutputOptions,
    png: Option<PngStream>,
}

impl OutputFile {
    /// The file at `path` for an image of `width x height` pixels.
    pub fn create(
        path: &Path,
        width: u32,
        height: u32,
        options: &OutputOptions,
    ) -> Result<OutputFile> {
        Ok(OutputFile {
            path: path.to_path_buf(),
            options: *options,
            png: PngStream::for_output(path, width, height, options)?,
        })
    }

    /// Whole rows of the image from `first_row` on, as the render finishes them (the
    /// rows a render's [`crate::render::Observer`] is handed).
    pub fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        if let Some(png) = &self.png {
            png.rows(first_row, pixels);
        }
    }

    /// Writes the file; `image` is the finished render, every row of which went
    /// through [`OutputFile::rows`] when the format streams.
    pub fn finish(self, image: &Image) -> Result<()> {
        match self.png {
            Some(png) => png.finish(),
            None => write_image(image, &self.path, &self.options),
        }
    }
}

/// Writes a file through a temporary file in the same folder, renamed over `path` only
/// once `write` has succeeded: a failed or interrupted run leaves no partial file.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&std::fs::File>) -> Result<()>,
) -> Result<()> {
    let dir = target_dir(path)?;
    let mut builder = tempfile::Builder::new();
    builder.prefix(".prism-").suffix(".part");
    // Temporary files are private by default; the output gets the permissions of any
    // file the user creates (0666 less the umask).
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder
        .tempfile_in(dir)
        .map_err(|e| Error::file(path, format!("cannot create a temporary file: {e}")))?;
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w)?;
        w.flush()
            .map_err(|e| Error::file(path, format!("cannot write: {e}")))?;
        // On disk before the name appears: a file that exists after a crash is whole.
        w.get_ref()
            .sync_all()
            .map_err(|e| Error::file(path, format!("cannot write: {e}")))?;
    }
    tmp.persist(path)
        .map_err(|e| Error::file(path, format!("cannot write: {}", e.error)))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> Image {
        Image::new(2, 1, vec![[1.0, 0.0, 0.0], [0.0, 0.5, 1.0]])
    }

    #[test]
    fn every_format_round_trips_through_the_image_crate() {
        let dir = tempfile::tempdir().unwrap();
        for ext in ["png", "bmp", "ppm", "tga", "PNG"] {
            let p = dir.path().join(format!("a.{ext}"));
            write_image(&tiny(), &p, &OutputOptions::classic()).unwrap();
            let back = image::open(&p).unwrap().to_rgb8();
            assert_eq!(back.as_raw(), &vec![255, 0, 0, 0, 128, 255], "{ext}");
        }
        let jpg = dir.path().join("a.jpg");
        write_image(&tiny(), &jpg, &OutputOptions::classic()).unwrap();
        assert_eq!(image::open(&jpg).unwrap().width(), 2);
        // Nothing but the outputs is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
    }

    #[test]
    fn bad_paths_are_refused_without_writing() {
        let dir = tempfile::tempdir().unwrap();
        let e = write_image(
            &tiny(),
            &dir.path().join("a.xyz"),
            &OutputOptions::classic(),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains(
                "unknown image extension `xyz`: expected one of png, bmp, jpg/jpeg, ppm, tga, \
                 exr, hdr"
            ),
            "{e}"
        );
        let e = write_image(
            &tiny(),
            &dir.path().join("missing/a.png"),
            &OutputOptions::classic(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// What `write_image` wrote before development existed: today's 8-bit values through
    /// the image crate.
    fn legacy_bytes(image: &Image, format: ImageFormat) -> Vec<u8> {
        let mut out = std::io::Cursor::new(Vec::new());
        let (w, h) = (image.width, image.height);
        image::write_buffer_with_format(
            &mut out,
            &image.to_rgb8(),
            w,
            h,
            ExtendedColorType::Rgb8,
            format,
        )
        .unwrap();
        out.into_inner()
    }

    /// Classic-model values and beyond: out of range, NaN, rounding edges.
    fn classic_render() -> Image {
        let values = [
            0.0,
            0.2,
            0.5,
            0.5 / 255.0,
            1.0,
            1.7,
            -0.3,
            f32::NAN,
            0.999,
            0.25,
        ];
        let pixels = (0..12).map(|i| [values[i % 10], values[(i + 3) % 10], values[(i + 7) % 10]]);
        Image::new(4, 3, pixels.collect())
    }

    #[test]
    fn classic_outputs_keep_their_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let image = classic_render();
        for (ext, format) in [
            ("png", ImageFormat::Png),
            ("bmp", ImageFormat::Bmp),
            ("jpg", ImageFormat::Jpeg),
            ("tga", ImageFormat::Tga),
        ] {
            let p = dir.path().join(format!("a.{ext}"));
            write_image(&image, &p, &OutputOptions::classic()).unwrap();
            let bytes = std::fs::read(&p).unwrap();
            let legacy = legacy_bytes(&image, format);
            if format == ImageFormat::Png {
                // Lossless: the pixels are what counts, not how they were compressed
                // (PNG files are written as the render streams them).
                let decoded = |b: &[u8]| image::load_from_memory(b).unwrap().to_rgb8();
                assert_eq!(decoded(&bytes), decoded(&legacy), "{ext}");
            } else {
                assert_eq!(bytes, legacy, "{ext}");
            }
        }
    }

    #[test]
    fn ppm_is_binary_pixmap() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.ppm");
        write_image(&tiny(), &p, &OutputOptions::classic()).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert!(bytes.starts_with(b"P6\n"), "{:?}", &bytes[..8]);
        // Netpbm allows any whitespace between the header's numbers.
        assert_eq!(bytes, b"P6\n2 1 255\n\xff\x00\x00\x00\x80\xff");
    }

    #[test]
    fn sixteen_bit_png_reads_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        let image = Image::new(2, 1, vec![[0.0, 0.5, 1.0], [0.001, 3.0, f32::NAN]]);
        let options = OutputOptions {
            png_bits: PngBits::Sixteen,
            ..OutputOptions::default()
        };
        write_image(&image, &p, &options).unwrap();
        let back = image::open(&p).unwrap();
        assert_eq!(back.color(), image::ColorType::Rgb16);
        // sRGB: 0.5 -> 0.7353570 * 65535 = 48191.6; 0.001 -> 0.01292 * 65535 = 846.7.
        assert_eq!(
            back.into_rgb16().into_raw(),
            [0, 48192, 65535, 847, 65535, 0]
        );
    }

    #[test]
    fn display_development_applies_to_eight_bit_outputs() {
        let dir = tempfile::tempdir().unwrap();
        let image = Image::new(1, 1, vec![[0.5, 0.25, 2.0]]);
        let options = OutputOptions {
            develop: Develop {
                exposure: 1.0,
                ..Develop::display()
            },
            ..OutputOptions::default()
        };
        for ext in ["png", "ppm", "bmp", "tga"] {
            let p = dir.path().join(format!("a.{ext}"));
            write_image(&image, &p, &options).unwrap();
            // Doubled to 1, 0.5 and 4: sRGB 255, 188 and clamped 255.
            let back = image::open(&p).unwrap().into_rgb8().into_raw();
            assert_eq!(back, [255, 188, 255], "{ext}");
        }
        assert_eq!(OutputOptions::default().develop, Develop::display());
        assert_eq!(OutputOptions::default().png_bits, PngBits::Eight);
    }

    #[test]
    fn png_bits_parse() {
        assert_eq!("8".parse::<PngBits>(), Ok(PngBits::Eight));
        assert_eq!("16".parse::<PngBits>(), Ok(PngBits::Sixteen));
        assert_eq!(PngBits::Sixteen.to_string(), "16");
        let e = "12".parse::<PngBits>().unwrap_err();
        assert_eq!(e, "unknown PNG depth `12`: expected 8 or 16");
    }

    #[test]
    fn linear_formats_by_extension() {
        let f = |name: &str| OutputFormat::from_path(Path::new(name)).unwrap();
        assert_eq!(
            (f("a.exr"), f("a.HDR")),
            (OutputFormat::Exr, OutputFormat::Hdr)
        );
        assert!(f("a.exr").is_linear() && f("a.hdr").is_linear() && !f("a.png").is_linear());
    }

    #[test]
    fn failed_encoding_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let empty = Image::new(0, 0, Vec::new());
        let old = dir.path().join("old.png");
        std::fs::write(&old, b"previous").unwrap();
        for name in ["a.png", "a.exr", "a.jpg", "old.png"] {
            let e =
                write_image(&empty, &dir.path().join(name), &OutputOptions::classic()).unwrap_err();
            assert!(e.to_string().contains("cannot encode image"), "{name}: {e}");
        }
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["old.png"]);
        assert_eq!(std::fs::read(&old).unwrap(), b"previous");
    }
}
