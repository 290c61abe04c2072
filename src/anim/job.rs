//! Rendering a range of frames to files and joining them into a video: what
//! `prism animate` does, with progress reported through callbacks.

use super::Animation;
use super::output::{FramePattern, Output};
use super::video::{self, VideoInfo};
use crate::error::{Error, Result};
use crate::film::OutputFile;
use crate::film::output::write_atomically;
use std::io::Write;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

/// Progress callbacks: a frame starts (with its number of progress units), units
/// finish (from any thread), a frame is done (rendered, or skipped because its file
/// exists).
pub struct FrameObserver<'a> {
    /// Frame `k` starts rendering, with the supersampled rows it will trace (its
    /// progress units).
    pub frame_start: &'a (dyn Fn(u32, u64) + Sync),
    /// That many more supersampled rows of the current frame are done (any thread).
    pub rows: &'a (dyn Fn(u64) + Sync),
    /// Frame `k` is done: `true` when it was skipped because its file existed.
    pub frame_done: &'a (dyn Fn(u32, bool) + Sync),
}

/// A frame's render as the frame observer and the frame's file see it.
struct FrameWatch<'a> {
    frame: u32,
    observer: &'a FrameObserver<'a>,
    /// Where rows go as they come; `None` when the frame is denoised, and so written
    /// whole once it is.
    file: Option<&'a OutputFile>,
}

impl crate::render::Observer for FrameWatch<'_> {
    fn begin(&self, _region: crate::render::Region, units: u64) {
        (self.observer.frame_start)(self.frame, units)
    }
    fn progress(&self, units: u64) {
        (self.observer.rows)(units)
    }
    fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        // A PNG frame is compressed while the frame renders.
        if let Some(file) = self.file {
            file.rows(first_row, pixels)
        }
    }
}

/// What rendering the frames did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FramesReport {
    /// Frames rendered and written by this run.
    pub rendered: u32,
    /// Frames whose file was already there (an earlier, interrupted run).
    pub skipped: u32,
    /// Rays traced over the rendered frames.
    pub rays: u64,
    /// Wall-clock seconds of the whole run, skipped frames included.
    pub seconds: f64,
}

/// Checks everything that can be checked before the first frame: every frame's camera,
/// the frame size for the video format, the folders. Nothing is written.
pub fn check(anim: &Animation, frames: Range<u32>, output: &Output) -> Result<()> {
    anim.check(frames)?;
    let size = anim.frame_size()?;
    if let Output::Video { path, format, .. } = output {
        video::check_size(*format, size.0, size.1, path)?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
            && !dir.is_dir()
        {
            return Err(Error::file(
                path,
                format!("output folder `{}` does not exist", dir.display()),
            ));
        }
    }
    let frames_dir = &output.frames().dir;
    if frames_dir.exists() && !frames_dir.is_dir() {
        return Err(Error::file(frames_dir, "exists and is not a folder"));
    }
    check_manifest(anim, frames_dir)
}

/// Age beyond which a temporary file in a frame folder is a crash's leftover.
const STALE_PART: std::time::Duration = std::time::Duration::from_secs(600);

/// The file in a frame folder that says which animation its frames are of.
pub const MANIFEST: &str = ".prism-animation";

fn manifest_text(anim: &Animation) -> String {
    // Denoised frames are other frames: a folder holds one kind.
    let denoised = if anim.denoise { "denoised\n" } else { "" };
    format!(
        "prism animation frames\nfingerprint {:016x}\n{denoised}",
        anim.fingerprint
    )
}

/// Refuses a frame folder whose frames were rendered from other inputs (animation,
/// scene or camera file): resuming would mix frames of two animations.
fn check_manifest(anim: &Animation, dir: &Path) -> Result<()> {
    let path = dir.join(MANIFEST);
    let Ok(found) = std::fs::read_to_string(&path) else {
        return Ok(());
    };
    if found != manifest_text(anim) {
        return Err(Error::file(
            dir,
            format!(
                "holds frames of another version of the animation (its {MANIFEST} does not \
                 match {} and the scene and camera files): delete the folder to render \
                 them again, or use another output",
                anim.path.display()
            ),
        ));
    }
    Ok(())
}

/// Creates the frame folder, removes temporary files a crashed run left in it, and
/// writes its manifest.
fn prepare_folder(anim: &Animation, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::file(dir, format!("cannot create the folder: {e}")))?;
    check_manifest(anim, dir)?;
    let entries =
        std::fs::read_dir(dir).map_err(|e| Error::file(dir, format!("cannot read: {e}")))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        // A temporary file lives for the seconds it takes to write one frame: one older
        // than ten minutes was left by a crash. Younger ones may be another machine's,
        // rendering other frames into the same folder.
        let stale = entry
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age > STALE_PART);
        if name.starts_with(".prism-") && name.ends_with(".part") && stale {
            let _ = std::fs::remove_file(entry.path());
        }
    }
    let path = dir.join(MANIFEST);
    if !path.is_file() {
        write_atomically(&path, |w| {
            w.write_all(manifest_text(anim).as_bytes())
                .map_err(|e| Error::file(&path, format!("cannot write: {e}")))
        })?;
    }
    Ok(())
}

