//! Binned SAH construction of a binary BVH (Wald, "On fast construction of SAH-based
//! bounding volume hierarchies", 2007): at each node the centroids are dropped into
//! [`BINS`] bins per axis and the plane between two bins with the least surface-area
//! cost wins, or the node becomes a leaf when that is cheaper.

use rayon::prelude::*;

use crate::math::{Aabb, Vec3};

const BINS: usize = 32;
/// Cost of descending a level relative to testing a leaf's four shapes at once. Leaves
/// gather their triangles' corners from the scene, which makes them dear: measured on the
/// bunny and the dragon, 0.5 casts rays 6–12 % faster than 2 for 12 % more tree bytes
/// (0.25 to 0.75 are within noise).
const TRAVERSAL_COST: f32 = 0.5;
/// Leaves hold at most this many shapes unless their centroids cannot be told apart.
pub const MAX_LEAF: usize = 8;
/// Deepest level of the binary tree; bounds the traversal stack. A node this deep
/// becomes a leaf however many shapes it holds (only pathological inputs get here).
pub const MAX_DEPTH: u32 = 64;

/// A node of the binary tree. Children of an inner node are adjacent: `first` and
/// `first + 1`. A leaf holds `order[first..first + count]`.
#[derive(Clone, Copy, Debug)]
pub struct Node2 {
    pub bounds: Aabb,
    pub first: u32,
    /// 0 for an inner node.
    pub count: u32,
}

