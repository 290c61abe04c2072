//! Ray queries over a scene's shapes: the closest hit, and whether a shadow ray is
//! blocked. One enum over the intersectors keeps the per-ray path free of dynamic
//! dispatch; every intersector must give the answers of [`ListAccel`], the reference.

mod bvh;
mod instances;
mod list;
mod octree;
pub mod simd;

pub use bvh::{Bvh, INDOOR_SHAPES, Leaves, MAX_SHAPES, PACKET_RAYS};
pub use instances::Instances;
pub use list::ListAccel;
pub use octree::Octree;
pub use simd::SimdLevel;

use crate::math::Ray;
use crate::scene::{NO_INSTANCE, Scene, ShapeId, Shapes};
use std::fmt;
use std::str::FromStr;

/// The closest intersection found: distance along the (unit) ray and the shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit: world-space distance from the origin.
    pub t: f32,
    /// Index of the shape hit: in the [`Shapes`] the intersector was built over, or in
    /// the object placed by `instance`.
    pub shape: u32,
    /// The instance whose object holds the shape, or [`NO_INSTANCE`].
    pub instance: u32,
}

impl Hit {
    /// A hit on shape `shape` of the shapes the intersector was built over.
    #[inline]
    pub const fn world(t: f32, shape: u32) -> Hit {
        Hit {
            t,
            shape,
            instance: NO_INSTANCE,
        }
    }

    /// The shape hit.
    #[inline]
    pub fn id(&self) -> ShapeId {
        ShapeId {
            instance: self.instance,
            shape: self.shape,
        }
    }

    /// Whether a hit at `t` on shape `shape` (in no instance) wins over `best`.
    #[inline]
    pub fn beats(t: f32, shape: u32, best: &Option<Hit>) -> bool {
        Hit::beats_id(t, ShapeId::world(shape), best)
    }

