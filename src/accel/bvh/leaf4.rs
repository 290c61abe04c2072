//! Leaf shapes four at a time: a leaf's triangles and rectangles are stored side by side
//! in lanes (structure of arrays) and one ray meets all four with 4-lane SIMD
//! Moller-Trumbore. Spheres ride in lanes of their own, met by a 4-lane test of their own.
//! (A leaf of four shapes is a `Leaf4`; "packet" is kept for rays traced together.)
//!
//! Each lane repeats, operation for operation, what [`intersect_parallelogram`] does in
//! scalar code (the same products, summed in the same order, and no fused multiply-add),
//! so a lane's distance equals the scalar one bit for bit and every intersector renders
//! the same image.
//!
//! [`intersect_parallelogram`]: crate::scene::shape::intersect_parallelogram

use glam::{Affine3A, BVec4A, Vec4};

use crate::math::{Aabb, Ray, Vec3};
use crate::scene::shape::EDGE_SLACK;
use crate::scene::shapes::OTHER;
use crate::scene::{Shape, Shapes, Sphere, Stored};

/// Shape indices must fit in a lane's `u32` with one value left for an empty lane.
pub const MAX_SHAPES: usize = 1 << 30;
// The tree takes more shapes than a scene may hold, so the scene's limit is the only
// one a reader can reach.
const _: () = assert!(crate::util::limits::MAX_SHAPES <= MAX_SHAPES);
const EMPTY_LANE: u32 = u32::MAX;

/// Up to four shapes. A triangle or rectangle lane holds its corner `p` and edges `e1`,
/// `e2`, and `max_sum` bounds `u + v` (1 for a triangle, 2 for a rectangle). A sphere
/// lane holds its centre in `p`, its radius in `radius` and zero edges; an empty lane
/// holds zero edges. Zero edges make the determinant 0, which the test rejects.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Leaf4 {
    p: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
    max_sum: Vec4,
    radius: Vec4,
    shape: [u32; 4],
}

/// One triangle or rectangle of a leaf, for tests against many rays.
#[derive(Clone, Copy, Debug)]
pub struct Flat {
    pub p: [f32; 3],
    pub e1: [f32; 3],
    pub e2: [f32; 3],
    pub max_sum: f32,
}

/// One ray's origin and direction in all four lanes: the per-ray constants of the leaf
/// test.
pub struct RayLanes {
    origin: [Vec4; 3],
    dir: [Vec4; 3],
}

impl RayLanes {
    #[inline]
    pub fn new(ray: &Ray) -> RayLanes {
        RayLanes {
            origin: ray.origin.to_array().map(Vec4::splat),
            dir: ray.dir.to_array().map(Vec4::splat),
        }
    }
}

/// One shape as a leaf test reads it.
pub enum Prim {
    Flat(Flat),
    Sphere(Sphere),
}

impl Prim {
    /// Shape `index` of `shapes`, with the edges the test needs computed from its
    /// corners (the same subtractions the scalar test makes, so the same bits).
    #[inline(always)]
    pub fn of(shapes: &Shapes, index: u32) -> Prim {
        let flat = |p: Vec3, e1: Vec3, e2: Vec3, max_sum| {
            Prim::Flat(Flat {
                p: p.to_array(),
                e1: e1.to_array(),
                e2: e2.to_array(),
                max_sum,
            })
        };
        match shapes.stored(index as usize) {
            Stored::Triangle(c) => {
                let v = shapes.positions();
                let [a, b, c] = c.map(|k| v[k as usize]);
                flat(a, b - a, c - a, 1.0)
            }
            Stored::Other(Shape::Rectangle(r)) => {
                let [a, b, _, d] = r.v;
                flat(a, b - a, d - a, 2.0)
            }
            Stored::Other(Shape::Sphere(s)) => Prim::Sphere(*s),
            Stored::Other(Shape::Triangle(_)) => unreachable!("triangles are indexed"),
        }
    }
}

