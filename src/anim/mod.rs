//! Scene motion: an animation file poses a [`Scene`] and [`Camera`] per frame; the
//! renderer is unchanged, and [`video`] joins the frames into a film.
//!
//! - [`file`](mod@file): the TOML animation file (`docs/animation.md`), parsed and checked;
//! - [`curve`]: keyframes and interpolation;
//! - [`motion`]: targets, motions and the rigid transforms they amount to;
//! - [`pose`]: the scene and camera at one instant;
//! - [`output`]: where frames go (numbered images or a video file) and `--frames`;
//! - [`job`]: rendering a range of frames to files, resuming, and joining them into a video;
//! - [`video`]: the MP4 (H.264), GIF and APNG encoders.
//!
//! Frame `k` is the instant `k / fps` seconds. Same inputs and seed: same frames, bit for
//! bit, for any thread count (each frame is a still render of its posed scene).

pub mod curve;
pub mod file;
pub mod job;
pub mod motion;
pub mod output;
pub mod pose;
pub mod video;

use crate::accel::Accel;
use crate::error::{Error, Result};
use crate::film::Image;
use crate::render::{CancelOn, Observer, RenderSettings, RenderStats, Renderer};
use crate::scene::{Camera, Scene};
use motion::{Target, Track};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Most frames an animation may have (a typo guard: about 11 hours at 24 fps).
pub const MAX_FRAMES: u32 = 1_000_000;
/// Lowest frame rate accepted (one frame per 100 s): every encoder keeps it exactly.
pub const MIN_FPS: f64 = 0.01;
/// Highest frame rate accepted.
pub const MAX_FPS: f64 = 1000.0;

/// A loaded animation: the starting scene and camera, timing, render settings, tracks.
#[derive(Clone, Debug)]
pub struct Animation {
    /// The animation file, for messages.
    pub path: PathBuf,
    /// The scene as its file states it, before any track moves it; every frame is
    /// posed from this.
    pub scene: Scene,
    /// The camera file's camera with the file's `[start]` overrides.
    pub camera: Camera,
    /// Length in frames, 1 to [`MAX_FRAMES`]: frames `0..frames` (from the file's
    /// `frames`, or its `duration` times `fps`, rounded).
    pub frames: u32,
    /// Frames per second, [`MIN_FPS`] to [`MAX_FPS`] (24 unless the file says).
    pub fps: f64,
    /// The file's `[render]` overrides; a caller may set threads and intersector.
    pub settings: RenderSettings,
    /// The file's `[[track]]`s in file order, each moving one target over time.
    pub tracks: Vec<Track>,
    /// How the frames are developed and stored: the job's output (the scene file's
    /// exposure and tone map, the integrator's transfer curve).
    pub output: crate::film::OutputOptions,
    /// The dialect its scene was read as.
    pub dialect: crate::format::SceneDialect,
    /// Whether each frame is denoised once rendered (`[render] denoise`, `prism animate
    /// --denoise`): its albedo and normal passes rendered and Open Image Denoise run on
    /// it before its file is written. Frames of a folder are all denoised or none (the
    /// folder's manifest says which).
    pub denoise: bool,
    /// Set from any thread (a signal handler) to stop: the frame being rendered is
    /// abandoned, none after it starts, and a video being encoded is not written.
    pub cancel: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// FNV-1a 64 of the animation file's text and the scene and camera files' bytes:
    /// what the frames' pixels depend on (with the file's `[render]` settings). A frame
    /// folder records it, so frames of another animation are never resumed.
    pub fingerprint: u64,
}

