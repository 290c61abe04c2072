//! A preview's session: the scene as last read, the camera in hand, and the frames the
//! render loop makes of them, coarse pass first. Every change (a camera move, a saved
//! file) starts a new generation; the render of an older one stops at its next tile.

use crate::accel::Accel;
use crate::error::Result;
use crate::film::{Image, file_bytes};
use crate::job::{Job, JobOptions, LookAt};
use crate::render::{Observer, RenderSettings, RenderStats, Renderer};
use crate::scene::Camera;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Downscaling of each pass, coarsest first; the last renders the job as it is, so the
/// final image is bit for bit the one `prism render` makes (for the path model, in
/// sample passes that end on it: [`crate::render::sample_totals`]).
const PASS_SCALES: [u32; 4] = [8, 4, 2, 1];
/// A coarse pass is kept only while its image is at least this many pixels across.
const MIN_PASS_SIDE: u32 = 8;

/// One image of the render loop.
#[derive(Clone)]
pub struct Frame {
    /// The generation (the scene and camera) it shows.
    pub generation: u64,
    /// Its pass, from 1, of `passes`.
    pub pass: u32,
    /// The passes of its generation.
    pub passes: u32,
    /// Samples a pixel it holds: 1 for a coarse pass, the job's `spp` for the final
    /// image, and the running total of the path model's sample passes between.
    pub samples: u32,
    /// Its size in pixels (a coarse pass is smaller than the final image).
    pub width: u32,
    /// Its height in pixels.
    pub height: u32,
    /// The linear image.
    pub image: Arc<Image>,
    /// The image as the PNG file `prism render` would write of it.
    pub png: Arc<Vec<u8>>,
    /// Seconds from the generation's start to this pass's end.
    pub elapsed: f64,
    /// Rays the pass traced.
    pub rays: u64,
    /// Seconds the pass took.
    pub seconds: f64,
    /// Whether the image was denoised (a full-size pass of a job that asks).
    pub denoised: bool,
}

impl Frame {
    /// Whether this is the generation's last pass: the final image.
    pub fn is_final(&self) -> bool {
        self.pass == self.passes
    }
}

/// What the page is told: the latest frame, the last error, the camera.
pub struct State {
    /// Bumped at every frame and every error: what a waiting client watches.
    pub version: u64,
    /// The scene as last read without error.
    pub job: Option<Arc<Job>>,
    /// The camera in hand; `None`: the scene's own.
    pub look: Option<LookAt>,
    /// The scene's camera when last read, to tell whether a saved file moved it.
    file_camera: Option<Camera>,
    /// The last reading or rendering error (`file:line:col: message`), until the next
    /// good reading.
    pub error: Option<String>,
    /// The latest frame.
    pub frame: Option<Frame>,
    /// For an animation file: its frame count, frame rate and the frame shown.
    pub animation: Option<Timeline>,
    /// Every file the last reading asked for: what the watch looks at.
    pub reads: Vec<PathBuf>,
}

/// Where in an animation the preview is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timeline {
    /// Frames of the animation.
    pub frames: u32,
    /// Frames a second.
    pub fps: f64,
    /// The frame shown, from 0.
    pub frame: u32,
}

/// The preview's shared state, its render loop and its reloads.
pub struct Session {
    scene_path: PathBuf,
    options: JobOptions,
    state: Mutex<State>,
    /// Signalled at every new version (clients waiting for a frame).
    published: Condvar,
    /// Signalled at every new generation (the render loop).
    work: Condvar,
    generation: AtomicU64,
    stop: AtomicBool,
}

impl Session {
    /// A session of the scene at `scene_path` read with `options`; the first reading's
    /// error is returned (the preview does not start on a scene that does not read).
    pub fn new(scene_path: &Path, options: JobOptions) -> Result<Arc<Session>> {
        let (read, reads) = crate::util::file::recording_reads(|| read(scene_path, &options, 0));
        let (job, animation) = read?;
        let session = Session {
            scene_path: scene_path.to_path_buf(),
            options,
            state: Mutex::new(State {
                version: 0,
                file_camera: Some(job.camera.clone()),
                job: Some(Arc::new(job)),
                look: None,
                error: None,
                frame: None,
                animation,
                reads,
            }),
            published: Condvar::new(),
            work: Condvar::new(),
            generation: AtomicU64::new(1),
            stop: AtomicBool::new(false),
        };
        Ok(Arc::new(session))
    }

    /// The scene file the session reads.
    pub fn scene_path(&self) -> &Path {
        &self.scene_path
    }