impl Leaf4 {
    /// Gathers `shapes[i]` for each `i` of `indices` (at most four) into lanes.
    #[inline(always)]
    pub fn new(shapes: &Shapes, indices: &[u32]) -> Leaf4 {
        debug_assert!(indices.len() <= 4);
        let corners = shapes.corner_slice();
        let positions = shapes.positions();
        let mut shape = [EMPTY_LANE; 4];
        // Empty lanes keep a triangle of zero edges, which the test rejects.
        let mut v = [[Vec3::ZERO; 3]; 4];
        for (lane, &index) in indices.iter().enumerate() {
            debug_assert!((index as usize) < shapes.len());
            // SAFETY: the tree only holds indices of `shapes`, which it borrows, so
            // they cannot go stale.
            let c = unsafe { *corners.get_unchecked(index as usize) };
            if c[0] == OTHER {
                // Leaves with other shapes are stored as copies; this serves callers
                // that mix them all the same.
                return Leaf4::mixed(shapes, indices);
            }
            shape[lane] = index;
            // SAFETY: a triangle's corners index `positions` (an invariant of `Shapes`).
            v[lane] = c.map(|k| unsafe { *positions.get_unchecked(k as usize) });
        }
        // Lanes built in registers: writing them one float at a time into the leaf
        // and reading them back as vectors stalled every load.
        Leaf4::of_corners(&v, shape)
    }

    /// [`Leaf4::new`] for the triangles of an object placed by `to_world` (mirrored
    /// where `flip`): their corners placed in world space as the flattened twin holds
    /// them.
    #[inline(always)]
    pub fn placed(shapes: &Shapes, indices: &[u32], to_world: &Affine3A, flip: bool) -> Leaf4 {
        debug_assert!(indices.len() <= 4);
        let corners = shapes.corner_slice();
        let positions = shapes.positions();
        let mut shape = [EMPTY_LANE; 4];
        // Each corner's object-space coordinates, axis by axis, a lane a triangle.
        let mut local = [[[0.0f32; 4]; 3]; 3];
        for (lane, &index) in indices.iter().enumerate() {
            // SAFETY: as in `new`; objects hold triangles only.
            let c = unsafe { *corners.get_unchecked(index as usize) };
            debug_assert!(c[0] != OTHER);
            shape[lane] = index;
            for (corner, &k) in local.iter_mut().zip(&c) {
                // SAFETY: a triangle's corners index `positions` (an invariant of `Shapes`).
                let p = unsafe { *positions.get_unchecked(k as usize) };
                for axis in 0..3 {
                    corner[axis][lane] = p[axis];
                }
            }
        }
        // The four triangles' corners placed together, each lane and axis by the
        // operations of `Affine3A::transform_point3a` (`place_corners`) in their order,
        // `((x_axis x + y_axis y) + z_axis z) + translation`: the same bits, without
        // gathering placed points back into lanes.
        let (m, t) = (&to_world.matrix3, to_world.translation);
        let [a, b, c] = local.map(|[x, y, z]| {
            let [x, y, z] = [x, y, z].map(Vec4::from_array);
            [0, 1, 2]
                .map(|axis| x * m.x_axis[axis] + y * m.y_axis[axis] + z * m.z_axis[axis] + t[axis])
        });
        let [b, c] = if flip { [c, b] } else { [b, c] };
        Leaf4::of_corner_lanes([a, b, c], shape)
    }

    /// Lanes of the triangles with corners `v`, edges subtracted as the scalar test
    /// subtracts them.
    #[inline(always)]
    fn of_corners(v: &[[Vec3; 3]; 4], shape: [u32; 4]) -> Leaf4 {
        let column = |corner: usize, axis: usize| {
            Vec4::new(
                v[0][corner][axis],
                v[1][corner][axis],
                v[2][corner][axis],
                v[3][corner][axis],
            )
        };
        let corners = [0, 1, 2].map(|corner| [0, 1, 2].map(|axis| column(corner, axis)));
        Leaf4::of_corner_lanes(corners, shape)
    }