impl Node2 {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The binary tree over `boxes`, and the order its leaves list the boxes in.
pub struct BinaryBvh {
    pub nodes: Vec<Node2>,
    pub order: Vec<u32>,
}

/// Ranges larger than this split their two halves across threads.
const PARALLEL_MIN: usize = 4096;

/// The tree as the parallel build makes it; flattened into [`Node2`]s afterwards.
enum Tree {
    Leaf {
        bounds: Aabb,
        start: u32,
        count: u32,
    },
    Inner {
        bounds: Aabb,
        children: Box<[Tree; 2]>,
    },
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
        .map(|(i, b)| PrimRef {
            min: b.min.to_array(),
            id: i as u32,
            max: b.max.to_array(),
        })
        .collect();
    let bounds = bounds_of(&refs);
    let centroids = centroids_of(&refs);
    let tree = subtree(&mut refs, 0, bounds, centroids, 0);
    let order = refs.iter().map(|r| r.id).collect();
    let mut nodes = Vec::with_capacity(2 * boxes.len() / 3 + 1);
    nodes.push(Node2 {
        bounds,
        first: 0,
        count: 0,
    });
    flatten(&tree, 0, &mut nodes);
    BinaryBvh { nodes, order }
}

/// Builds the subtree over `items`, which sit at `start` in the whole order.
fn subtree(items: &mut [PrimRef], start: usize, bounds: Aabb, centroids: Aabb, depth: u32) -> Tree {
    let count = items.len();
    let split = if count > 1 && depth < MAX_DEPTH {
        best_split(items, bounds, centroids)
    } else {
        None
    };
    let mid = match split {
        Some(split) => Some(partition(items, &split)),
        // Coincident centroids: halve the range if it is too big for one leaf.
        None if count > MAX_LEAF && depth < MAX_DEPTH => Some(count / 2),
        None => None,
    };
    let Some(mid) = mid.filter(|&m| m > 0 && m < count) else {
        return Tree::Leaf {
            bounds,
            start: start as u32,
            count: count as u32,
        };
    };
    let (left, right) = items.split_at_mut(mid);
    let child = |items: &mut [PrimRef], start: usize| {
        let bounds = bounds_of(items);
        let centroids = centroids_of(items);
        subtree(items, start, bounds, centroids, depth + 1)
    };
    let (l, r) = if count > PARALLEL_MIN {
        rayon::join(|| child(left, start), || child(right, start + mid))
    } else {
        (child(left, start), child(right, start + mid))
    };
    Tree::Inner {
        bounds,
        children: Box::new([l, r]),
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

/// Writes `tree` into `nodes[at]`, its children side by side after the nodes so far.
fn flatten(tree: &Tree, at: usize, nodes: &mut Vec<Node2>) {
    match tree {
        &Tree::Leaf {
            bounds,
            start,
            count,
        } => {
            nodes[at] = Node2 {
                bounds,
                first: start,
                count,
            }
        }
        Tree::Inner { bounds, children } => {
            let first = nodes.len();
            nodes[at] = Node2 {
                bounds: *bounds,
                first: first as u32,
                count: 0,
            };
            let placeholder = Node2 {
                bounds: Aabb::EMPTY,
                first: 0,
                count: 0,
            };
            nodes.extend([placeholder, placeholder]);
            flatten(&children[0], first, nodes);
            flatten(&children[1], first + 1, nodes);
        }
    }
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
        (((c[self.axis] - self.min) * self.scale) as usize).min(BINS - 1)
    }
}

/// The cheapest split by SAH, or `None` when a leaf is at least as cheap.
fn best_split(items: &[PrimRef], bounds: Aabb, centroids: Aabb) -> Option<Split> {
    let extent = centroids.extent();
    let splits = [0, 1, 2].map(|axis| Split {
        axis,
        bin: 0,
        min: centroids.min[axis],
        scale: BINS as f32 * (1.0 - 1e-6) / extent[axis],
    });
    let live = [0, 1, 2].map(|axis| extent[axis] > 0.0);
    // One pass over the shapes bins all three axes.
    let mut all_bins = [[EMPTY_BIN; BINS]; 3];
    for r in items {
        let (b, c) = (r.bounds(), r.center());
        for axis in 0..3 {
            if live[axis] {
                let bin = &mut all_bins[axis][splits[axis].bin_of(c)];
                bin.bounds = bin.bounds.union(b);
                bin.count += 1;
            }
        }
    }
    let mut best: Option<(f32, Split)> = None;
    for axis in 0..3 {
        if !live[axis] {
            continue;
        }
        let split = &splits[axis];
        let bins = &all_bins[axis];
        // right_cost[k]: area x count of bins k.. (sweep from the right).
        let mut right_cost = [0.0f32; BINS];
        let mut acc = EMPTY_BIN;
        for k in (1..BINS).rev() {
            acc.bounds = acc.bounds.union(bins[k].bounds);
            acc.count += bins[k].count;
            right_cost[k] = half_area(&acc.bounds) * packets(acc.count as usize);
        }
        let mut acc = EMPTY_BIN;
        for k in 1..BINS {
            acc.bounds = acc.bounds.union(bins[k - 1].bounds);
            acc.count += bins[k - 1].count;
            if acc.count == 0 || acc.count as usize == items.len() {
                continue;
            }
            let cost = half_area(&acc.bounds) * packets(acc.count as usize) + right_cost[k];
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((
                    cost,
                    Split {
                        axis,
                        bin: k,
                        min: split.min,
                        scale: split.scale,
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

/// Moves the items left of the split plane to the front; returns how many there are.
fn partition(items: &mut [PrimRef], split: &Split) -> usize {
    let (mut i, mut j) = (0, items.len());
    while i < j {
        if split.bin_of(items[i].center()) < split.bin {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    i
}

/// Cost of testing `n` shapes: leaves test them four at a time.
fn packets(n: usize) -> f32 {
    n.div_ceil(4) as f32
}

/// Half the surface area: the SAH only compares areas, so the factor 2 is dropped.
fn half_area(b: &Aabb) -> f32 {
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
        assert_eq!(a.nodes.len(), b.nodes.len());
        for (x, y) in a.nodes.iter().zip(&b.nodes) {
            assert_eq!((x.bounds, x.first, x.count), (y.bounds, y.first, y.count));
        }
    }

    #[test]
    fn every_box_is_in_one_leaf_inside_its_ancestors() {
        let boxes = boxes(3000);
        let tree = build(&boxes);
        let mut seen = vec![0u32; boxes.len()];
        let mut stack = vec![0usize];
        while let Some(at) = stack.pop() {
            let node = tree.nodes[at];
            if node.is_leaf() {
                assert!(node.count as usize <= MAX_LEAF);
                for &i in &tree.order[node.first as usize..(node.first + node.count) as usize] {
                    seen[i as usize] += 1;
                    assert_eq!(node.bounds.union(boxes[i as usize]), node.bounds);
                }
            } else {
                for child in [node.first as usize, node.first as usize + 1] {
                    let inner = tree.nodes[child].bounds;
                    assert_eq!(node.bounds.union(inner), node.bounds);
                    stack.push(child);
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }
}
