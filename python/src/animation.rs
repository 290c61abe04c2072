//! An animation file from Python: its frames rendered all at once (`prism.animate`,
//! what `prism animate` does) or one at a time (a cluster task), and the video joined
//! from them once every frame exists. Frames go through the library's frame folders:
//! the same names, the same manifest, the same atomic writes, so a folder started by
//! one front end is resumed by another.

use crate::errors::{IntoPy, to_py};
use crate::watch::{self, Counter};
use prism::anim::job::{self, FrameObserver};
use prism::anim::output::{Output, parse_frame_range};
use prism::film::file_bytes;
use prism::film::{Image, write_image};
use prism::render::{CancelOn, Renderer};
use prism::scene::Scene;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// A loaded animation file (and the scene and camera files it names).
#[pyclass(frozen, module = "prism._prism")]
pub struct Animation {
    anim: Arc<prism::anim::Animation>,
}

fn output_of(py: Python<'_>, output: &Path) -> PyResult<Output> {
    Output::from_path(output).py_err(py)
}

/// Poses and renders frame `k`; stops early when `cancel` is set.
fn render_one(
    anim: &prism::anim::Animation,
    k: u32,
    posed: &mut Scene,
    still: Option<&prism::accel::Accel>,
    cancel: &AtomicBool,
) -> prism::Result<Image> {
    let camera = anim.pose_into(k, posed)?;
    let renderer = Renderer::new(posed, &camera, anim.settings.clone())?;
    let (image, _) = match still {
        Some(accel) => renderer.render_with(accel, &CancelOn(cancel))?,
        None => renderer.render(&CancelOn(cancel))?,
    };
    Ok(image)
}

#[pymethods]
impl Animation {
    /// Reads the animation file; `threads` and `accel` as `prism animate` takes them.
    #[new]
    #[pyo3(signature = (path, threads = None, accel = None))]
    fn new(
        py: Python<'_>,
        path: PathBuf,
        threads: Option<usize>,
        accel: Option<&str>,
    ) -> PyResult<Animation> {
        let mut anim = py
            .detach(|| prism::anim::Animation::load(&path))
            .py_err(py)?;
        anim.settings.threads = threads;
        if let Some(name) = accel {
            anim.settings.accel = name
                .parse()
                .map_err(pyo3::exceptions::PyValueError::new_err)?;
        }
        Ok(Animation {
            anim: Arc::new(anim),
        })
    }

    #[getter]
    fn path(&self) -> PathBuf {
        self.anim.path.clone()
    }

    #[getter]
    fn frames(&self) -> u32 {
        self.anim.frames
    }

    #[getter]
    fn fps(&self) -> f64 {
        self.anim.fps
    }

    /// The frames' width and height.
    #[getter]
    fn size(&self, py: Python<'_>) -> PyResult<(u32, u32)> {
        self.anim.frame_size().py_err(py)
    }

    /// What the frames' pixels depend on (the files' contents), as 16 hex digits.
    #[getter]
    fn fingerprint(&self) -> String {
        format!("{:016x}", self.anim.fingerprint)
    }

    /// `--frames` text (`A..B`, `A..=B`, `A..`, `..B`, `N`) as `(start, end)`; `None`
    /// is every frame.
    #[pyo3(signature = (text = None))]
    fn frame_range(&self, py: Python<'_>, text: Option<&str>) -> PyResult<(u32, u32)> {
        match text {
            Some(t) => parse_frame_range(t, self.anim.frames)
                .map(|r| (r.start, r.end))
                .py_err(py),
            None => Ok((0, self.anim.frames)),
        }
    }

    /// Checks everything `prism animate` checks before its first frame, creates the
    /// frame folder with its manifest, and returns the frames of `start..end` whose
    /// file does not exist yet.
    fn prepare(&self, py: Python<'_>, output: PathBuf, start: u32, end: u32) -> PyResult<Vec<u32>> {
        let out = output_of(py, &output)?;
        let anim = &*self.anim;
        py.detach(|| {
            job::check(anim, start..end, &out)?;
            // An empty range: the folder is made ready and nothing is rendered.
            let nothing = FrameObserver {
                frame_start: &|_, _| {},
                rows: &|_| {},
                frame_done: &|_, _| {},
            };
            job::render_frames(anim, start..start, out.frames(), &nothing)?;
            Ok((start..end)
                .filter(|&k| !out.frames().path_of(k).is_file())
                .collect())
        })
        .py_err(py)
    }

