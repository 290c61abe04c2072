//! An eight-wide bounding volume hierarchy: built as a binary tree by binned SAH, then
//! collapsed so each node holds eight child boxes side by side (structure of arrays).
//! One ray meets all eight with a handful of 8-lane AVX2 operations, or as two halves of
//! four lanes on SSE2; either way the same children are entered.
//!
//! Closest-hit rays visit children nearest first and skip any whose entry lies beyond
//! the best hit so far; shadow rays stop at the first blocker.

mod boxes;
pub(super) mod build;
mod coherent;
mod collapse;
mod few;
mod leaf4;
mod placed;
mod scattered;
mod stack;
mod walls;

pub use coherent::PACKET_RAYS;

pub use leaf4::MAX_SHAPES;
pub use placed::PlacedRay;
pub use walls::INDOOR_SHAPES;

/// How a BVH's leaves hold their triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Leaves {
    /// By index: a leaf names its triangles and the traversal gathers their corners
    /// from the mesh's shared vertices. Four bytes a triangle beside the nodes.
    Indexed,
    /// By copy: each leaf holds its triangles' corners and edges four to a block,
    /// laid out as the leaf test reads them. On a mesh about fifty bytes a triangle
    /// more (a 192-byte block for a leaf of one shape at worst), and 10–40 % more rays
    /// a second, most on large meshes and on packets.
    Copied,
}

use super::Hit;
use super::simd::SimdLevel;
use crate::math::{Aabb, Ray};
use crate::scene::Shapes;
#[cfg(target_arch = "x86_64")]
use boxes::Boxes8;
use boxes::{BoxTest, Boxes4, inverse};
use build::MAX_DEPTH;
use collapse::Collapsed;
use few::FewFlats;
use glam::Vec4;
use leaf4::{Leaf4, RayLanes, padded_bounds};
use rayon::prelude::*;
use stack::{Entry, Stack};
use walls::Indoors;

/// Entries the traversal stack needs: each level pushes at most eight and pops one.
const STACK: usize = (WIDTH - 1) * MAX_DEPTH as usize + WIDTH;
/// Relative slack of the box test, so rounding never culls a box a hit lies in.
const BOX_SLACK: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Children per node.
const WIDTH: usize = 8;
/// Marks a leaf stored as [`Leaf4`] copies with precomputed edges rather than shape
/// indices.
const STORED: u32 = 1 << 31;
/// Scenes of at most this many shapes are one leaf: every ray tests them all.
const TINY_SCENE: usize = 16;
/// The root of a tree with inner nodes: node 0.
const EMPTY_ROOT: Entry = Entry {
    child: 0,
    count: 0,
    t: 0.0,
};

/// Eight child boxes, one lane each (two halves of four, so SSE2 reads a half and AVX2
/// the whole row). A lane whose box is empty (min +inf, max -inf) is never hit, which is
/// how nodes with fewer than eight children pad.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node8 {
    min: [[Vec4; 2]; 3],
    max: [[Vec4; 2]; 3],
    /// Inner child: node index. Leaf child: its first entry in `Bvh::prims`.
    child: [u32; WIDTH],
    /// 0 for an inner child; for a leaf its number of shapes (in `Bvh::prims`), or
    /// [`STORED`] and its number of [`Leaf4`]s (in `Bvh::stored`).
    count: [u32; WIDTH],
}

const EMPTY_NODE: Node8 = Node8 {
    min: [[Vec4::INFINITY; 2]; 3],
    max: [[Vec4::NEG_INFINITY; 2]; 3],
    child: [0; WIDTH],
    count: [0; WIDTH],
};

impl Node8 {
    /// The entry of the one child in `mask` (entered at `t[lane]`), where exactly one
    /// is hit: the traversal goes straight on to it, past the stack.
    #[inline(always)]
    fn only_child(&self, mask: u32, t: &[f32; WIDTH]) -> Option<Entry> {
        (mask != 0 && mask & (mask - 1) == 0).then(|| {
            let lane = mask.trailing_zeros() as usize;
            self.entry(lane, t[lane])
        })
    }

