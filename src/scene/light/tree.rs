//! A tree over the lights, to choose one light a shading point in time that grows with
//! the depth of the tree rather than the number of lights (pbrt-v4's BVH light sampler,
//! after Conty Estevez and Kulla's many-light sampling).
//!
//! Each node bounds its lights' positions, the directions they emit in (a cone of
//! normals widened by how far their light spreads beyond it) and their power. From a
//! point and its normal a node's importance is that power over the squared distance,
//! dimmed by how far the point lies outside the cone and how obliquely the node's box
//! can light the surface; it is zero only where no light below the node can reach the
//! point. A sample walks down from the root, picking each child in proportion to its
//! importance; the probability of the light it reaches is the product of those picks,
//! which [`LightTree::pmf`] retraces for any light from the turns that lead to it.
//!
//! Lights whose light does not fall with distance the way the bounds assume (directional
//! lights, point and spot lights without inverse-square falloff) and the environment
//! stand beside the tree. A few of them (a sun and a sky) are each sampled at every
//! vertex, beside the one light the tree draws: drawn instead, each would take as many
//! draws as the whole tree, and a scene of lamps under a sky would spend half its
//! samples on the sky. Many of them are drawn uniformly, each as likely as the whole
//! tree, as pbrt draws its infinite lights.

mod bounds;

pub use bounds::{DirectionCone, LightBounds};

use super::{Falloff, Light, LightKind};
use crate::math::{Aabb, ONE_BELOW, Vec3};
use crate::scene::{Scene, Surface};

/// Buckets along an axis where a node's split is chosen (pbrt's count).
const BUCKETS: usize = 12;
/// Below this depth nodes split where the cost is least; from it on, in halves by count,
/// so that no light's way down (at most 30 + 32 turns for 2^32 lights) is longer than a
/// [`Trail`] holds however the lights lie, and its top two bits stay clear.
const SAH_DEPTH: u32 = 30;
/// Lights beside the tree (the environment among them) up to this many are each sampled
/// at every vertex rather than drawn.
const EACH_APART_UP_TO: usize = 4;
/// A light's way down from the root: bit `d` set where it lies below the second child at
/// depth `d`.
type Trail = u64;
/// The trail of a light neither the tree holds nor is drawn beside it.
const NOT_IN_TREE: Trail = Trail::MAX;
/// The trail of a light drawn beside the tree.
const APART: Trail = Trail::MAX - 1;

/// A node: its lights' bounds, and either its second child (the first follows it) or
/// its light.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: LightBounds,
    /// Inner: the second child's index. Leaf: the light's index in the scene.
    child_or_light: u32,
    leaf: bool,
}

/// A node as a walk meets it ([`LightTree::step`]).
enum Step {
    Leaf(u32),
    Inner {
        ci: [f32; 2],
        sum: f32,
        second: usize,
    },
}

/// What a sample chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Picked {
    /// The scene's light of this index.
    Light(u32),
    /// The environment.
    Environment,
}

/// The lights of a scene in a tree, and those drawn beside it.
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    nodes: Vec<Node>,
    /// By light: its way down, [`APART`] or [`NOT_IN_TREE`].
    trails: Vec<Trail>,
    /// Lights drawn beside the tree, uniformly.
    apart: Vec<u32>,
    /// Whether the environment is drawn beside the tree too.
    environment: bool,
}

impl LightTree {
    /// The tree over `scene`'s lights (`surfaces` give mesh lights' emission); with
    /// `environment` the environment is drawn beside it.
    pub fn new(scene: &Scene, surfaces: &[Surface], environment: bool) -> LightTree {
        let mut apart = Vec::new();
        let mut bounded = Vec::new();
        let mut trails = vec![NOT_IN_TREE; scene.lights.len()];
        for (k, light) in scene.lights.iter().enumerate() {
            match LightBounds::of(light, scene, surfaces) {
                Some(b) => bounded.push((k as u32, b)),
                None if is_apart(light) => {
                    apart.push(k as u32);
                    trails[k] = APART;
                }
                None => {}
            }
        }
        let mut tree = LightTree {
            nodes: Vec::with_capacity(2 * bounded.len()),
            trails,
            apart,
            environment,
        };
        if !bounded.is_empty() {
            tree.build(&mut bounded, 0, 0);
        }
        tree
    }

    /// Lights and the environment drawn beside the tree.
    fn apart_count(&self) -> usize {
        self.apart.len() + usize::from(self.environment)
    }

