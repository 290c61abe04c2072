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

/// A mesh's arrays as Python hands them over: its name, then little-endian `f32`
/// vertices, `u32` faces, and optional normals, texture coordinates and colours.
type MeshArrays = (
    String,
    Vec<u8>,
    Vec<u8>,
    Option<Vec<u8>>,
    Option<Vec<u8>>,
    Option<Vec<u8>>,
);

/// A scene given as the scene file's schema in JSON text, its mesh objects' arrays
/// beside it: `(name, vertices, faces, normals, uvs, colors)` with little-endian f32 and u32
/// bytes (`prism.scene_from_dict` makes both from a dict and NumPy arrays).
#[pyfunction]
#[pyo3(signature = (json, meshes, folder, transforms = Vec::new()))]
pub fn scene_from_json(
    py: Python<'_>,
    json: &str,
    meshes: Vec<MeshArrays>,
    folder: PathBuf,
    // Borrowed: ten thousand placements are not copied out of Python to be read once.
    transforms: Vec<(String, pyo3::pybacked::PyBackedBytes)>,
) -> PyResult<Scene> {
    let value: serde_json::Value =
        serde_json::from_str(json).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let floats = |b: &[u8]| -> Vec<f32> {
        b.chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    };
    let triples = |v: Vec<f32>| v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut arrays = std::collections::HashMap::new();
    for (name, vertices, faces, normals, uvs, colors) in meshes {
        let mesh = format::scene_file::ArrayMesh {
            vertices: triples(floats(&vertices)),
            faces: faces
                .chunks_exact(12)
                .map(|c| {
                    let u = |k: usize| u32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
                    [u(0), u(4), u(8)]
                })
                .collect(),
            normals: normals.map(|n| triples(floats(&n))),
            uvs: uvs.map(|t| floats(&t).chunks_exact(2).map(|c| [c[0], c[1]]).collect()),
            colors: colors.map(|c| triples(floats(&c))),
        };
        arrays.insert(name, mesh);
    }
    // Placements as little-endian f64, sixteen a matrix, row by row.
    let placements = transforms
        .into_iter()
        .map(|(name, bytes)| {
            let matrices = bytes
                .chunks_exact(128)
                .map(|m| {
                    let at = |k: usize| {
                        f64::from_le_bytes(m[8 * k..8 * k + 8].try_into().expect("8 bytes"))
                    };
                    std::array::from_fn(|r| std::array::from_fn(|c| at(4 * r + c)))
                })
                .collect();
            (name, matrices)
        })
        .collect();
    let path = folder.join("<scene dict>");
    let file = py
        .detach(|| format::scene_file::from_value(&value, &folder, &arrays, placements))
        .py_err(py)?;
    Ok(Scene {
        path,
        file: Arc::new(file),
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
