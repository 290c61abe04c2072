//! One still image (or a region of it) from a loaded scene, as `prism render` makes it:
//! the same `job::resolve`, the same renderer, the same development for 8-bit output.

use crate::camera::Camera;
use crate::errors::{IntoPy, to_py};
use crate::options::job_options;
use crate::scene::Scene;
use crate::watch::{self, Counter};
use prism::film::Image;
use prism::film::Transfer;
use prism::job::Job;
use prism::render::{CancelOn, Progress, Rows};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub(crate) fn resolve(
    py: Python<'_>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Job> {
    let o = job_options(camera, options)?;
    let file = (*scene.file).clone();
    py.detach(|| prism::job::resolve(file, &o)).py_err(py)
}

/// How often a live preview is refreshed while a render runs.
const PREVIEW_EVERY: Duration = Duration::from_millis(250);

/// Renders; returns the pixels (f32 radiance, or developed u8 with `srgb`), the width,
/// the height and the NumPy dtype name. With `preview`, a callable
/// `preview(rgb8, width, height)` is given the image as it forms (rows not rendered yet
/// black, developed as `srgb` develops), at most every quarter second, and once more
/// at the end.
#[pyfunction]
#[pyo3(signature = (scene, camera = None, options = None, progress = None, srgb = false, preview = None))]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'py, PyDict>>,
    progress: Option<Bound<'py, PyAny>>,
    srgb: bool,
    preview: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyByteArray>, u32, u32, &'static str)> {
    let job = resolve(py, scene, camera, options)?;
    let cancel = AtomicBool::new(false);
    let renderer = job.renderer().py_err(py)?;
    let counter = Counter::new(renderer.rows_to_trace());
    let region = renderer.region();
    let develop = job.output.develop;
    // The image as it forms: rows land here as the render finishes them.
    let partial = Mutex::new(Image::new(
        region.width,
        region.height,
        vec![[0.0; 3]; region.width as usize * region.height as usize],
    ));
    let fresh = AtomicBool::new(false);
    let previewing = preview.is_some();
    let keep_rows = Rows(|y: u32, rows: &[[f32; 3]]| {
        if previewing {
            let start = y as usize * region.width as usize;
            let mut image = partial.lock().unwrap_or_else(|e| e.into_inner());
            image.pixels[start..start + rows.len()].copy_from_slice(rows);
            fresh.store(true, Ordering::Relaxed);
        }
    });
    let mut shown = Instant::now();
    let mut show = |force: bool| -> PyResult<()> {
        let Some(cb) = &preview else {
            return Ok(());
        };
        if !(force || fresh.load(Ordering::Relaxed) && shown.elapsed() >= PREVIEW_EVERY) {
            return Ok(());
        }
        fresh.store(false, Ordering::Relaxed);
        shown = Instant::now();
        let bytes = develop.to_rgb8(&partial.lock().unwrap_or_else(|e| e.into_inner()));
        cb.call1((PyBytes::new(py, &bytes), region.width, region.height))?;
        Ok(())
    };
    let watch = (CancelOn(&cancel), (Progress(|n| counter.add(n)), keep_rows));
    let result = watch::run_ticking(
        py,
        &cancel,
        &counter,
        progress.as_ref(),
        &mut || show(false),
        || renderer.render(&watch),
    )?;
    let (image, _stats) = result.map_err(|e| to_py(py, e))?;
    // Denoised when the options ask (a Prism without OIDN refused them as they resolved).
    let image = py
        .detach(|| job.denoised(&renderer, image, &[]))
        .py_err(py)?;
    let (w, h) = (image.width, image.height);
    let display = srgb || previewing;
    let rgb8 = if display {
        develop.to_rgb8(&image)
    } else {
        Vec::new()
    };
    if let Some(cb) = &preview {
        cb.call1((PyBytes::new(py, &rgb8), w, h))?;
    }
    if srgb {
        Ok((PyByteArray::new(py, &rgb8), w, h, "u1"))
    } else {
        let bytes: &[u8] = bytemuck::cast_slice(&image.pixels);
        Ok((PyByteArray::new(py, bytes), w, h, "<f4"))
    }
}

/// What a render with these options would be, without rendering: the full frame's
/// size, the shading model and how the command line would develop it for an 8-bit file.
#[pyfunction]
#[pyo3(signature = (scene, camera = None, options = None))]
pub fn plan<'py>(
    py: Python<'py>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut job = resolve(py, scene, camera, options)?;
    job.settings.region = None;
    let renderer = job.renderer().py_err(py)?;
    let develop = job.output.develop;
    let d = PyDict::new(py);
    d.set_item("width", renderer.camera().width)?;
    d.set_item("height", renderer.camera().height)?;
    d.set_item("integrator", job.settings.integrator.name())?;
    d.set_item("exposure", develop.exposure)?;
    d.set_item("tonemap", develop.tonemap.name())?;
    let transfer = match develop.transfer {
        Transfer::Classic => "classic",
        Transfer::Srgb => "srgb",
    };
    d.set_item("transfer", transfer)?;
    d.set_item("png_bits", job.output.png_bits.to_string())?;
    d.set_item("exr_precision", job.output.exr_precision.to_string())?;
    d.set_item("warnings", job.warnings.clone())?;
    Ok(d)
}

/// Renders passes `names` (`albedo`, `normal`, `depth`) of the image the same options
/// make: each through the image's own camera samples and filter. Returns, per pass,
/// its f32 pixels (three channels; depth's value in each), width and height.
#[pyfunction]
#[pyo3(signature = (scene, names, camera = None, options = None))]
pub fn render_passes<'py>(
    py: Python<'py>,
    scene: &Scene,
    names: Vec<String>,
    camera: Option<&Camera>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Vec<(Bound<'py, PyByteArray>, u32, u32)>> {
    let aovs = names
        .iter()
        .map(|n| n.parse::<prism::options::Aov>())
        .collect::<Result<Vec<_>, String>>()
        .map_err(pyo3::exceptions::PyValueError::new_err)?;
    let job = resolve(py, scene, camera, options)?;
    let renderer = job.renderer().py_err(py)?;
    let images = py.detach(|| renderer.render_aovs(&aovs)).py_err(py)?;
    Ok(images
        .iter()
        .map(|image| {
            let bytes: &[u8] = bytemuck::cast_slice(&image.pixels);
            (PyByteArray::new(py, bytes), image.width, image.height)
        })
        .collect())
}
