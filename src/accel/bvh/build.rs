//! Binned SAH construction of a binary BVH (Wald, "On fast construction of SAH-based
//! bounding volume hierarchies", 2007): at each node the centroids are dropped into
//! [`BINS`] bins per axis and the plane between two bins with the least surface-area
//! cost wins, or the node becomes a leaf when that is cheaper.

use rayon::prelude::*;

use crate::math::{Aabb, Vec3};

const BINS: usize = 32;
/// Cost of descending a level relative to testing a leaf's four shapes at once. The
/// binary levels are collapsed into eight-wide nodes, so a level costs little: on the
/// bunny and the dragon 0.5 cast rays 6–12 % faster than 2 (0.25 to 0.75 within noise),
/// and on the Cornell box's path rays 0.25 tests 1.3 leaves of four a closest hit
/// instead of 3.0, 20 % sooner.
const TRAVERSAL_COST: f32 = 0.25;
/// Leaves hold at most this many shapes unless their centroids cannot be told apart.
pub const MAX_LEAF: usize = 8;
/// Deepest level of the binary tree; bounds the traversal stack. A node this deep
/// becomes a leaf however many shapes it holds (only pathological inputs get here).
pub const MAX_DEPTH: u32 = 64;

/// The binary tree over `boxes`, and the order its leaves list the boxes in.
pub struct BinaryBvh {
    pub tree: Tree,
    pub order: Vec<u32>,
}

/// Ranges larger than this split their two halves across threads.
const PARALLEL_MIN: usize = 4096;

/// A node of the binary tree, as the parallel build makes it. A leaf holds
/// `order[start..start + count]`.
#[derive(Debug, PartialEq)]
pub enum Tree {
    Leaf {
        bounds: Aabb,
        start: u32,
        count: u32,
    },
    Inner {
        bounds: Aabb,
        /// Nodes in this subtree, itself included.
        nodes: u32,
        children: Box<[Tree; 2]>,
    },
}

impl Tree {
    pub fn bounds(&self) -> &Aabb {
        match self {
            Tree::Leaf { bounds, .. } | Tree::Inner { bounds, .. } => bounds,
        }
    }

    /// Nodes in this subtree, itself included.
    pub fn nodes(&self) -> usize {
        match self {
            Tree::Leaf { .. } => 1,
            Tree::Inner { nodes, .. } => *nodes as usize,
        }
    }
}

/// A shape's box and index, the unit the build sorts: partitioning these rather than
/// indices into the boxes keeps every pass over a node's shapes sequential in memory
/// (on large meshes the indirection's cache misses were most of the build).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct PrimRef {
    min: [f32; 3],
    id: u32,
    max: [f32; 3],
}

impl PrimRef {
    /// Shape `id` with box `b`. A shape with a NaN coordinate is never hit, but a NaN
    /// in a box would spread to the bounds of the nodes above it (how far depends on
    /// the order of the unions), hiding shapes that can be hit: such a shape gets a
    /// point box at the origin instead, where rays that pass test it and miss.
    fn new(id: u32, b: &Aabb) -> PrimRef {
        if b.min.is_nan() || b.max.is_nan() {
            return PrimRef {
                min: [0.0; 3],
                id,
                max: [0.0; 3],
            };
        }
        PrimRef {
            min: b.min.to_array(),
            id,
            max: b.max.to_array(),
        }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::from_array(self.min),
            max: Vec3::from_array(self.max),
        }
    }

    #[inline(always)]
    fn center(&self) -> Vec3 {
        self.bounds().center()
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Aabb::EMPTY,
    count: 0,
};

/// Builds the tree; `boxes` must be non-empty. Subtrees of large ranges build in
/// parallel; the result does not depend on the thread count.
pub fn build(boxes: &[Aabb]) -> BinaryBvh {
    let mut refs: Vec<PrimRef> = boxes
        .par_iter()
        .enumerate()
        .map(|(i, b)| PrimRef::new(i as u32, b))
        .collect();
    let all = Side::of(&refs);
    let tree = subtree(&mut refs, 0, all, 0);
    let order = refs.iter().map(|r| r.id).collect();
    BinaryBvh { tree, order }
}

