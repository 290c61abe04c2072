//! Frames into a film: MP4 (H.264), animated GIF and animated PNG, with no outside
//! program. Each encoder takes 8-bit RGB frames of one size in order; the file is
//! written to a temporary name beside the target and renamed into place only when
//! complete.

mod apng;
mod colr;
mod gif;
#[cfg(feature = "h264")]
mod mp4;

use super::output::VideoFormat;
use crate::error::{Error, Result};
use crate::film::output::write_atomically;
use std::io::Write;
use std::path::Path;

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoInfo {
    /// Number of frames in the file.
    pub frames: u32,
    /// Size of the file written, in bytes (0 if it could not be read back).
    pub bytes: u64,
    /// The frame rate the file plays at on average: GIF delays are whole hundredths of
    /// a second (each frame is rounded so the whole film lasts as long as asked), MP4
    /// keeps the requested rate to 1/1000 of a frame per second, APNG to the nearest
    /// fraction of 16-bit numbers it can write (23.976 is exact).
    pub fps: f64,
}

/// Smallest width and height the H.264 encoder takes (one macroblock).
pub const MP4_MIN: u32 = 16;

/// Largest frame H.264 gets from the encoder (level 5.2).
pub const MP4_MAX: (u32, u32) = (3840, 2160);

/// Checks, before rendering, that frames of this size can go into this format.
pub fn check_size(format: VideoFormat, width: u32, height: u32, path: &Path) -> Result<()> {
    let refuse = |why: String| Err(Error::file(path, why));
    match format {
        VideoFormat::Mp4 => {
            if width < MP4_MIN || height < MP4_MIN {
                return refuse(format!(
                    "the H.264 encoder needs frames at least {MP4_MIN}x{MP4_MIN}, found \
                     {width}x{height}: set [render] width and height"
                ));
            }
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

/// What to tell the user about a GIF's timing at `fps`, if anything: GIF delays are
/// whole hundredths of a second.
pub fn gif_timing_note(fps: f64) -> Option<String> {
    if gif::too_fast_for_browsers(fps) {
        return Some(format!(
            "at {fps} fps some GIF frames last less than 2 hundredths of a second, which \
             browsers show for longer: use 50 fps or less for a GIF, or MP4 or APNG"
        ));
    }
    let hundredths = 100.0 / fps;
    (hundredths.fract() != 0.0).then(|| {
        format!(
            "GIF delays are whole hundredths of a second: frames last {} or {} hundredths, \
             so the film keeps {fps} fps on average",
            hundredths.floor(),
            hundredths.ceil()
        )
    })
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
    let mut fps_played = fps;
    write_atomically(path, |out| {
        let mut encoder: Box<dyn Encoder + '_> = match format {
            #[cfg(feature = "h264")]
            VideoFormat::Mp4 => Box::new(mp4::Mp4::new(&mut *out, path, width, height, fps)?),
            #[cfg(not(feature = "h264"))]
            VideoFormat::Mp4 => {
                return Err(Error::file(
                    path,
                    "this Prism is built without H.264 (the `h264` feature): MP4 output is \
                     not available",
                ));
            }
            VideoFormat::Gif => Box::new(gif::Gif::new(&mut *out, path, width, height, fps)?),
            VideoFormat::Apng => {
                Box::new(apng::Apng::new(&mut *out, path, width, height, fps, count)?)
            }
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
        fps_played = encoder.finish()?;
        if format == VideoFormat::Mp4 {
            out.flush().map_err(|e| write_error(path, e))?;
            colr::tag_bt601(out.get_ref()).map_err(|e| write_error(path, e))?;
        }
        Ok(())
    })?;
    let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
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
