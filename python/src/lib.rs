//! `prism._prism`: the Rust half of Prism's Python package. It turns Python values into
//! the library's options and back; the public API, its docstrings and the NumPy
//! conversions live in `python/prism/__init__.py`, so this module stays free of NumPy
//! and builds once for every Python from 3.9 on (abi3).
//!
//! - [`errors`]: Prism's errors as the package's exceptions;
//! - [`watch`]: running a job off the GIL while Ctrl-C and progress are served;
//! - [`options`]: a Python dict of render options to `JobOptions`;
//! - [`scene`], [`camera`]: the loaded scene file and the camera choice;
//! - [`still`]: rendering one image (or a region of it);
//! - [`progressive`]: an image in sample passes, as an iterator;
//! - [`image`]: writing pixels in every output format;
//! - [`animation`]: the frames of an animation, one or all, and the video.

mod animation;
mod camera;
mod errors;
mod image;
mod options;
mod progressive;
mod scene;
mod still;
mod watch;

use pyo3::prelude::*;

/// Confines every later read of this process to `folder` (`prism --restrict-paths`).
#[pyfunction]
fn restrict_paths(py: Python<'_>, folder: std::path::PathBuf) -> PyResult<()> {
    prism::util::file::restrict_reads_to(&folder)
        .map_err(|e| errors::to_py(py, prism::Error::Settings(format!("restrict_paths: {e}"))))
}

#[pymodule]
fn _prism(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::Scene>()?;
    m.add_class::<camera::Camera>()?;
    m.add_class::<animation::Animation>()?;
    m.add_class::<progressive::SamplePasses>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(still::render, m)?)?;
    m.add_function(wrap_pyfunction!(still::render_passes, m)?)?;
    m.add_function(wrap_pyfunction!(still::plan, m)?)?;
    m.add_function(wrap_pyfunction!(progressive::render_progressive, m)?)?;
    m.add_function(wrap_pyfunction!(image::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(image::encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(restrict_paths, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // Benchmarks refuse a debug build: `maturin develop` (the test suite's build)
    // renders about a fifth slower than the wheel users install.
    m.add(
        "BUILD",
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        },
    )?;
    Ok(())
}
