//! The shadow rays of an area light's samples seen from one shading point, traced as one
//! packet. They leave from the same point toward a small patch, so their frustum is
//! tight: on the bunny scene's sphere light (16 samples) they were 42 % of a render
//! traced one at a time.
//!
//! A sample's light is added when the batch is resolved, in the order the samples were
//! drawn and with the same arithmetic as one at a time, so the image does not change.

use crate::accel::{Accel, PACKET_RAYS};
use crate::math::{Ray, Vec3};
use crate::render::NO_RAY;

/// Light samples waiting for their shadow answers: up to [`PACKET_RAYS`].
pub(super) struct ShadowBatch {
    /// The shadow rays to trace, packed, and the distance each must cover.
    rays: [Ray; PACKET_RAYS],
    t_max: [f32; PACKET_RAYS],
    traced: usize,
    /// Per sample, in order: its irradiance, its shading factor, and whether its shadow
    /// ray is traced (a sample on the point itself needs none and is seen).
    samples: [(Vec3, Vec3, bool); PACKET_RAYS],
    len: usize,
}

impl ShadowBatch {
    pub(super) fn new() -> ShadowBatch {
        ShadowBatch {
            rays: [NO_RAY; PACKET_RAYS],
            t_max: [0.0; PACKET_RAYS],
            traced: 0,
            samples: [(Vec3::ZERO, Vec3::ZERO, false); PACKET_RAYS],
            len: 0,
        }
    }

    pub(super) fn is_full(&self) -> bool {
        self.len == PACKET_RAYS
    }

    /// Adds a sample of irradiance `e` and shading factor `shade`, whose shadow ray
    /// (and the distance it must cover) is `shadow`. The batch must not be full.
    pub(super) fn push(&mut self, shadow: Option<(Ray, f32)>, e: Vec3, shade: Vec3) {
        if let Some((ray, t_max)) = shadow {
            self.rays[self.traced] = ray;
            self.t_max[self.traced] = t_max;
            self.traced += 1;
        }
        self.samples[self.len] = (e, shade, shadow.is_some());
        self.len += 1;
    }

    /// Traces the waiting shadow rays against `accel` as one packet (`blocks` says which
    /// shapes stop light), then hands `add` each sample's light, `vis * e * shade`, in
    /// order; empties the batch.
    pub(super) fn resolve(
        &mut self,
        accel: &Accel,
        blocks: impl Fn(u32) -> bool,
        mut add: impl FnMut(Vec3),
    ) {
        let blocked = if self.traced > 0 {
            accel.occluded_packet(
                &self.rays[..self.traced],
                &self.t_max[..self.traced],
                blocks,
            )
        } else {
            0
        };
        let mut k = 0;
        for &(e, shade, traced) in &self.samples[..self.len] {
            let vis = if traced && blocked >> k & 1 == 1 {
                Vec3::ZERO
            } else {
                Vec3::ONE
            };
            k += usize::from(traced);
            add(vis * e * shade);
        }
        self.traced = 0;
        self.len = 0;
    }
}
