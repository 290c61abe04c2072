//! Animated PNG: lossless 8-bit RGB frames, looping for ever. Players that do not know
//! APNG show the first frame.

use super::{Encoder, write_error};
use crate::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

pub struct Apng<W: Write> {
    path: PathBuf,
    writer: png::Writer<W>,
    fps: f64,
}

/// Frame delay as a fraction of a second `(numerator, denominator)`: exact for whole
/// frame rates, else to 1/100 of a frame per second.
pub fn delay_for(fps: f64) -> (u16, u16) {
    if fps.fract() == 0.0 && fps <= u16::MAX as f64 {
        (1, fps as u16)
    } else {
        (
            100,
            (fps * 100.0).round().clamp(1.0, u16::MAX as f64) as u16,
        )
    }
}

impl<W: Write> Apng<W> {
    pub fn new(
        out: W,
        path: &Path,
        width: u32,
        height: u32,
        fps: f64,
        frames: u32,
    ) -> Result<Apng<W>> {
        let mut encoder = png::Encoder::new(out, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder
            .set_animated(frames, 0)
            .map_err(|e| write_error(path, e))?;
        let (num, den) = delay_for(fps);
        encoder
            .set_frame_delay(num, den)
            .map_err(|e| write_error(path, e))?;
        let writer = encoder.write_header().map_err(|e| write_error(path, e))?;
        Ok(Apng {
            path: path.to_path_buf(),
            writer,
            fps: den as f64 / num as f64,
        })
    }
}

impl<W: Write> Encoder for Apng<W> {
    fn push(&mut self, rgb: &[u8]) -> Result<()> {
        self.writer
            .write_image_data(rgb)
            .map_err(|e| write_error(&self.path, e))
    }

    fn finish(self: Box<Self>) -> Result<f64> {
        let path = self.path.clone();
        self.writer.finish().map_err(|e| write_error(&path, e))?;
        Ok(self.fps)
    }
}
