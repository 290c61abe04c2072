//! A four-wide bounding volume hierarchy: built as a binary tree by binned SAH, then
//! collapsed so each node holds four child boxes side by side (structure of arrays), and
//! one ray meets all four with a handful of 4-lane SIMD operations.
//!
//! Closest-hit rays visit children nearest first and skip any whose entry lies beyond
//! the best hit so far; shadow rays stop at the first blocker.

mod build;
mod packet;

pub use packet::MAX_SHAPES;

use super::Hit;
use crate::math::{Aabb, Ray};
use crate::scene::Shape;
use build::{BinaryBvh, MAX_DEPTH};
use glam::Vec4;
use packet::{Packet, PacketRay, padded_bounds};
use std::mem::MaybeUninit;

/// Entries the traversal stack needs: each level pushes at most four and pops one.
const STACK: usize = 3 * MAX_DEPTH as usize + 4;
/// Relative slack of the box test, so rounding never culls a box a hit lies in.
const BOX_SLACK: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Four child boxes, one lane each. A lane whose box is empty (min +inf, max -inf) is
/// never hit, which is how nodes with fewer than four children pad.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node4 {
    min: [Vec4; 3],
    max: [Vec4; 3],
    /// Inner child: node index. Leaf child: first packet.
    child: [u32; 4],
    /// 0 for an inner child, else the leaf's number of packets.
    count: [u32; 4],
}

const EMPTY_NODE: Node4 = Node4 {
    min: [Vec4::INFINITY; 3],
    max: [Vec4::NEG_INFINITY; 3],
    child: [0; 4],
    count: [0; 4],
};

/// A pending child: where it is, and how far along the ray its box starts.
#[derive(Clone, Copy)]
struct Entry {
    child: u32,
    count: u32,
    t: f32,
}

/// The traversal stack. Its slots are left uninitialised: clearing a few kilobytes
/// per ray cost more than a tenth of the traversal time.
struct Stack {
    items: [MaybeUninit<Entry>; STACK],
    len: usize,
}

impl Stack {
    #[inline]
    fn new(root: Entry) -> Stack {
        let mut stack = Stack {
            items: [const { MaybeUninit::uninit() }; STACK],
            len: 0,
        };
        stack.push(root);
        stack
    }

    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: slots below `len` were written by `push` or `push_sorted`.
        Some(unsafe { self.items[self.len].assume_init() })
    }

    #[inline]
    fn push(&mut self, e: Entry) {
        self.items[self.len] = MaybeUninit::new(e);
        self.len += 1;
    }

    /// Pushes `e` among the entries above `base`, kept farthest first, so the nearest
    /// is popped next.
    #[inline]
    fn push_sorted(&mut self, e: Entry, base: usize) {
        let mut i = self.len;
        while i > base {
            // SAFETY: base <= i - 1 < len, a written slot.
            let below = unsafe { self.items[i - 1].assume_init() };
            if below.t >= e.t {
                break;
            }
            self.items[i] = MaybeUninit::new(below);
            i -= 1;
        }
        self.items[i] = MaybeUninit::new(e);
        self.len += 1;
    }
}

/// Per-ray constants of the slab test. Each axis reads its near plane from `min` or
/// `max` by the sign of the direction, so an empty (inverted) box is missed.
struct RayBoxes {
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    negative: [bool; 3],
}

impl RayBoxes {
    #[inline]
    fn new(ray: &Ray) -> RayBoxes {
        let o = ray.origin.to_array();
        let d = ray.dir.to_array();
        // A zero component gives a huge finite inverse rather than infinity, so a
        // plane through the origin gives 0 * big = 0 and never 0 * inf = NaN.
        let inv = |x: f32| {
            let i = 1.0 / x;
            if i.is_finite() {
                i
            } else {
                1e30f32.copysign(x)
            }
        };
        RayBoxes {
            origin: o.map(Vec4::splat),
            inv_dir: d.map(|x| Vec4::splat(inv(x))),
            negative: d.map(|x| x.is_sign_negative()),
        }
    }

    /// Lanes whose box the ray enters before `t_max`, and the entry distances.
    #[inline]
    fn hit(&self, node: &Node4, t_max: f32) -> (u32, Vec4) {
        let mut t_near = Vec4::ZERO;
        let mut t_far = Vec4::splat(t_max);
        for axis in 0..3 {
            let (near, far) = if self.negative[axis] {
                (node.max[axis], node.min[axis])
            } else {
                (node.min[axis], node.max[axis])
            };
            t_near = t_near.max((near - self.origin[axis]) * self.inv_dir[axis]);
            t_far = t_far.min((far - self.origin[axis]) * self.inv_dir[axis]);
        }
        (t_near.cmple(t_far * BOX_SLACK).bitmask(), t_near)
    }
}