/// Builds the subtree over `items` (measured by `side`), which sit at `start` in the
/// whole order.
fn subtree(items: &mut [PrimRef], start: usize, side: Side, depth: u32) -> Tree {
    let (count, bounds) = (items.len(), side.bounds);
    let split = if count > 1 && depth < MAX_DEPTH {
        best_split(items, bounds, side.centroids)
    } else {
        None
    };
    let halves = match split {
        Some(split) => Some(partition(items, &split)),
        // Coincident centroids: halve the range if it is too big for one leaf.
        None if count > MAX_LEAF && depth < MAX_DEPTH => {
            let (left, right) = items.split_at(count / 2);
            Some([Side::of(left), Side::of(right)])
        }
        None => None,
    };
    let Some([left_side, right_side]) = halves.filter(|[l, _]| l.count > 0 && l.count < count)
    else {
        return Tree::Leaf {
            bounds,
            start: start as u32,
            count: count as u32,
        };
    };
    let mid = left_side.count;
    let (left, right) = items.split_at_mut(mid);
    let child =
        |items: &mut [PrimRef], start: usize, side: Side| subtree(items, start, side, depth + 1);
    let (l, r) = if count > PARALLEL_MIN {
        rayon::join(
            || child(left, start, left_side),
            || child(right, start + mid, right_side),
        )
    } else {
        (
            child(left, start, left_side),
            child(right, start + mid, right_side),
        )
    };
    Tree::Inner {
        bounds,
        nodes: (1 + l.nodes() + r.nodes()) as u32,
        children: Box::new([l, r]),
    }
}

/// One side of a split: how many shapes, their bounds and their centroids' bounds.
#[derive(Clone, Copy)]
struct Side {
    count: usize,
    bounds: Aabb,
    centroids: Aabb,
}

impl Side {
    const EMPTY: Side = Side {
        count: 0,
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
    };

    fn of(items: &[PrimRef]) -> Side {
        Side {
            count: items.len(),
            bounds: bounds_of(items),
            centroids: centroids_of(items),
        }
    }

    #[inline(always)]
    fn add(&mut self, r: &PrimRef) {
        self.count += 1;
        self.bounds = self.bounds.union(r.bounds());
        self.centroids = self.centroids.grow(r.center());
    }
}

fn bounds_of(items: &[PrimRef]) -> Aabb {
    items
        .iter()
        .fold(Aabb::EMPTY, |acc, r| acc.union(r.bounds()))
}

fn centroids_of(items: &[PrimRef]) -> Aabb {
    items
        .iter()
        .fold(Aabb::EMPTY, |acc, r| acc.grow(r.center()))
}

/// A plane between bins `bin - 1` and `bin` on `axis`.
struct Split {
    axis: usize,
    bin: usize,
    min: f32,
    scale: f32,
}

impl Split {
    #[inline]
    fn bin_of(&self, c: Vec3) -> usize {
        bin_index((c[self.axis] - self.min) * self.scale)
    }
}

/// The bin `x` bins past the first falls in: its whole part, held to the bins (NaN
/// goes to the first, as a saturating cast would put it).
#[inline(always)]
fn bin_index(x: f32) -> usize {
    let x = x.max(0.0).min((BINS - 1) as f32);
    // SAFETY: `x` is a number in 0..=BINS - 1, which a u32 holds.
    unsafe { x.to_int_unchecked::<u32>() as usize }
}

