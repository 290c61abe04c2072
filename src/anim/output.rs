//! Where the frames of an animation go, told by the output path, and which frames to
//! render (`--frames`).
//!
//! | output | result |
//! |---|---|
//! | an existing folder, a path ending in `/`, or a path without extension | numbered PNG frames `frame_0000.png`, ... in that folder (created if missing) |
//! | a path with `%04d` (or `%d`, `%0Nd`) in its file name | numbered images; the extension picks the image format |
//! | `.mp4` | H.264 video in an MP4 container |
//! | `.gif` | animated GIF |
//! | `.apng` or `.png` | animated PNG (lossless) |
//!
//! Every file is written atomically (temporary file, then rename), so a frame file that
//! exists is complete: a rerun skips it. Videos are built from numbered PNG frames kept
//! in `OUTPUT.frames/` beside the video until the video is written, so an interrupted
//! video render resumes too.

use crate::error::{Error, Result};
use crate::film::OutputFormat;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Numbered frame files: `dir/prefix{k:0width}suffix`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FramePattern {
    /// Folder the frames are written in (`.` for a bare file name).
    pub dir: PathBuf,
    /// File name before the frame number.
    pub prefix: String,
    /// Minimum digits of the frame number, zero-padded (1 to 9).
    pub width: usize,
    /// File name after the frame number, with the extension that picks the format.
    pub suffix: String,
}

impl FramePattern {
    /// `frame_0000.png`, ... in `dir`.
    pub fn in_folder(dir: &Path) -> FramePattern {
        FramePattern {
            dir: dir.to_path_buf(),
            prefix: "frame_".into(),
            width: 4,
            suffix: ".png".into(),
        }
    }

    /// The file of frame number `frame` (counted from 0).
    pub fn path_of(&self, frame: u32) -> PathBuf {
        let width = self.width;
        self.dir
            .join(format!("{}{frame:0width$}{}", self.prefix, self.suffix))
    }
}

/// The video formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VideoFormat {
    /// H.264 in an MP4 container (`.mp4`).
    Mp4,
    /// Animated GIF (`.gif`).
    Gif,
    /// Animated PNG, lossless (`.apng` or `.png`).
    Apng,
}

/// What `prism animate` writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Output {
    /// Numbered image files, one per frame, and nothing more.
    Frames(FramePattern),
    /// A video file, made from the PNG frames in `frames`.
    Video {
        /// The video file to write.
        path: PathBuf,
        /// Its container and codec, from the extension.
        format: VideoFormat,
        /// The PNG frames it is made from, in `OUTPUT.frames/` beside it.
        frames: FramePattern,
    },
}

const EXPECTED: &str = "expected a folder, a file name with %04d, or a file ending in .mp4, \
                        .gif, .apng or .png";

impl Output {
    /// The output `path` names. Nothing is created.
    pub fn from_path(path: &Path) -> Result<Output> {
        let text = path.to_string_lossy();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if name.contains('%') {
            return pattern(path, &name).map(Output::Frames);
        }
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if path.is_dir() || text.ends_with('/') || ext.is_none() {
            return Ok(Output::Frames(FramePattern::in_folder(path)));
        }
        let ext = ext.unwrap_or_default();
        let format = match ext.as_str() {
            "mp4" => VideoFormat::Mp4,
            "gif" => VideoFormat::Gif,
            "apng" | "png" => VideoFormat::Apng,
            _ => {
                return Err(Error::file(
                    path,
                    format!("unknown output extension `{ext}`: {EXPECTED}"),
                ));
            }
        };
        let mut work = path.as_os_str().to_owned();
        work.push(".frames");
        Ok(Output::Video {
            path: path.to_path_buf(),
            format,
            frames: FramePattern::in_folder(Path::new(&work)),
        })
    }

    /// Where the frames are written.
    pub fn frames(&self) -> &FramePattern {
        match self {
            Output::Frames(p) => p,
            Output::Video { frames, .. } => frames,
        }
    }
}

