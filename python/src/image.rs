//! Pixels from Python into image files, through the library's writers: the formats,
//! the development and the atomic write of `prism render`.

use crate::errors::IntoPy;
use prism::film::{Develop, ExrPrecision, Image, OutputOptions, PngBits, ToneMap, Transfer};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// Row-major RGB samples as the library's image. `u1` samples become `v / 255`, which
/// classic development turns back into `v` exactly.
fn image_of(data: &[u8], width: u32, height: u32, dtype: &str) -> PyResult<Image> {
    let n = width as usize * height as usize * 3;
    let values: Vec<f32> = match dtype {
        "<f4" if data.len() == n * 4 => data
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect(),
        "u1" if data.len() == n => data.iter().map(|&v| f32::from(v) / 255.0).collect(),
        _ => {
            return Err(PyValueError::new_err(format!(
                "expected {width}x{height}x3 samples of float32 or uint8, found {} bytes of {dtype}",
                data.len()
            )));
        }
    };
    let pixels = values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Image::new(width, height, pixels))
}

fn parse<T: std::str::FromStr<Err = String>>(text: &str) -> PyResult<T> {
    text.parse().map_err(PyValueError::new_err)
}

/// Writes pixels to `path` in the format its extension names (atomically). Float
/// samples are radiance, developed for 8- and 16-bit formats; 8-bit samples are stored
/// as they are (and as `v / 255` in the linear formats, EXR and HDR).
#[pyfunction]
#[pyo3(signature = (data, width, height, dtype, path, exposure = 0.0, tonemap = "clamp", transfer = "srgb", png_bits = 8, exr_precision = "half"))]
#[allow(clippy::too_many_arguments)]
pub fn write_image(
    py: Python<'_>,
    data: &[u8],
    width: u32,
    height: u32,
    dtype: &str,
    path: PathBuf,
    exposure: f32,
    tonemap: &str,
    transfer: &str,
    png_bits: u32,
    exr_precision: &str,
) -> PyResult<()> {
    let image = image_of(data, width, height, dtype)?;
    let develop = if dtype == "u1" {
        Develop::classic()
    } else {
        if !(exposure.is_finite() && exposure.abs() <= 64.0) {
            return Err(PyValueError::new_err(format!(
                "expected an exposure in stops between -64 and 64, found {exposure}"
            )));
        }
        let transfer = match transfer {
            "srgb" => Transfer::Srgb,
            "classic" => Transfer::Classic,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown transfer `{transfer}`: expected srgb or classic"
                )));
            }
        };
        Develop {
            exposure,
            tonemap: parse::<ToneMap>(tonemap)?,
            transfer,
        }
    };
    let options = OutputOptions {
        develop,
        png_bits: parse::<PngBits>(&png_bits.to_string())?,
        exr_precision: parse::<ExrPrecision>(exr_precision)?,
    };
    py.detach(|| prism::film::write_image(&image, &path, &options))
        .py_err(py)
}

/// An 8-bit image as the bytes of a PNG file, for notebooks.
#[pyfunction]
pub fn encode_png<'py>(
    py: Python<'py>,
    data: &[u8],
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyBytes>> {
    let image = image_of(data, width, height, "u1")?;
    let bytes = prism::film::file_bytes(&image, "png", &OutputOptions::classic()).py_err(py)?;
    Ok(PyBytes::new(py, &bytes))
}
