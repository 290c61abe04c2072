//! The path model's samples, spread over each pixel's area, traced in packets of
//! [`PACKET_RAYS`] that run across pixels: a strip's pixels are taken a tile of
//! [`TILE_COLUMNS`] x [`TILE_ROWS`] at a time and each pixel's samples in order, so a
//! packet holds sixteen samples of one pixel where a pass adds that many, and sixteen
//! neighbouring pixels' samples where it adds one (a progressive render's first
//! passes, a preview's). Packets always full but for a strip's last: the paths'
//! lanes and waves are as wide at one sample a pixel as at sixteen.
//!
//! Every sample draws from its own stream and each packet's paths are traced as each
//! would be alone, so how samples are grouped changes no number: a pixel's sum takes
//! its samples in order, whatever packets they went in.

use super::{
    CameraRays, Integrator, NO_RAY, Observer, PixelSampler, PixelStreams, RayCount, Renderer,
    StreamLanes, TILE_COLUMNS, WeightedColor,
};
use crate::accel::{Accel, PACKET_RAYS};
use crate::math::Ray;
use std::ops::Range;

/// Where a pixel's samples are summed: a running [`WeightedColor`], or a sample
/// pass's stored sum (its floats as they were).
pub(super) trait PixelSum {
    /// Adds the sum of a sample traced alone.
    fn add_sample(&mut self, sample: &WeightedColor);
}

impl PixelSum for WeightedColor {
    #[inline]
    fn add_sample(&mut self, sample: &WeightedColor) {
        self.sum += sample.sum;
        self.weight += sample.weight;
    }
}

/// A packet being filled: each place's camera ray, its sample's stream, and the pixel
/// (its index in the strip) its radiance is added to.
struct Packet {
    rays: [Ray; PACKET_RAYS],
    samplers: [PixelSampler; PACKET_RAYS],
    pixel: [usize; PACKET_RAYS],
    len: usize,
}

impl Renderer<'_> {
    /// Adds samples `samples` of every pixel of a strip (whole rows of `row_len`
    /// supersampled pixels from `origin`) to the pixel's sum in `sums` (row after
    /// row), in packets across pixels as the module says. Stops at the next pixel once
    /// `observer` cancels, the samples of the packet in hand not added.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_strip_samples<I: Integrator, S: PixelSum>(
        &self,
        integrator: &I,
        accel: &Accel,
        rays: &CameraRays,
        origin: (u32, u32),
        row_len: usize,
        samples: Range<u32>,
        sums: &mut [S],
        count: &mut RayCount,
        observer: &dyn Observer,
    ) {
        let rows = sums.len() / row_len.max(1);
        let mut packet = Packet {
            rays: [NO_RAY; PACKET_RAYS],
            samplers: std::array::from_fn(|_| PixelSampler::idle()),
            pixel: [0; PACKET_RAYS],
            len: 0,
        };
        let lanes = if integrator.sixteen_lanes() {
            StreamLanes::Sixteen
        } else {
            StreamLanes::Eight
        };
        for x0 in (0..row_len).step_by(TILE_COLUMNS) {
            for r in 0..rows {
                for c in x0..(x0 + TILE_COLUMNS).min(row_len) {
                    // A pixel of many samples is a long wait: Ctrl-C should not last
                    // a strip.
                    if observer.cancelled() {
                        return;
                    }
                    let k = r * row_len + c;
                    let (x, y) = (origin.0 + c as u32, origin.1 + r as u32);
                    let streams = PixelStreams::new(self.plan.seed, x, y);
                    let mut first = samples.start;
                    while first < samples.end {
                        let at = packet.len;
                        let n = ((samples.end - first) as usize).min(PACKET_RAYS - at);
                        streams.samples_into(first, &mut packet.samplers[at..at + n], lanes);
                        for i in at..at + n {
                            let sampler = &mut packet.samplers[i];
                            let jitter = sampler.next_2d();
                            let lens = sampler.next_2d();
                            packet.rays[i] = rays.through(x, y, jitter, lens);
                            packet.pixel[i] = k;
                        }
                        packet.len += n;
                        first += n as u32;
                        if packet.len == PACKET_RAYS {
                            trace(integrator, accel, &mut packet, sums, count);
                        }
                    }
                }
            }
        }
        trace(integrator, accel, &mut packet, sums, count);
    }
}

/// Traces `packet`'s camera rays (a lone ray alone), adds each path's radiance to its
/// pixel's sum in packet order, and empties it.
#[inline]
fn trace<I: Integrator, S: PixelSum>(
    integrator: &I,
    accel: &Accel,
    packet: &mut Packet,
    sums: &mut [S],
    count: &mut RayCount,
) {
    let n = std::mem::take(&mut packet.len);
    // Each path's own sum, then added to its pixel's: 0 + l is l (a -0 becomes +0,
    // which adds to a pixel's sum as -0 would, as a sum that starts at +0 is never -0).
    let mut own = [WeightedColor::default(); PACKET_RAYS];
    match n {
        0 => return,
        1 => {
            integrator.trace_camera_ray(packet.rays[0], &mut packet.samplers[0], &mut own[0], count)
        }
        _ => {
            let mut hits = [None; PACKET_RAYS];
            accel.closest_packet(&packet.rays[..n], f32::INFINITY, &mut hits[..n]);
            integrator.trace_camera_packet(
                &packet.rays[..n],
                &hits[..n],
                &mut packet.samplers[..n],
                &mut own[..n],
                count,
            );
        }
    }
    for (&k, own) in packet.pixel[..n].iter().zip(&own) {
        sums[k].add_sample(own);
    }
}

#[cfg(test)]
mod tests;
