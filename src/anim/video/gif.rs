//! Animated GIF: a palette of 256 colours per frame (NeuQuant), looping for ever.
//!
//! GIF delays are whole hundredths of a second. Frame `k` lasts
//! `round(100 (k + 1) / fps) - round(100 k / fps)` hundredths, so the frames keep time
//! with the requested rate and the whole film lasts as long as asked (24 fps: frames of
//! 4 and 5 hundredths, 5 seconds for 120 frames). Above 50 fps some frames get less than
//! 2 hundredths, which browsers do not honour (they show such frames for about 1/10 s).

use super::{Encoder, write_error};
use crate::error::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Quantiser speed, 1 (best) to 30 (fastest); 10 is the gif crate's balance.
const SPEED: i32 = 10;

pub struct Gif<W: Write> {
    path: PathBuf,
    encoder: gif::Encoder<W>,
    width: u16,
    height: u16,
    fps: f64,
    frame: u64,
}

/// Hundredths of a second from the start to frame `k`.
fn start_of(k: u64, fps: f64) -> f64 {
    (100.0 * k as f64 / fps).round()
}

/// Delay of frame `k` in hundredths of a second.
pub fn delay_for(k: u64, fps: f64) -> u16 {
    (start_of(k + 1, fps) - start_of(k, fps)).clamp(0.0, u16::MAX as f64) as u16
}

/// Whether some frame at this rate is shorter than browsers show (2 hundredths).
pub fn too_fast_for_browsers(fps: f64) -> bool {
    fps > 50.0
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
            fps,
            frame: 0,
        })
    }
}

impl<W: Write> Encoder for Gif<W> {
    fn push(&mut self, rgb: &[u8]) -> Result<()> {
        let mut frame = gif::Frame::from_rgb_speed(self.width, self.height, rgb, SPEED);
        frame.delay = delay_for(self.frame, self.fps);
        self.frame += 1;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| write_error(&self.path, e))
    }

    fn finish(self: Box<Self>) -> Result<f64> {
        let path = self.path.clone();
        let total = start_of(self.frame, self.fps);
        let fps = if total > 0.0 {
            self.frame as f64 * 100.0 / total
        } else {
            self.fps
        };
        let mut out = self
            .encoder
            .into_inner()
            .map_err(|e| write_error(&path, e))?;
        out.flush().map_err(|e| write_error(&path, e))?;
        Ok(fps)
    }
}
