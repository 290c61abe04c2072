//! The scene's shapes, stored so a mesh costs what it must: triangles name their corners
//! in one shared array of positions (a closed mesh has about half a vertex per triangle),
//! and spheres and rectangles, rare and few, are kept whole beside them.
//!
//! A shape is still one number, its index; [`Shapes::get`] gives it back as a [`Shape`]
//! value. Intersectors that want the raw layout read `Shapes::corners` and
//! [`Shapes::positions`].

use super::shape::{Shape, Triangle};
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;
use std::fmt;

/// The corner triple of a shape that is not a triangle: `[OTHER, index into others, 0]`.
pub(crate) const OTHER: u32 = u32::MAX;

/// What a shape index holds, in the layout the intersectors read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stored<'a> {
    /// A triangle: indices of its corners in [`Shapes::positions`], in file order.
    Triangle([u32; 3]),
    /// A sphere or rectangle.
    Other(&'a Shape),
}

/// Every triangle's corners index `positions` (each mutator keeps it so), which is what
/// lets the intersectors read corners without bounds checks.
#[derive(Clone, Default)]
pub struct Shapes {
    positions: Vec<Vec3>,
    corners: Vec<[u32; 3]>,
    others: Vec<Shape>,
}

impl Shapes {
    /// An empty set of shapes.
    pub fn new() -> Shapes {
        Shapes::default()
    }

    /// Number of shapes, triangles and others together.
    #[inline]
    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// Whether there are no shapes at all.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }

    /// Shape `i`. Panics when `i` is out of range, as indexing a slice does.
    #[inline]
    pub fn get(&self, i: usize) -> Shape {
        match self.stored(i) {
            Stored::Triangle(c) => Shape::Triangle(Triangle {
                v: c.map(|k| self.positions[k as usize]),
            }),
            Stored::Other(s) => *s,
        }
    }

    /// Shape `i`, or `None` past the end.
    #[inline]
    pub fn try_get(&self, i: usize) -> Option<Shape> {
        (i < self.len()).then(|| self.get(i))
    }

    /// Whether shape `i` is a triangle (of a mesh or not).
    #[inline]
    pub fn is_triangle(&self, i: usize) -> bool {
        self.corners[i][0] != OTHER
    }

    /// Where shape `i` sits in [`Shapes::others`] when it is not a triangle. Panics
    /// when `i` is out of range.
    #[inline]
    pub(crate) fn other_index(&self, i: usize) -> Option<usize> {
        let c = self.corners[i];
        (c[0] == OTHER).then_some(c[1] as usize)
    }

    /// The spheres and rectangles, in the order [`Shapes::other_index`] counts them.
    pub(crate) fn others(&self) -> &[Shape] {
        &self.others
    }