/// The cheapest split by SAH, or `None` when a leaf is at least as cheap.
fn best_split(items: &[PrimRef], bounds: Aabb, centroids: Aabb) -> Option<Split> {
    let extent = centroids.extent();
    let origin = centroids.min;
    let scale = Vec3::splat(BINS as f32 * (1.0 - 1e-6)) / extent;
    let live = [0, 1, 2].map(|axis| extent[axis] > 0.0);
    // One pass over the shapes bins all three axes; `used` marks the bins filled.
    let mut all_bins = [[EMPTY_BIN; BINS]; 3];
    let mut used = [0u32; 3];
    for r in items {
        let (b, c) = (r.bounds(), r.center());
        let at = (c - origin) * scale;
        for axis in 0..3 {
            if live[axis] {
                let k = bin_index(at[axis]);
                let bin = &mut all_bins[axis][k];
                bin.bounds = bin.bounds.union(b);
                bin.count += 1;
                used[axis] |= 1 << k;
            }
        }
    }
    // Planes are priced only after a filled bin: the planes up to the next filled bin
    // part the shapes alike and cost the same, and the first of them wins the tie.
    let mut best: Option<(f32, Split)> = None;
    for axis in 0..3 {
        if !live[axis] {
            continue;
        }
        let bins = &all_bins[axis];
        // right_cost[k], for a filled bin k: area x count of bins k.. (from the right).
        let mut right_cost = [0.0f32; BINS];
        let mut acc = EMPTY_BIN;
        let mut rest = used[axis];
        while rest != 0 {
            let k = (u32::BITS - 1 - rest.leading_zeros()) as usize;
            rest &= !(1 << k);
            acc.bounds = acc.bounds.union(bins[k].bounds);
            acc.count += bins[k].count;
            right_cost[k] = half_area(&acc.bounds) * packets(acc.count as usize);
        }
        let mut acc = EMPTY_BIN;
        let mut rest = used[axis];
        while rest != 0 {
            let k = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            if rest == 0 {
                break;
            }
            let next = rest.trailing_zeros() as usize;
            acc.bounds = acc.bounds.union(bins[k].bounds);
            acc.count += bins[k].count;
            let cost = half_area(&acc.bounds) * packets(acc.count as usize) + right_cost[next];
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((
                    cost,
                    Split {
                        axis,
                        bin: k + 1,
                        min: origin[axis],
                        scale: scale[axis],
                    },
                ));
            }
        }
    }
    let (cost, split) = best?;
    let area = half_area(&bounds);
    let split_cost = TRAVERSAL_COST + cost / area;
    let leaf_cost = packets(items.len());
    // A degenerate (flat or zero-area, or NaN) node compares costs by counts alone.
    let degenerate = area.is_nan() || area <= 0.0;
    let splits_pay = degenerate || split_cost < leaf_cost || items.len() > MAX_LEAF;
    splits_pay.then_some(split)
}

/// Moves the items left of the split plane to the front, and describes the two sides
/// (the left first), found on the same pass.
fn partition(items: &mut [PrimRef], split: &Split) -> [Side; 2] {
    let (mut left, mut right) = (Side::EMPTY, Side::EMPTY);
    let (mut i, mut j) = (0, items.len());
    while i < j {
        if split.bin_of(items[i].center()) < split.bin {
            left.add(&items[i]);
            i += 1;
        } else {
            j -= 1;
            right.add(&items[i]);
            items.swap(i, j);
        }
    }
    [left, right]
}

/// Cost of testing `n` shapes: leaves test them four at a time.
pub(super) fn packets(n: usize) -> f32 {
    n.div_ceil(4) as f32
}

