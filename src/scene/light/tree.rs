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

use super::{Falloff, Light, LightKind};
use crate::math::{Aabb, Vec3, cross, normalize};
use crate::scene::{Scene, Shape, Surface};
use std::f32::consts::{FRAC_PI_2, PI};

/// Buckets along an axis where a node's split is chosen (pbrt's count).
const BUCKETS: usize = 12;
/// Below this depth nodes split where the cost is least; from it on, in halves by count,
/// so that no light's way down (at most 30 + 32 turns for 2^32 lights) is longer than a
/// [`Trail`] holds however the lights lie, and its top two bits stay clear.
const SAH_DEPTH: u32 = 30;
/// Importance is kept below this, so that two children's sum stays finite.
const MAX_IMPORTANCE: f32 = f32::MAX / 4.0;
/// Lights beside the tree (the environment among them) up to this many are each sampled
/// at every vertex rather than drawn.
const EACH_APART_UP_TO: usize = 4;
/// The angle beyond a spot light's outer cone where its bounds stop: a margin far above
/// the rounding of the angles the importance compares, so no lit point reads zero.
const SPOT_MARGIN: f32 = 0.02;

/// A light's way down from the root: bit `d` set where it lies below the second child at
/// depth `d`.
type Trail = u64;
/// The trail of a light neither the tree holds nor is drawn beside it.
const NOT_IN_TREE: Trail = Trail::MAX;
/// The trail of a light drawn beside the tree.
const APART: Trail = Trail::MAX - 1;

/// A cone of directions: its axis and the cosine of its half-angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    /// Unit axis.
    pub w: Vec3,
    /// Cosine of the half-angle: 1 for the axis alone, -1 for every direction.
    pub cos_theta: f32,
}

impl DirectionCone {
    /// Every direction.
    pub const SPHERE: DirectionCone = DirectionCone {
        w: Vec3::Z,
        cos_theta: -1.0,
    };

    /// The axis alone.
    pub fn of(w: Vec3) -> DirectionCone {
        DirectionCone { w, cos_theta: 1.0 }
    }

    /// Whether `dir` (unit) lies inside the cone.
    pub fn holds(&self, dir: Vec3) -> bool {
        self.w.dot(dir) >= self.cos_theta
    }

    /// The narrowest cone (up to rounding, which widens it) holding both.
    pub fn union(self, b: DirectionCone) -> DirectionCone {
        let a = self;
        let theta_a = safe_acos(a.cos_theta);
        let theta_b = safe_acos(b.cos_theta);
        let theta_d = angle_between(a.w, b.w);
        if (theta_d + theta_b).min(PI) <= theta_a {
            return a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return b;
        }
        let theta_o = (theta_a + theta_d + theta_b) / 2.0;
        if theta_o >= PI {
            return DirectionCone::SPHERE;
        }
        let theta_r = theta_o - theta_a;
        let axis = cross(a.w, b.w);
        if axis.length_squared() == 0.0 {
            return DirectionCone::SPHERE;
        }
        // `a.w` turned by `theta_r` toward `b.w`, about their common normal (to which
        // `a.w` is square, so Rodrigues' formula loses its third term).
        let k = normalize(axis);
        let (sin_r, cos_r) = theta_r.sin_cos();
        let w = a.w * cos_r + cross(k, a.w) * sin_r;
        // Rounding in the rotation and the cosine could leave an edge direction a hair
        // outside: widen by a few parts in a million of a radian.
        DirectionCone {
            w: normalize(w),
            cos_theta: (theta_o + 1e-5).min(PI).cos(),
        }
    }
}

/// Bounds of some lights: where they are, the directions they emit in, and their power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Where the lights lie.
    pub bounds: Aabb,
    /// Their power (watts, the brightest channel): what a node is chosen in proportion
    /// to, at equal distance and angle.
    pub phi: f32,
    /// The axis of their normals (or emitting directions).
    pub w: Vec3,
    /// Cosine of the half-angle of the cone of normals about `w`.
    pub cos_theta_o: f32,
    /// Cosine of how far beyond a normal their light spreads (a flat emitter: 90°).
    pub cos_theta_e: f32,
    /// Whether they emit on both sides of their normals.
    pub two_sided: bool,
}

impl LightBounds {
    /// Bounds of lights at `bounds` whose normals lie in `cone`, emitting `phi` to at
    /// most `theta_e` beyond them.
    fn new(bounds: Aabb, phi: f32, cone: DirectionCone, cos_theta_e: f32) -> LightBounds {
        LightBounds {
            bounds,
            phi: phi.min(MAX_IMPORTANCE),
            w: cone.w,
            cos_theta_o: cone.cos_theta,
            cos_theta_e,
            two_sided: false,
        }
    }

