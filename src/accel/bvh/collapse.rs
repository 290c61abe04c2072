//! The binary tree collapsed into eight-wide nodes, chosen by dynamic programming over
//! the binary tree (Ylitie, Karras and Laine, "Efficient incoherent ray traversal on
//! GPUs through compressed wide BVHs", 2017): of every way to cut each binary subtree
//! into at most eight members, the one of least surface-area cost, a wide node costing
//! its area and a leaf its area times its blocks of four. The leaves are the binary
//! tree's; only which binary nodes become wide nodes is chosen.

use super::build::{Tree, half_area, packets};
use super::leaf4::Leaf4;
use super::{EMPTY_NODE, Entry, Node8, STORED, WIDTH};
use crate::math::Aabb;
use crate::scene::Shapes;
use rayon::prelude::*;

/// A collapsed tree: its nodes (the root first), and the shape indices and leaf
/// copies its leaves point into.
#[derive(Default)]
pub(super) struct Collapsed {
    pub(super) nodes: Vec<Node8>,
    pub(super) prims: Vec<u32>,
    pub(super) stored: Vec<Leaf4>,
}

impl Collapsed {
    /// Collapses `tree` (whose leaves list `order`'s shapes) into these, its root at
    /// the next node.
    pub(super) fn collapse(&mut self, shapes: &Shapes, tree: &Tree, order: &[u32]) {
        let slot = self.nodes.len();
        self.nodes.push(EMPTY_NODE);
        let plan = Plan::of(tree);
        self.collapse_into(shapes, (tree, 0), order, slot, &plan);
    }

    /// Stores the shapes `leaf` as a leaf: their indices when all are triangles, else
    /// [`Leaf4`]s with precomputed edges.
    pub(super) fn leaf(&mut self, shapes: &Shapes, leaf: &[u32]) -> Entry {
        if leaf.iter().all(|&i| shapes.is_triangle(i as usize)) {
            let child = self.prims.len() as u32;
            self.prims.extend_from_slice(leaf);
            Entry {
                child,
                count: leaf.len() as u32,
                t: 0.0,
            }
        } else {
            let child = self.stored.len() as u32;
            self.stored
                .extend(leaf.chunks(4).map(|four| Leaf4::mixed(shapes, four)));
            Entry {
                child,
                count: STORED | leaf.len().div_ceil(4) as u32,
                t: 0.0,
            }
        }
    }

    /// Stores every leaf of triangle indices as [`Leaf4`] copies instead, after the
    /// others (for [`super::Leaves::Copied`]), and drops the indices. `root` is the
    /// tree's entry, itself a leaf in a scene of a few shapes. The collapse walks the
    /// tree on one thread; the copies, most of the bytes, are made on all of them.
    pub(super) fn copy_triangle_leaves(&mut self, shapes: &Shapes, root: &mut Entry) {
        // Each block of up to four: its leaf's first index and how many it takes.
        let mut blocks: Vec<(u32, u32)> = Vec::new();
        let mut next_block = self.stored.len() as u32;
        // An indexed leaf's entry becomes that of its blocks; any other stays.
        let mut copy = |e: Entry| {
            if e.count == 0 || e.count & STORED != 0 {
                return e;
            }
            for start in (0..e.count).step_by(4) {
                blocks.push((e.child + start, (e.count - start).min(4)));
            }
            let copied = Entry {
                child: next_block,
                count: STORED | e.count.div_ceil(4),
                t: 0.0,
            };
            next_block += e.count.div_ceil(4);
            copied
        };
        *root = copy(*root);
        for node in &mut self.nodes {
            for lane in 0..WIDTH {
                node.set_entry(lane, copy(node.entry(lane, 0.0)));
            }
        }
        let prims = std::mem::take(&mut self.prims);
        self.stored.par_extend(
            blocks.par_iter().map(|&(first, n)| {
                Leaf4::mixed(shapes, &prims[first as usize..(first + n) as usize])
            }),
        );
    }

