//! The image being made: linear RGB (0..1 for the classic model, unbounded radiance for
//! the physically based one), the resampler that turns a supersampled frame into it, its
//! development into display values, and the writers and readers that store it.

pub mod denoise;
pub mod develop;
pub mod output;
pub mod resample;
pub mod stream;
pub mod tev;

pub use crate::util::hdr::{ExrPrecision, read_linear_image};
pub use crate::util::image::{Image, quantize};
pub use denoise::denoise;
pub use develop::{Develop, ToneMap, Transfer};
pub use output::{
    OutputFile, OutputFormat, OutputOptions, PngBits, file_bytes, write_exr_with_passes,
    write_image,
};
pub use stream::PngStream;