    /// Where frame `k` of `output` is written.
    fn frame_path(&self, py: Python<'_>, output: PathBuf, k: u32) -> PyResult<PathBuf> {
        Ok(output_of(py, &output)?.frames().path_of(k))
    }

    /// Renders the frames `frames` of `output` whose file does not exist, each written
    /// atomically as it finishes; `progress(done, total)` counts frames. Ctrl-C stops
    /// the frame being rendered and raises `KeyboardInterrupt`. Returns the number of
    /// frames rendered.
    #[pyo3(signature = (output, frames, progress = None))]
    fn render_frames<'py>(
        &self,
        py: Python<'py>,
        output: PathBuf,
        frames: Vec<u32>,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<u32> {
        let out = output_of(py, &output)?;
        let pattern = out.frames();
        let anim = &*self.anim;
        let cancel = AtomicBool::new(false);
        let counter = Counter::new(frames.len() as u64);
        let result = watch::run(
            py,
            &cancel,
            &counter,
            progress.as_ref(),
            || -> prism::Result<u32> {
                let mut posed = anim.scene.clone();
                let mut still = None;
                let mut rendered = 0;
                for &k in &frames {
                    let path = pattern.path_of(k);
                    if !path.is_file() {
                        // Built at the first frame rendered, as `prism animate` does.
                        if still.is_none() {
                            still = Some(anim.still_geometry()?);
                        }
                        let accel = still.as_ref().and_then(Option::as_ref);
                        let image = render_one(anim, k, &mut posed, accel, &cancel)?;
                        // Developed as `prism animate` develops its frames.
                        write_image(&image, &path, &anim.output)?;
                        rendered += 1;
                    }
                    counter.add(1);
                }
                Ok(rendered)
            },
        )?;
        result.map_err(|e| to_py(py, e))
    }

    /// Renders frame `k` and returns the bytes of its file in `output`'s frame format,
    /// without writing anything: what a cluster task sends back to the driver.
    fn render_frame_bytes<'py>(
        &self,
        py: Python<'py>,
        output: PathBuf,
        k: u32,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let out = output_of(py, &output)?;
        let ext = out.frames().suffix.trim_start_matches('.').to_string();
        let anim = &*self.anim;
        let cancel = AtomicBool::new(false);
        let counter = Counter::new(1);
        let result = watch::run(py, &cancel, &counter, None, || {
            let image = render_one(anim, k, &mut anim.scene.clone(), None, &cancel)?;
            file_bytes(&image, &ext, &anim.output)
        })?;
        Ok(PyBytes::new(py, &result.map_err(|e| to_py(py, e))?))
    }

    /// For a video output: once every frame of the animation is in the frame folder,
    /// joins them into the video (and deletes the frames unless `keep_frames`). Returns
    /// `missing` (frames not there yet) and, when written, `video` (frames, bytes, fps).
    #[pyo3(signature = (output, keep_frames = false))]
    fn finish<'py>(
        &self,
        py: Python<'py>,
        output: PathBuf,
        keep_frames: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let out = output_of(py, &output)?;
        let anim = &*self.anim;
        let missing = job::missing_frames(out.frames(), anim.frames);
        let d = PyDict::new(py);
        d.set_item("missing", missing)?;
        d.set_item("video", py.None())?;
        if matches!(out, Output::Video { .. }) && missing == 0 {
            let all = 0..anim.frames;
            let (info, _seconds) = py
                .detach(|| {
                    let encoded = job::encode_frames(anim, all.clone(), &out, &|| {})?;
                    // The stamp `prism animate` leaves, so its rerun does no work.
                    if let Output::Video { path, .. } = &out {
                        job::mark_video_current(anim, path)?;
                    }
                    Ok::<_, prism::Error>(encoded)
                })
                .py_err(py)?;
            if !keep_frames {
                job::remove_frames(out.frames(), all);
            }
            let v = PyDict::new(py);
            v.set_item("frames", info.frames)?;
            v.set_item("bytes", info.bytes)?;
            v.set_item("fps", info.fps)?;
            d.set_item("video", v)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "<prism.Animation {} ({} frames at {} fps)>",
            self.anim.path.display(),
            self.anim.frames,
            self.anim.fps
        )
    }
}