    /// Shape `i` as stored. Panics when `i` is out of range.
    #[inline]
    pub fn stored(&self, i: usize) -> Stored<'_> {
        let c = self.corners[i];
        if c[0] == OTHER {
            Stored::Other(&self.others[c[1] as usize])
        } else {
            Stored::Triangle(c)
        }
    }

    /// Every triangle's corners index these.
    #[inline]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// One corner triple a shape; `[OTHER, ..]` for a shape that is not a triangle.
    #[inline]
    pub(crate) fn corner_slice(&self) -> &[[u32; 3]] {
        &self.corners
    }

    /// Every shape in index order, as [`Shape`] values.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Shape> + DoubleEndedIterator + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Every shape in index order, as [`Shape`] values, in parallel.
    pub fn par_iter(&self) -> impl IndexedParallelIterator<Item = Shape> + '_ {
        (0..self.len()).into_par_iter().map(|i| self.get(i))
    }

    /// Every shape in index order, copied out whole (triangles with their own corners).
    pub fn to_vec(&self) -> Vec<Shape> {
        self.iter().collect()
    }

    /// Room for `shapes` more shape indices (not their positions, which grow with each
    /// push).
    pub fn reserve(&mut self, shapes: usize) {
        self.corners.reserve(shapes);
    }

    /// Appends `shape`; a triangle gets three positions of its own.
    pub fn push(&mut self, shape: Shape) {
        match shape {
            Shape::Triangle(t) => {
                let first = self.positions.len() as u32;
                self.positions.extend_from_slice(&t.v);
                self.corners.push([first, first + 1, first + 2]);
            }
            other => self.push_other(other),
        }
    }

    /// The shapes `keep` names (indices into these, in that order), with the positions
    /// only their triangles use: the same corners in the same order, so every shape
    /// intersects as it does here, bit for bit. Allocates exactly, plus a table of four
    /// bytes a position while it copies.
    pub fn subset(&self, keep: &[u32]) -> Shapes {
        let triangles = || {
            keep.iter().filter_map(|&i| match self.stored(i as usize) {
                Stored::Triangle(c) => Some(c),
                Stored::Other(_) => None,
            })
        };
        // Where each position of these lands in the subset's: first marked used, then
        // numbered in the order the kept triangles first name them.
        const UNUSED: u32 = u32::MAX;
        let mut moved: Vec<u32> = Vec::new();
        let mut used = 0;
        for c in triangles() {
            if moved.is_empty() {
                moved = vec![UNUSED; self.positions.len()];
            }
            for k in c {
                if moved[k as usize] == UNUSED {
                    moved[k as usize] = 0;
                    used += 1;
                }
            }
        }
        moved.fill(UNUSED);
        let others = keep.len() - triangles().count();
        let mut out = Shapes {
            positions: Vec::with_capacity(used),
            corners: Vec::with_capacity(keep.len()),
            others: Vec::with_capacity(others),
        };
        for &i in keep {
            match self.stored(i as usize) {
                Stored::Triangle(c) => {
                    let c = c.map(|k| {
                        let slot = &mut moved[k as usize];
                        if *slot == UNUSED {
                            *slot = out.positions.len() as u32;
                            out.positions.push(self.positions[k as usize]);
                        }
                        *slot
                    });
                    out.corners.push(c);
                }
                Stored::Other(shape) => out.push_other(*shape),
            }
        }
        out
    }

    fn push_other(&mut self, shape: Shape) {
        self.corners.push([OTHER, self.others.len() as u32, 0]);
        self.others.push(shape);
    }

    /// Appends a mesh: `triangles` index `positions`, which the triangles share.
    /// Indices past `positions` are the caller's error (readers check them).
    pub fn push_mesh(&mut self, positions: &[Vec3], triangles: &[[u32; 3]]) {
        let base = self.positions.len();
        assert!(
            base + positions.len() < OTHER as usize,
            "too many mesh positions"
        );
        let n = positions.len() as u32;
        assert!(
            triangles.par_iter().flatten().all(|&k| k < n),
            "a mesh corner beyond its positions"
        );
        let base = base as u32;
        self.positions.extend_from_slice(positions);
        self.corners
            .par_extend(triangles.par_iter().map(|t| t.map(|k| k + base)));
    }

    /// Replaces shape `i` by `shape`. A triangle's shared corners are left to the
    /// shapes that share them: it gets three new positions instead, so each call adds
    /// three (rebuild from a copy, as posing does, rather than calling it in a loop).
    pub fn set(&mut self, i: usize, shape: Shape) {
        let old = self.corners[i];
        match (old[0] == OTHER, shape) {
            (_, Shape::Triangle(t)) => {
                let first = self.positions.len() as u32;
                self.positions.extend_from_slice(&t.v);
                self.corners[i] = [first, first + 1, first + 2];
            }
            (true, other) => self.others[old[1] as usize] = other,
            (false, other) => {
                self.corners[i] = [OTHER, self.others.len() as u32, 0];
                self.others.push(other);
            }
        }
    }

    /// Appends every shape of `other` with its points moved by `point` (a triangle's
    /// shared corners stay shared) and, where `flip`, its winding reversed. Spheres go
    /// through `sphere`, which may refuse them.
    pub fn append_placed<E>(
        &mut self,
        other: &Shapes,
        point: impl Fn(Vec3) -> Vec3 + Sync,
        flip: bool,
        sphere: impl Fn(super::Sphere) -> Result<super::Sphere, E>,
    ) -> Result<(), E> {
        let base = self.positions.len();
        assert!(
            base + other.positions.len() < OTHER as usize,
            "too many mesh positions"
        );
        let base = base as u32;
        self.positions
            .par_extend(other.positions.par_iter().map(|&p| point(p)));
        self.corners.reserve(other.len());
        for i in 0..other.len() {
            match other.stored(i) {
                Stored::Triangle(c) => {
                    let c = c.map(|k| k + base);
                    self.corners.push(if flip { [c[0], c[2], c[1]] } else { c });
                }
                Stored::Other(Shape::Sphere(s)) => {
                    let mut s = sphere(*s)?;
                    s.center = point(s.center);
                    self.push_other(Shape::Sphere(s));
                }
                Stored::Other(Shape::Rectangle(r)) => {
                    let mut r = *r;
                    r.v = r.v.map(&point);
                    if flip {
                        r.v.swap(1, 3);
                    }
                    self.push_other(Shape::Rectangle(r));
                }
                Stored::Other(Shape::Triangle(_)) => unreachable!("triangles are indexed"),
            }
        }
        Ok(())
    }

    /// Bytes of the positions, corner triples and other shapes.
    pub fn memory_bytes(&self) -> usize {
        self.positions.capacity() * size_of::<Vec3>()
            + self.corners.capacity() * size_of::<[u32; 3]>()
            + self.others.capacity() * size_of::<Shape>()
    }

    /// World-space box around every shape; [`Aabb::EMPTY`] when there are none.
    pub fn bounds(&self) -> Aabb {
        self.par_iter()
            .map(|s| s.bounds())
            .reduce(|| Aabb::EMPTY, Aabb::union)
    }
}