    /// The bounds of `light`, or `None` where it is drawn beside the tree (directional,
    /// no inverse-square falloff) or emits nothing. `surfaces` give a mesh light's
    /// emission.
    pub fn of(light: &Light, scene: &Scene, surfaces: &[Surface]) -> Option<LightBounds> {
        let radiance = (light.color * light.intensity).max_element().max(0.0);
        let at = Aabb::EMPTY.grow(light.position);
        let bounds = match &light.kind {
            LightKind::Directional { .. } => return None,
            LightKind::Point | LightKind::Spot { .. }
                if light.falloff != Falloff::InverseSquare =>
            {
                return None;
            }
            LightKind::Point => {
                LightBounds::new(at, 4.0 * PI * radiance, DirectionCone::SPHERE, 0.0)
            }
            LightKind::Spot {
                direction,
                cos_inner,
                cos_outer,
                ..
            } => {
                // The wider cone, whichever is called outer: the edge's fade may light
                // either way between them.
                let widest = cos_inner.min(*cos_outer).clamp(-1.0, 1.0);
                let axis = direction.normalize_or_zero();
                let cone = if axis == Vec3::ZERO {
                    DirectionCone::SPHERE
                } else {
                    DirectionCone {
                        w: axis,
                        cos_theta: widest,
                    }
                };
                LightBounds::new(at, 4.0 * PI * radiance, cone, SPOT_MARGIN.cos())
            }
            LightKind::Quad { u, v } => {
                let p = light.position;
                let corners = [
                    p - 0.5 * (*u + *v),
                    p + 0.5 * (*u - *v),
                    p + 0.5 * (*u + *v),
                ];
                let bounds = Aabb::from_points(&corners).grow(p - 0.5 * (*u - *v));
                let normal = cross(*u, *v).normalize_or_zero();
                flat(bounds, PI * radiance * light.flat_area(), normal)?
            }
            LightKind::Disk { normal, radius } => {
                let r = Vec3::splat(radius.abs());
                let bounds = Aabb {
                    min: light.position - r,
                    max: light.position + r,
                };
                let area = light.flat_area();
                flat(bounds, PI * radiance * area, normal.normalize_or(Vec3::Y))?
            }
            LightKind::Sphere { radius } => {
                let r = Vec3::splat(radius.abs());
                let bounds = Aabb {
                    min: light.position - r,
                    max: light.position + r,
                };
                let area = 4.0 * PI * radius * radius;
                LightBounds::new(bounds, PI * radiance * area, DirectionCone::SPHERE, 0.0)
            }
            LightKind::Mesh { shapes, .. } => {
                let mut bounds = Aabb::EMPTY;
                let mut cone: Option<DirectionCone> = None;
                let mut phi = 0.0f32;
                for &shape in shapes {
                    let Shape::Triangle(tri) = scene.shape_at(shape) else {
                        continue;
                    };
                    let le =
                        surfaces[scene.material_index(shape) as usize].emission * light.intensity;
                    let area = 0.5 * cross(tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]).length();
                    bounds = bounds.union(tri.bounds());
                    phi += PI * area * le.max_element().max(0.0);
                    let normal = DirectionCone::of(tri.normal());
                    cone = Some(cone.map_or(normal, |c| c.union(normal)));
                }
                let cone = cone?;
                LightBounds::new(bounds, phi, cone, 0.0)
            }
        };
        (bounds.phi > 0.0 && !bounds.bounds.is_empty()).then_some(bounds)
    }

    /// Both bounds together.
    pub fn union(self, b: LightBounds) -> LightBounds {
        let a = self;
        if a.phi == 0.0 {
            return b;
        }
        if b.phi == 0.0 {
            return a;
        }
        let cone = DirectionCone {
            w: a.w,
            cos_theta: a.cos_theta_o,
        }
        .union(DirectionCone {
            w: b.w,
            cos_theta: b.cos_theta_o,
        });
        LightBounds {
            bounds: a.bounds.union(b.bounds),
            phi: (a.phi + b.phi).min(MAX_IMPORTANCE),
            w: cone.w,
            cos_theta_o: cone.cos_theta,
            cos_theta_e: a.cos_theta_e.min(b.cos_theta_e),
            two_sided: a.two_sided || b.two_sided,
        }
    }

    /// How much light the bounded lights may send to point `p` of a surface with normal
    /// `n` (either side; zero: `n` unknown), up to a common factor: zero only where none
    /// can reach it.
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let pc = self.bounds.center();
        let d2 = p
            .distance_squared(pc)
            .max(self.bounds.extent().length() / 2.0);
        // The cone of directions from `p` that the box subtends (its bounding sphere's).
        let radius = if self.bounds.extent() == Vec3::ZERO {
            0.0
        } else {
            pc.distance(self.bounds.max)
        };
        let center_d2 = p.distance_squared(pc);
        let cos_theta_b = if center_d2 < radius * radius {
            -1.0
        } else {
            safe_sqrt(1.0 - radius * radius / center_d2)
        };
        let sin_theta_b = safe_sqrt(1.0 - cos_theta_b * cos_theta_b);
        // The angle at the lights between their cone's axis and the way to `p`, less the
        // cone's half-angle and the box's: how far outside every light's cone `p` lies.
        let wi = (p - pc).normalize_or_zero();
        let mut cos_theta_w = self.w.dot(wi);
        if self.two_sided {
            cos_theta_w = cos_theta_w.abs();
        }
        let sin_theta_w = safe_sqrt(1.0 - cos_theta_w * cos_theta_w);
        let sin_theta_o = safe_sqrt(1.0 - self.cos_theta_o * self.cos_theta_o);
        let cos_theta_x = cos_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, self.cos_theta_o);
        let sin_theta_x = sin_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, self.cos_theta_o);
        let cos_theta_p = cos_sub_clamped(sin_theta_x, cos_theta_x, sin_theta_b, cos_theta_b);
        if cos_theta_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_theta_p / d2;
        if n != Vec3::ZERO {
            let cos_theta_i = wi.dot(n).abs();
            let sin_theta_i = safe_sqrt(1.0 - cos_theta_i * cos_theta_i);
            importance *= cos_sub_clamped(sin_theta_i, cos_theta_i, sin_theta_b, cos_theta_b);
        }
        if importance > 0.0 {
            importance.min(MAX_IMPORTANCE)
        } else {
            0.0
        }
    }

    /// The box's centre: where the build sorts the lights by.
    fn centroid(&self) -> Vec3 {
        self.bounds.center()
    }
}

