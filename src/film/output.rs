//! Image files by extension, written atomically: a temporary file beside the target,
//! renamed over it only once complete, so a failed run never leaves a partial image.

use super::Image;
use crate::{Error, Result};
use image::ImageFormat;
use std::io::{BufWriter, Write};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Bmp,
    Jpeg,
    Ppm,
    Tga,
}

impl OutputFormat {
    pub const EXTENSIONS: &'static str = "png, bmp, jpg/jpeg, ppm, tga";

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

    fn image_format(self) -> ImageFormat {
        match self {
            OutputFormat::Png => ImageFormat::Png,
            OutputFormat::Bmp => ImageFormat::Bmp,
            OutputFormat::Jpeg => ImageFormat::Jpeg,
            OutputFormat::Ppm => ImageFormat::Pnm,
            OutputFormat::Tga => ImageFormat::Tga,
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
    target_dir(path)?;
    Ok(format)
}

/// Writes `image` to `path` in the format its extension names.
pub fn write_image(image: &Image, path: &Path) -> Result<()> {
    let format = check_output_path(path)?;
    write_atomically(path, |w| {
        image::write_buffer_with_format(
            w,
            &image.to_rgb8(),
            image.width,
            image.height,
            image::ExtendedColorType::Rgb8,
            format.image_format(),
        )
        .map_err(|e| Error::file(path, format!("cannot encode image: {e}")))
    })
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
            write_image(&tiny(), &p).unwrap();
            let back = image::open(&p).unwrap().to_rgb8();
            assert_eq!(back.as_raw(), &vec![255, 0, 0, 0, 128, 255], "{ext}");
        }
        let jpg = dir.path().join("a.jpg");
        write_image(&tiny(), &jpg).unwrap();
        assert_eq!(image::open(&jpg).unwrap().width(), 2);
        // Nothing but the outputs is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
    }

    #[test]
    fn bad_paths_are_refused_without_writing() {
        let dir = tempfile::tempdir().unwrap();
        let e = write_image(&tiny(), &dir.path().join("a.xyz")).unwrap_err();
        assert!(
            e.to_string().contains("unknown image extension `xyz`"),
            "{e}"
        );
        let e = write_image(&tiny(), &dir.path().join("missing/a.png")).unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
