//! Shapes as the BVH stores them: 40 bytes each, in leaf order, so a leaf's shapes sit
//! side by side in memory and a triangle's edges are not recomputed for every ray.

use crate::math::{Aabb, Ray, Vec3};
use crate::scene::shape::{EDGE_SLACK, intersect_parallelogram};
use crate::scene::{Shape, Sphere};

const KIND_SHIFT: u32 = 30;
const TRIANGLE: u32 = 0;
const RECTANGLE: u32 = 1;
const SPHERE: u32 = 2;
/// Shape indices must leave the two top bits free for the kind.
pub const MAX_SHAPES: usize = 1 << KIND_SHIFT;

/// A triangle or rectangle as `p` + edges `e1`, `e2`; a sphere as centre `p` and radius
/// `e1[0]`. The edges are exactly the ones [`Shape::intersect`] computes, so both give the
/// same distance bit for bit and every intersector renders the same image.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Prim {
    p: [f32; 3],
    /// Shape index in the low 30 bits, kind in the top two.
    tag: u32,
    e1: [f32; 3],
    e2: [f32; 3],
}

impl Prim {
    pub fn new(shape: &Shape, index: u32) -> Prim {
        debug_assert!((index as usize) < MAX_SHAPES);
        let (kind, p, e1, e2) = match *shape {
            Shape::Triangle(t) => {
                let [a, b, c] = t.v;
                (TRIANGLE, a, b - a, c - a)
            }
            Shape::Rectangle(r) => {
                let [a, b, _, d] = r.v;
                (RECTANGLE, a, b - a, d - a)
            }
            Shape::Sphere(s) => (SPHERE, s.center, Vec3::new(s.radius, 0.0, 0.0), Vec3::ZERO),
        };
        Prim {
            p: p.to_array(),
            tag: index | kind << KIND_SHIFT,
            e1: e1.to_array(),
            e2: e2.to_array(),
        }
    }

    #[inline]
    pub fn shape(&self) -> u32 {
        self.tag & ((1 << KIND_SHIFT) - 1)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let p = Vec3::from_array(self.p);
        let e1 = Vec3::from_array(self.e1);
        match self.tag >> KIND_SHIFT {
            TRIANGLE => intersect_parallelogram(ray, p, e1, Vec3::from_array(self.e2), 1.0, t_max),
            RECTANGLE => intersect_parallelogram(ray, p, e1, Vec3::from_array(self.e2), 2.0, t_max),
            _ => Sphere {
                center: p,
                radius: self.e1[0],
            }
            .intersect(ray, t_max),
        }
    }
}

/// Bounds the BVH files a shape under: the shape's box grown by the barycentric slack a
/// triangle or rectangle test accepts beyond its edges, and by a few units in the last
/// place of its coordinates, so no hit the shape's own test reports falls outside it.
pub fn padded_bounds(shape: &Shape) -> Aabb {
    let b = shape.bounds();
    let slack = match shape {
        Shape::Sphere(_) => 0.0,
        _ => 4.0 * EDGE_SLACK * b.extent().max_element(),
    };
    let magnitude = b.min.abs().max(b.max.abs()).max_element();
    let pad = Vec3::splat(slack + 16.0 * f32::EPSILON * magnitude);
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}