pub struct Bvh {
    nodes: Vec<Node4>,
    packets: Vec<Packet>,
    shape_count: usize,
}

impl Bvh {
    /// Builds over `shapes`. More than [`MAX_SHAPES`] shapes is the caller's error.
    pub fn build(shapes: &[Shape]) -> Bvh {
        assert!(shapes.len() <= MAX_SHAPES, "too many shapes for the BVH");
        if shapes.is_empty() {
            return Bvh {
                nodes: Vec::new(),
                packets: Vec::new(),
                shape_count: 0,
            };
        }
        let boxes: Vec<Aabb> = shapes.iter().map(padded_bounds).collect();
        let binary = build::build(&boxes);
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(binary.nodes.len() / 2 + 1),
            packets: Vec::with_capacity(shapes.len() / 2 + 1),
            shape_count: shapes.len(),
        };
        bvh.nodes.push(EMPTY_NODE);
        bvh.collapse(&binary, shapes, 0, 0);
        bvh.nodes.shrink_to_fit();
        bvh.packets.shrink_to_fit();
        bvh
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn shape_count(&self) -> usize {
        self.shape_count
    }

    /// Bytes held by the nodes and the leaf-ordered shape copies.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * size_of::<Node4>() + self.packets.capacity() * size_of::<Packet>()
    }

    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let boxes = RayBoxes::new(ray);
        let lanes = PacketRay::new(ray);
        let mut best: Option<Hit> = None;
        let mut stack = Stack::new(Entry {
            child: 0,
            count: 0,
            t: 0.0,
        });
        while let Some(entry) = stack.pop() {
            let bound = Hit::bound(&best, t_max);
            if entry.t > bound * BOX_SLACK {
                continue;
            }
            if entry.count > 0 {
                let first = entry.child as usize;
                for packet in &self.packets[first..first + entry.count as usize] {
                    let (mut mask, t) = packet.intersect_flat(&lanes, Hit::bound(&best, t_max));
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let shape = packet.shape(lane);
                        if Hit::beats(t[lane], shape, &best) {
                            best = Some(Hit { t: t[lane], shape });
                        }
                    }
                    let mut spheres = packet.sphere_lanes();
                    while spheres != 0 {
                        let lane = spheres.trailing_zeros() as usize;
                        spheres &= spheres - 1;
                        let shape = packet.shape(lane);
                        if let Some(t) =
                            packet.sphere(lane).intersect(ray, Hit::bound(&best, t_max))
                            && Hit::beats(t, shape, &best)
                        {
                            best = Some(Hit { t, shape });
                        }
                    }
                }
                continue;
            }
            let node = &self.nodes[entry.child as usize];
            let (mut mask, t_near) = boxes.hit(node, bound);
            let t_near = t_near.to_array();
            let base = stack.len;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let e = Entry {
                    child: node.child[lane],
                    count: node.count[lane],
                    t: t_near[lane],
                };
                stack.push_sorted(e, base);
            }
        }
        best
    }

    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let boxes = RayBoxes::new(ray);
        let lanes = PacketRay::new(ray);
        let mut stack = Stack::new(Entry {
            child: 0,
            count: 0,
            t: 0.0,
        });
        while let Some(entry) = stack.pop() {
            if entry.count > 0 {
                let first = entry.child as usize;
                for packet in &self.packets[first..first + entry.count as usize] {
                    let mut mask = packet.intersect_flat(&lanes, t_max).0;
                    let mut spheres = packet.sphere_lanes();
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        if blocks(packet.shape(lane)) {
                            return true;
                        }
                    }
                    while spheres != 0 {
                        let lane = spheres.trailing_zeros() as usize;
                        spheres &= spheres - 1;
                        if blocks(packet.shape(lane))
                            && packet.sphere(lane).intersect(ray, t_max).is_some()
                        {
                            return true;
                        }
                    }
                }
                continue;
            }
            let node = &self.nodes[entry.child as usize];
            let (mut mask, _) = boxes.hit(node, t_max);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                stack.push(Entry {
                    child: node.child[lane],
                    count: node.count[lane],
                    t: 0.0,
                });
            }
        }
        false
    }
}