/// Half the surface area: the SAH only compares areas, so the factor 2 is dropped.
pub(super) fn half_area(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let e = b.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boxes scattered by a fixed hash, enough to build in parallel.
    fn boxes(n: usize) -> Vec<Aabb> {
        (0..n as u32)
            .map(|i| {
                let h = |k: u32| (i.wrapping_mul(2_654_435_761).rotate_left(k) % 1000) as f32;
                let p = Vec3::new(h(0), h(11), h(22));
                Aabb {
                    min: p,
                    max: p + Vec3::splat(1.0 + h(7) % 5.0),
                }
            })
            .collect()
    }

    #[test]
    fn the_tree_does_not_depend_on_the_thread_count() {
        let boxes = boxes(5 * PARALLEL_MIN);
        let on = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| build(&boxes))
        };
        let (a, b) = (on(1), on(3));
        assert_eq!(a.order, b.order);
        assert_eq!(a.tree.nodes(), b.tree.nodes());
        assert!(a.tree == b.tree);
    }

    #[test]
    fn every_box_is_in_one_leaf_inside_its_ancestors() {
        let mut boxes = boxes(3000);
        // Boxes of one centre and many sizes: no plane parts them, so the range is
        // halved as it is.
        boxes.extend((1..20).map(|k| Aabb {
            min: Vec3::splat(500.0 - k as f32),
            max: Vec3::splat(500.0 + k as f32),
        }));
        let built = build(&boxes);
        let mut seen = vec![0u32; boxes.len()];
        let mut stack = vec![&built.tree];
        let mut nodes = 0;
        while let Some(node) = stack.pop() {
            nodes += 1;
            match node {
                &Tree::Leaf {
                    bounds,
                    start,
                    count,
                } => {
                    assert!(count as usize <= MAX_LEAF);
                    for &i in &built.order[start as usize..(start + count) as usize] {
                        seen[i as usize] += 1;
                        assert_eq!(bounds.union(boxes[i as usize]), bounds);
                    }
                }
                Tree::Inner {
                    bounds, children, ..
                } => {
                    for child in children.iter() {
                        assert_eq!(bounds.union(*child.bounds()), *bounds);
                        stack.push(child);
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert_eq!(built.tree.nodes(), nodes);
    }

    /// The plane every candidate is priced for, the first of the cheapest: the split
    /// [`best_split`] must find pricing only the planes after filled bins.
    fn best_split_of_every_plane(
        items: &[PrimRef],
        bounds: Aabb,
        centroids: Aabb,
    ) -> Option<Split> {
        let extent = centroids.extent();
        let mut best: Option<(f32, Split)> = None;
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let split = |bin| Split {
                axis,
                bin,
                min: centroids.min[axis],
                scale: BINS as f32 * (1.0 - 1e-6) / extent[axis],
            };
            let mut bins = [EMPTY_BIN; BINS];
            for r in items {
                let bin = &mut bins[split(0).bin_of(r.center())];
                bin.bounds = bin.bounds.union(r.bounds());
                bin.count += 1;
            }
            for k in 1..BINS {
                let side = |range: std::ops::Range<usize>| {
                    bins[range].iter().fold(EMPTY_BIN, |acc, b| Bin {
                        bounds: acc.bounds.union(b.bounds),
                        count: acc.count + b.count,
                    })
                };
                let (left, right) = (side(0..k), side(k..BINS));
                if left.count == 0 || right.count == 0 {
                    continue;
                }
                let cost = half_area(&left.bounds) * packets(left.count as usize)
                    + half_area(&right.bounds) * packets(right.count as usize);
                if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                    best = Some((cost, split(k)));
                }
            }
        }
        let (cost, split) = best?;
        let area = half_area(&bounds);
        let pays = area.is_nan()
            || area <= 0.0
            || TRAVERSAL_COST + cost / area < packets(items.len())
            || items.len() > MAX_LEAF;
        pays.then_some(split)
    }

    /// Pricing only the planes after filled bins changes no split, and the two sides
    /// found while partitioning are those of the parted shapes: the tree is the one of
    /// every plane priced and every side measured again.
    #[test]
    fn splits_and_sides_are_those_of_every_plane_and_every_shape() {
        let all = boxes(20_000);
        let mut checked = 0;
        for n in [2usize, 3, 5, 8, 9, 17, 40, 100, 1000, 20_000] {
            for offset in [0, 7, 501] {
                let Some(chosen) = all.get(offset..offset + n) else {
                    continue;
                };
                let mut items: Vec<PrimRef> = chosen
                    .iter()
                    .enumerate()
                    .map(|(i, b)| PrimRef::new(i as u32, b))
                    .collect();
                let (bounds, centroids) = (bounds_of(&items), centroids_of(&items));
                let fast = best_split(&items, bounds, centroids);
                let slow = best_split_of_every_plane(&items, bounds, centroids);
                let key = |s: &Option<Split>| s.as_ref().map(|s| (s.axis, s.bin));
                assert_eq!(key(&fast), key(&slow), "{n} shapes from {offset}");
                let Some(split) = fast else { continue };
                let [left, right] = partition(&mut items, &split);
                let (l, r) = items.split_at(left.count);
                for (side, part) in [(left, l), (right, r)] {
                    let whole = Side::of(part);
                    assert_eq!(side.count, whole.count);
                    assert_eq!(side.bounds, whole.bounds);
                    assert_eq!(side.centroids, whole.centroids);
                }
                assert!(l.iter().all(|r| split.bin_of(r.center()) < split.bin));
                assert!(r.iter().all(|r| split.bin_of(r.center()) >= split.bin));
                checked += 1;
            }
        }
        assert!(checked > 20);
    }

    #[test]
    fn a_bin_index_is_held_to_the_bins_as_a_saturating_cast_would_be() {
        for x in [
            -1e30,
            -1.0,
            -0.0,
            0.0,
            0.5,
            1.0,
            30.999,
            31.0,
            31.5,
            32.0,
            1e30,
            f32::NAN,
        ] {
            let cast = (x as usize).min(BINS - 1);
            assert_eq!(bin_index(x), cast, "{x}");
        }
        assert_eq!(bin_index(f32::INFINITY), BINS - 1);
        assert_eq!(bin_index(f32::NEG_INFINITY), 0);
    }
}