    /// The state, locked.
    pub fn state(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The current generation.
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Acquire)
    }

    /// Starts a new generation: the running render stops, the loop starts again.
    fn bump(&self, state: &mut State) {
        self.generation.fetch_add(1, Ordering::AcqRel);
        state.version += 1;
        self.work.notify_all();
        self.published.notify_all();
    }

    /// Puts the camera in hand (`None`: back to the scene's own).
    pub fn set_look(&self, look: Option<LookAt>) -> Result<()> {
        let mut state = self.state();
        if let (Some(look), Some(job)) = (&look, &state.job) {
            // Refused before it replaces the camera in hand.
            job.camera_looking(look)?;
        }
        state.look = look;
        self.bump(&mut state);
        Ok(())
    }

    /// Reads the scene again (a file it reads was saved): the camera in hand stays,
    /// unless the file's own camera moved. A file that no longer reads keeps the last
    /// image and shows its error.
    pub fn reload(&self) {
        let at = self.state().animation.map_or(0, |t| t.frame);
        let (read, reads) =
            crate::util::file::recording_reads(|| read(&self.scene_path, &self.options, at));
        let mut state = self.state();
        // A reading that fails still says which files to watch (the one to fix).
        state.reads = reads;
        match read {
            Ok((job, animation)) => {
                state.animation = animation;
                if state.file_camera.as_ref() != Some(&job.camera) {
                    state.look = None;
                }
                state.file_camera = Some(job.camera.clone());
                state.job = Some(Arc::new(job));
                state.error = None;
                self.bump(&mut state);
            }
            Err(e) => {
                state.error = Some(e.to_string());
                state.version += 1;
                self.published.notify_all();
            }
        }
    }

    /// Shows frame `frame` of an animation (clamped to its frames).
    pub fn set_frame(&self, frame: u32) -> Result<()> {
        let Some(timeline) = self.state().animation else {
            return Err(crate::error::Error::Settings(
                "the scene is not an animation".into(),
            ));
        };
        let frame = frame.min(timeline.frames.saturating_sub(1));
        let (job, animation) = read(&self.scene_path, &self.options, frame)?;
        let mut state = self.state();
        state.animation = animation;
        // The frame's own camera is the file's now: a later save keeps the camera in
        // hand unless it moves it.
        state.file_camera = Some(job.camera.clone());
        state.job = Some(Arc::new(job));
        self.bump(&mut state);
        Ok(())
    }

    /// Waits until the state is newer than `version`, or `timeout` has passed; returns
    /// the state then.
    pub fn wait_newer(&self, version: u64, timeout: Duration) -> MutexGuard<'_, State> {
        let state = self.state();
        let (state, _) = self
            .published
            .wait_timeout_while(state, timeout, |s| {
                s.version <= version && !self.stop.load(Ordering::Relaxed)
            })
            .unwrap_or_else(|e| e.into_inner());
        state
    }

    /// Asks the render loop to end (it returns within a tile).
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Release);
        let _g = self.state();
        self.work.notify_all();
        self.published.notify_all();
    }

    /// Whether [`Session::stop`] was called.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Acquire)
    }

    /// The render loop: renders each generation pass by pass until told to stop. One
    /// intersector serves every generation of the same reading of the scene.
    pub fn render_loop(&self) {
        let mut done = 0;
        while !self.stopped() {
            let Some(job) = self.next_job(done) else {
                return;
            };
            let accel = match Renderer::new(&job.scene, &job.camera, job.settings.clone())
                .and_then(|r| r.build_accel())
            {
                Ok(accel) => accel,
                Err(e) => {
                    done = self.generation();
                    self.fail(e.to_string());
                    continue;
                }
            };
            // Generations of this reading: camera moves. A new reading ends the run.
            loop {
                let (generation, look) = {
                    let state = self.state();
                    let same = state.job.as_ref().is_some_and(|j| Arc::ptr_eq(j, &job));
                    if !same || self.stopped() {
                        break;
                    }
                    (self.generation(), state.look)
                };
                if generation != done {
                    self.render_generation(&job, &accel, look, generation);
                    done = generation;
                }
                let state = self.state();
                if self.generation() == done {
                    let _unused = self
                        .work
                        .wait_while(state, |_| self.generation() == done && !self.stopped())
                        .unwrap_or_else(|e| e.into_inner());
                }
            }
        }
    }

    /// The job to render once the generation is newer than `done`.
    fn next_job(&self, done: u64) -> Option<Arc<Job>> {
        let state = self.state();
        let state = self
            .work
            .wait_while(state, |s| {
                !self.stopped() && (self.generation() == done || s.job.is_none())
            })
            .unwrap_or_else(|e| e.into_inner());
        if self.stopped() {
            return None;
        }
        state.job.clone()
    }

    fn fail(&self, message: String) {
        let mut state = self.state();
        state.error = Some(message);
        state.version += 1;
        self.published.notify_all();
    }

    /// Renders `generation`'s passes, publishing each; stops when a newer one starts.
    fn render_generation(&self, job: &Job, accel: &Accel, look: Option<LookAt>, generation: u64) {
        let camera = match look.map(|l| job.camera_looking(&l)).transpose() {
            Ok(c) => c.unwrap_or_else(|| job.camera.clone()),
            Err(e) => return self.fail(e.to_string()),
        };
        let renderer = match Renderer::new(&job.scene, &camera, job.settings.clone()) {
            Ok(r) => r,
            Err(e) => return self.fail(e.to_string()),
        };
        let full = (renderer.camera().width, renderer.camera().height);
        let coarse: Vec<u32> = PASS_SCALES
            .into_iter()
            .filter(|&s| s > 1 && full.0 / s >= MIN_PASS_SIDE && full.1 / s >= MIN_PASS_SIDE)
            .collect();
        // The path model's full-size image comes in sample passes, each adding to the
        // sums of the last; where the sums do not fit the memory budget, in one.
        let mut progressive = renderer.progressive();
        let passes = (coarse.len() + progressive.totals().len()) as u32;
        let start = Instant::now();
        let watch = Current {
            session: self,
            generation,
        };
        // Publishes pass `pass`'s image, of `samples` a pixel, as the latest frame.
        // False when the generation is over: a newer one started, or the render failed
        // (and says so).
        let publish =
            |pass: u32, samples: u32, denoised: bool, rendered: Result<(Image, RenderStats)>| {
                let (image, stats) = match rendered {
                    Ok(out) => out,
                    Err(crate::error::Error::Interrupted) => return false,
                    Err(e) => {
                        self.fail(e.to_string());
                        return false;
                    }
                };
                let png = match file_bytes(&image, "png", &job.output) {
                    Ok(png) => png,
                    Err(e) => {
                        self.fail(e.to_string());
                        return false;
                    }
                };
                let mut state = self.state();
                if self.generation() != generation {
                    return false;
                }
                state.frame = Some(Frame {
                    generation,
                    pass,
                    passes,
                    samples,
                    width: image.width,
                    height: image.height,
                    image: Arc::new(image),
                    png: Arc::new(png),
                    elapsed: start.elapsed().as_secs_f64(),
                    rays: stats.rays,
                    seconds: stats.elapsed.as_secs_f64(),
                    denoised,
                });
                state.version += 1;
                self.published.notify_all();
                true
            };
        let mut pass = 0;
        for &scale in &coarse {
            // A coarse pass: a smaller frame of the same view, one sample a pixel.
            let settings = RenderSettings {
                width: Some((full.0 / scale).max(1)),
                height: Some((full.1 / scale).max(1)),
                aa: Some(1),
                spp: Some(1),
                region: None,
                ..job.settings.clone()
            };
            let rendered = Renderer::new(&job.scene, &camera, settings)
                .and_then(|r| r.render_with(accel, &watch));
            pass += 1;
            if !publish(pass, 1, false, rendered) {
                return;
            }
        }
        // A job that asks is denoised at every full-size pass, so the image forms
        // denoised and ends on `prism render --denoise`'s.
        let guides = match job.denoise_guides(&renderer, accel, &watch) {
            Ok(guides) => guides,
            Err(crate::error::Error::Interrupted) => return,
            Err(e) => return self.fail(e.to_string()),
        };
        while let Some((to, rendered)) = progressive.next_pass(&renderer, accel, &watch) {
            // Denoising cannot be stopped part-way: a newer generation skips it.
            let rendered = rendered.and_then(|(image, stats)| {
                if watch.cancelled() {
                    return Err(crate::error::Error::Interrupted);
                }
                Ok((job.denoised(&renderer, image, &guides)?, stats))
            });
            pass += 1;
            if !publish(pass, to, job.denoise, rendered) {
                return;
            }
        }
    }
}