    /// Lanes of the triangles whose corners are `[a, b, c]`, each axis by axis a lane
    /// a triangle.
    #[inline(always)]
    fn of_corner_lanes([a, b, c]: [[Vec4; 3]; 3], shape: [u32; 4]) -> Leaf4 {
        Leaf4 {
            e1: [0, 1, 2].map(|axis| b[axis] - a[axis]),
            e2: [0, 1, 2].map(|axis| c[axis] - a[axis]),
            p: a,
            max_sum: Vec4::ONE,
            radius: Vec4::ZERO,
            shape,
        }
    }

    /// [`Leaf4::new`] for any shapes, spheres and rectangles too, one lane at a time.
    pub fn mixed(shapes: &Shapes, indices: &[u32]) -> Leaf4 {
        let mut leaf = Leaf4 {
            p: [Vec4::ZERO; 3],
            e1: [Vec4::ZERO; 3],
            e2: [Vec4::ZERO; 3],
            max_sum: Vec4::ZERO,
            radius: Vec4::ZERO,
            shape: [EMPTY_LANE; 4],
        };
        for (lane, &index) in indices.iter().enumerate() {
            leaf.shape[lane] = index;
            match Prim::of(shapes, index) {
                Prim::Flat(f) => {
                    for axis in 0..3 {
                        leaf.p[axis][lane] = f.p[axis];
                        leaf.e1[axis][lane] = f.e1[axis];
                        leaf.e2[axis][lane] = f.e2[axis];
                    }
                    leaf.max_sum[lane] = f.max_sum;
                }
                Prim::Sphere(s) => {
                    for axis in 0..3 {
                        leaf.p[axis][lane] = s.center[axis];
                    }
                    leaf.radius[lane] = s.radius;
                }
            }
        }
        leaf
    }

    /// Shape index of `lane`.
    #[inline]
    pub fn shape(&self, lane: usize) -> u32 {
        self.shape[lane]
    }

    /// Lanes (bit `i` for lane `i`) whose triangle or rectangle the ray meets in
    /// `(0, t_max)`, with the distances.
    #[inline]
    pub fn intersect_flat(&self, ray: &RayLanes, t_max: f32) -> (u32, Vec4) {
        let [dx, dy, dz] = ray.dir;
        let [e1x, e1y, e1z] = self.e1;
        let [e2x, e2y, e2z] = self.e2;
        // pvec = dir x e2
        let px = dy * e2z - dz * e2y;
        let py = dz * e2x - dx * e2z;
        let pz = dx * e2y - dy * e2x;
        let det = e1x * px + e1y * py + e1z * pz;
        let inv_det = Vec4::ONE / det;
        // tvec = origin - p
        let tx = ray.origin[0] - self.p[0];
        let ty = ray.origin[1] - self.p[1];
        let tz = ray.origin[2] - self.p[2];
        let u = (tx * px + ty * py + tz * pz) * inv_det;
        // qvec = tvec x e1
        let qx = ty * e1z - tz * e1y;
        let qy = tz * e1x - tx * e1z;
        let qz = tx * e1y - ty * e1x;
        let v = (dx * qx + dy * qy + dz * qz) * inv_det;
        let t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;

        let lo = Vec4::splat(-EDGE_SLACK);
        let hi = Vec4::splat(1.0 + EDGE_SLACK);
        let finite = det.is_finite_mask() & det.cmpne(Vec4::ZERO);
        let inside: BVec4A = u.cmpge(lo)
            & u.cmple(hi)
            & v.cmpge(lo)
            & v.cmple(hi)
            & (u + v).cmple(self.max_sum + Vec4::splat(EDGE_SLACK));
        let in_range = t.cmpgt(Vec4::ZERO) & t.cmplt(Vec4::splat(t_max));
        ((finite & inside & in_range).bitmask(), t)
    }

