//! The top of a two-level hierarchy: a binary BVH over the world boxes of a scene's
//! instances, each leading to the one BVH of the object it places. A mesh placed a
//! thousand times is one tree and a thousand transforms.

use super::Hit;
use super::bvh::{Bvh, Leaves, PlacedRay, build};
use crate::math::{Aabb, Ray, Vec3};
use crate::scene::{Instance, Object, ShapeId};
use glam::{Affine3A, Mat3A};
use rayon::prelude::*;

/// The relative slack of the top level's box test, as the BVH's.
const BOX_SLACK: f32 = 1.0 + 4.0 * f32::EPSILON;

/// A box in six floats ([`Aabb`] pads its corners to sixteen bytes each): each
/// instance and each node of the top tree holds one.
#[derive(Clone, Copy, Debug)]
struct PackedBox {
    min: glam::Vec3,
    max: glam::Vec3,
}

impl PackedBox {
    fn pack(b: &Aabb) -> PackedBox {
        PackedBox {
            min: b.min.into(),
            max: b.max.into(),
        }
    }

    #[inline(always)]
    fn get(&self) -> Aabb {
        Aabb {
            min: self.min.into(),
            max: self.max.into(),
        }
    }
}

/// A node of the top tree: a leaf lists `order[first..first + count]`; an inner node
/// (`count` 0) has its left child next to it and its right child at `first`.
#[derive(Clone, Copy, Debug)]
struct TopNode {
    bounds: PackedBox,
    first: u32,
    count: u32,
}

/// What the rounding bound of one instance needs, worked out as a ray meets it (from
/// its transform, the transform's inverse and its box: held, it would be twelve bytes
/// an instance).
#[derive(Clone, Copy, Debug)]
struct Rounding {
    /// The largest row sum of |A⁻¹|: how much a world error grows in object space.
    inverse_norm: f32,
    /// Relative error of a point taken into object space, in units of epsilon.
    relative: f32,
    /// Object-space distance covering the rounding of placed corners and of the world
    /// leaf test.
    corners: f32,
}

/// Every instance of a scene, over the objects' own trees.
pub struct Instances<'s> {
    instances: &'s [Instance],
    objects: Vec<Bvh<'s>>,
    /// Each instance's world box, grown by the rounding of its placed corners.
    boxes: Vec<PackedBox>,
    nodes: Vec<TopNode>,
    order: Vec<u32>,
}

impl<'s> Instances<'s> {
    /// Builds a tree per object and the top tree over `instances`.
    pub fn build(objects: &'s [Object], instances: &'s [Instance]) -> Instances<'s> {
        let trees: Vec<Bvh<'s>> = objects
            .iter()
            .map(|o| Bvh::build_object(&o.shapes, Leaves::Indexed))
            .collect();
        let object_bounds: Vec<Aabb> = objects.par_iter().map(Object::bounds).collect();
        let boxes: Vec<PackedBox> = instances
            .par_iter()
            .map(|i| {
                let world = i.world_bounds(&object_bounds[i.object() as usize]);
                PackedBox::pack(&pad_world(world))
            })
            .collect();
        let mut top = Instances {
            instances,
            objects: trees,
            boxes,
            nodes: Vec::new(),
            order: Vec::new(),
        };
        let live: Vec<u32> = (0..instances.len() as u32)
            .filter(|&i| !top.boxes[i as usize].get().is_empty())
            .collect();
        if !live.is_empty() {
            let live_boxes: Vec<Aabb> = live.iter().map(|&i| top.boxes[i as usize].get()).collect();
            let binary = build::build(&live_boxes);
            top.order = binary.order.iter().map(|&k| live[k as usize]).collect();
            top.nodes.reserve_exact(binary.tree.nodes());
            top.flatten(&binary.tree);
        }
        top
    }

    fn flatten(&mut self, tree: &build::Tree) {
        match tree {
            build::Tree::Leaf {
                bounds,
                start,
                count,
            } => self.nodes.push(TopNode {
                bounds: PackedBox::pack(bounds),
                first: *start,
                count: *count,
            }),
            build::Tree::Inner {
                bounds, children, ..
            } => {
                let at = self.nodes.len();
                self.nodes.push(TopNode {
                    bounds: PackedBox::pack(bounds),
                    first: 0,
                    count: 0,
                });
                self.flatten(&children[0]);
                self.nodes[at].first = self.nodes.len() as u32;
                self.flatten(&children[1]);
            }
        }
    }

    /// Bytes held beyond the instances and objects themselves.
    pub fn memory_bytes(&self) -> usize {
        self.objects.iter().map(Bvh::memory_bytes).sum::<usize>()
            + self.boxes.capacity() * size_of::<PackedBox>()
            + self.nodes.capacity() * size_of::<TopNode>()
            + self.order.capacity() * size_of::<u32>()
    }

    /// The ray as instance `index` meets it, its boxes grown to cover every rounding
    /// up to distance `t_far`.
    #[inline]
    fn placed<'a>(&'a self, ray: &'a Ray, index: u32, t_far: f32) -> PlacedRay<'a> {
        let instance = &self.instances[index as usize];
        let to_world = instance.to_world();
        let from_world = to_world.inverse();
        let r = rounding_of(&to_world, &from_world, &self.boxes[index as usize].get());
        let local = Ray {
            origin: from_world.transform_point3a(ray.origin),
            dir: from_world.transform_vector3a(ray.dir),
        };
        // The object-space ray's point at t is off by at most this much: the
        // transform's rounding of the origin and direction, grown by the distance.
        let e = r.relative * f32::EPSILON;
        let origin_error = e
            * (r.inverse_norm * ray.origin.abs().max_element()
                + from_world.translation.abs().max_element());
        let dir_error = e * r.inverse_norm * ray.dir.abs().max_element();
        let pad = 2.0 * (r.corners + origin_error + t_far * dir_error);
        PlacedRay {
            world: ray,
            local,
            pad: if pad.is_finite() { pad } else { f32::MAX },
            to_world,
            instance,
            index,
        }
    }

    /// Updates `best` with the nearest hit before `t_max` on any instance.
    pub fn closest(&self, ray: &Ray, t_max: f32, best: &mut Option<Hit>) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = Vec3::from_array(ray.dir.to_array().map(inverse));
        let mut stack = [(0u32, 0.0f32); STACK];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let (at, t_near) = stack[len];
            let bound = Hit::bound(best, t_max);
            if t_near > bound * BOX_SLACK {
                continue;
            }
            let node = &self.nodes[at as usize];
            if node.count > 0 {
                for &i in &self.order[node.first as usize..][..node.count as usize] {
                    let bound = Hit::bound(best, t_max);
                    let Some((_, t_far)) = slab(&self.boxes[i as usize].get(), ray, inv, bound)
                    else {
                        continue;
                    };
                    let placed = self.placed(ray, i, t_far);
                    let object = self.instances[i as usize].object() as usize;
                    self.objects[object].closest_placed(&placed, t_max, best);
                }
                continue;
            }
            let children = [at + 1, node.first];
            let hits =
                children.map(|c| slab(&self.nodes[c as usize].bounds.get(), ray, inv, bound));
            // The farther child is pushed first, so the nearer is met first.
            let far_first = match hits {
                [Some(a), Some(b)] if b.0 < a.0 => [0, 1],
                _ => [1, 0],
            };
            for k in far_first {
                if let Some((t0, _)) = hits[k] {
                    stack[len] = (children[k], t0);
                    len += 1;
                }
            }
        }
    }

    /// Whether a shape for which `blocks` holds, of any instance, meets the ray before
    /// `t_max`.
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: &impl Fn(ShapeId) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let inv = Vec3::from_array(ray.dir.to_array().map(inverse));
        let mut stack = [0u32; STACK];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let at = stack[len];
            let node = &self.nodes[at as usize];
            if slab(&node.bounds.get(), ray, inv, t_max).is_none() {
                continue;
            }
            if node.count == 0 {
                stack[len] = at + 1;
                stack[len + 1] = node.first;
                len += 2;
                continue;
            }
            for &i in &self.order[node.first as usize..][..node.count as usize] {
                let Some((_, t_far)) = slab(&self.boxes[i as usize].get(), ray, inv, t_max) else {
                    continue;
                };
                let placed = self.placed(ray, i, t_far);
                let object = self.instances[i as usize].object() as usize;
                if self.objects[object].occluded_placed(&placed, t_max, blocks) {
                    return true;
                }
            }
        }
        false
    }
}

