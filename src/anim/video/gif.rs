//! Animated GIF: a palette of 256 colours per frame (NeuQuant), looping for ever.
//!
//! GIF delays are whole hundredths of a second, so the frame rate a GIF plays at is
//! 100 / round(100 / fps): 24 fps plays at 25, 30 at 33.3, 60 at 50.

use super::{Encoder, write_error};
use crate::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Quantiser speed, 1 (best) to 30 (fastest); 10 is the gif crate's balance.
const SPEED: i32 = 10;

pub struct Gif<W: Write> {
    path: PathBuf,
    encoder: gif::Encoder<W>,
    width: u16,
    height: u16,
    delay: u16,
}

/// Delay per frame in hundredths of a second (at least 2: browsers slow down 0 and 1).
pub fn delay_for(fps: f64) -> u16 {
    (100.0 / fps).round().clamp(2.0, u16::MAX as f64) as u16
}

impl<W: Write> Gif<W> {
    pub fn new(out: W, path: &Path, width: u32, height: u32, fps: f64) -> Result<Gif<W>> {
        let (width, height) = (width as u16, height as u16);
        let mut encoder =
            gif::Encoder::new(out, width, height, &[]).map_err(|e| write_error(path, e))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| write_error(path, e))?;
        Ok(Gif {
            path: path.to_path_buf(),
            encoder,
            width,
            height,
            delay: delay_for(fps),
        })
    }
}

impl<W: Write> Encoder for Gif<W> {
    fn push(&mut self, rgb: &[u8]) -> Result<()> {
        let mut frame = gif::Frame::from_rgb_speed(self.width, self.height, rgb, SPEED);
        frame.delay = self.delay;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| write_error(&self.path, e))
    }

    fn finish(self: Box<Self>) -> Result<f64> {
        let path = self.path.clone();
        let fps = 100.0 / self.delay as f64;
        let mut out = self
            .encoder
            .into_inner()
            .map_err(|e| write_error(&path, e))?;
        out.flush().map_err(|e| write_error(&path, e))?;
        Ok(fps)
    }
}
