//! The binary tree collapsed into eight-wide nodes: each node takes its binary node's
//! children, then repeatedly the children of the largest inner one among them, until it
//! holds eight.

use super::build::Tree;
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
        self.collapse_into(shapes, tree, order, slot);
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

    /// Fills `nodes[slot]` with up to eight descendants of binary node `tree`, and
    /// appends what they hold.
    fn collapse_into(&mut self, shapes: &Shapes, tree: &Tree, order: &[u32], slot: usize) {
        let (members, len) = members(tree);
        let members = &members[..len];
        let mut node = EMPTY_NODE;
        let mut inner = [(tree, 0usize); WIDTH];
        let mut inner_len = 0;
        for (lane, &m) in members.iter().enumerate() {
            node.set_box(lane, m.bounds());
            if let Tree::Inner { .. } = m {
                node.child[lane] = self.nodes.len() as u32;
                self.nodes.push(EMPTY_NODE);
                inner[inner_len] = (m, node.child[lane] as usize);
                inner_len += 1;
            } else {
                let e = self.leaf_of(shapes, m, order);
                node.child[lane] = e.child;
                node.count[lane] = e.count;
            }
        }
        self.nodes[slot] = node;
        for &(m, child_slot) in &inner[..inner_len] {
            self.collapse_into(shapes, m, order, child_slot);
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

/// Up to eight descendants of `tree`: its children, then repeatedly the children of
/// the largest inner one among them (the last of equals), in order.
fn members(tree: &Tree) -> ([&Tree; WIDTH], usize) {
    let mut members = [tree; WIDTH];
    let mut len = 1;
    if let Tree::Inner { children, .. } = tree {
        members[..2].copy_from_slice(&[&children[0], &children[1]]);
        len = 2;
    }
    while len < WIDTH {
        let mut widest: Option<(usize, f32)> = None;
        for (i, m) in members[..len].iter().enumerate() {
            if let Tree::Inner { bounds, .. } = m {
                let a = area(bounds);
                if widest.is_none_or(|(_, w)| a.total_cmp(&w).is_ge()) {
                    widest = Some((i, a));
                }
            }
        }
        let Some((i, _)) = widest else { break };
        let Tree::Inner { children, .. } = members[i] else {
            unreachable!("only inner members are opened")
        };
        members.copy_within(i + 1..len, i + 2);
        members[i] = &children[0];
        members[i + 1] = &children[1];
        len += 1;
    }
    (members, len)
}

fn area(b: &Aabb) -> f32 {
    let e = b.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}
