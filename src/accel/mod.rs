//! Ray queries over a scene's shapes: the closest hit, and whether a shadow ray is
//! blocked. One enum over the intersectors keeps the per-ray path free of dynamic
//! dispatch; every intersector must give the answers of [`ListAccel`], the reference.

mod bvh;
mod list;
mod octree;
pub mod simd;

pub use bvh::{Bvh, Leaves, MAX_SHAPES, PACKET_RAYS};
pub use list::ListAccel;
pub use octree::Octree;
pub use simd::SimdLevel;

use crate::math::Ray;
use crate::scene::Shapes;
use std::fmt;
use std::str::FromStr;

/// The closest intersection found: distance along the (unit) ray and the shape index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit: world-space distance from the origin.
    pub t: f32,
    /// Index of the shape hit, in the [`Shapes`] the intersector was built over.
    pub shape: u32,
}

impl Hit {
    /// Whether a hit at `t` on `shape` wins over `best`: nearer, or as near with a lower
    /// index. Breaking ties by index makes every intersector pick the same shape where
    /// two coincide (a room's walls share edges), whatever order it tests them in.
    #[inline]
    pub fn beats(t: f32, shape: u32, best: &Option<Hit>) -> bool {
        match best {
            None => true,
            Some(b) => t < b.t || (t == b.t && shape < b.shape),
        }
    }

    /// The distance bound to test the next shape with, so a tie can still be seen.
    #[inline]
    pub fn bound(best: &Option<Hit>, t_max: f32) -> f32 {
        best.map_or(t_max, |b| b.t.next_up())
    }
}

/// Which intersector to build.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AccelKind {
    /// Every ray against every shape: the reference.
    List,
    /// The report's octree (section 2.4), with its fixes.
    Octree,
    /// An eight-wide SAH bounding volume hierarchy whose leaves index the mesh's
    /// triangles: fast and compact.
    #[default]
    Bvh,
    /// The same hierarchy with each leaf's triangles copied into it: the fastest, at
    /// about twice the memory on a mesh ([`Leaves::Copied`]).
    BvhCopied,
}

impl AccelKind {
    /// Every intersector, in the order messages list them (the default first).
    pub const ALL: [AccelKind; 4] = [
        AccelKind::Bvh,
        AccelKind::BvhCopied,
        AccelKind::Octree,
        AccelKind::List,
    ];

    /// The name front ends accept and print (`--accel bvh`); parsed back by `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            AccelKind::List => "list",
            AccelKind::Octree => "octree",
            AccelKind::Bvh => "bvh",
            AccelKind::BvhCopied => "bvh-copied",
        }
    }
}

impl fmt::Display for AccelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for AccelKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        crate::options::by_name(s, &AccelKind::ALL, AccelKind::name, "intersector")
    }
}

/// An intersector built over a slice of shapes.
pub enum Accel<'s> {
    /// [`AccelKind::List`]: the brute-force reference.
    List(ListAccel<'s>),
    /// [`AccelKind::Octree`].
    Octree(Octree<'s>),
    /// [`AccelKind::Bvh`] or [`AccelKind::BvhCopied`], as its [`Leaves`] say.
    Bvh(Bvh<'s>),
}

impl<'s> Accel<'s> {
    /// Builds the `kind` intersector over `shapes`, which it borrows for its lifetime.
    pub fn build(kind: AccelKind, shapes: &'s Shapes) -> Accel<'s> {
        match kind {
            AccelKind::List => Accel::List(ListAccel::new(shapes)),
            AccelKind::Octree => Accel::Octree(Octree::build(shapes)),
            AccelKind::Bvh => Accel::Bvh(Bvh::build(shapes, Leaves::Indexed)),
            AccelKind::BvhCopied => Accel::Bvh(Bvh::build(shapes, Leaves::Copied)),
        }
    }

    /// Number of shapes the intersector was built over.
    pub fn shape_count(&self) -> usize {
        match self {
            Accel::List(a) => a.shape_count(),
            Accel::Octree(a) => a.shape_count(),
            Accel::Bvh(a) => a.shape_count(),
        }
    }

    /// Bytes the intersector holds beyond the shapes themselves.
    pub fn memory_bytes(&self) -> usize {
        match self {
            Accel::List(_) => 0,
            Accel::Octree(a) => a.memory_bytes(),
            Accel::Bvh(a) => a.memory_bytes(),
        }
    }

    /// The nearest hit with `0 < t < t_max`.
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        match self {
            Accel::List(a) => a.closest(ray, t_max),
            Accel::Octree(a) => a.closest(ray, t_max),
            Accel::Bvh(a) => a.closest(ray, t_max),
        }
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        match self {
            Accel::List(a) => a.occluded(ray, t_max, blocks),
            Accel::Octree(a) => a.occluded(ray, t_max, blocks),
            Accel::Bvh(a) => a.occluded(ray, t_max, blocks),
        }
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays into `hits`, the answers
    /// of [`Accel::closest`]: the BVH traces them as one packet.
    #[inline]
    pub fn closest_packet(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        match self {
            Accel::Bvh(a) => a.closest_packet(rays, t_max, hits),
            _ => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.closest(ray, t_max);
                }
            }
        }
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays that need not run
    /// together (a pixel's paths after their first bounce) into `hits`, the answers of
    /// [`Accel::closest`]: the BVH of a few flat shapes meets them all at once, any
    /// other intersector one at a time.
    #[inline]
    pub fn closest_many(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        match self {
            Accel::Bvh(a) => a.closest_many(rays, t_max, hits),
            _ => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.closest(ray, t_max);
                }
            }
        }
    }

    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) are blocked before
    /// their `t_max[i]`: the answers of [`Accel::occluded`], as one packet in the BVH.
    #[inline]
    pub fn occluded_packet(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(u32) -> bool,
    ) -> u32 {
        match self {
            Accel::Bvh(a) => a.occluded_packet(rays, t_max, blocks),
            _ => rays
                .iter()
                .zip(t_max)
                .enumerate()
                .map(|(i, (ray, &t))| u32::from(self.occluded(ray, t, &blocks)) << i)
                .sum(),
        }
    }
}

#[cfg(test)]
mod tests;