/// FNV-1a, 64 bits: a hash that stays the same across Rust versions and machines.
pub fn fnv1a(mut hash: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        hash ^= b as u64;
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// FNV-1a's starting value.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

impl Animation {
    /// Whether [`Animation::cancel`] was set.
    pub fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// Reads an animation file and the scene and camera files it names (relative to it).
    pub fn load(path: &Path) -> Result<Animation> {
        file::load(path)
    }

    /// The instant of frame `k`, in seconds.
    pub fn time_of(&self, frame: u32) -> f64 {
        frame as f64 / self.fps
    }

    /// The scene and camera of frame `k`.
    pub fn pose(&self, frame: u32) -> Result<(Scene, Camera)> {
        pose::pose(&self.scene, &self.camera, &self.tracks, self.time_of(frame))
            .map_err(|e| Error::parse(&self.path, e.line, e.message))
    }

    /// Poses `posed` at frame `k` and returns the camera. `posed` starts as a copy of
    /// [`Animation::scene`] and can be reused from frame to frame: only the shapes and
    /// lights the tracks move are written.
    pub fn pose_into(&self, frame: u32, posed: &mut Scene) -> Result<Camera> {
        pose::pose_into(
            &self.scene,
            &self.camera,
            &self.tracks,
            self.time_of(frame),
            posed,
        )
        .map_err(|e| Error::parse(&self.path, e.line, e.message))
    }

    /// Checks that every frame in `frames` can be posed (no camera on its look-at
    /// point), before anything is rendered.
    pub fn check(&self, frames: Range<u32>) -> Result<()> {
        for k in frames {
            pose::pose_camera(&self.scene, &self.camera, &self.tracks, self.time_of(k)).map_err(
                |e| Error::parse(&self.path, e.line, format!("frame {k}: {}", e.message)),
            )?;
        }
        Ok(())
    }

    /// Output size of every frame.
    pub fn frame_size(&self) -> Result<(u32, u32)> {
        let r = Renderer::new(&self.scene, &self.camera, self.settings.clone())?;
        Ok((r.region().width, r.region().height))
    }

    /// Frame `k` as a still's job: the posed scene and camera, the animation's
    /// settings and development (a preview's frame of an animation).
    pub fn frame_job(&self, frame: u32) -> Result<crate::job::Job> {
        let (scene, camera) = self.pose(frame)?;
        Ok(crate::job::Job {
            scene,
            camera,
            settings: self.settings.clone(),
            output: self.output,
            dialect: self.dialect,
            warnings: Vec::new(),
            denoise: self.denoise,
        })
    }

    /// Renders frame `k`, reporting to `observer` as a still's render does.
    pub fn render_frame(
        &self,
        frame: u32,
        observer: &dyn Observer,
    ) -> Result<(Image, RenderStats)> {
        let mut posed = self.scene.clone();
        self.render_frame_in(frame, &mut posed, None, observer)
    }

    /// [`Animation::render_frame`] posing the scene in `posed` (see
    /// [`Animation::pose_into`]), so a run of frames copies the scene once. With
    /// `still`, an intersector from [`Animation::still_geometry`], no intersector is
    /// built for the frame. The render stops when `observer` or [`Animation::cancel`]
    /// asks.
    pub fn render_frame_in(
        &self,
        frame: u32,
        posed: &mut Scene,
        still: Option<&Accel>,
        observer: &dyn Observer,
    ) -> Result<(Image, RenderStats)> {
        let camera = self.pose_into(frame, posed)?;
        let renderer = Renderer::new(posed, &camera, self.settings.clone())?;
        let never = AtomicBool::new(false);
        let watch = (CancelOn(self.cancel.as_deref().unwrap_or(&never)), observer);
        let (image, stats) = match still {
            Some(accel) => renderer.render_with(accel, &watch)?,
            None => renderer.render(&watch)?,
        };
        if self.denoise && !self.cancelled() {
            return Ok((renderer.denoise(&image, &[])?, stats));
        }
        Ok((image, stats))
    }

    /// The intersector every frame can share when no track moves a shape (the camera
    /// and lights may move): built once, on the render's threads. `None` when shapes
    /// move, so each frame builds its own.
    pub fn still_geometry(&self) -> Result<Option<Accel<'_>>> {
        let moves_shapes = self.tracks.iter().any(|t| match &t.target {
            Target::Camera => false,
            Target::Objects(selection) => {
                !(selection.shapes.is_empty() && selection.instances.is_empty())
            }
        });
        if moves_shapes {
            return Ok(None);
        }
        let renderer = Renderer::new(&self.scene, &self.camera, self.settings.clone())?;
        renderer.build_accel().map(Some)
    }
}

#[cfg(test)]
mod tests;
