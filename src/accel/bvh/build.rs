//! Binned SAH construction of a binary BVH (Wald, "On fast construction of SAH-based
//! bounding volume hierarchies", 2007): at each node the centroids are dropped into
//! [`BINS`] bins per axis and the plane between two bins with the least surface-area
//! cost wins, or the node becomes a leaf when that is cheaper.

use crate::math::{Aabb, Vec3};

const BINS: usize = 32;
/// Cost of visiting a four-wide node relative to testing one shape (leaves test four
/// shapes at once, so a node costs about two; measured on the bunny, 1 to 4 are within
/// a few per cent).
const TRAVERSAL_COST: f32 = 2.0;
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

struct Task {
    node: usize,
    depth: u32,
    start: usize,
    end: usize,
    centroids: Aabb,
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

/// Builds the tree; `boxes` must be non-empty.
pub fn build(boxes: &[Aabb]) -> BinaryBvh {
    let centers: Vec<Vec3> = boxes.iter().map(Aabb::center).collect();
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    let bounds = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
    let centroids = Aabb::from_points(&centers);
    let mut nodes = Vec::with_capacity(2 * boxes.len() / 3 + 1);
    nodes.push(Node2 {
        bounds,
        first: 0,
        count: 0,
    });
    let mut tasks = vec![Task {
        node: 0,
        depth: 0,
        start: 0,
        end: boxes.len(),
        centroids,
    }];
    while let Some(task) = tasks.pop() {
        let Task {
            node,
            depth,
            start,
            end,
            centroids,
        } = task;
        let count = end - start;
        let items = &mut order[start..end];
        let split = if count > 1 && depth < MAX_DEPTH {
            best_split(items, boxes, &centers, nodes[node].bounds, centroids)
        } else {
            None
        };
        let mid = match split {
            Some(split) => Some(partition(items, &centers, &split)),
            // Coincident centroids: halve the range if it is too big for one leaf.
            None if count > MAX_LEAF && depth < MAX_DEPTH => Some(count / 2),
            None => None,
        };
        let Some(mid) = mid.filter(|&m| m > 0 && m < count) else {
            nodes[node].first = start as u32;
            nodes[node].count = count as u32;
            continue;
        };
        let left = nodes.len();
        nodes[node].first = left as u32;
        for (a, b) in [(start, start + mid), (start + mid, end)] {
            let ids = &order[a..b];
            let child_bounds = ids
                .iter()
                .fold(Aabb::EMPTY, |acc, &i| acc.union(boxes[i as usize]));
            let child_centroids = ids
                .iter()
                .fold(Aabb::EMPTY, |acc, &i| acc.grow(centers[i as usize]));
            tasks.push(Task {
                node: nodes.len(),
                depth: depth + 1,
                start: a,
                end: b,
                centroids: child_centroids,
            });
            nodes.push(Node2 {
                bounds: child_bounds,
                first: 0,
                count: 0,
            });
        }
    }
    BinaryBvh { nodes, order }
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
fn best_split(
    items: &[u32],
    boxes: &[Aabb],
    centers: &[Vec3],
    bounds: Aabb,
    centroids: Aabb,
) -> Option<Split> {
    let extent = centroids.extent();
    let mut best: Option<(f32, Split)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let split = Split {
            axis,
            bin: 0,
            min: centroids.min[axis],
            scale: BINS as f32 * (1.0 - 1e-6) / extent[axis],
        };
        let mut bins = [EMPTY_BIN; BINS];
        for &i in items {
            let b = &mut bins[split.bin_of(centers[i as usize])];
            b.bounds = b.bounds.union(boxes[i as usize]);
            b.count += 1;
        }
        // right_cost[k]: area x count of bins k.. (sweep from the right).
        let mut right_cost = [0.0f32; BINS];
        let mut acc = EMPTY_BIN;
        for k in (1..BINS).rev() {
            acc.bounds = acc.bounds.union(bins[k].bounds);
            acc.count += bins[k].count;
            right_cost[k] = half_area(&acc.bounds) * acc.count as f32;
        }
        let mut acc = EMPTY_BIN;
        for k in 1..BINS {
            acc.bounds = acc.bounds.union(bins[k - 1].bounds);
            acc.count += bins[k - 1].count;
            if acc.count == 0 || acc.count as usize == items.len() {
                continue;
            }
            let cost = half_area(&acc.bounds) * acc.count as f32 + right_cost[k];
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((cost, Split { bin: k, ..split }));
            }
        }
    }
    let (cost, split) = best?;
    let area = half_area(&bounds);
    let split_cost = TRAVERSAL_COST + cost / area;
    let leaf_cost = items.len() as f32;
    // A degenerate (flat or zero-area, or NaN) node compares costs by counts alone.
    let degenerate = area.is_nan() || area <= 0.0;
    let splits_pay = degenerate || split_cost < leaf_cost || items.len() > MAX_LEAF;
    splits_pay.then_some(split)
}

/// Moves the items left of the split plane to the front; returns how many there are.
fn partition(items: &mut [u32], centers: &[Vec3], split: &Split) -> usize {
    let (mut i, mut j) = (0, items.len());
    while i < j {
        if split.bin_of(centers[items[i] as usize]) < split.bin {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    i
}

/// Half the surface area: the SAH only compares areas, so the factor 2 is dropped.
fn half_area(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let e = b.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}