/// `dir/prefix%0Nd.ext` split up; the extension must be an image format Prism writes.
fn pattern(path: &Path, name: &str) -> Result<FramePattern> {
    let bad = |why: &str| Error::file(path, format!("bad frame pattern `{name}`: {why}"));
    let at = name.find('%').unwrap_or(0);
    let (prefix, rest) = name.split_at(at);
    let rest = &rest[1..];
    let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    let after = &rest[digits.len()..];
    let Some(suffix) = after.strip_prefix('d') else {
        return Err(bad("expected %d or %0Nd, such as %04d"));
    };
    if suffix.contains('%') {
        return Err(bad("expected one %d"));
    }
    let width = if digits.is_empty() {
        1
    } else {
        digits
            .parse::<usize>()
            .ok()
            .filter(|&w| (1..=9).contains(&w))
            .ok_or_else(|| bad("expected a width from 1 to 9"))?
    };
    OutputFormat::from_path(Path::new(&format!("frame{suffix}")))?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok(FramePattern {
        dir,
        prefix: prefix.to_string(),
        width,
        suffix: suffix.to_string(),
    })
}

/// Parses `--frames`: `A..B` (B excluded), `A..=B`, `A..`, `..B` or one frame `N`,
/// checked against an animation of `count` frames.
pub fn parse_frame_range(text: &str, count: u32) -> Result<Range<u32>> {
    let bad = || {
        Error::Settings(format!(
            "--frames: expected A..B, A..=B, A.., ..B or N (frame numbers from 0), found `{text}`"
        ))
    };
    let number = |s: &str, default: u32| -> Result<u32> {
        if s.is_empty() {
            Ok(default)
        } else {
            s.trim().parse().map_err(|_| bad())
        }
    };
    if text.trim().is_empty() {
        return Err(bad());
    }
    let range = if let Some((a, b)) = text.split_once("..=") {
        number(a, 0)?..number(b, u32::MAX - 1)?.saturating_add(1)
    } else if let Some((a, b)) = text.split_once("..") {
        number(a, 0)?..number(b, count)?
    } else {
        let n = number(text, 0)?;
        n..n.saturating_add(1)
    };
    if range.start >= range.end || range.end > count {
        return Err(Error::Settings(format!(
            "--frames {text}: the animation has frames 0..{count} (0 to {}), and the range \
             must hold at least one",
            count - 1
        )));
    }
    Ok(range)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_by_path() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        assert_eq!(
            Output::from_path(d).unwrap(),
            Output::Frames(FramePattern::in_folder(d))
        );
        assert_eq!(
            Output::from_path(&d.join("new")).unwrap(),
            Output::Frames(FramePattern::in_folder(&d.join("new")))
        );
        let Output::Frames(p) = Output::from_path(&d.join("shot_%05d.bmp")).unwrap() else {
            panic!()
        };
        assert_eq!(p.path_of(42), d.join("shot_00042.bmp"));
        let Output::Frames(p) = Output::from_path(Path::new("f%d.png")).unwrap() else {
            panic!()
        };
        assert_eq!(p.path_of(7), Path::new("./f7.png"));
        assert_eq!(
            FramePattern::in_folder(d).path_of(3),
            d.join("frame_0003.png")
        );
        let Output::Video { format, frames, .. } = Output::from_path(&d.join("a.MP4")).unwrap()
        else {
            panic!()
        };
        assert_eq!(format, VideoFormat::Mp4);
        assert_eq!(frames.dir, d.join("a.MP4.frames"));
        for (name, f) in [("a.gif", VideoFormat::Gif), ("a.apng", VideoFormat::Apng)] {
            let Output::Video { format, .. } = Output::from_path(&d.join(name)).unwrap() else {
                panic!()
            };
            assert_eq!(format, f);
        }
    }

    #[test]
    fn bad_outputs_are_refused() {
        let e = Output::from_path(Path::new("film.avi"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("film.avi: unknown output extension `avi`"),
            "{e}"
        );
        for bad in ["f%x.png", "f%04d%04d.png", "f%04d.xyz", "f%00d.png"] {
            assert!(Output::from_path(Path::new(bad)).is_err(), "{bad}");
        }
    }

    #[test]
    fn frame_ranges() {
        assert_eq!(parse_frame_range("2..5", 10).unwrap(), 2..5);
        assert_eq!(parse_frame_range("2..=5", 10).unwrap(), 2..6);
        assert_eq!(parse_frame_range("7..", 10).unwrap(), 7..10);
        assert_eq!(parse_frame_range("..3", 10).unwrap(), 0..3);
        assert_eq!(parse_frame_range("9", 10).unwrap(), 9..10);
        for bad in ["5..2", "3..3", "0..11", "10", "a..b", "", "-1..2", "0..=10"] {
            assert!(parse_frame_range(bad, 10).is_err(), "{bad}");
        }
    }
}