    /// Sphere lanes the ray meets in `(0, t_max)`, with the distances: every sphere of
    /// the leaf at once, each lane the operations of [`Sphere::intersect`] in the same
    /// order (dot products summed x, y then z, as glam's), so the same bits.
    #[inline]
    pub fn intersect_spheres(&self, ray: &RayLanes, t_max: f32) -> (u32, Vec4) {
        let [dx, dy, dz] = ray.dir;
        let ox = ray.origin[0] - self.p[0];
        let oy = ray.origin[1] - self.p[1];
        let oz = ray.origin[2] - self.p[2];
        let b = ox * dx + oy * dy + oz * dz;
        let px = ox - b * dx;
        let py = oy - b * dy;
        let pz = oz - b * dz;
        let r2 = self.radius * self.radius;
        let disc = r2 - (px * px + py * py + pz * pz);
        let c = (ox * ox + oy * oy + oz * oz) - r2;
        let q = -b - b.signum() * disc.sqrt();
        let a = c / q;
        let ordered = a.cmplt(q);
        let at_zero = q.cmpeq(Vec4::ZERO);
        let t0 = Vec4::select(at_zero, Vec4::ZERO, Vec4::select(ordered, a, q));
        let t1 = Vec4::select(at_zero, Vec4::ZERO, Vec4::select(ordered, q, a));
        let bound = Vec4::splat(t_max);
        let first = t0.cmpgt(Vec4::ZERO) & t0.cmplt(bound);
        let second = t1.cmpgt(Vec4::ZERO) & t1.cmplt(bound);
        // `!(disc < 0)`, not `disc >= 0`: a NaN discriminant goes on, as in the scalar
        // test, and is then rejected by its NaN distances.
        let meets = !disc.cmplt(Vec4::ZERO) & (first | second);
        let spheres = self.sphere_lanes();
        (meets.bitmask() & spheres, Vec4::select(first, t0, t1))
    }

    /// The shape of `lane` as a leaf test reads it; `None` for an empty lane.
    #[inline(always)]
    pub fn prim(&self, lane: usize) -> Option<Prim> {
        if self.shape[lane] == EMPTY_LANE {
            return None;
        }
        if self.radius[lane] > 0.0 {
            return Some(Prim::Sphere(self.sphere(lane)));
        }
        let at = |v: &[Vec4; 3]| [v[0][lane], v[1][lane], v[2][lane]];
        Some(Prim::Flat(Flat {
            p: at(&self.p),
            e1: at(&self.e1),
            e2: at(&self.e2),
            max_sum: self.max_sum[lane],
        }))
    }

    /// Lanes holding a sphere.
    #[inline]
    pub fn sphere_lanes(&self) -> u32 {
        self.radius.cmpgt(Vec4::ZERO).bitmask()
    }