    /// Fills `nodes[slot]` with the members `plan` gives binary node `tree` (with its
    /// index in the plan), and appends what they hold.
    fn collapse_into(
        &mut self,
        shapes: &Shapes,
        tree: Indexed,
        order: &[u32],
        slot: usize,
        plan: &Plan,
    ) {
        let (members, len) = plan.members(tree);
        let members = &members[..len];
        let mut node = EMPTY_NODE;
        let mut inner = [(tree, 0usize); WIDTH];
        let mut inner_len = 0;
        for (lane, &m) in members.iter().enumerate() {
            node.set_box(lane, m.0.bounds());
            if let Tree::Inner { .. } = m.0 {
                node.child[lane] = self.nodes.len() as u32;
                self.nodes.push(EMPTY_NODE);
                inner[inner_len] = (m, node.child[lane] as usize);
                inner_len += 1;
            } else {
                let e = self.leaf_of(shapes, m.0, order);
                node.child[lane] = e.child;
                node.count[lane] = e.count;
            }
        }
        self.nodes[slot] = node;
        for &(m, child_slot) in &inner[..inner_len] {
            self.collapse_into(shapes, m, order, child_slot, plan);
        }
    }

    /// The leaf of binary leaf `m`.
    fn leaf_of(&mut self, shapes: &Shapes, m: &Tree, order: &[u32]) -> Entry {
        let Tree::Leaf { start, count, .. } = *m else {
            unreachable!("an inner node is not a leaf")
        };
        let (first, count) = (start as usize, count as usize);
        self.leaf(shapes, &order[first..first + count])
    }
}

/// A binary node and its index in depth-first order (the root 0, a node's left child
/// right after it, its right child after the left's subtree).
type Indexed<'t> = (&'t Tree, usize);

/// The children of inner node `(tree, index)`, indexed.
fn children(tree: Indexed) -> Option<[Indexed; 2]> {
    let (Tree::Inner { children, .. }, i) = tree else {
        return None;
    };
    Some([
        (&children[0], i + 1),
        (&children[1], i + 1 + children[0].nodes()),
    ])
}

/// The cheapest cut of every binary subtree, by depth-first index: for `k` slots
/// (entry `k - 1`), how its inner node spreads over them: 0 when it takes one slot,
/// itself a wide node, or `j` when its left child takes `j` of them and its right
/// child the rest. Leaves always take one slot.
struct Plan {
    split: Vec<[u8; WIDTH]>,
}

impl Plan {
    fn of(tree: &Tree) -> Plan {
        let mut plan = Plan {
            split: vec![[0; WIDTH]; tree.nodes()],
        };
        plan.cost((tree, 0));
        plan
    }

    /// The least cost of `tree`'s subtree as at most `k` members of a wide node, for
    /// each `k` (entry `k - 1`), the choices made recorded.
    fn cost(&mut self, tree: Indexed) -> [f32; WIDTH] {
        let Some([left, right]) = children(tree) else {
            let Tree::Leaf { bounds, count, .. } = tree.0 else {
                unreachable!("a node without children is a leaf")
            };
            return [leaf_cost(bounds, *count); WIDTH];
        };
        let (l, r) = (self.cost(left), self.cost(right));
        // Spread over k slots: the left child takes j of them, the right k - j. The
        // first split stands unless one is cheaper, so a NaN area (a degenerate box)
        // still gives each child a slot.
        let spread = |k: usize| {
            (2..k).map(|j| (l[j - 1] + r[k - j - 1], j as u8)).fold(
                (l[0] + r[k - 2], 1),
                |best, c| if c.0 < best.0 { c } else { best },
            )
        };
        // As a wide node of its own, its children spread over all eight of its slots.
        let (wide, j) = spread(WIDTH);
        let mut split = [0; WIDTH];
        split[0] = j;
        let mut cost = [half_area(tree.0.bounds()) + wide; WIDTH];
        for k in 2..=WIDTH {
            let (c, j) = spread(k);
            if c < cost[k - 1] {
                (cost[k - 1], split[k - 1]) = (c, j);
            }
        }
        self.split[tree.1] = split;
        cost
    }

