//! Prism's errors as Python exceptions, defined in `prism/errors.py` so that they can
//! have two bases (a `SceneError` is a `PrismError` and a `ValueError`): the file, line
//! and column of the Rust error become attributes.

use prism::Error;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::path::Path;

/// Converts a library error into the matching exception of `prism.errors`.
pub fn to_py(py: Python<'_>, error: Error) -> PyErr {
    let message = error.to_string();
    let (class, file, line, column) = match &error {
        Error::Parse { path, line, .. } => ("SceneError", Some(path), Some(*line), None),
        Error::ParseAt {
            path, line, column, ..
        } => ("SceneError", Some(path), Some(*line), Some(*column)),
        Error::File { path, .. } => ("FileError", Some(path), None, None),
        Error::Data { .. } => ("SceneError", None, None, None),
        Error::Settings(_) => ("SettingsError", None, None, None),
        Error::Denoise(_) => ("PrismError", None, None, None),
        Error::Interrupted => return PyKeyboardInterrupt::new_err("render interrupted"),
    };
    match raise(py, class, &message, file.map(|p| p.as_path()), line, column) {
        Ok(err) | Err(err) => err,
    }
}

fn raise(
    py: Python<'_>,
    class: &str,
    message: &str,
    file: Option<&Path>,
    line: Option<usize>,
    column: Option<usize>,
) -> PyResult<PyErr> {
    let module = py.import("prism.errors")?;
    let exc = module.getattr(class)?.call1((message,))?;
    exc.setattr("file", file.map(|p| p.to_string_lossy().into_owned()))?;
    exc.setattr("line", line)?;
    exc.setattr("column", column)?;
    Ok(PyErr::from_value(exc))
}

/// `Result<T, prism::Error>` to `PyResult<T>`.
pub trait IntoPy<T> {
    fn py_err(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> IntoPy<T> for prism::Result<T> {
    fn py_err(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, e))
    }
}