/// Renders each frame of `frames` whose file does not exist yet into `pattern`, each
/// written atomically: a file that exists is a complete frame.
pub fn render_frames(
    anim: &Animation,
    frames: Range<u32>,
    pattern: &FramePattern,
    observer: &FrameObserver,
) -> Result<FramesReport> {
    prepare_folder(anim, &pattern.dir)?;
    let start = Instant::now();
    let mut report = FramesReport::default();
    // One copy of the scene (textures included) for the whole run; each frame rewrites
    // only what moves.
    let mut posed = anim.scene.clone();
    let mut still = None;
    for k in frames {
        if anim.cancelled() {
            return Err(Error::Interrupted);
        }
        let path = pattern.path_of(k);
        if path.is_file() {
            report.skipped += 1;
            (observer.frame_done)(k, true);
            continue;
        }
        if still.is_none() {
            // Built at the first frame rendered, so a resumed run that skips every
            // frame builds nothing.
            still = Some(anim.still_geometry()?);
        }
        let size = anim.frame_size()?;
        // A PNG frame is compressed while the frame renders, unless it is denoised.
        let file = if anim.denoise {
            None
        } else {
            Some(OutputFile::create(&path, size.0, size.1, &anim.output)?)
        };
        let watch = FrameWatch {
            frame: k,
            observer,
            file: file.as_ref(),
        };
        let (image, stats) = anim.render_frame_in(
            k,
            &mut posed,
            still.as_ref().and_then(Option::as_ref),
            &watch,
        )?;
        if anim.cancelled() {
            return Err(Error::Interrupted);
        }
        match file {
            Some(file) => file.finish(&image)?,
            None => crate::film::write_image(&image, &path, &anim.output)?,
        }
        report.rendered += 1;
        report.rays += stats.rays;
        (observer.frame_done)(k, false);
    }
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// Joins the frame files of `frames` into the video `output` names; `progress` is
/// called after each frame. Returns what was written and the seconds it took.
pub fn encode_frames(
    anim: &Animation,
    frames: Range<u32>,
    output: &Output,
    progress: &dyn Fn(),
) -> Result<(VideoInfo, f64)> {
    let Output::Video {
        path,
        format,
        frames: pattern,
    } = output
    else {
        return Err(Error::Settings("not a video output".into()));
    };
    let start = Instant::now();
    let size = anim.frame_size()?;
    let first = frames.start;
    let info = video::encode(
        *format,
        path,
        size,
        anim.fps,
        frames.len() as u32,
        &mut |i| {
            // Stopping here drops the half-written video (it is a temporary file).
            if anim.cancelled() {
                return Err(Error::Interrupted);
            }
            read_frame(&pattern.path_of(first + i), size)
        },
        progress,
    )?;
    Ok((info, start.elapsed().as_secs_f64()))
}

/// A frame file as 8-bit RGB, checked to be the animation's size.
fn read_frame(path: &Path, (width, height): (u32, u32)) -> Result<Vec<u8>> {
    let image = image::open(path)
        .map_err(|e| Error::file(path, format!("cannot read frame: {e}")))?
        .to_rgb8();
    if image.dimensions() != (width, height) {
        return Err(Error::file(
            path,
            format!(
                "frame is {}x{}, the animation's frames are {width}x{height}: delete the \
                 frames of an earlier run with other settings",
                image.width(),
                image.height()
            ),
        ));
    }
    Ok(image.into_raw())
}

/// Frames of `0..count` whose file is not in `pattern`'s folder yet.
pub fn missing_frames(pattern: &FramePattern, count: u32) -> u32 {
    (0..count)
        .filter(|&k| !pattern.path_of(k).is_file())
        .count() as u32
}

/// Deletes the frame files of `frames` and the folder's manifest, and then the folder
/// if that left it empty.
pub fn remove_frames(pattern: &FramePattern, frames: Range<u32>) {
    for k in frames {
        let _ = std::fs::remove_file(pattern.path_of(k));
    }
    let _ = std::fs::remove_file(pattern.dir.join(MANIFEST));
    let _ = std::fs::remove_dir(&pattern.dir);
}

/// The stamp beside a finished video (`.NAME.prism`): the fingerprint of the animation
/// it was made from, so a rerun of a finished film does no work.
fn video_stamp(video: &Path) -> std::path::PathBuf {
    let name = video
        .file_name()
        .map_or_else(|| "video".into(), |n| n.to_string_lossy().into_owned());
    video.with_file_name(format!(".{name}.prism"))
}

fn stamp_text(anim: &Animation) -> String {
    format!(
        "prism video 1\nfingerprint {:016x}\nframes {}\n",
        anim.fingerprint, anim.frames
    )
}

/// Whether `video` exists and was made from this very animation (same files, same
/// frame count): then there is nothing to render or encode.
pub fn video_is_current(anim: &Animation, video: &Path) -> bool {
    video.is_file()
        && std::fs::read_to_string(video_stamp(video)).is_ok_and(|t| t == stamp_text(anim))
}

/// Records that `video` now holds `anim` (after it was encoded).
pub fn mark_video_current(anim: &Animation, video: &Path) -> Result<()> {
    let stamp = video_stamp(video);
    write_atomically(&stamp, |w| {
        w.write_all(stamp_text(anim).as_bytes())
            .map_err(|e| Error::file(&stamp, format!("cannot write: {e}")))
    })
}
