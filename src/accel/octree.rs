//! The report's octree (section 2.4), with the fixes of SPEC 3.7.
//!
//! A leaf splits into eight equal boxes once it holds [`SPLIT_AT`] shapes, and a shape
//! goes into every child its bounds touch (closed boxes, so flat shapes lying on a cell
//! face count). Unlike the 2014 program the root is the scene's bounds rather than a
//! fixed cube, depth is limited, a split that separates nothing is not made, and a ray
//! walks the cells front to back with one stack instead of restarting from the root at
//! every cell.

use super::Hit;
use crate::math::{Aabb, Ray, Vec3};
use crate::scene::Shapes;
use rayon::prelude::*;

/// A leaf with this many shapes splits (the report's threshold).
pub const SPLIT_AT: usize = 5;
/// Deepest level; with 8 children per level a traversal stack of `7 * MAX_DEPTH + 1`
/// entries always suffices.
pub const MAX_DEPTH: u32 = 10;
const STACK: usize = 7 * MAX_DEPTH as usize + 1;
/// Shapes remembered per ray as already tested.
const MAILBOX: usize = 8;

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: first index into `items`; inner node: index of the first of 8 children.
    first: u32,
    /// Leaf: number of items; inner node: `u32::MAX`.
    count: u32,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.count != u32::MAX
    }
}

/// The report's octree over a scene's shapes: cells of the scene's bounds, split eight
/// ways, with each leaf listing the shapes its closed box touches.
pub struct Octree<'s> {
    shapes: &'s Shapes,
    nodes: Vec<Node>,
    items: Vec<u32>,
}

impl<'s> Octree<'s> {
    /// Builds the tree over `shapes`, from a root slightly larger than their bounds.
    pub fn build(shapes: &'s Shapes) -> Octree<'s> {
        let boxes: Vec<Aabb> = shapes.par_iter().map(|s| s.bounds()).collect();
        let root = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        let root = if root.is_empty() {
            Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            }
        } else {
            root
        };
        // Pad so no axis is flat and shapes on the outer faces lie strictly inside.
        // From half extents, and clamped, so a scene spanning ±f32::MAX keeps finite
        // cells (an infinite root made every child's bounds NaN).
        let half = (root.max * 0.5 - root.min * 0.5).max_element().max(0.5);
        let pad = half * 2e-4;
        let limit = Vec3::splat(f32::MAX);
        let root = Aabb {
            min: (root.min - Vec3::splat(pad)).max(-limit),
            max: (root.max + Vec3::splat(pad)).min(limit),
        };
        let mut tree = Octree {
            shapes,
            nodes: vec![Node {
                bounds: root,
                first: 0,
                count: 0,
            }],
            items: Vec::new(),
        };
        let all: Vec<u32> = (0..shapes.len() as u32).collect();
        tree.fill(0, all, &boxes, 0);
        tree
    }

    fn fill(&mut self, node: usize, members: Vec<u32>, boxes: &[Aabb], depth: u32) {
        let bounds = self.nodes[node].bounds;
        if members.len() >= SPLIT_AT && depth < MAX_DEPTH {
            let children: Vec<(Aabb, Vec<u32>)> = (0..8)
                .map(|i| {
                    let b = child_bounds(&bounds, i);
                    let inside = members
                        .iter()
                        .copied()
                        .filter(|&m| boxes[m as usize].overlaps(&b))
                        .collect();
                    (b, inside)
                })
                .collect();
            // A split where every child still holds every shape only multiplies work.
            if children.iter().any(|(_, c)| c.len() < members.len()) {
                let first = self.nodes.len();
                self.nodes[node].first = first as u32;
                self.nodes[node].count = u32::MAX;
                for (b, _) in &children {
                    self.nodes.push(Node {
                        bounds: *b,
                        first: 0,
                        count: 0,
                    });
                }
                for (i, (_, c)) in children.into_iter().enumerate() {
                    self.fill(first + i, c, boxes, depth + 1);
                }
                return;
            }
        }
        self.nodes[node].first = self.items.len() as u32;
        self.nodes[node].count = members.len() as u32;
        self.items.extend(members);
    }

