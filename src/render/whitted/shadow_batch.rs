//! The shadow rays of an area light's samples seen from one shading point, traced as one
//! packet. They leave from the same point toward a small patch, so their frustum is
//! tight: on the bunny scene's sphere light (16 samples) they were 42 % of a render
//! traced one at a time.
//!
//! A sample's light is added when the batch is resolved, in the order the samples were
//! drawn and with the same arithmetic as one at a time, so the image does not change.
//! Where surfaces tint shadow rays, the packet asks only whether a ray meets anything
//! that is not clear to shadows; the few that do are settled one at a time.

use crate::accel::{Accel, PACKET_RAYS};
use crate::math::{Ray, Vec3};
use crate::scene::light::stratified::lanes::LANES;

use super::LightSample;
use std::mem::MaybeUninit;

// A chunk of a light's sample lanes fills one packet of shadow rays.
const _: () = assert!(LANES == PACKET_RAYS);

/// Light samples waiting for their shadow answers: up to [`PACKET_RAYS`].
///
/// A batch is made at every shading point an area light lights, so its arrays are left
/// uninitialised: clearing their two kilobytes cost the area-lit scenes 5-8 % of their
/// render time. Only the first `traced` rays and `len` samples are ever read.
pub(super) struct ShadowBatch {
    /// The shadow rays to trace, packed, and the distance each must cover.
    rays: [MaybeUninit<Ray>; PACKET_RAYS],
    t_max: [MaybeUninit<f32>; PACKET_RAYS],
    traced: usize,
    /// Per sample, in order: the sample, its shading factor, and whether its shadow ray
    /// is traced (a sample on the point itself needs none and is seen).
    samples: [MaybeUninit<(LightSample, Vec3, bool)>; PACKET_RAYS],
    len: usize,
}

impl ShadowBatch {
    pub(super) fn new() -> ShadowBatch {
        ShadowBatch {
            rays: [const { MaybeUninit::uninit() }; PACKET_RAYS],
            t_max: [const { MaybeUninit::uninit() }; PACKET_RAYS],
            traced: 0,
            samples: [const { MaybeUninit::uninit() }; PACKET_RAYS],
            len: 0,
        }
    }

    pub(super) fn is_full(&self) -> bool {
        self.len == PACKET_RAYS
    }

    /// Whether any sample waiting has a shadow ray to trace.
    #[cfg(test)]
    pub(super) fn traces(&self) -> bool {
        self.traced > 0
    }

    /// Adds sample `ls` of shading factor `shade`, whose shadow ray (and the distance it
    /// must cover) is `shadow`. The batch must not be full.
    pub(super) fn push(&mut self, shadow: Option<(Ray, f32)>, ls: LightSample, shade: Vec3) {
        if let Some((ray, t_max)) = shadow {
            self.rays[self.traced].write(ray);
            self.t_max[self.traced].write(t_max);
            self.traced += 1;
        }
        self.samples[self.len].write((ls, shade, shadow.is_some()));
        self.len += 1;
    }

    /// Traces the waiting shadow rays against `accel` as one packet, asking whether each
    /// meets a shape for which `meets` holds; `settle` gives the visibility of a sample
    /// whose ray does (unmet ones are seen whole). Then hands `add` each sample's
    /// light, `vis * e * shade`, in order, and empties the batch.
    pub(super) fn resolve(
        &mut self,
        accel: &Accel,
        meets: impl Fn(crate::scene::ShapeId) -> bool,
        mut settle: impl FnMut(&LightSample) -> Vec3,
        mut add: impl FnMut(Vec3),
    ) {
        let met = if self.traced > 0 {
            let (rays, t_max) = self.traced();
            accel.occluded_packet(rays, t_max, meets)
        } else {
            0
        };
        let mut k = 0;
        for (ls, shade, traced) in self.waiting() {
            let vis = if *traced && met >> k & 1 == 1 {
                settle(ls)
            } else {
                Vec3::ONE
            };
            k += usize::from(*traced);
            add(vis * ls.e * *shade);
        }
        self.traced = 0;
        self.len = 0;
    }

    /// The shadow rays `push` packed, and the distance each must cover.
    fn traced(&self) -> (&[Ray], &[f32]) {
        // SAFETY: `push` writes each array from the start and counts an entry only
        // once written, and nothing else changes the counts but `resolve`'s reset;
        // a `MaybeUninit<T>` has the layout of `T`.
        unsafe {
            (
                std::slice::from_raw_parts(self.rays.as_ptr().cast::<Ray>(), self.traced),
                std::slice::from_raw_parts(self.t_max.as_ptr().cast::<f32>(), self.traced),
            )
        }
    }

    /// The samples waiting, in the order `push` added them.
    fn waiting(&self) -> &[(LightSample, Vec3, bool)] {
        // SAFETY: as in `traced`, for the first `len` samples.
        unsafe { std::slice::from_raw_parts(self.samples.as_ptr().cast(), self.len) }
    }
}
