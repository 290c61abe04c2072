//! The samples of one pixel stepped together, vertex by vertex, in any scene: each path
//! takes its step as [`Path::radiance`] takes it (the same code: [`Path::vertex`]),
//! then the rays of the paths still going are met together
//! ([`crate::accel::Accel::closest_many`]), so the intersector can trace them side by
//! side where it knows how. A pixel's value is therefore the same bit for bit either
//! way. Scenes the vectorised lanes take ([`Path::lanes_apply`]) go there instead.

use super::lanes::LANES;
use super::{Path, PathState};
use crate::accel::Hit;
use crate::math::{Ray, Vec3};
use crate::render::{NO_RAY, PixelSampler, RayCount};

impl Path<'_> {
    /// Radiance along each of `rays` (at most [`LANES`]), whose closest hits are
    /// `hits`, each drawing from its own sampler: [`Path::radiance`] of each.
    pub(super) fn radiance_wave(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
        out: &mut [Vec3],
    ) {
        let n = rays.len();
        debug_assert!(n <= LANES && hits.len() == n && samplers.len() == n);
        let mut paths: [PathState; LANES] =
            std::array::from_fn(|i| PathState::new(rays.get(i).copied().unwrap_or(NO_RAY)));
        let mut wave_hits = [None; LANES];
        wave_hits[..n].copy_from_slice(hits);
        let mut going = [0usize; LANES];
        let mut m = n;
        for (k, g) in going.iter_mut().enumerate().take(n) {
            *g = k;
        }
        while m > 0 {
            // Each path's step, keeping those that go on in order.
            let mut kept = 0;
            for k in 0..m {
                let i = going[k];
                if self.vertex(&mut paths[i], wave_hits[i], &mut samplers[i], count) {
                    going[kept] = i;
                    kept += 1;
                }
            }
            m = kept;
            // Their next hits, together.
            let mut wave_rays = [NO_RAY; LANES];
            for k in 0..m {
                wave_rays[k] = paths[going[k]].ray;
            }
            let mut found = [None; LANES];
            self.accel
                .closest_many(&wave_rays[..m], f32::INFINITY, &mut found[..m]);
            for k in 0..m {
                wave_hits[going[k]] = found[k];
            }
        }
        for (o, path) in out.iter_mut().zip(&paths).take(n) {
            *o = path.radiance();
        }
    }
}
