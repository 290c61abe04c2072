//! A room's walls cast no shadow inside it. A triangle or rectangle lying flat on a
//! face of the scene's bounding box (a floor, a back wall, a ceiling) has the whole
//! scene on one side, so a shadow ray that stays on that side cannot meet it. Yet in
//! the tree it is a leaf like any other, and every shadow ray leaving the wall starts
//! inside that leaf's box and tests it. In a small scene such rays walk a second tree
//! built without the walls, where each ray's segment is shown, by a test of a few
//! comparisons, to keep off every one of them.
//!
//! The test proves what the triangle test would answer, not merely what exact
//! arithmetic would: a skipped wall could not have reported a hit, rounding included.
//! Take a wall in the plane `x = c`. Its edges have no `x` part, so in the
//! Möller–Trumbore test (a rectangle's is the triangle's of three of its corners) the
//! numerator of `t` is `(o_x - c) C` and the determinant `-d_x C`, each to a relative
//! error of at most `2u / κ + u` (`u` the unit roundoff, `C` the edges' in-plane
//! cross product, at least `κ` times their lengths' product): the other products are
//! exact zeros, and the two that are not are bounded by Cauchy–Schwarz. So `t` is
//! `-(o_x - c) / d_x` to within `4u / κ + 4u`, where `o_x - c` is the very float the
//! test subtracts. A ray on the wall's inner side moving away from it, or along it,
//! meets it at no `t > 0`; one moving toward it meets it no sooner than its limit
//! when the plane lies a margin of [`MARGIN`] beyond the limit. The bounds on the
//! wall's edges and on the ray's height and slope keep every product clear of
//! underflow, so the relative errors hold; a product that overflows makes the test's
//! `t` infinite or NaN, which is no hit either.

use super::{Bvh, Leaves, SimdLevel};
use crate::math::{Aabb, Ray};
use crate::scene::{Shape, Shapes, Stored};

/// Scenes of at most this many shapes get the second tree: their shadow rays spend
/// much of a short walk on the wall they leave, and the tree costs a few megabytes at
/// most to hold twice. Path traced, the Cornell box (36 triangles) takes 0.94x the
/// time, and the Blender showcase (7,950, its ground the box's floor) 0.99x.
pub const INDOOR_SHAPES: usize = 65_536;

/// How far beyond a ray's limit, relative to it, a wall it moves toward must lie: at
/// least 12 times the triangle test's relative error in `t` for walls at [`MIN_SINE`].
const MARGIN: f32 = 1.0 / 1024.0;
/// The least sine of the angle between a wall's edges (`κ` above).
const MIN_SINE: f64 = 1.0 / 256.0;
/// A wall's edges are between these lengths.
const EDGE_LENGTHS: (f64, f64) = (1.0 / (1u64 << 20) as f64, (1u64 << 20) as f64);
/// A ray starts at least this far inside a wall's plane...
const MIN_HEIGHT: f32 = 1.0 / (1u64 << 40) as f32;
/// ...and moves along it, or across it at least this steeply.
const MIN_SLOPE: f32 = 1.0 / (1u64 << 40) as f32;

/// A face of the scene's box that walls lie on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Face {
    axis: usize,
    /// The face's coordinate on `axis`.
    plane: f32,
    /// +1 where the scene lies above `plane`, -1 where below.
    inward: f32,
}

impl Face {
    /// Whether a ray from `o` along `d` (their parts on the face's axis) keeps off
    /// every wall on this face for `t` in `(0, t_max)`.
    #[inline(always)]
    fn clears(&self, o: f32, d: f32, t_max: f32) -> bool {
        // The triangle test's own subtraction (a wall's first corner lies on the plane).
        let height = (o - self.plane) * self.inward;
        let slope = d * self.inward;
        // Bitwise, not short-circuit: no branch, so the lanes' test stays in vector
        // registers.
        let away = (slope == 0.0) | (slope >= MIN_SLOPE);
        let short = (slope <= -MIN_SLOPE) & (height >= t_max * -slope * (1.0 + MARGIN));
        (height >= MIN_HEIGHT) & (away | short)
    }
}

/// The faces of the scene's box that hold walls.
#[derive(Debug)]
struct Walls {
    faces: Vec<Face>,
}

