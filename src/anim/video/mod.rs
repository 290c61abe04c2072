//! Frames into a film: MP4 (H.264), animated GIF and animated PNG, with no outside
//! program. Each encoder takes 8-bit RGB frames of one size in order; the file is
//! written to a temporary name beside the target and renamed into place only when
//! complete.

mod apng;
mod colr;
mod gif;
mod mp4;

use super::output::VideoFormat;
use crate::{Error, Result};
use std::io::BufWriter;
use std::path::Path;

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoInfo {
    pub frames: u32,
    pub bytes: u64,
    /// The frame rate the file really plays at: GIF delays are whole hundredths of a
    /// second (24 fps becomes 25), MP4 and APNG keep the requested rate to 1/1000 and
    /// 1/100 of a frame per second.
    pub fps: f64,
}

/// Largest frame H.264 gets from the encoder (level 5.2).
pub const MP4_MAX: (u32, u32) = (3840, 2160);

/// Checks, before rendering, that frames of this size can go into this format.
pub fn check_size(format: VideoFormat, width: u32, height: u32, path: &Path) -> Result<()> {
    let refuse = |why: String| Err(Error::file(path, why));
    match format {
        VideoFormat::Mp4 => {
            if !width.is_multiple_of(2) || !height.is_multiple_of(2) {
                return refuse(format!(
                    "H.264 (4:2:0) needs an even width and height, found {width}x{height}: \
                     set [render] width and height to even numbers"
                ));
            }
            let (big, small) = (width.max(height), width.min(height));
            if big > MP4_MAX.0 || small > MP4_MAX.1 {
                return refuse(format!(
                    "the H.264 encoder takes frames up to {}x{}, found {width}x{height}",
                    MP4_MAX.0, MP4_MAX.1
                ));
            }
        }
        VideoFormat::Gif => {
            if width > u16::MAX as u32 || height > u16::MAX as u32 {
                return refuse(format!(
                    "a GIF frame is at most 65535 pixels a side, found {width}x{height}"
                ));
            }
        }
        VideoFormat::Apng => {}
    }
    Ok(())
}

/// An encoder that is handed frames one by one.
trait Encoder {
    fn push(&mut self, rgb: &[u8]) -> Result<()>;
    /// Writes what is left; returns the frame rate the file plays at.
    fn finish(self: Box<Self>) -> Result<f64>;
}

/// Encodes `count` frames of `width` x `height`, obtained in order from `frame(i)` (8-bit
/// RGB rows, top to bottom), into `path`. `progress` is called after each frame.
pub fn encode(
    format: VideoFormat,
    path: &Path,
    (width, height): (u32, u32),
    fps: f64,
    count: u32,
    frame: &mut dyn FnMut(u32) -> Result<Vec<u8>>,
    progress: &dyn Fn(),
) -> Result<VideoInfo> {
    check_size(format, width, height, path)?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".prism-").suffix(".part");
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder
        .tempfile_in(dir)
        .map_err(|e| Error::file(path, format!("cannot create a temporary file: {e}")))?;
    let fps_played = {
        let out = BufWriter::new(tmp.as_file());
        let mut encoder: Box<dyn Encoder + '_> = match format {
            VideoFormat::Mp4 => Box::new(mp4::Mp4::new(out, path, width, height, fps)?),
            VideoFormat::Gif => Box::new(gif::Gif::new(out, path, width, height, fps)?),
            VideoFormat::Apng => Box::new(apng::Apng::new(out, path, width, height, fps, count)?),
        };
        for i in 0..count {
            let rgb = frame(i)?;
            if rgb.len() != width as usize * height as usize * 3 {
                return Err(Error::file(
                    path,
                    format!("frame {i} is not {width}x{height} RGB"),
                ));
            }
            encoder.push(&rgb)?;
            progress();
        }
        encoder.finish()?
    };
    if format == VideoFormat::Mp4 {
        colr::tag_bt601(tmp.as_file()).map_err(|e| write_error(path, e))?;
    }
    let bytes = tmp.as_file().metadata().map(|m| m.len()).unwrap_or(0);
    tmp.persist(path)
        .map_err(|e| Error::file(path, format!("cannot write: {}", e.error)))?;
    Ok(VideoInfo {
        frames: count,
        bytes,
        fps: fps_played,
    })
}

/// An encoding or write error, named after the file.
fn write_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::file(path, format!("cannot write: {e}"))
}

#[cfg(test)]
mod tests;
