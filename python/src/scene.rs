//! A loaded scene file. It is parsed once; every render resolves its camera and
//! settings from a copy, as `prism render` does from the file.

use crate::errors::IntoPy;
use prism::format::{self, SceneDialect, SceneFile};
use prism::info::SceneInfo;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A scene read from a file: `.objx` (2014), `.obj` (Wavefront) or `.toml` (Prism).
#[pyclass(frozen, module = "prism._prism")]
pub struct Scene {
    pub path: PathBuf,
    pub file: Arc<SceneFile>,
}

/// The dialect `--dialect NAME` means.
fn dialect_named(name: &str) -> PyResult<SceneDialect> {
    SceneDialect::named(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown dialect `{name}`: expected {}",
            SceneDialect::names().join(", ")
        ))
    })
}

/// Reads a scene file; `dialect` overrides the one its extension names.
#[pyfunction]
#[pyo3(signature = (path, dialect = None))]
pub fn load_scene(py: Python<'_>, path: PathBuf, dialect: Option<&str>) -> PyResult<Scene> {
    let dialect = dialect.map(dialect_named).transpose()?;
    let file = py
        .detach(|| match dialect {
            Some(d) => format::load_as(&path, d),
            None => format::load(&path),
        })
        .py_err(py)?;
    Ok(Scene {
        path,
        file: Arc::new(file),
    })
}

#[pymethods]
impl Scene {
    /// What `prism info --json` prints, as a dict.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = serde_json::to_string(&SceneInfo::of(&self.file))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (json,))
    }

    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    #[getter]
    fn dialect(&self) -> &'static str {
        self.file.dialect.name()
    }

    /// What was read but not understood, as `file:line: message`.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.file.warnings.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "<prism.Scene {} ({}, {} shapes, {} lights)>",
            self.path.display(),
            self.file.dialect.name(),
            self.file.scene.shapes.len(),
            self.file.scene.lights.len()
        )
    }

    /// Jupyter shows a scene as a table of what it holds.
    fn _repr_html_(&self) -> String {
        let i = SceneInfo::of(&self.file);
        let esc = |s: &str| {
            s.replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('>', "&gt;")
        };
        let rows = [
            ("file", esc(&self.path.display().to_string())),
            ("dialect", i.dialect.to_string()),
            (
                "shapes",
                format!("{} triangles, {} spheres", i.triangles, i.spheres),
            ),
            ("objects", esc(&i.object_names.join(", "))),
            ("materials", i.materials.to_string()),
            ("lights", i.light_kinds.join(", ")),
            ("bounds", format!("{:?} – {:?}", i.bounds[0], i.bounds[1])),
        ];
        let body: String = rows
            .iter()
            .map(|(k, v)| format!("<tr><th style=\"text-align:left\">{k}</th><td>{v}</td></tr>"))
            .collect();
        format!("<table>{body}</table>")
    }
}