    /// The members of the wide node made of inner node `tree`: its children's cuts
    /// over eight slots, in order.
    fn members<'t>(&self, tree: Indexed<'t>) -> ([Indexed<'t>; WIDTH], usize) {
        let mut out = [tree; WIDTH];
        let mut len = 0;
        match children(tree) {
            Some([left, right]) => {
                // A node that takes one slot keeps in entry 0 how it spreads as a
                // wide node (one slot never splits).
                let j = self.split[tree.1][0] as usize;
                self.cut(left, j, &mut out, &mut len);
                self.cut(right, WIDTH - j, &mut out, &mut len);
            }
            None => len = 1,
        }
        (out, len)
    }

    /// Appends the members of `tree`'s cheapest cut into `k` slots.
    fn cut<'t>(
        &self,
        tree: Indexed<'t>,
        k: usize,
        out: &mut [Indexed<'t>; WIDTH],
        len: &mut usize,
    ) {
        if let Some([left, right]) = children(tree) {
            let j = self.split[tree.1][k - 1] as usize;
            if k > 1 && j > 0 {
                self.cut(left, j, out, len);
                self.cut(right, k - j, out, len);
                return;
            }
        }
        out[*len] = tree;
        *len += 1;
    }
}

/// A leaf's cost as a member: its area times the blocks of four its test takes, as
/// the build prices it.
fn leaf_cost(bounds: &Aabb, count: u32) -> f32 {
    half_area(bounds) * packets(count as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// Scattered boxes of several sizes, as a mesh's triangles are.
    fn boxes(n: usize, seed: u32) -> Vec<Aabb> {
        (0..n as u32)
            .map(|i| {
                let h =
                    |k: u32| ((i ^ seed).wrapping_mul(2_654_435_761).rotate_left(k) % 1000) as f32;
                let p = Vec3::new(h(0), h(11), h(22));
                Aabb {
                    min: p,
                    max: p + Vec3::splat(1.0 + h(7) % 40.0),
                }
            })
            .collect()
    }

    /// A member's cost: a leaf's area times its blocks, or an inner node's area and
    /// the cheapest wide node of it.
    fn member_cost(m: &Tree) -> f64 {
        match m {
            Tree::Leaf { bounds, count, .. } => leaf_cost(bounds, *count) as f64,
            Tree::Inner {
                bounds, children, ..
            } => {
                let mut best = f64::INFINITY;
                for a in cuts(&children[0]) {
                    for b in cuts(&children[1]) {
                        if a.len() + b.len() <= WIDTH {
                            let c: f64 = a.iter().chain(&b).map(|m| member_cost(m)).sum();
                            best = best.min(c);
                        }
                    }
                }
                half_area(bounds) as f64 + best
            }
        }
    }

    /// The shapes of `t`'s leaves.
    fn shapes_below(t: &Tree) -> usize {
        match t {
            Tree::Leaf { count, .. } => *count as usize,
            Tree::Inner { children, .. } => shapes_below(&children[0]) + shapes_below(&children[1]),
        }
    }

    /// Every cut of `t`'s subtree into at most eight members.
    fn cuts(t: &Tree) -> Vec<Vec<&Tree>> {
        let mut all = vec![vec![t]];
        if let Tree::Inner { children, .. } = t {
            for a in cuts(&children[0]) {
                for b in cuts(&children[1]) {
                    if a.len() + b.len() <= WIDTH {
                        all.push(a.iter().chain(&b).copied().collect());
                    }
                }
            }
        }
        all
    }

    #[test]
    fn each_wide_node_is_the_cheapest_cut_of_its_binary_subtree() {
        for (n, seed) in [(12, 1), (20, 2), (27, 3), (33, 4)] {
            let binary = super::super::build::build(&boxes(n, seed));
            let plan = Plan::of(&binary.tree);
            // Every wide node the collapse makes, from the root down.
            let mut pending = vec![(&binary.tree, 0)];
            let mut wide = 0;
            while let Some(node) = pending.pop() {
                let (members, len) = plan.members(node);
                let chosen: f64 = members[..len].iter().map(|m| member_cost(m.0)).sum();
                let best = member_cost(node.0) - half_area(node.0.bounds()) as f64;
                assert!(
                    (chosen - best).abs() <= 1e-4 * best,
                    "{n} boxes: a wide node costs {chosen}, its cheapest cut {best}"
                );
                // The members hold the subtree's shapes, and at most eight.
                let held: usize = members[..len].iter().map(|m| shapes_below(m.0)).sum();
                assert_eq!(held, shapes_below(node.0));
                assert!((2..=WIDTH).contains(&len));
                pending.extend(
                    members[..len]
                        .iter()
                        .filter(|m| matches!(m.0, Tree::Inner { .. })),
                );
                wide += 1;
            }
            assert!(wide >= 1);
        }
    }
}
