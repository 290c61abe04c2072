//! The camera a render uses when the scene's own will not do: a 2014 `.cmr` file, or a
//! look-at. Either is applied as the command line applies `CAMERA` or `--look-from`,
//! `--look-at`, `--up`, `--fov`, `--width`, `--height`, so the image is the same.

use crate::errors::IntoPy;
use prism::job::{JobOptions, LookAt};
use prism::math::Vec3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

#[derive(Clone, Debug)]
enum Kind {
    File(PathBuf),
    LookAt {
        look: LookAt,
        width: Option<u32>,
        height: Option<u32>,
    },
}

/// A camera for `prism.render`: `Camera.from_file(path)` or `Camera.look_at(...)`.
#[pyclass(frozen, module = "prism._prism")]
#[derive(Clone, Debug)]
pub struct Camera {
    kind: Kind,
}

#[pymethods]
impl Camera {
    /// A 2014 camera file (`.cmr`), read now so that a bad file fails here.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Camera> {
        prism::format::load_camera(&path).py_err(py)?;
        Ok(Camera {
            kind: Kind::File(path),
        })
    }

    /// A right-handed look-at camera; `fov` is the horizontal field of view in degrees.
    #[staticmethod]
    #[pyo3(signature = (from_, at, up = (0.0, 1.0, 0.0), fov = 40.0, width = None, height = None))]
    fn look_at(
        from_: (f32, f32, f32),
        at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
        width: Option<u32>,
        height: Option<u32>,
    ) -> PyResult<Camera> {
        let v = |(x, y, z): (f32, f32, f32)| Vec3::new(x, y, z);
        let (from, at, up) = (v(from_), v(at), v(up));
        if !(from.is_finite() && at.is_finite() && up.is_finite()) || from == at {
            return Err(PyValueError::new_err(
                "from_ and at must be different finite points, and up finite",
            ));
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(PyValueError::new_err(format!(
                "fov must be between 0 and 180 degrees, found {fov}"
            )));
        }
        Ok(Camera {
            kind: Kind::LookAt {
                look: LookAt {
                    from: Some(from),
                    at: Some(at),
                    up: Some(up),
                    fov: Some(fov),
                },
                width,
                height,
            },
        })
    }

    fn __repr__(&self) -> String {
        match &self.kind {
            Kind::File(path) => format!("Camera.from_file({:?})", path.display().to_string()),
            Kind::LookAt {
                look,
                width,
                height,
            } => {
                let t = |v: Option<Vec3>| v.map(|v| (v.x, v.y, v.z));
                format!(
                    "Camera.look_at({:?}, {:?}, up={:?}, fov={:?}, width={:?}, height={:?})",
                    t(look.from),
                    t(look.at),
                    t(look.up),
                    look.fov,
                    width,
                    height
                )
            }
        }
    }
}

impl Camera {
    /// Sets the camera's part of the options; the render's own width and height, applied
    /// after, win over the look-at's.
    pub fn apply(&self, o: &mut JobOptions) {
        match &self.kind {
            Kind::File(path) => o.camera_file = Some(path.clone()),
            Kind::LookAt {
                look,
                width,
                height,
            } => {
                o.look = *look;
                o.render.width = *width;
                o.render.height = *height;
            }
        }
    }
}
