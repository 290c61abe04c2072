//! H.264 in MP4: OpenH264 (built from its bundled source) encodes, the `mp4` crate muxes.
//!
//! OpenH264's traps, handled here: frame skipping and rate control are off, so every
//! frame is coded, at a constant quantiser (26, OpenH264's base; adaptive quantisation
//! keeps it within 18..40); the colour description BT.601 limited range is written into
//! the stream's parameter set (OpenH264's RGB to YUV conversion uses those
//! coefficients), and in the container's `colr` box ([`super::colr`]); the width and height must be even (checked before rendering, in
//! [`super::check_size`]). In debug builds the C++ is still optimised: the dev profile
//! builds every dependency, and so `cc`, at opt-level 3 (see `Cargo.toml`).

use super::{Encoder, write_error};
use crate::error::{Error, Result};
use ::mp4::{AvcConfig, MediaConfig, Mp4Config, Mp4Sample, Mp4Writer, TrackConfig, TrackType};
use openh264::OpenH264API;
use openh264::encoder::{
    EncoderConfig, FrameRate, IntraFramePeriod, QpRange, RateControlMode, VuiConfig,
};
use openh264::formats::{RgbSliceU8, YUVBuffer};
use std::io::{Seek, Write};
use std::path::{Path, PathBuf};

/// Ticks per frame in the track's time scale: the time scale is the frame rate times
/// this, so rates with up to three decimals are exact.
const TICKS: u32 = 1000;

pub struct Mp4<W: Write + Seek> {
    path: PathBuf,
    encoder: openh264::encoder::Encoder,
    out: Option<W>,
    writer: Option<Mp4Writer<W>>,
    width: u32,
    height: u32,
    timescale: u32,
    frame: u64,
    yuv: YUVBuffer,
}

impl<W: Write + Seek> Mp4<W> {
    pub fn new(out: W, path: &Path, width: u32, height: u32, fps: f64) -> Result<Mp4<W>> {
        // A zero time scale would divide by zero in the muxer.
        let timescale = (fps * TICKS as f64).round();
        if !(timescale >= 1.0 && timescale <= u32::MAX as f64) {
            return Err(Error::file(
                path,
                format!("cannot encode {fps} fps in MP4: the rate must be at least 0.001 fps"),
            ));
        }
        let timescale = timescale as u32;
        let config = EncoderConfig::new()
            .skip_frames(false)
            .rate_control_mode(RateControlMode::Off)
            .qp(QpRange::new(18, 40))
            .max_frame_rate(FrameRate::from_hz(fps as f32))
            // A key frame every two seconds, so players can seek.
            .intra_frame_period(IntraFramePeriod::from_num_frames(
                (fps * 2.0).round().max(1.0) as u32,
            ))
            .vui(VuiConfig::bt601())
            .num_threads(1);
        let encoder =
            openh264::encoder::Encoder::with_api_config(OpenH264API::from_source(), config)
                .map_err(|e| write_error(path, format!("cannot start the H.264 encoder: {e}")))?;
        Ok(Mp4 {
            path: path.to_path_buf(),
            encoder,
            out: Some(out),
            writer: None,
            width,
            height,
            timescale,
            frame: 0,
            yuv: YUVBuffer::new(width as usize, height as usize),
        })
    }

    /// Starts the container once the encoder has produced the parameter sets.
    fn start(&mut self, sps: &[u8], pps: &[u8]) -> Result<()> {
        let path = &self.path;
        let brand = |s: &str| s.parse().expect("four ASCII letters");
        let config = Mp4Config {
            major_brand: brand("isom"),
            minor_version: 512,
            compatible_brands: vec![brand("isom"), brand("iso2"), brand("avc1"), brand("mp41")],
            // The movie's time scale is the track's, so the container's duration is as
            // exact as the stream's (a coarser one loses time on every frame).
            timescale: self.timescale,
        };
        let out = self.out.take().expect("started once");
        let mut writer = Mp4Writer::write_start(out, &config).map_err(|e| write_error(path, e))?;
        writer
            .add_track(&TrackConfig {
                track_type: TrackType::Video,
                timescale: self.timescale,
                language: "und".into(),
                media_conf: MediaConfig::AvcConfig(AvcConfig {
                    width: self.width as u16,
                    height: self.height as u16,
                    seq_param_set: sps.to_vec(),
                    pic_param_set: pps.to_vec(),
                }),
            })
            .map_err(|e| write_error(path, e))?;
        self.writer = Some(writer);
        Ok(())
    }
}

/// A NAL unit without its Annex B start code.
fn strip_start_code(nal: &[u8]) -> &[u8] {
    nal.strip_prefix(&[0, 0, 0, 1])
        .or_else(|| nal.strip_prefix(&[0, 0, 1]))
        .unwrap_or(nal)
}

impl<W: Write + Seek> Encoder for Mp4<W> {
    fn push(&mut self, rgb: &[u8]) -> Result<()> {
        let (w, h) = (self.width as usize, self.height as usize);
        self.yuv.read_rgb8(RgbSliceU8::new(rgb, (w, h)));
        let millis = (self.frame as f64 * 1000.0 * TICKS as f64 / self.timescale as f64) as u64;
        let stream = self
            .encoder
            .encode_at(&self.yuv, openh264::Timestamp::from_millis(millis))
            .map_err(|e| write_error(&self.path, format!("H.264 encoder: {e}")))?;
        let (mut sps, mut pps, mut sample, mut sync) = (None, None, Vec::new(), false);
        for l in 0..stream.num_layers() {
            let layer = stream.layer(l).expect("layer in range");
            for n in 0..layer.nal_count() {
                let nal = strip_start_code(layer.nal_unit(n).expect("NAL in range"));
                let Some(&header) = nal.first() else { continue };
                match header & 0x1f {
                    7 => sps = Some(nal.to_vec()),
                    8 => pps = Some(nal.to_vec()),
                    kind => {
                        sync |= kind == 5;
                        sample.extend_from_slice(&(nal.len() as u32).to_be_bytes());
                        sample.extend_from_slice(nal);
                    }
                }
            }
        }
        if sample.is_empty() {
            return Err(Error::file(
                &self.path,
                format!("the H.264 encoder skipped frame {}", self.frame),
            ));
        }
        if self.writer.is_none() {
            match (sps, pps) {
                (Some(s), Some(p)) => self.start(&s, &p)?,
                _ => {
                    return Err(Error::file(
                        &self.path,
                        "the H.264 encoder gave no parameter sets with its first frame",
                    ));
                }
            }
        }
        let writer = self.writer.as_mut().expect("started");
        writer
            .write_sample(
                1,
                &Mp4Sample {
                    start_time: self.frame * TICKS as u64,
                    duration: TICKS,
                    rendering_offset: 0,
                    is_sync: sync,
                    bytes: bytes::Bytes::from(sample),
                },
            )
            .map_err(|e| write_error(&self.path, e))?;
        self.frame += 1;
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<f64> {
        let fps = self.timescale as f64 / TICKS as f64;
        let path = self.path.clone();
        let mut writer = self
            .writer
            .ok_or_else(|| Error::file(&path, "no frame to encode"))?;
        writer.write_end().map_err(|e| write_error(&path, e))?;
        let mut out = writer.into_writer();
        out.flush().map_err(|e| write_error(&path, e))?;
        Ok(fps)
    }
}