    /// Child `lane` as a traversal entry, its box entered at `t`.
    #[inline(always)]
    fn entry(&self, lane: usize, t: f32) -> Entry {
        Entry {
            child: self.child[lane],
            count: self.count[lane],
            t,
        }
    }

    fn set_entry(&mut self, lane: usize, e: Entry) {
        self.child[lane] = e.child;
        self.count[lane] = e.count;
    }

    fn set_box(&mut self, lane: usize, b: &Aabb) {
        for axis in 0..3 {
            self.min[axis][lane / 4][lane % 4] = b.min[axis];
            self.max[axis][lane / 4][lane % 4] = b.max[axis];
        }
    }
}

/// The eight-wide BVH over a scene's shapes, which it borrows: built once, then read
/// by any number of threads.
pub struct Bvh<'s> {
    shapes: &'s Shapes,
    /// Where every ray starts: node 0, or for a scene of a few shapes one leaf of them
    /// all (a node test would cost more than it culls).
    root: Entry,
    nodes: Vec<Node8>,
    /// Shape indices, leaf by leaf: a leaf names its shapes and the traversal reads
    /// their corners from the scene, so the tree adds four bytes a shape to the nodes.
    /// Empty with [`Leaves::Copied`].
    prims: Vec<u32>,
    /// Leaves copied into [`Leaf4`]s with their edges precomputed: those holding a
    /// sphere or a rectangle (such shapes are few, and gathering them cost a 2014 scene
    /// a tenth of its time), and with [`Leaves::Copied`] every leaf.
    stored: Vec<Leaf4>,
    shape_count: usize,
    simd: SimdLevel,
    /// A scene of a few flat shapes, for [`Bvh::closest_many`] and
    /// [`Bvh::occluded_many`].
    few: Option<FewFlats>,
    /// A small scene's walls, and a tree without them for the shadow rays that keep
    /// off them.
    indoors: Option<Box<Indoors<'s>>>,
}