/// Stops a render once its generation is no longer the current one.
struct Current<'a> {
    session: &'a Session,
    generation: u64,
}

impl Observer for Current<'_> {
    fn cancelled(&self) -> bool {
        self.session.generation() != self.generation || self.session.stopped()
    }
}

/// Whether `path` is an animation: an animation file (it names a `scene`) or a Prism
/// scene file with an `[animation]` table.
fn is_animation(path: &Path) -> bool {
    let toml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    toml && crate::util::text::read_text(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("scene") || t.contains_key("animation"))
}

/// The job to render: the scene file's, or frame `frame` of an animation (its own
/// settings, with the caller's threads, intersector, memory budget and denoising).
fn read(path: &Path, options: &JobOptions, frame: u32) -> Result<(Job, Option<Timeline>)> {
    if !is_animation(path) {
        return Ok((crate::job::prepare(path, options)?, None));
    }
    let mut anim = crate::anim::Animation::load(path)?;
    anim.settings.threads = options.threads;
    if let Some(accel) = options.accel {
        anim.settings.accel = accel;
    }
    anim.settings.max_memory = options.max_memory;
    if options.render.denoise == Some(true) {
        crate::film::denoise::check_available()?;
        anim.denoise = true;
    }
    let frame = frame.min(anim.frames.saturating_sub(1));
    let timeline = Timeline {
        frames: anim.frames,
        fps: anim.fps,
        frame,
    };
    Ok((anim.frame_job(frame)?, Some(timeline)))
}
