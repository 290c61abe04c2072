//! One still image (or a region of it) from a loaded scene, as `prism render` makes it:
//! the same `job::resolve`, the same renderer, the same development for 8-bit output.

use crate::camera::Camera;
use crate::errors::{IntoPy, to_py};
use crate::options::job_options;
use crate::scene::Scene;
use crate::watch::{self, Counter};
use prism::film::Transfer;
use prism::job::Job;
use prism::render::{CancelOn, Progress};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::sync::atomic::AtomicBool;

fn resolve(
    py: Python<'_>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Job> {
    let o = job_options(camera, options)?;
    let file = (*scene.file).clone();
    py.detach(|| prism::job::resolve(file, &o)).py_err(py)
}

/// Renders; returns the pixels (f32 radiance, or developed u8 with `srgb`), the width,
/// the height and the NumPy dtype name.
#[pyfunction]
#[pyo3(signature = (scene, camera = None, options = None, progress = None, srgb = false))]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    camera: Option<&Camera>,
    options: Option<&Bound<'py, PyDict>>,
    progress: Option<Bound<'py, PyAny>>,
    srgb: bool,
) -> PyResult<(Bound<'py, PyByteArray>, u32, u32, &'static str)> {
    let job = resolve(py, scene, camera, options)?;
    let cancel = AtomicBool::new(false);
    let renderer = job.renderer().py_err(py)?;
    let counter = Counter::new(renderer.rows_to_trace());
    let result = watch::run(py, &cancel, &counter, progress.as_ref(), || {
        renderer.render(&(CancelOn(&cancel), Progress(|n| counter.add(n))))
    })?;
    let (image, _stats) = result.map_err(|e| to_py(py, e))?;
    let (w, h) = (image.width, image.height);
    if srgb {
        let bytes = job.output.develop.to_rgb8(&image);
        Ok((PyByteArray::new(py, &bytes), w, h, "u1"))
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