    /// Whether the lights beside the tree (and the environment) are each sampled at
    /// every vertex, so that a draw picks among the tree's lights alone.
    pub fn samples_apart_each(&self) -> bool {
        (1..=EACH_APART_UP_TO).contains(&self.apart_count())
    }

    /// The lights beside the tree, in the scene's order.
    pub fn apart(&self) -> &[u32] {
        &self.apart
    }

    /// The odds of drawing beside the tree: each thing drawn there counts as much as
    /// the whole tree; none where those are each sampled.
    fn p_apart(&self) -> f32 {
        let apart = self.apart_count();
        let tree = usize::from(!self.nodes.is_empty());
        if apart == 0 || self.samples_apart_each() {
            0.0
        } else {
            apart as f32 / (apart + tree) as f32
        }
    }

    /// The odds of one light beside the tree (or the environment): 1 where each is
    /// sampled.
    fn pmf_apart(&self) -> f32 {
        if self.samples_apart_each() {
            1.0
        } else {
            self.p_apart() / self.apart_count() as f32
        }
    }

    /// Builds the node of `lights` at depth `depth` (its trail bits so far `trail`),
    /// returning its index.
    fn build(&mut self, lights: &mut [(u32, LightBounds)], depth: u32, trail: Trail) -> u32 {
        let at = self.nodes.len() as u32;
        if let [(k, b)] = lights {
            self.nodes.push(Node {
                bounds: *b,
                child_or_light: *k,
                leaf: true,
            });
            self.trails[*k as usize] = trail;
            return at;
        }
        let mid = if depth < SAH_DEPTH {
            split(lights)
        } else {
            halve(lights)
        };
        let bounds = lights
            .iter()
            .fold(None::<LightBounds>, |acc, (_, b)| {
                Some(acc.map_or(*b, |a| a.union(*b)))
            })
            .expect("a node holds a light");
        self.nodes.push(Node {
            bounds,
            child_or_light: 0,
            leaf: false,
        });
        let (first, second) = lights.split_at_mut(mid);
        self.build(first, depth + 1, trail);
        let second_at = self.build(second, depth + 1, trail | (1 << depth));
        self.nodes[at as usize].child_or_light = second_at;
        at
    }

    /// Draws a light for point `p` with normal `n` (zero: unknown) by `u` in [0, 1): what
    /// it picked and the probability it had; `None` where no light reaches `p`.
    pub fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(Picked, f32)> {
        let p_apart = self.p_apart();
        if u < p_apart {
            let count = self.apart_count();
            let i = ((u / p_apart * count as f32) as usize).min(count - 1);
            let picked = match self.apart.get(i) {
                Some(&k) => Picked::Light(k),
                None => Picked::Environment,
            };
            return Some((picked, p_apart / count as f32));
        }
        if self.nodes.is_empty() {
            return None;
        }
        let mut u = ((u - p_apart) / (1.0 - p_apart)).min(ONE_BELOW);
        let mut pmf = 1.0 - p_apart;
        let mut at = 0usize;
        loop {
            let (ci, sum, second) = match self.step(at, p, n)? {
                Step::Leaf(light) => return Some((Picked::Light(light), pmf)),
                Step::Inner { ci, sum, second } => (ci, sum, second),
            };
            let p0 = ci[0] / sum;
            if u < p0 {
                pmf *= p0;
                u = (u / p0).min(ONE_BELOW);
                at += 1;
            } else {
                pmf *= ci[1] / sum;
                u = ((u - p0) / (1.0 - p0)).min(ONE_BELOW);
                at = second;
            }
        }
    }

    /// The probability with which [`LightTree::sample`] from `p` with normal `n` draws
    /// the scene's light `light` (1 for a light beside the tree sampled at every vertex).
    pub fn pmf(&self, p: Vec3, n: Vec3, light: u32) -> f32 {
        let mut trail = match self.trails.get(light as usize) {
            None | Some(&NOT_IN_TREE) => return 0.0,
            Some(&APART) => return self.pmf_apart(),
            Some(&trail) => trail,
        };
        let mut pmf = 1.0 - self.p_apart();
        let mut at = 0usize;
        loop {
            let (ci, sum, second) = match self.step(at, p, n) {
                None => return 0.0,
                Some(Step::Leaf(_)) => return pmf,
                Some(Step::Inner { ci, sum, second }) => (ci, sum, second),
            };
            let bit = (trail & 1) as usize;
            pmf *= ci[bit] / sum;
            trail >>= 1;
            at = if bit == 0 { at + 1 } else { second };
        }
    }