    /// Whether a hit at `t` on `id` wins over `best`: nearer, or as near and earlier in
    /// [`ShapeId::order`]. Breaking ties by index makes every intersector pick the same
    /// shape where two coincide (a room's walls share edges), whatever order it tests
    /// them in, and a scene of instances the shape its flattened twin picks.
    #[inline]
    pub fn beats_id(t: f32, id: ShapeId, best: &Option<Hit>) -> bool {
        match best {
            None => true,
            Some(b) => t < b.t || (t == b.t && id.order() < b.id().order()),
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
pub enum Intersector<'s> {
    /// [`AccelKind::List`]: the brute-force reference.
    List(ListAccel<'s>),
    /// [`AccelKind::Octree`].
    Octree(Octree<'s>),
    /// [`AccelKind::Bvh`] or [`AccelKind::BvhCopied`], as its [`Leaves`] say.
    Bvh(Bvh<'s>),
}

impl<'s> Intersector<'s> {
    /// Builds the `kind` intersector over `shapes`, which it borrows for its lifetime.
    pub fn build(kind: AccelKind, shapes: &'s Shapes) -> Intersector<'s> {
        match kind {
            AccelKind::List => Intersector::List(ListAccel::new(shapes)),
            AccelKind::Octree => Intersector::Octree(Octree::build(shapes)),
            AccelKind::Bvh => Intersector::Bvh(Bvh::build(shapes, Leaves::Indexed)),
            AccelKind::BvhCopied => Intersector::Bvh(Bvh::build(shapes, Leaves::Copied)),
        }
    }

    /// Number of shapes the intersector was built over.
    pub fn shape_count(&self) -> usize {
        match self {
            Intersector::List(a) => a.shape_count(),
            Intersector::Octree(a) => a.shape_count(),
            Intersector::Bvh(a) => a.shape_count(),
        }
    }

    /// Bytes the intersector holds beyond the shapes themselves.
    pub fn memory_bytes(&self) -> usize {
        match self {
            Intersector::List(_) => 0,
            Intersector::Octree(a) => a.memory_bytes(),
            Intersector::Bvh(a) => a.memory_bytes(),
        }
    }

    /// The nearest hit with `0 < t < t_max`.
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        match self {
            Intersector::List(a) => a.closest(ray, t_max),
            Intersector::Octree(a) => a.closest(ray, t_max),
            Intersector::Bvh(a) => a.closest(ray, t_max),
        }
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        match self {
            Intersector::List(a) => a.occluded(ray, t_max, blocks),
            Intersector::Octree(a) => a.occluded(ray, t_max, blocks),
            Intersector::Bvh(a) => a.occluded(ray, t_max, blocks),
        }
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays into `hits`, the answers
    /// of [`Intersector::closest`]: the BVH traces them as one packet.
    #[inline]
    pub fn closest_packet(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        match self {
            Intersector::Bvh(a) => a.closest_packet(rays, t_max, hits),
            _ => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.closest(ray, t_max);
                }
            }
        }
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays that need not run
    /// together (a pixel's paths after their first bounce) into `hits`, the answers of
    /// [`Intersector::closest`]: the BVH of a few flat shapes meets them all at once, any
    /// other intersector one at a time.
    #[inline]
    pub fn closest_many(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        match self {
            Intersector::Bvh(a) => a.closest_many(rays, t_max, hits),
            _ => {
                for (hit, ray) in hits.iter_mut().zip(rays) {
                    *hit = self.closest(ray, t_max);
                }
            }
        }
    }

    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) that need not run
    /// together meet a shape before their `t_max[i]`: the answers of
    /// [`Intersector::occluded`] with every shape blocking. The BVH tests its root's
    /// boxes against them all at once, any other intersector takes them one at a time.
    #[inline]
    pub fn occluded_many(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        match self {
            Intersector::Bvh(a) => a.occluded_many(rays, t_max),
            _ => rays
                .iter()
                .zip(t_max)
                .enumerate()
                .map(|(i, (ray, &t))| u32::from(self.occluded(ray, t, |_| true)) << i)
                .sum(),
        }
    }

    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) are blocked before
    /// their `t_max[i]`: the answers of [`Intersector::occluded`], as one packet in the BVH.
    #[inline]
    pub fn occluded_packet(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(u32) -> bool,
    ) -> u32 {
        match self {
            Intersector::Bvh(a) => a.occluded_packet(rays, t_max, blocks),
            _ => rays
                .iter()
                .zip(t_max)
                .enumerate()
                .map(|(i, (ray, &t))| u32::from(self.occluded(ray, t, &blocks)) << i)
                .sum(),
        }
    }
}

/// The intersector of a whole scene: its own shapes through the chosen intersector,
/// and the objects its instances place through a two-level BVH. Every query answers as
/// it would on the scene flattened.
pub struct Accel<'s> {
    /// The scene's own shapes.
    pub world: Intersector<'s>,
    /// The instances, where the scene has any.
    instances: Option<Instances<'s>>,
}

impl<'s> From<Intersector<'s>> for Accel<'s> {
    fn from(world: Intersector<'s>) -> Accel<'s> {
        Accel {
            world,
            instances: None,
        }
    }
}

impl<'s> Accel<'s> {
    /// Builds the `kind` intersector over `shapes`, which it borrows for its lifetime.
    pub fn build(kind: AccelKind, shapes: &'s Shapes) -> Accel<'s> {
        Intersector::build(kind, shapes).into()
    }

    /// Builds over every shape of `scene`: its own through the `kind` intersector,
    /// the objects its instances place through one BVH each under a BVH of instances.
    pub fn build_scene(kind: AccelKind, scene: &'s Scene) -> Accel<'s> {
        Accel {
            world: Intersector::build(kind, &scene.shapes),
            instances: (!scene.instances.is_empty())
                .then(|| Instances::build(&scene.objects, &scene.instances)),
        }
    }

    /// Number of shapes the scene's own intersector was built over.
    pub fn shape_count(&self) -> usize {
        self.world.shape_count()
    }

    /// Bytes the intersector holds beyond the shapes themselves.
    pub fn memory_bytes(&self) -> usize {
        self.world.memory_bytes() + self.instances.as_ref().map_or(0, Instances::memory_bytes)
    }

    /// The nearest hit with `0 < t < t_max`.
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best = self.world.closest(ray, t_max);
        if let Some(i) = &self.instances {
            i.closest(ray, t_max, &mut best);
        }
        best
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(ShapeId) -> bool) -> bool {
        self.world
            .occluded(ray, t_max, |s| blocks(ShapeId::world(s)))
            || self
                .instances
                .as_ref()
                .is_some_and(|i| i.occluded(ray, t_max, &blocks))
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays into `hits`, the answers
    /// of [`Accel::closest`]: the BVH traces them as one packet.
    #[inline]
    pub fn closest_packet(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        self.world.closest_packet(rays, t_max, hits);
        self.instances_closest(rays, t_max, hits);
    }

    /// The closest hit of each of up to [`PACKET_RAYS`] rays that need not run
    /// together into `hits`, the answers of [`Accel::closest`].
    #[inline]
    pub fn closest_many(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        self.world.closest_many(rays, t_max, hits);
        self.instances_closest(rays, t_max, hits);
    }

    fn instances_closest(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        if let Some(i) = &self.instances {
            for (hit, ray) in hits.iter_mut().zip(rays) {
                i.closest(ray, t_max, hit);
            }
        }
    }

    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) that need not run
    /// together meet a shape before their `t_max[i]`: the answers of
    /// [`Accel::occluded`] with every shape blocking.
    #[inline]
    pub fn occluded_many(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        let mut blocked = self.world.occluded_many(rays, t_max);
        if let Some(i) = &self.instances {
            for (k, (ray, &t)) in rays.iter().zip(t_max).enumerate() {
                if blocked & (1 << k) == 0 && i.occluded(ray, t, &|_| true) {
                    blocked |= 1 << k;
                }
            }
        }
        blocked
    }

    /// Which of up to [`PACKET_RAYS`] rays (bit `i` for ray `i`) are blocked before
    /// their `t_max[i]`: the answers of [`Accel::occluded`].
    #[inline]
    pub fn occluded_packet(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(ShapeId) -> bool,
    ) -> u32 {
        let mut blocked = self
            .world
            .occluded_packet(rays, t_max, |s| blocks(ShapeId::world(s)));
        if let Some(i) = &self.instances {
            for (k, (ray, &t)) in rays.iter().zip(t_max).enumerate() {
                if blocked & (1 << k) == 0 && i.occluded(ray, t, &blocks) {
                    blocked |= 1 << k;
                }
            }
        }
        blocked
    }
}

#[cfg(test)]
mod tests;