impl Walls {
    /// The walls of `shapes`, if any: each a triangle or rectangle whose corners all
    /// share the box's least or greatest coordinate on an axis, of usable shape. With
    /// them the indices of every other shape.
    fn of(shapes: &Shapes) -> Option<(Walls, Vec<u32>)> {
        let bounds = shapes.bounds();
        let mut faces = Vec::new();
        let mut others = Vec::with_capacity(shapes.len());
        for i in 0..shapes.len() {
            // The corners the leaf test takes its origin and edges from, then any other
            // (a rectangle's fourth is its third repeated for a triangle).
            let v = match shapes.stored(i) {
                Stored::Triangle(c) => {
                    let [a, b, c] = c.map(|k| shapes.positions()[k as usize]);
                    Some([a, b, c, c])
                }
                Stored::Other(Shape::Rectangle(r)) => {
                    let [a, b, c, d] = r.v;
                    Some([a, b, d, c])
                }
                Stored::Other(_) => None,
            };
            let face = v.and_then(|v| {
                let v = v.map(|p| p.to_array());
                (0..3).find_map(|axis| wall_face(&v, axis, &bounds))
            });
            match face {
                Some(face) if !faces.contains(&face) => faces.push(face),
                Some(_) => {}
                None => others.push(i as u32),
            }
        }
        (!faces.is_empty()).then_some((Walls { faces }, others))
    }

    /// Whether `ray` keeps off every wall for `t` in `(0, t_max)`.
    #[inline(always)]
    fn clear(&self, ray: &Ray, t_max: f32) -> bool {
        let (o, d) = (ray.origin.to_array(), ray.dir.to_array());
        self.faces
            .iter()
            .all(|f| f.clears(o[f.axis], d[f.axis], t_max))
    }
}

/// The face of `bounds` that the shape with corners `v` lies flat on along `axis`, if
/// it does and is a usable wall.
fn wall_face(v: &[[f32; 3]; 4], axis: usize, bounds: &Aabb) -> Option<Face> {
    let plane = v[0][axis];
    let inward = if plane == bounds.min[axis] {
        1.0
    } else if plane == bounds.max[axis] {
        -1.0
    } else {
        return None;
    };
    let flat = v.iter().all(|p| p[axis] == plane);
    (flat && usable(&[v[0], v[1], v[2]], axis)).then_some(Face {
        axis,
        plane,
        inward,
    })
}

/// Whether the triangle with corners `v` (or the rectangle with these three), flat
/// on `axis`, is shaped as the error bound assumes: edges (as the leaf test subtracts
/// them) neither tiny nor huge, and not nearly parallel.
fn usable(v: &[[f32; 3]; 3], axis: usize) -> bool {
    let edge = |k: usize| [0, 1, 2].map(|a| f64::from(v[k][a] - v[0][a]));
    let (e1, e2) = (edge(1), edge(2));
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    let cross = (e1[a] * e2[b] - e1[b] * e2[a]).abs();
    let length = |e: [f64; 3]| (e[a] * e[a] + e[b] * e[b]).sqrt();
    let (l1, l2) = (length(e1), length(e2));
    let sized = |l: f64| (EDGE_LENGTHS.0..=EDGE_LENGTHS.1).contains(&l);
    sized(l1) && sized(l2) && cross >= MIN_SINE * l1 * l2
}

/// The walls of a small scene, and a tree of its other shapes for the shadow rays
/// that keep off them.
pub(super) struct Indoors<'s> {
    walls: Walls,
    tree: Bvh<'s>,
}

impl<'s> Indoors<'s> {
    /// For a scene of at most [`INDOOR_SHAPES`] shapes with walls.
    pub(super) fn of(shapes: &'s Shapes, simd: SimdLevel, leaves: Leaves) -> Option<Indoors<'s>> {
        if shapes.len() > INDOOR_SHAPES {
            return None;
        }
        let (walls, others) = Walls::of(shapes)?;
        let tree = Bvh::build_over(shapes, &others, simd, leaves);
        Some(Indoors { walls, tree })
    }

    /// Whether `ray` keeps off every wall for `t` in `(0, t_max)`.
    #[inline(always)]
    pub(super) fn clear(&self, ray: &Ray, t_max: f32) -> bool {
        self.walls.clear(ray, t_max)
    }

    /// The tree without the walls.
    pub(super) fn tree(&self) -> &Bvh<'s> {
        &self.tree
    }

    /// Which of the rays in the lanes (bit `i` for lane `i`) keep off every wall
    /// before their limits: [`Indoors::clear`] for each, all at once.
    #[inline(always)]
    pub(super) fn clear_lanes<const N: usize>(
        &self,
        origin: &[[f32; N]; 3],
        dir: &[[f32; N]; 3],
        t_max: &[f32; N],
    ) -> u32 {
        let mut clear = [true; N];
        for f in &self.walls.faces {
            for i in 0..N {
                clear[i] &= f.clears(origin[f.axis][i], dir[f.axis][i], t_max[i]);
            }
        }
        (0..N).map(|i| u32::from(clear[i]) << i).sum()
    }

    pub(super) fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.walls.faces.capacity() * size_of::<Face>()
    }
}

#[cfg(test)]
mod tests;