impl<'s> Bvh<'s> {
    /// Builds over `shapes`, its leaves as `leaves` says. More than [`MAX_SHAPES`]
    /// shapes is the caller's error.
    pub fn build(shapes: &'s Shapes, leaves: Leaves) -> Bvh<'s> {
        Bvh::build_with(shapes, SimdLevel::current(), leaves)
    }

    /// Builds over `shapes`, to be traversed with `simd` (or the baseline, where the
    /// processor lacks it).
    pub fn build_with(shapes: &'s Shapes, simd: SimdLevel, leaves: Leaves) -> Bvh<'s> {
        assert!(shapes.len() <= MAX_SHAPES, "too many shapes for the BVH");
        let all: Vec<u32> = (0..shapes.len() as u32).collect();
        let mut bvh = Bvh::build_over(shapes, &all, simd, leaves);
        bvh.few = FewFlats::of(shapes);
        bvh.indoors = Indoors::of(shapes, simd, leaves).map(Box::new);
        bvh
    }

    /// Builds over an object's `shapes` for its placed copies ([`Bvh::closest_placed`],
    /// [`Bvh::occluded_placed`]), without what only a scene's own rays use.
    pub fn build_object(shapes: &'s Shapes, leaves: Leaves) -> Bvh<'s> {
        assert!(shapes.len() <= MAX_SHAPES, "too many shapes for the BVH");
        let all: Vec<u32> = (0..shapes.len() as u32).collect();
        Bvh::build_over(shapes, &all, SimdLevel::current(), leaves)
    }

    /// Builds over the shapes of `shapes` that `subset` names (each once), which its
    /// hits name by their index in `shapes`.
    fn build_over(shapes: &'s Shapes, subset: &[u32], simd: SimdLevel, leaves: Leaves) -> Bvh<'s> {
        let mut bvh = Bvh {
            shapes,
            root: EMPTY_ROOT,
            nodes: Vec::new(),
            prims: Vec::new(),
            stored: Vec::new(),
            shape_count: subset.len(),
            simd: simd.supported(),
            few: None,
            indoors: None,
        };
        if subset.is_empty() {
            return bvh;
        }
        let mut out = Collapsed::default();
        if subset.len() <= TINY_SCENE {
            bvh.root = out.leaf(shapes, subset);
        } else {
            let boxes: Vec<Aabb> = subset
                .par_iter()
                .map(|&i| padded_bounds(&shapes.get(i as usize)))
                .collect();
            let mut binary = build::build(&boxes);
            if subset.len() < shapes.len() {
                for shape in &mut binary.order {
                    *shape = subset[*shape as usize];
                }
            }
            out.nodes.reserve_exact(binary.tree.nodes() / 2 + 1);
            out.prims.reserve_exact(subset.len());
            out.collapse(shapes, &binary.tree, &binary.order);
        }
        if leaves == Leaves::Copied {
            out.copy_triangle_leaves(shapes, &mut bvh.root);
        }
        bvh.nodes = out.nodes;
        bvh.prims = out.prims;
        bvh.stored = out.stored;
        bvh.nodes.shrink_to_fit();
        bvh.stored.shrink_to_fit();
        bvh
    }

    /// Eight-wide inner nodes; 0 when the scene is empty or small enough to be one leaf.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of shapes the tree was built over.
    pub fn shape_count(&self) -> usize {
        self.shape_count
    }

    /// The instructions the traversal runs on.
    pub fn simd(&self) -> SimdLevel {
        self.simd
    }

    /// Bytes held by the nodes and the leaves (shape indices and copies).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * size_of::<Node8>()
            + self.prims.capacity() * size_of::<u32>()
            + self.stored.capacity() * size_of::<Leaf4>()
            + self.few.as_ref().map_or(0, FewFlats::memory_bytes)
            + self.indoors.as_ref().map_or(0, |i| i.memory_bytes())
    }

    /// The nearest hit with `0 < t < t_max`; of equally near ones, the lowest index.
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.root.count > 0 {
            // A scene of a few shapes is one leaf: no boxes to set up, no stack.
            let mut best = None;
            self.leaf_closest(self.root, &RayLanes::new(ray), ray, t_max, &mut best);
            return best;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.closest_avx2(ray, t_max) };
        }
        self.closest_sse2(ray, t_max)
    }

    /// [`Bvh::closest`] on four lanes. Not inlined, like the AVX2 one: the traversal
    /// stack would otherwise sit in the frame of every caller, a shading recursion's
    /// at every level.
    #[inline(never)]
    fn closest_sse2(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.closest_in(Boxes4::<false>::new(ray), ray, t_max)
    }

    /// [`Bvh::closest`] compiled for AVX2: the same operations, VEX-encoded.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn closest_avx2(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        match Boxes8::new(ray) {
            Some(boxes) => self.closest_in(boxes, ray, t_max),
            None => self.closest_sse2(ray, t_max),
        }
    }

    #[inline(always)]
    fn closest_in(&self, boxes: impl BoxTest, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.shape_count == 0 {
            return None;
        }
        let lanes = RayLanes::new(ray);
        let mut best: Option<Hit> = None;
        // `Hit::bound(&best, t_max)`, which only a leaf changes.
        let mut bound = t_max;
        let mut stack = Stack::new(self.root);
        'pop: while let Some(mut entry) = stack.pop() {
            if entry.t > bound * BOX_SLACK {
                continue;
            }
            // Down the tree through the nearest child hit, the others stacked: a child
            // just hit is entered before the bound, so it needs no test of its own.
            loop {
                if entry.count > 0 {
                    self.leaf_closest(entry, &lanes, ray, t_max, &mut best);
                    bound = Hit::bound(&best, t_max);
                    continue 'pop;
                }
                let node = self.node(entry);
                let (mask, t_near) = boxes.hit(node, bound);
                entry = match node.only_child(mask, &t_near) {
                    Some(only) => only,
                    None if mask == 0 => continue 'pop,
                    None => stack.push_children_but_nearest(node, mask, &t_near),
                };
            }
        }
        best
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`: the
    /// traversal stops at the first such.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        match &self.indoors {
            Some(indoors) if indoors.clear(ray, t_max) => {
                indoors.tree().occluded_whole(ray, t_max, blocks)
            }
            _ => self.occluded_whole(ray, t_max, blocks),
        }
    }

    /// [`Bvh::occluded`] on the whole tree.
    #[inline]
    fn occluded_whole(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        if self.root.count > 0 {
            return self.leaf_blocks(self.root, &RayLanes::new(ray), t_max, &blocks);
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.occluded_avx2(ray, t_max, blocks) };
        }
        self.occluded_sse2(ray, t_max, blocks)
    }

    /// [`Bvh::occluded`] on four lanes, not inlined (see [`Bvh::closest_sse2`]).
    #[inline(never)]
    fn occluded_sse2(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        self.occluded_in(Boxes4::<false>::new(ray), ray, t_max, blocks)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn occluded_avx2(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        match Boxes8::new(ray) {
            Some(boxes) => self.occluded_in(boxes, ray, t_max, blocks),
            None => self.occluded_sse2(ray, t_max, blocks),
        }
    }

    #[inline(always)]
    fn occluded_in(
        &self,
        boxes: impl BoxTest,
        ray: &Ray,
        t_max: f32,
        blocks: impl Fn(u32) -> bool,
    ) -> bool {
        if self.shape_count == 0 {
            return false;
        }
        self.occluded_below(
            &mut Stack::new(self.root),
            &boxes,
            &RayLanes::new(ray),
            t_max,
            &blocks,
        )
    }

    /// The walk of [`Bvh::occluded`] from the entries on `stack`.
    #[inline(always)]
    fn occluded_below(
        &self,
        stack: &mut Stack,
        boxes: &impl BoxTest,
        lanes: &RayLanes,
        t_max: f32,
        blocks: &impl Fn(u32) -> bool,
    ) -> bool {
        let mut next: Option<Entry> = None;
        while let Some(entry) = next.take().or_else(|| stack.pop()) {
            if entry.count > 0 {
                if self.leaf_blocks(entry, lanes, t_max, blocks) {
                    return true;
                }
                continue;
            }
            let node = self.node(entry);
            let (mut mask, t_near) = boxes.hit(node, t_max);
            next = node.only_child(mask, &t_near);
            if next.is_some() {
                continue;
            }
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                stack.push(node.entry(lane, 0.0));
            }
        }
        false
    }
}

impl Bvh<'_> {
    /// The inner node `entry` names, its children's row requested from memory at once.
    /// Which child the traversal takes next is known only once the box test is done,
    /// and that row has a cache line of its own: asked for then, it is a second wait
    /// after the boxes' (on the dragon, shadow rays 7 % and closest hits 4 % more a
    /// second when it is asked for with them).
    #[inline(always)]
    fn node(&self, entry: Entry) -> &Node8 {
        debug_assert!(entry.count == 0 && (entry.child as usize) < self.nodes.len());
        // SAFETY: inner entries are written by the collapse, which names only nodes it
        // made, and the nodes never change after the build.
        let node = unsafe { self.nodes.get_unchecked(entry.child as usize) };
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            // SAFETY: a prefetch reads nothing and faults on no address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(node.child.as_ptr().cast()) };
        }
        node
    }

    /// Asks for the memory of `entry` ahead of its visit: a node's four cache lines,
    /// or a copied leaf's first block.
    #[inline(always)]
    fn prefetch(&self, entry: Entry) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            let (at, lines): (*const i8, usize) = if entry.count == 0 {
                (
                    self.nodes
                        .as_ptr()
                        .wrapping_add(entry.child as usize)
                        .cast(),
                    4,
                )
            } else if entry.count & STORED != 0 {
                (
                    self.stored
                        .as_ptr()
                        .wrapping_add(entry.child as usize)
                        .cast(),
                    3,
                )
            } else {
                return;
            };
            for line in 0..lines {
                // SAFETY: a prefetch reads nothing and faults on no address.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(at.wrapping_add(64 * line)) };
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = entry;
    }

    /// Updates `best` with the hits of the shapes of leaf `entry`.
    #[inline(always)]
    fn leaf_closest(
        &self,
        entry: Entry,
        lanes: &RayLanes,
        ray: &Ray,
        t_max: f32,
        best: &mut Option<Hit>,
    ) {
        let first = entry.child as usize;
        if entry.count & STORED != 0 {
            let n = (entry.count & !STORED) as usize;
            for leaf in &self.stored[first..first + n] {
                leaf4_closest(leaf, lanes, ray, t_max, best);
            }
        } else {
            for four in self.prims[first..first + entry.count as usize].chunks(4) {
                let leaf = Leaf4::new(self.shapes, four);
                leaf4_closest(&leaf, lanes, ray, t_max, best);
            }
        }
    }

    /// Whether a shape of leaf `entry` for which `blocks` holds meets the ray.
    #[inline(always)]
    fn leaf_blocks(
        &self,
        entry: Entry,
        lanes: &RayLanes,
        t_max: f32,
        blocks: &impl Fn(u32) -> bool,
    ) -> bool {
        // Loops, not iterator closures: a closure would not inherit the caller's
        // instruction set.
        let first = entry.child as usize;
        if entry.count & STORED != 0 {
            let n = (entry.count & !STORED) as usize;
            for leaf in &self.stored[first..first + n] {
                if leaf4_blocks(leaf, lanes, t_max, blocks) {
                    return true;
                }
            }
        } else {
            for four in self.prims[first..first + entry.count as usize].chunks(4) {
                let leaf = Leaf4::new(self.shapes, four);
                if leaf4_blocks(&leaf, lanes, t_max, blocks) {
                    return true;
                }
            }
        }
        false
    }
}

/// Updates `best` with the hits of one leaf leaf.
#[inline(always)]
fn leaf4_closest(leaf: &Leaf4, lanes: &RayLanes, ray: &Ray, t_max: f32, best: &mut Option<Hit>) {
    let (mut mask, t) = leaf.intersect_flat(lanes, Hit::bound(best, t_max));
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let shape = leaf.shape(lane);
        if Hit::beats(t[lane], shape, best) {
            *best = Some(Hit::world(t[lane], shape));
        }
    }
    let spheres = leaf.sphere_lanes();
    if spheres == 0 {
        return;
    }
    if spheres & (spheres - 1) == 0 {
        let lane = spheres.trailing_zeros() as usize;
        let shape = leaf.shape(lane);
        if let Some(t) = leaf.sphere(lane).intersect(ray, Hit::bound(best, t_max))
            && Hit::beats(t, shape, best)
        {
            *best = Some(Hit::world(t, shape));
        }
        return;
    }
    // All spheres against one bound: a sphere's distance does not depend on the bound,
    // only whether it counts, and one the tighter bound of a nearer sphere would have
    // rejected cannot beat that sphere (ties included, the bound being a step past).
    let (mut mask, t) = leaf.intersect_spheres(lanes, Hit::bound(best, t_max));
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let shape = leaf.shape(lane);
        if Hit::beats(t[lane], shape, best) {
            *best = Some(Hit::world(t[lane], shape));
        }
    }
}

/// Whether a shape of one leaf leaf for which `blocks` holds meets the ray.
#[inline(always)]
fn leaf4_blocks(leaf: &Leaf4, lanes: &RayLanes, t_max: f32, blocks: &impl Fn(u32) -> bool) -> bool {
    let mut mask = leaf.intersect_flat(lanes, t_max).0;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if blocks(leaf.shape(lane)) {
            return true;
        }
    }
    if leaf.sphere_lanes() == 0 {
        return false;
    }
    // Hit first: `blocks` may note the shapes it is asked about (the whitted model's
    // walk through glass), and a sphere the ray misses is not on its way.
    let mut mask = leaf.intersect_spheres(lanes, t_max).0;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if blocks(leaf.shape(lane)) {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests;