/// Entries the top traversal's stack needs: one a level and one more, at the build's
/// deepest level.
const STACK: usize = build::MAX_DEPTH as usize + 2;

/// The reciprocal of a direction component, finite (as the BVH's).
#[inline]
fn inverse(x: f32) -> f32 {
    let i = 1.0 / x;
    if i.is_finite() {
        i
    } else {
        1e30f32.copysign(x)
    }
}

/// Where the ray enters and leaves box `b` within `(0, t_max)`, with the BVH's slack.
#[inline]
fn slab(b: &Aabb, ray: &Ray, inv: Vec3, t_max: f32) -> Option<(f32, f32)> {
    let t_a = (b.min - ray.origin) * inv;
    let t_b = (b.max - ray.origin) * inv;
    let t0 = t_a.min(t_b).max_element().max(0.0);
    let t1 = t_a.max(t_b).min_element().min(t_max);
    (t0 <= t1 * BOX_SLACK).then_some((t0, t1 * BOX_SLACK))
}

/// A world box grown by a few units in the last place of its coordinates, so the
/// rounding of placed corners never leaves it.
fn pad_world(b: Aabb) -> Aabb {
    if b.is_empty() {
        return b;
    }
    let magnitude = b.min.abs().max(b.max.abs()).max_element();
    let pad = Vec3::splat(16.0 * f32::EPSILON * magnitude);
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}

/// The rounding bound of the instance placed by `to_world` (whose inverse is
/// `from_world`), its padded world box `world`.
#[inline]
fn rounding_of(to_world: &Affine3A, from_world: &Affine3A, world: &Aabb) -> Rounding {
    let inverse_norm = row_sum_norm(&from_world.matrix3);
    let condition = row_sum_norm(&to_world.matrix3) * inverse_norm;
    let magnitude = world.min.abs().max(world.max.abs()).max_element();
    Rounding {
        inverse_norm,
        // Three products summed and a translation added, each rounded, through an
        // inverse itself off by about the condition number.
        relative: 8.0 + 4.0 * condition,
        // A placed corner is off by a few ulps of the world's magnitude, and the world
        // leaf test accepts as much again (the BVH pads its own boxes so).
        corners: 32.0 * f32::EPSILON * magnitude * inverse_norm,
    }
}

fn row_sum_norm(a: &Mat3A) -> f32 {
    let t = a.transpose();
    [t.x_axis, t.y_axis, t.z_axis]
        .iter()
        .map(|r| r.abs().element_sum())
        .fold(0.0, f32::max)
}

#[cfg(test)]
mod tests;
