//! Light under a subsurface: a random walk through the surface's medium (as Cycles'
//! and Arnold's random-walk subsurface), from where the BSDF sent the path in to where
//! the walk meets a surface again. There light leaves through a diffuse exit: the
//! lights are sampled from the exit point and the path goes on from it.
//!
//! Each step picks one colour channel by the share of the path's throughput it carries
//! (so a path that dispersion left with one channel keeps to it) and draws a free
//! flight by that channel's extinction; the step is weighed by the channels' densities
//! mixed in the same shares (one-sample MIS over the channels, as Cycles and pbrt-v4
//! walk a coloured medium): [`Medium::flight`] and [`Medium::weigh`].

use super::{Bsdf, Path, PathState};
use crate::math::{Ray, Vec3, offset_origin};
use crate::render::bsdf::medium::Medium;
use crate::render::bsdf::{PhongBsdf, Terms};
use crate::render::{PixelSampler, RayCount};
use crate::scene::ShapeId;

/// Steps after which a walk is taken as absorbed: bounds the work of a walk in a
/// nearly white medium, or in an open mesh's medium that has no far side.
pub const MAX_WALK_STEPS: u32 = 256;

impl Path<'_> {
    /// The path, having entered `medium` at `p` (geometric normal `ng` on the side it
    /// came from) along `dir`, walks through it and leaves where it meets a surface;
    /// false where it ends inside.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn through_medium(
        &self,
        path: &mut PathState,
        medium: &Medium,
        p: Vec3,
        ng: Vec3,
        dir: Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> bool {
        if !self.bounced(path, sampler) {
            return false;
        }
        let ray = Ray::new(offset_origin(p, ng, dir), dir);
        let Some((ray, t, shape)) = self.walk(path, medium, ray, sampler, count) else {
            return false;
        };
        // The exit: a diffuse surface facing the way the walk was going.
        let sp = self.scene.surface_point(shape, &ray, t, false);
        let (ng, n) = if ray.dir.dot(sp.ng) > 0.0 {
            (sp.ng, sp.n)
        } else {
            (-sp.ng, -sp.n)
        };
        let exit = Bsdf::Phong(PhongBsdf::new(&Terms::diffuse(Vec3::ONE), n, n, ng));
        let last = path.depth >= self.max_depth;
        path.l += path.beta * self.direct(&exit, &sp, ng, last, sampler, count);
        self.scatter(path, &exit, sp.p, ng, sampler, count)
    }

    /// The walk from `ray`'s origin inside `medium`: each free flight drawn, the
    /// path's throughput weighed for it, until a flight meets a surface. The last
    /// flight's ray, its distance and the shape it meets; `None` where the walk ends
    /// inside (absorbed, or [`MAX_WALK_STEPS`] taken).
    fn walk(
        &self,
        path: &mut PathState,
        medium: &Medium,
        mut ray: Ray,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Option<(Ray, f32, ShapeId)> {
        for _ in 0..MAX_WALK_STEPS {
            let (u, v) = (sampler.next_f32(), sampler.next_f32());
            let flight = medium.flight(path.beta, u, v)?;
            count.rays += 1;
            let hit = self.accel.closest(&ray, flight);
            let t = hit.map_or(flight, |h| h.t);
            path.beta = medium.weigh(path.beta, t, hit.is_none())?;
            if let Some(hit) = hit {
                return Some((ray, hit.t, hit.id()));
            }
            ray = Ray::new(ray.at(flight), medium.scatter(ray.dir, sampler.next_2d()));
        }
        None
    }
}