impl Bvh {
    /// Fills `nodes[slot]` with up to four descendants of binary node `at`: its
    /// children, then repeatedly the children of the largest inner one among them.
    /// Leaves become runs of packets.
    fn collapse(&mut self, binary: &BinaryBvh, shapes: &[Shape], at: usize, slot: usize) {
        let src = &binary.nodes;
        let mut members: Vec<usize> = if src[at].is_leaf() {
            vec![at]
        } else {
            let first = src[at].first as usize;
            vec![first, first + 1]
        };
        while members.len() < 4 {
            let widest = members
                .iter()
                .enumerate()
                .filter(|&(_, &m)| !src[m].is_leaf())
                .max_by(|a, b| area(&src[*a.1].bounds).total_cmp(&area(&src[*b.1].bounds)));
            let Some((i, &m)) = widest else { break };
            let first = src[m].first as usize;
            members[i] = first;
            members.insert(i + 1, first + 1);
        }
        let mut node = EMPTY_NODE;
        let mut inner = Vec::new();
        for (lane, &m) in members.iter().enumerate() {
            let b = src[m].bounds;
            for axis in 0..3 {
                node.min[axis][lane] = b.min[axis];
                node.max[axis][lane] = b.max[axis];
            }
            if src[m].is_leaf() {
                let (first, count) = (src[m].first as usize, src[m].count as usize);
                let leaf = &binary.order[first..first + count];
                node.child[lane] = self.packets.len() as u32;
                node.count[lane] = leaf.len().div_ceil(4) as u32;
                self.packets
                    .extend(leaf.chunks(4).map(|four| Packet::new(shapes, four)));
            } else {
                node.child[lane] = self.nodes.len() as u32;
                self.nodes.push(EMPTY_NODE);
                inner.push((m, node.child[lane] as usize));
            }
        }
        self.nodes[slot] = node;
        for (m, child_slot) in inner {
            self.collapse(binary, shapes, m, child_slot);
        }
    }
}

fn area(b: &Aabb) -> f32 {
    let e = b.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::scene::{Sphere, Triangle};

    #[test]
    fn a_grid_of_triangles_is_hit_where_it_is_and_nowhere_else() {
        // 32 x 32 unit squares as triangle pairs in the plane z = 0.
        let mut shapes = Vec::new();
        for y in 0..32 {
            for x in 0..32 {
                let p = |dx: f32, dy: f32| Vec3::new(x as f32 + dx, y as f32 + dy, 0.0);
                shapes.push(Shape::Triangle(Triangle {
                    v: [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)],
                }));
                shapes.push(Shape::Triangle(Triangle {
                    v: [p(0.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
                }));
            }
        }
        let bvh = Bvh::build(&shapes);
        assert!(bvh.node_count() > 1);
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 2.5), Vec3::new(0.0, 0.0, -1.0));
        // (10.75, 3.25) lies in the lower-right triangle of square (10, 3).
        let hit = bvh.closest(&down(10.75, 3.25), f32::INFINITY).unwrap();
        assert_eq!(hit.t, 2.5);
        assert_eq!(hit.shape, 2 * (3 * 32 + 10));
        let hit = bvh.closest(&down(10.25, 3.75), f32::INFINITY).unwrap();
        assert_eq!(hit.shape, 2 * (3 * 32 + 10) + 1);
        assert_eq!(bvh.closest(&down(40.0, 3.0), f32::INFINITY), None);
        assert_eq!(bvh.closest(&down(10.75, 3.25), 2.0), None);
        assert!(bvh.occluded(&down(10.75, 3.25), 3.0, |_| true));
        assert!(!bvh.occluded(&down(10.75, 3.25), 2.0, |_| true));
        assert!(!bvh.occluded(&down(10.75, 3.25), 3.0, |s| s != 2 * (3 * 32 + 10)));
    }

    #[test]
    fn one_shape_and_no_shapes() {
        let one = [Shape::Sphere(Sphere {
            center: Vec3::new(0.0, 0.0, 10.0),
            radius: 2.0,
        })];
        let bvh = Bvh::build(&one);
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(bvh.closest(&ray, f32::INFINITY).map(|h| h.t), Some(8.0));
        assert!(Bvh::build(&[]).closest(&ray, f32::INFINITY).is_none());
        assert!(!Bvh::build(&[]).occluded(&ray, f32::INFINITY, |_| true));
    }

    #[test]
    fn coincident_shapes_beyond_a_leaf_still_build_and_tie_to_the_lowest_index() {
        let tri = Shape::Triangle(Triangle {
            v: [
                Vec3::new(-1.0, -1.0, 5.0),
                Vec3::new(1.0, -1.0, 5.0),
                Vec3::new(0.0, 1.0, 5.0),
            ],
        });
        let shapes = vec![tri; 100];
        let bvh = Bvh::build(&shapes);
        let hit = bvh.closest(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY);
        assert_eq!(hit, Some(Hit { t: 5.0, shape: 0 }));
    }
}