    /// Number of cells, leaves and stored shape references (for statistics and tests).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of shapes the tree was built over.
    pub fn shape_count(&self) -> usize {
        self.shapes.len()
    }

    /// Bytes held by the cells and their shape lists.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * size_of::<Node>() + self.items.capacity() * size_of::<u32>()
    }

    /// The nearest hit with `0 < t < t_max`, ties going to the lower shape index.
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.walk(ray, t_max, |shape, _| {
            let s = self.shapes.get(shape as usize);
            if let Some(t) = s.intersect(ray, Hit::bound(&best, t_max))
                && Hit::beats(t, shape, &best)
            {
                best = Some(Hit::world(t, shape));
            }
            (false, best.map_or(t_max, |b| b.t))
        });
        best
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`; stops
    /// at the first such hit.
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        let mut hit = false;
        self.walk(ray, t_max, |shape, t_limit| {
            hit = blocks(shape)
                && self
                    .shapes
                    .get(shape as usize)
                    .intersect(ray, t_limit)
                    .is_some();
            (hit, t_limit)
        });
        hit
    }

    /// Visits the shapes of the leaves the ray crosses, nearest cell first. `visit`
    /// returns whether to stop and the new distance bound: cells entered beyond it are
    /// skipped, which is what makes front-to-back order pay.
    #[inline]
    fn walk(&self, ray: &Ray, t_max: f32, mut visit: impl FnMut(u32, f32) -> (bool, f32)) {
        let inv_dir = ray.dir.recip();
        // Children are numbered by bits x=1, y=2, z=4 set for the upper half; XOR with the
        // signs of the direction lists them in an order where no cell precedes one that
        // can hide it.
        let flip = (ray.dir.x < 0.0) as usize
            | ((ray.dir.y < 0.0) as usize) << 1
            | ((ray.dir.z < 0.0) as usize) << 2;
        let mut t_limit = t_max;
        let mut stack = [(0u32, 0f32); STACK];
        let Some((t0, _)) = self.nodes[0]
            .bounds
            .hit_interval(ray.origin, inv_dir, t_limit)
        else {
            return;
        };
        stack[0] = (0, t0);
        let mut len = 1;
        // Shapes spanning many cells (walls, floors) sit in many leaves; a small ring of
        // the shapes tested last skips most repeated tests. A repeat could not change
        // the answer: its hit, if any, was already seen.
        let mut recent = [u32::MAX; MAILBOX];
        let mut slot = 0;
        while len > 0 {
            len -= 1;
            let (index, t_enter) = stack[len];
            if t_enter > t_limit {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.is_leaf() {
                let items = &self.items[node.first as usize..(node.first + node.count) as usize];
                for &shape in items {
                    if recent.contains(&shape) {
                        continue;
                    }
                    recent[slot] = shape;
                    slot = (slot + 1) % MAILBOX;
                    let (stop, limit) = visit(shape, t_limit);
                    if stop {
                        return;
                    }
                    t_limit = limit;
                }
                continue;
            }
            // Push far children first so the nearest is popped next.
            for i in (0..8).rev() {
                let child = node.first as usize + (i ^ flip);
                if let Some((t0, _)) = self.nodes[child]
                    .bounds
                    .hit_interval(ray.origin, inv_dir, t_limit)
                {
                    stack[len] = (child as u32, t0);
                    len += 1;
                }
            }
        }
    }
}

fn child_bounds(b: &Aabb, i: usize) -> Aabb {
    let mid = b.center();
    let pick = |bit: usize, lo: f32, m: f32, hi: f32| {
        if i & bit == 0 { (lo, m) } else { (m, hi) }
    };
    let (x0, x1) = pick(1, b.min.x, mid.x, b.max.x);
    let (y0, y1) = pick(2, b.min.y, mid.y, b.max.y);
    let (z0, z1) = pick(4, b.min.z, mid.z, b.max.z);
    Aabb {
        min: Vec3::new(x0, y0, z0),
        max: Vec3::new(x1, y1, z1),
    }
}
