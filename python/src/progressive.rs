//! A render in sample passes as a Python iterator: the image after 1, 2, 4 … samples a
//! pixel up to the job's `spp` (`prism::render::Progressive`, the preview's passes),
//! each pass the means of all samples so far, the last `prism render`'s image bit for
//! bit.
//!
//! The passes run on a thread of their own that owns the job; each image waits there
//! until Python asks for it, and the next pass is rendered meanwhile. Waiting for one
//! releases the GIL and serves Ctrl-C; dropping or closing the iterator stops the
//! render at its next strip.

use crate::camera::Camera;
use crate::errors::{IntoPy, to_py};
use crate::scene::Scene;
use prism::film::{Develop, Image};
use prism::render::CancelOn;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

/// How often Ctrl-C is looked at while a pass is awaited.
const POLL: Duration = Duration::from_millis(50);

/// One pass: its samples a pixel and its linear image.
type Pass = prism::Result<(u32, Image)>;

/// A pass as Python receives it: samples a pixel, f32 pixels, the 8-bit pixels
/// `prism render` would write (when asked for), width, height.
type PyPass<'py> = (
    u32,
    Bound<'py, PyByteArray>,
    Option<Bound<'py, PyBytes>>,
    u32,
    u32,
);

/// The sample passes of one render, in order.
#[pyclass(module = "prism._prism")]
pub struct SamplePasses {
    cancel: Arc<AtomicBool>,
    /// `None` once the passes are over (the last given, an error raised, closed).
    passes: Mutex<Option<Receiver<Pass>>>,
    worker: Mutex<Option<JoinHandle<()>>>,
    /// Samples a pixel after each pass.
    totals: Vec<u32>,
    /// How each pass is developed to 8 bits, when it is asked for.
    develop: Option<Develop>,
}

/// Starts rendering the passes of the image `render` would make with these options;
/// with `developed`, each pass comes with its 8-bit pixels too, developed as `render`'s
/// `srgb=True` develops them.
#[pyfunction]
#[pyo3(signature = (scene, camera = None, options = None, developed = false))]
pub fn render_progressive(
    py: Python<'_>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'_, PyDict>>,
    developed: bool,
) -> PyResult<SamplePasses> {
    let job = crate::still::resolve(py, scene, camera, options)?;
    let develop = developed.then_some(job.output.develop);
    // Asked here so that bad settings raise at the call, not at the first pass.
    let totals = job.renderer().py_err(py)?.pass_totals();
    let cancel = Arc::new(AtomicBool::new(false));
    // No room in the channel: a pass is handed over only when Python asks, and the
    // worker renders the next one while Python looks at it.
    let (tx, rx) = sync_channel(0);
    let stop = Arc::clone(&cancel);
    let worker = std::thread::Builder::new()
        .name("prism-passes".into())
        .spawn(move || render_passes(&job, &stop, &tx))
        .map_err(|e| {
            to_py(
                py,
                prism::Error::Settings(format!("cannot start the render: {e}")),
            )
        })?;
    Ok(SamplePasses {
        cancel,
        passes: Mutex::new(Some(rx)),
        worker: Mutex::new(Some(worker)),
        totals,
        develop,
    })
}

/// Renders every pass of `job`, handing each to `tx`, until the last, an error, a
/// cancel or a receiver that is gone.
fn render_passes(job: &prism::job::Job, cancel: &AtomicBool, tx: &SyncSender<Pass>) {
    let run = || -> prism::Result<()> {
        let renderer = job.renderer()?;
        let accel = renderer.build_accel()?;
        let watch = CancelOn(cancel);
        let guides = job.denoise_guides(&renderer, &accel, &watch)?;
        let mut progressive = renderer.progressive();
        while let Some((to, rendered)) = progressive.next_pass(&renderer, &accel, &watch) {
            let (image, _) = rendered?;
            if cancel.load(Ordering::Relaxed) {
                break;
            }
            let image = job.denoised(&renderer, image, &guides)?;
            if tx.send(Ok((to, image))).is_err() {
                break;
            }
        }
        Ok(())
    };
    // A render stopped by `close` ends the passes; its interruption is not an error.
    if let Err(e) = run()
        && !cancel.load(Ordering::Relaxed)
    {
        let _ = tx.send(Err(e));
    }
}

impl SamplePasses {
    /// Returns the receiver `__next__` waited on, unless the render was stopped
    /// meanwhile (by `close` on another thread): then it is dropped, which frees a
    /// worker waiting to hand over a pass, so that `close` can join it.
    fn put_back(&self, rx: Receiver<Pass>) {
        let mut passes = self.passes.lock().unwrap_or_else(|e| e.into_inner());
        if !self.cancel.load(Ordering::Relaxed) {
            *passes = Some(rx);
        }
    }

    /// Stops the render and waits for its thread.
    fn stop(&self) {
        self.cancel.store(true, Ordering::Relaxed);
        // Dropping the receiver frees a worker waiting to hand over a pass.
        self.passes.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(worker) = self.worker.lock().unwrap_or_else(|e| e.into_inner()).take() {
            let _ = worker.join();
        }
    }
}

#[pymethods]
impl SamplePasses {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    /// The next pass's samples a pixel, its f32 pixels, width and height; `None` after
    /// the last.
    fn __next__<'py>(&self, py: Python<'py>) -> PyResult<Option<PyPass<'py>>> {
        loop {
            let Some(rx) = self.passes.lock().unwrap_or_else(|e| e.into_inner()).take() else {
                if self.cancel.load(Ordering::Relaxed) {
                    return Ok(None);
                }
                return Err(pyo3::exceptions::PyRuntimeError::new_err(
                    "another thread is waiting for this render's next pass",
                ));
            };
            let (rx, got) = py.detach(move || {
                let got = rx.recv_timeout(POLL);
                (rx, got)
            });
            match got {
                Ok(Ok((to, image))) => {
                    self.put_back(rx);
                    let develop = self.develop;
                    let (image, rgb8) = py.detach(move || {
                        let rgb8 = develop.map(|d| d.to_rgb8(&image));
                        (image, rgb8)
                    });
                    let bytes: &[u8] = bytemuck::cast_slice(&image.pixels);
                    let rgb8 = rgb8.map(|rgb8| PyBytes::new(py, &rgb8));
                    let pixels = PyByteArray::new(py, bytes);
                    return Ok(Some((to, pixels, rgb8, image.width, image.height)));
                }
                Ok(Err(e)) => {
                    self.stop();
                    return Err(to_py(py, e));
                }
                // The last pass was handed over and the worker is done.
                Err(RecvTimeoutError::Disconnected) => {
                    self.stop();
                    return Ok(None);
                }
                Err(RecvTimeoutError::Timeout) => {
                    self.put_back(rx);
                    if let Err(e) = py.check_signals() {
                        py.detach(|| self.stop());
                        return Err(e);
                    }
                }
            }
        }
    }

    /// Samples a pixel after each pass.
    #[getter]
    fn totals(&self) -> Vec<u32> {
        self.totals.clone()
    }

    /// Stops the render; the iterator then ends.
    fn close(&self, py: Python<'_>) {
        py.detach(|| self.stop());
    }
}

impl Drop for SamplePasses {
    /// Waits for the worker with the GIL released: a pass past its last cancel check
    /// (a denoise) may take a moment, and other Python threads go on meanwhile.
    fn drop(&mut self) {
        Python::attach(|py| py.detach(|| self.stop()));
    }
}