    /// The sphere of `lane` (which must hold one).
    #[inline]
    pub fn sphere(&self, lane: usize) -> Sphere {
        Sphere {
            center: Vec3::new(self.p[0][lane], self.p[1][lane], self.p[2][lane]),
            radius: self.radius[lane],
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Rectangle, Triangle};

    /// The leaf's sphere test against `ray`, lane by lane the scalar test of
    /// `shapes[lane]` bit for bit (and no hit in a lane that holds no sphere); the
    /// scalar answers.
    fn assert_sphere_lanes_are_scalar(
        leaf: &Leaf4,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
    ) -> [Option<f32>; 4] {
        let (mask, t) = leaf.intersect_spheres(&RayLanes::new(ray), t_max);
        std::array::from_fn(|lane| {
            let simd = (mask >> lane & 1 == 1).then(|| t[lane]);
            let Some(Shape::Sphere(_)) = shapes.get(lane) else {
                assert_eq!(simd, None, "lane {lane} holds no sphere");
                return None;
            };
            let scalar = shapes[lane].intersect(ray, t_max);
            assert_eq!(
                scalar.map(f32::to_bits),
                simd.map(f32::to_bits),
                "ray {ray:?} t_max {t_max} lane {lane}"
            );
            scalar
        })
    }

    /// A 6 x 6 square facing the rays of the tests, at z = 7.
    fn square_at_z7() -> Shape {
        Shape::Rectangle(Rectangle {
            v: [
                Vec3::new(-3.0, -3.0, 7.0),
                Vec3::new(3.0, -3.0, 7.0),
                Vec3::new(3.0, 3.0, 7.0),
                Vec3::new(-3.0, 3.0, 7.0),
            ],
        })
    }

    /// Spheres three to a leaf beside a rectangle, against rays from outside, from
    /// inside, from points on the surface (the case of every reflected ray), grazing
    /// the edges and with bounds cutting through them: each sphere lane gives what the
    /// scalar test gives, bit for bit.
    #[test]
    fn sphere_lanes_give_the_scalar_distance_bit_for_bit() {
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(0x5fe7e, 3);
        let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
        let (mut hits, mut cut_by_bound) = (0, 0);
        for _ in 0..500 {
            let point = |u: &mut dyn FnMut() -> f32, scale: f32| {
                Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * scale
            };
            let spheres: Vec<Sphere> = (0..3)
                .map(|_| Sphere {
                    center: point(&mut unit, 6.0),
                    radius: 0.05 + 2.0 * unit().powi(2),
                })
                .collect();
            let mut shapes: Vec<Shape> = spheres.iter().map(|&s| Shape::Sphere(s)).collect();
            shapes.insert(1, square_at_z7());
            let leaf = Leaf4::new(&Shapes::from(&shapes[..]), &[0, 1, 2, 3]);
            assert_eq!(leaf.sphere_lanes(), 0b1101);
            for k in 0..40 {
                let target = &spheres[k % 3];
                let origin = match k % 4 {
                    // On the sphere, as a reflected ray leaves it.
                    0 => {
                        target.center + point(&mut unit, 2.0).normalize_or(Vec3::X) * target.radius
                    }
                    1 => target.center + point(&mut unit, target.radius),
                    _ => point(&mut unit, 20.0),
                };
                // Toward the sphere's edge, grazing it, or anywhere.
                let aim = target.center + point(&mut unit, 2.0 * target.radius * (k % 3) as f32);
                let dir = (aim - origin).normalize_or(Vec3::Y);
                let ray = Ray::new(origin, dir);
                let t_max = if k % 5 == 0 {
                    f32::INFINITY
                } else {
                    25.0 * unit()
                };
                let answers = assert_sphere_lanes_are_scalar(&leaf, &shapes, &ray, t_max);
                for lane in [0, 2, 3] {
                    let scalar = answers[lane];
                    hits += usize::from(scalar.is_some());
                    let unbounded = shapes[lane].intersect(&ray, f32::INFINITY);
                    cut_by_bound += usize::from(unbounded.is_some() && scalar != unbounded);
                }
            }
        }
        assert!(hits > 10_000, "{hits} hits");
        assert!(cut_by_bound > 1_000, "{cut_by_bound} cut by the bound");
    }

    /// The corners of the sphere test: from the centre (b = +0 and -0), tangent rays
    /// (a zero discriminant), q = 0, a radius squared to zero, NaN directions and
    /// origins, and bounds of zero, below zero, NaN and infinity. Each sphere lane
    /// answers as the scalar test.
    #[test]
    fn sphere_lanes_match_the_scalar_test_at_its_corners() {
        let unit = Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let shapes = [
            Shape::Sphere(unit),
            square_at_z7(),
            Shape::Sphere(Sphere {
                center: Vec3::new(0.0, 0.0, 3.0),
                radius: 2.0,
            }),
            // A radius whose square underflows to zero (readers refuse a zero radius).
            Shape::Sphere(Sphere {
                center: Vec3::new(-0.0, 5.0, -0.0),
                radius: 1e-30,
            }),
        ];
        let leaf = Leaf4::new(&Shapes::from(&shapes[..]), &[0, 1, 2, 3]);
        let nan = f32::NAN;
        let rays = [
            Ray::new(Vec3::ZERO, Vec3::X),
            Ray::new(Vec3::new(-0.0, -0.0, -0.0), Vec3::new(0.0, -1.0, 0.0)),
            Ray::new(Vec3::new(-5.0, 1.0, 0.0), Vec3::X),
            Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
            Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::Y),
            Ray::new(Vec3::new(0.0, 5.0, -3.0), Vec3::Z),
            Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::new(nan, 0.0, 1.0)),
            Ray::new(Vec3::new(nan, 0.0, -5.0), Vec3::Z),
            Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO),
        ];
        for ray in rays {
            for t_max in [f32::INFINITY, 1e-30, 0.0, -1.0, nan, 4.0] {
                assert_sphere_lanes_are_scalar(&leaf, &shapes, &ray, t_max);
            }
        }
    }

    #[test]
    fn each_lane_gives_the_scalar_distance_bit_for_bit() {
        let shapes = [
            Shape::Triangle(Triangle {
                v: [
                    Vec3::new(-1.3, -0.7, 5.1),
                    Vec3::new(1.7, -1.1, 4.9),
                    Vec3::new(0.1, 1.9, 5.3),
                ],
            }),
            Shape::Sphere(Sphere {
                center: Vec3::new(0.0, 0.0, 9.0),
                radius: 2.0,
            }),
            square_at_z7(),
        ];
        let leaf = Leaf4::new(&Shapes::from(&shapes[..]), &[0, 1, 2]);
        assert_eq!(leaf.sphere_lanes(), 0b010);
        assert_eq!(
            leaf.sphere(1),
            Sphere {
                center: Vec3::new(0.0, 0.0, 9.0),
                radius: 2.0
            }
        );
        for k in 0..50 {
            let a = k as f32 * 0.37;
            let ray = Ray::new(
                Vec3::new(0.3 * a.sin(), 0.2 * a.cos(), 0.1),
                Vec3::new(0.2 * a.cos(), 0.15 * a.sin(), 1.0),
            );
            let (mask, t) = leaf.intersect_flat(&RayLanes::new(&ray), f32::INFINITY);
            assert_eq!(
                mask & 0b1010,
                0,
                "sphere and empty lanes are never flat hits"
            );
            for lane in [0, 2] {
                let scalar = shapes[lane].intersect(&ray, f32::INFINITY);
                let simd = (mask >> lane & 1 == 1).then(|| t[lane]);
                assert_eq!(
                    scalar.map(f32::to_bits),
                    simd.map(f32::to_bits),
                    "ray {k} lane {lane}"
                );
            }
        }
    }

    proptest::proptest! {
        /// A placed leaf's lanes are the triangles `place_corners` places, corner for
        /// corner and bit for bit, for one to four triangles, mirrored or not: the
        /// flattened twin's triangles.
        #[test]
        fn placed_lanes_are_the_corners_place_corners_places(
            corners in proptest::collection::vec(
                proptest::array::uniform3(proptest::array::uniform3(-50.0f32..50.0)), 1..=4),
            columns in proptest::array::uniform4(proptest::array::uniform3(-4.0f32..4.0)),
        ) {
            let to_world = glam::Affine3A::from_cols_array(&[
                columns[0][0], columns[0][1], columns[0][2],
                columns[1][0], columns[1][1], columns[1][2],
                columns[2][0], columns[2][1], columns[2][2],
                columns[3][0] * 25.0, columns[3][1] * 25.0, columns[3][2] * 25.0,
            ]);
            let mut shapes = Shapes::new();
            for v in &corners {
                shapes.push(Shape::Triangle(Triangle { v: v.map(Vec3::from_array) }));
            }
            let indices: Vec<u32> = (0..corners.len() as u32).collect();
            for flip in [false, true] {
                let leaf = Leaf4::placed(&shapes, &indices, &to_world, flip);
                let mut v = [[Vec3::ZERO; 3]; 4];
                for (lane, c) in corners.iter().enumerate() {
                    v[lane] = crate::scene::instance::place_corners(
                        &to_world, flip, c.map(Vec3::from_array));
                }
                let mut shape = [EMPTY_LANE; 4];
                shape[..indices.len()].copy_from_slice(&indices);
                let expected = Leaf4::of_corners(&v, shape);
                let bits = |l: &Leaf4| {
                    [l.p, l.e1, l.e2].map(|axes| axes.map(|a| a.to_array().map(f32::to_bits)))
                };
                for lane in 0..indices.len() {
                    proptest::prop_assert_eq!(
                        bits(&leaf).map(|axes| axes.map(|a| a[lane])),
                        bits(&expected).map(|axes| axes.map(|a| a[lane])),
                        "lane {} flip {}", lane, flip
                    );
                }
                proptest::prop_assert_eq!(leaf.shape, expected.shape);
            }
        }
    }
}