/// The bounds of a one-sided flat emitter facing `normal`; `None` for a degenerate one.
fn flat(bounds: Aabb, phi: f32, normal: Vec3) -> Option<LightBounds> {
    (normal != Vec3::ZERO).then(|| LightBounds::new(bounds, phi, DirectionCone::of(normal), 0.0))
}

/// `cos(a - b)` from the sines and cosines of `a` and `b`, or 1 where `a < b`.
#[inline]
fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 1.0;
    }
    cos_a * cos_b + sin_a * sin_b
}

/// `sin(a - b)` from the sines and cosines of `a` and `b`, or 0 where `a < b`.
#[inline]
fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 0.0;
    }
    sin_a * cos_b - cos_a * sin_b
}

#[inline]
fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

#[inline]
fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// The angle between unit vectors, accurate near 0 and π too.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * safe_asin((a + b).length() / 2.0)
    } else {
        2.0 * safe_asin((b - a).length() / 2.0)
    }
}

#[inline]
fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

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
        let mut u = ((u - p_apart) / (1.0 - p_apart)).min(ONE_MINUS_EPSILON);
        let mut pmf = 1.0 - p_apart;
        let mut at = 0usize;
        loop {
            let (ci, sum, second) = match self.step(at, p, n)? {
                Step::Leaf(light) => return Some((Picked::Light(light), pmf)),
                Step::Inner { ci, sum, second } => (ci, sum, second),
            };
            let p0 = ci[0] / sum;
            if u < p0 {
                pmf *= ci[0] / sum;
                u = (u / p0).min(ONE_MINUS_EPSILON);
                at += 1;
            } else {
                pmf *= ci[1] / sum;
                u = ((u - p0) / (1.0 - p0)).min(ONE_MINUS_EPSILON);
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

/// The largest float below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

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
            let cost = cost(&below, kr) + cost(&above, kr);
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

/// The split cost of one side (pbrt's): its power times the solid angle its directions
/// may cover times its box's surface area, stretched by `kr` for thin splits.
fn cost(b: &LightBounds, kr: f32) -> f32 {
    let theta_o = safe_acos(b.cos_theta_o);
    let theta_e = safe_acos(b.cos_theta_e);
    let theta_w = (theta_o + theta_e).min(PI);
    let sin_theta_o = safe_sqrt(1.0 - b.cos_theta_o * b.cos_theta_o);
    let m_omega = 2.0 * PI * (1.0 - b.cos_theta_o)
        + FRAC_PI_2
            * (2.0 * theta_w * sin_theta_o
                - (theta_o - 2.0 * theta_w).cos()
                - 2.0 * theta_o * sin_theta_o
                + b.cos_theta_o);
    let e = b.bounds.extent();
    let area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
    b.phi * m_omega * kr * area
}

#[cfg(test)]
mod tests;
