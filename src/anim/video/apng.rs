//! Animated PNG: lossless 8-bit RGB frames, looping for ever. Players that do not know
//! APNG show the first frame.

use super::{Encoder, write_error};
use crate::error::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

pub struct Apng<W: Write> {
    path: PathBuf,
    writer: png::Writer<W>,
    fps: f64,
}

/// Frame delay as a fraction of a second `(numerator, denominator)`, both 16-bit: the
/// closest to `1 / fps` among whole frame rates, rates in thousandths, hundredths and
/// tenths of a frame per second, and delays in thousandths to whole seconds. Whole
/// rates and rates with three decimals below 65.536 fps (23.976, 29.97) are exact.
pub fn delay_for(fps: f64) -> (u16, u16) {
    let fits = |x: f64| x >= 1.0 && x <= u16::MAX as f64;
    let mut candidates = Vec::new();
    for scale in [1.0, 1000.0, 100.0, 10.0] {
        // A rate of n / scale frames per second: a delay of scale / n.
        let n = (fps * scale).round();
        if fits(n) {
            candidates.push((scale as u16, n as u16));
        }
        // A delay of n / scale seconds.
        let n = (scale / fps).round();
        if fits(n) {
            candidates.push((n as u16, scale as u16));
        }
    }
    let error = |&(num, den): &(u16, u16)| (num as f64 / den as f64 * fps - 1.0).abs();
    let mut best = (1, 1);
    let mut best_error = f64::INFINITY;
    for c in candidates {
        if error(&c) < best_error {
            best_error = error(&c);
            best = c;
        }
    }
    best
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