    /// Node `at` as a walk from `p` (normal `n`) meets it: a leaf's light, or an inner
    /// node's children's importances, their sum and the second child's index; `None`
    /// where no light below it can reach `p` (the root's own bounds, at a lone leaf).
    #[inline]
    fn step(&self, at: usize, p: Vec3, n: Vec3) -> Option<Step> {
        let node = &self.nodes[at];
        if node.leaf {
            let reaches = at > 0 || node.bounds.importance(p, n) > 0.0;
            return reaches.then_some(Step::Leaf(node.child_or_light));
        }
        let second = node.child_or_light as usize;
        let ci = [
            self.nodes[at + 1].bounds.importance(p, n),
            self.nodes[second].bounds.importance(p, n),
        ];
        let sum = ci[0] + ci[1];
        (sum > 0.0).then_some(Step::Inner { ci, sum, second })
    }

    /// The probability with which [`LightTree::sample`] draws the environment (1 where
    /// it is sampled at every vertex).
    pub fn environment_pmf(&self) -> f32 {
        if self.environment {
            self.pmf_apart()
        } else {
            0.0
        }
    }
}

/// Whether `light` is drawn beside the tree rather than left out: it has light to give
/// but no bounds in space the importance could weigh.
fn is_apart(light: &Light) -> bool {
    let gives = (light.color * light.intensity).max_element() > 0.0;
    gives
        && match light.kind {
            LightKind::Directional { .. } => true,
            LightKind::Point | LightKind::Spot { .. } => light.falloff != Falloff::InverseSquare,
            _ => false,
        }
}

/// Orders `lights` (at least two) for a split where the cost of the two halves is
/// least (pbrt's surface-area and orientation heuristic over buckets of centroids),
/// and returns where the second half starts; [`halve`]s them where no split is better.
fn split(lights: &mut [(u32, LightBounds)]) -> usize {
    let (bounds, centroids) = lights
        .iter()
        .fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), (_, l)| {
            (b.union(l.bounds), c.grow(l.centroid()))
        });
    let diagonal = bounds.extent();
    let bucket = |l: &LightBounds, axis: usize| {
        let (lo, hi) = (centroids.min[axis], centroids.max[axis]);
        let b = (BUCKETS as f32 * ((l.centroid()[axis] - lo) / (hi - lo))) as usize;
        b.min(BUCKETS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if centroids.max[axis] == centroids.min[axis] || diagonal[axis] <= 0.0 {
            continue;
        }
        let mut buckets = [None::<LightBounds>; BUCKETS];
        for (_, l) in lights.iter() {
            let b = &mut buckets[bucket(l, axis)];
            *b = Some(b.map_or(*l, |a| a.union(*l)));
        }
        let kr = diagonal.max_element() / diagonal[axis];
        for i in 0..BUCKETS - 1 {
            let merged = |range: &[Option<LightBounds>]| {
                range.iter().flatten().fold(None::<LightBounds>, |acc, b| {
                    Some(acc.map_or(*b, |a| a.union(*b)))
                })
            };
            let (Some(below), Some(above)) = (merged(&buckets[..=i]), merged(&buckets[i + 1..]))
            else {
                continue;
            };
            let cost = below.cost(kr) + above.cost(kr);
            if cost > 0.0 && best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, i));
            }
        }
    }
    let Some((_, axis, i)) = best else {
        return halve(lights);
    };
    let mut mid = 0;
    for k in 0..lights.len() {
        if bucket(&lights[k].1, axis) <= i {
            lights.swap(k, mid);
            mid += 1;
        }
    }
    if mid == 0 || mid == lights.len() {
        halve(lights)
    } else {
        mid
    }
}

/// Orders `lights` (at least two) into halves by count, the first nearer the low end
/// of the axis along which their centres spread most, and returns where the second
/// starts.
fn halve(lights: &mut [(u32, LightBounds)]) -> usize {
    let centroids = lights
        .iter()
        .fold(Aabb::EMPTY, |c, (_, l)| c.grow(l.centroid()));
    let spread = centroids.extent();
    let axis = if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    };
    let half = lights.len() / 2;
    lights.select_nth_unstable_by(half, |(ka, a), (kb, b)| {
        a.centroid()[axis]
            .total_cmp(&b.centroid()[axis])
            .then(ka.cmp(kb))
    });
    half
}

#[cfg(test)]
mod tests;