impl From<Vec<Shape>> for Shapes {
    fn from(shapes: Vec<Shape>) -> Shapes {
        shapes.into_iter().collect()
    }
}

impl From<&[Shape]> for Shapes {
    fn from(shapes: &[Shape]) -> Shapes {
        shapes.iter().copied().collect()
    }
}

impl FromIterator<Shape> for Shapes {
    fn from_iter<I: IntoIterator<Item = Shape>>(iter: I) -> Shapes {
        let mut shapes = Shapes::new();
        shapes.extend(iter);
        shapes
    }
}

impl Extend<Shape> for Shapes {
    fn extend<I: IntoIterator<Item = Shape>>(&mut self, iter: I) {
        for s in iter {
            self.push(s);
        }
    }
}

/// Equal when they hold the same shapes in the same order, however stored.
impl PartialEq for Shapes {
    fn eq(&self, other: &Shapes) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl PartialEq<Vec<Shape>> for Shapes {
    fn eq(&self, other: &Vec<Shape>) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter().copied())
    }
}

impl fmt::Debug for Shapes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Rectangle, Sphere};

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    fn square() -> Rectangle {
        Rectangle {
            v: [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
        }
    }

    #[test]
    fn a_mesh_shares_its_positions_and_reads_back_as_triangles() {
        let mut s = Shapes::new();
        s.push(Shape::Sphere(Sphere {
            center: v(0., 0., 5.),
            radius: 1.0,
        }));
        let quad = [v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 0.), v(0., 2., 0.)];
        s.push_mesh(&quad, &[[0, 1, 2], [0, 2, 3]]);
        s.push(Shape::Rectangle(square()));
        assert_eq!(s.len(), 4);
        assert_eq!(s.positions().len(), 4, "two triangles, four shared corners");
        assert_eq!(s.stored(1), Stored::Triangle([0, 1, 2]));
        assert_eq!(
            s.get(2),
            Shape::Triangle(Triangle {
                v: [quad[0], quad[2], quad[3]]
            })
        );
        assert_eq!(s.get(3), Shape::Rectangle(square()));
        assert_eq!(s.try_get(4), None);
        let b = s.bounds();
        assert_eq!((b.min, b.max), (v(-1., -1., 0.), v(2., 2., 6.)));
    }

    #[test]
    fn equal_shapes_compare_equal_however_stored() {
        let quad = [v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 0.), v(0., 2., 0.)];
        let mut shared = Shapes::new();
        shared.push_mesh(&quad, &[[0, 1, 2], [0, 2, 3]]);
        let loose = Shapes::from(shared.to_vec());
        assert_eq!(loose.positions().len(), 6);
        assert_eq!(shared, loose);
        assert_eq!(shared, shared.to_vec());
    }

    #[test]
    fn a_subset_keeps_its_shapes_and_only_the_positions_they_use() {
        let mut s = Shapes::new();
        s.push(Shape::Sphere(Sphere {
            center: v(0., 0., 5.),
            radius: 1.0,
        }));
        // A fan of four triangles around corner 0, then a loose triangle.
        let fan = [
            v(0., 0., 0.),
            v(1., 0., 0.),
            v(1., 1., 0.),
            v(0., 1., 0.),
            v(-1., 1., 0.),
            v(-1., 0., 0.),
        ];
        s.push_mesh(&fan, &[[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]);
        s.push(Shape::Rectangle(square()));
        s.push(Shape::Triangle(Triangle {
            v: [v(5., 0., 0.), v(6., 0., 0.), v(5., 1., 0.)],
        }));
        let keep = [6, 3, 0, 1, 5];
        let sub = s.subset(&keep);
        assert_eq!(sub.len(), keep.len());
        for (k, &i) in keep.iter().enumerate() {
            assert_eq!(sub.get(k), s.get(i as usize), "shape {k} of the subset");
        }
        // Triangles 1 and 3 of the fan share corner 0: 5 of the fan's corners, and the
        // loose triangle's 3.
        assert_eq!(sub.positions().len(), 8);
        assert_eq!(sub.others().len(), 2);
        assert!(sub.memory_bytes() <= s.memory_bytes());
        // Allocated exactly: no slack a growing vector leaves.
        assert_eq!(
            sub.memory_bytes(),
            8 * size_of::<Vec3>() + 5 * size_of::<[u32; 3]>() + 2 * size_of::<Shape>()
        );
        assert!(s.subset(&[]).is_empty());
        assert!(
            s.subset(&[0, 5]).positions().is_empty(),
            "no triangle, no positions"
        );
    }

    #[test]
    fn setting_a_shared_triangle_leaves_its_neighbour_in_place() {
        let quad = [v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 0.), v(0., 2., 0.)];
        let mut s = Shapes::new();
        s.push_mesh(&quad, &[[0, 1, 2], [0, 2, 3]]);
        let before = s.get(1);
        let moved = Triangle {
            v: [v(9., 0., 0.), v(9., 1., 0.), v(9., 0., 1.)],
        };
        s.set(0, Shape::Triangle(moved));
        assert_eq!(s.get(0), Shape::Triangle(moved));
        assert_eq!(s.get(1), before);
        s.set(1, Shape::Rectangle(square()));
        assert_eq!(s.get(1), Shape::Rectangle(square()));
        let ball = Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 3.0,
        });
        s.set(1, ball);
        assert_eq!(s.get(1), ball);
        assert_eq!(s.others.len(), 1, "an other replaced in place");
    }

    #[test]
    fn placing_moves_every_point_and_flips_the_winding() {
        let mut mesh = Shapes::new();
        mesh.push_mesh(&[v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.)], &[[0, 1, 2]]);
        mesh.push(Shape::Rectangle(square()));
        mesh.push(Shape::Sphere(Sphere {
            center: v(1., 1., 1.),
            radius: 1.0,
        }));
        let mut s = Shapes::new();
        s.push(Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        }));
        let shift = v(10., 0., 0.);
        s.append_placed(&mesh, |p| p + shift, true, Ok::<_, ()>)
            .unwrap();
        assert_eq!(
            s.get(1),
            Shape::Triangle(Triangle {
                v: [v(10., 0., 0.), v(10., 1., 0.), v(11., 0., 0.)]
            })
        );
        let r = square().v.map(|p| p + shift);
        assert_eq!(
            s.get(2),
            Shape::Rectangle(Rectangle {
                v: [r[0], r[3], r[2], r[1]]
            })
        );
        assert_eq!(
            s.get(3),
            Shape::Sphere(Sphere {
                center: v(11., 1., 1.),
                radius: 1.0
            })
        );
        let refused = s.append_placed(&mesh, |p| p, false, |_| Err("no spheres"));
        assert_eq!(refused, Err("no spheres"));
    }
}
