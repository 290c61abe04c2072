//! The render options of `prism.render` (a dict of the keyword arguments that are not
//! `None`) as the library's `JobOptions`: the same struct the command line fills, so
//! a render from Python is the render `prism render` makes with the same options.

use crate::camera::Camera;
use prism::job::JobOptions;
use prism::render::Region;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Options over the scene's own; unknown keys are a `TypeError`, as for a function.
pub fn job_options(
    camera: Option<&Camera>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<JobOptions> {
    let mut o = JobOptions::default();
    if let Some(camera) = camera {
        camera.apply(&mut o);
    }
    let Some(options) = options else {
        return Ok(o);
    };
    for (key, value) in options.iter() {
        let key: String = key.extract()?;
        if value.is_none() {
            continue;
        }
        match key.as_str() {
            "width" => o.render.width = Some(value.extract()?),
            "height" => o.render.height = Some(value.extract()?),
            "aa" => o.render.aa = Some(value.extract()?),
            // `dof_rays` is the older name of `spp`.
            "spp" | "dof_rays" => o.render.spp = Some(value.extract()?),
            "seed" => o.render.seed = Some(value.extract()?),
            "camera_name" => o.camera_name = Some(value.extract()?),
            "smooth" => o.smooth = value.extract()?,
            "up_axis" => {
                o.up_axis = Some(match value.extract::<String>()?.as_str() {
                    "y" => prism::math::Vec3::Y,
                    "z" => prism::math::Vec3::Z,
                    other => {
                        return Err(PyValueError::new_err(format!(
                            "up_axis must be \"y\" or \"z\", found {other:?}"
                        )));
                    }
                })
            }
            "camera_index" => o.camera_index = Some(value.extract()?),
            "environment" => {
                let file: std::path::PathBuf = value.extract()?;
                o.environment = Some(prism::job::EnvironmentMap::new(file));
            }
            "material" => o.material = Some(value.extract()?),
            // Read below, once the environment they turn and scale is known.
            "environment_rotate" | "environment_strength" => {}
            "threads" => o.threads = Some(value.extract()?),
            "max_depth" => o.render.max_depth = Some(value.extract()?),
            "min_weight" => o.render.min_weight = Some(value.extract()?),
            "light_sampling" => o.render.light_sampling = Some(parse(&value)?),
            "max_memory" => {
                o.max_memory = Some(match value.extract::<String>() {
                    Ok(text) => {
                        prism::render::memory::parse_size(&text).map_err(PyValueError::new_err)?
                    }
                    Err(_) => value.extract()?,
                })
            }
            "filter" => o.render.filter = Some(parse(&value)?),
            "integrator" => o.render.integrator = Some(parse(&value)?),
            "exposure" => {
                let stops: f32 = value.extract()?;
                let checked = prism::film::develop::parse_exposure(&stops.to_string());
                o.render.exposure = Some(checked.map_err(PyValueError::new_err)?);
            }
            "tonemap" => o.render.tonemap = Some(parse(&value)?),
            "denoise" => o.render.denoise = Some(value.extract()?),
            "png_bits" => {
                let bits: u32 = value.extract()?;
                o.png_bits = bits.to_string().parse().map_err(PyValueError::new_err)?;
            }
            "exr_precision" => o.exr_precision = parse(&value)?,
            "accel" => o.accel = Some(parse(&value)?),
            "region" => {
                let (x, y, width, height): (u32, u32, u32, u32) = value.extract()?;
                o.region = Some(Region {
                    x,
                    y,
                    width,
                    height,
                });
            }
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "unknown render option `{key}`"
                )));
            }
        }
    }
    for (key, rotate) in [
        ("environment_rotate", true),
        ("environment_strength", false),
    ] {
        let Some(value) = options.get_item(key)?.filter(|v| !v.is_none()) else {
            continue;
        };
        let Some(env) = &mut o.environment else {
            return Err(PyValueError::new_err(format!("{key} needs environment")));
        };
        if rotate {
            env.rotate = value.extract()?;
        } else {
            env.strength = value.extract()?;
        }
    }
    Ok(o)
}

/// A name the library parses (`"lanczos"`, `"whitted"`, `"bvh"`).
fn parse<T: std::str::FromStr<Err = String>>(value: &Bound<'_, PyAny>) -> PyResult<T> {
    let name: String = value.extract()?;
    name.parse().map_err(PyValueError::new_err)
}
