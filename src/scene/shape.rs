//! The three surfaces of the 2014 format: sphere, triangle and rectangle.
//!
//! Each answers the geometric questions the renderer asks: where a ray first meets it,
//! its geometric normal, its bounds, and the planar coordinates a texture is read at.

use crate::math::{Aabb, Ray, Vec3, cross};

/// Barycentric slack of triangle and rectangle tests. Two faces that share an edge must
/// not let a ray slip between them; the 2014 program grew each triangle by the same
/// relative amount about its centroid for the same reason.
pub(crate) const EDGE_SLACK: f32 = 1e-5;

/// A sphere given by its centre and radius, in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre in world space.
    pub center: Vec3,
    /// Radius in world units.
    pub radius: f32,
}

/// A triangle with vertices in file order; its normal follows the right-hand rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertices in world space, in file order (counter-clockwise seen from the normal
    /// side).
    pub v: [Vec3; 3],
}

/// A rectangle `v0 v1 v2 v3` (checked to be one when parsed). Its normal is that of the
/// triangle `v0 v1 v2`; texture x runs along `v1 - v0`, y along `v3 - v0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    /// Corners in world space, in order around the rectangle; `v1` and `v3` neighbour
    /// `v0`.
    pub v: [Vec3; 4],
}

/// One surface of a scene, as stored in the scene and tested by the intersectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// A triangle, on its own or one of a mesh.
    Triangle(Triangle),
    /// A flat rectangle, intersected as one parallelogram rather than two triangles.
    Rectangle(Rectangle),
}

/// Where a texture is read on a surface: planar coordinates `(x, y)` in the shape's own
/// frame (world units; for a sphere, the unit square) and the extent of the shape in that
/// frame, `[x0, x0 + len_x] x [y0, y0 + len_y]`, which the stretch, fit and crop modes map
/// the image onto.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceCoords {
    /// Planar x coordinate of the point in the shape's frame.
    pub x: f32,
    /// Planar y coordinate of the point in the shape's frame.
    pub y: f32,
    /// Lower `x` bound of the shape's extent in its frame.
    pub x0: f32,
    /// Lower `y` bound of the shape's extent in its frame.
    pub y0: f32,
    /// Width of the shape along `x`, in the same units as `x`.
    pub len_x: f32,
    /// Height of the shape along `y`, in the same units as `y`.
    pub len_y: f32,
}

impl Sphere {
    /// Distance to the first intersection in `(0, t_max)`. From inside, the far wall.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        // The form of "Precision improvements for ray/sphere intersection" (Ray Tracing
        // Gems, ch. 7): the discriminant from the perpendicular offset, not b^2 - c, so
        // small spheres far away do not lose their edges to cancellation.
        let oc = ray.origin - self.center;
        let b = oc.dot(ray.dir);
        let perp = oc - b * ray.dir;
        let r2 = self.radius * self.radius;
        let disc = r2 - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let c = oc.length_squared() - r2;
        let q = -b - b.signum() * disc.sqrt();
        let (t0, t1) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            let (a, bb) = (c / q, q);
            if a < bb { (a, bb) } else { (bb, a) }
        };
        if t0 > 0.0 && t0 < t_max {
            Some(t0)
        } else if t1 > 0.0 && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// Outward unit normal at `p`, a point on the surface; `+Z` if `p` is the centre.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        (p - self.center).normalize_or(Vec3::Z)
    }

    /// Axis-aligned box that just encloses the sphere.
    pub fn bounds(&self) -> Aabb {
        let r = Vec3::splat(self.radius);
        Aabb {
            min: self.center - r,
            max: self.center + r,
        }
    }

    /// The 2014 mapping: polar angle and azimuth each pass through an arcsine, which
    /// stretches the image near the equator and the seam less than a plain lat-long map.
    pub fn surface_coords(&self, p: Vec3) -> SurfaceCoords {
        use std::f32::consts::PI;
        let n = self.normal(p);
        let theta = n.z.clamp(-1.0, 1.0).acos();
        let mut phi = n.y.atan2(n.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let x = (2.0 * theta / PI - 1.0).clamp(-1.0, 1.0).asin() / PI + 0.5;
        let y = (phi / PI - 1.0).clamp(-1.0, 1.0).asin() / PI + 0.5;
        SurfaceCoords {
            x,
            y,
            x0: 0.0,
            y0: 0.0,
            len_x: 1.0,
            len_y: 1.0,
        }
    }
}

/// Moller-Trumbore over the parallelogram spanned by `e1`, `e2` from `v0`; `max_sum`
/// bounds `u + v` (1 for a triangle, 2 for a parallelogram).
#[inline]
pub(crate) fn intersect_parallelogram(
    ray: &Ray,
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    max_sum: f32,
    t_max: f32,
) -> Option<f32> {
    let pvec = cross(ray.dir, e2);
    let det = e1.dot(pvec);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = ray.origin - v0;
    let u = tvec.dot(pvec) * inv_det;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&u) {
        return None;
    }
    let qvec = cross(tvec, e1);
    let v = ray.dir.dot(qvec) * inv_det;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&v) || u + v > max_sum + EDGE_SLACK {
        return None;
    }
    let t = e2.dot(qvec) * inv_det;
    (t > 0.0 && t < t_max).then_some(t)
}

impl Triangle {
    /// Distance to the intersection in `(0, t_max)`, if any; both sides are hit (no
    /// culling).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let [a, b, c] = self.v;
        intersect_parallelogram(ray, a, b - a, c - a, 1.0, t_max)
    }

    /// Unit normal by the right-hand rule over `v0 v1 v2`; `+Z` if the triangle is
    /// degenerate.
    pub fn normal(&self) -> Vec3 {
        let [a, b, c] = self.v;
        cross(b - a, c - a).normalize_or(Vec3::Z)
    }

    /// Axis-aligned box of the three vertices.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.v)
    }

    /// Frame with origin `v0`, x along `v0 - v1`, y in the plane, perpendicular to x and
    /// toward `v2`; the extent is the triangle's bounding box in that frame.
    pub fn surface_coords(&self, p: Vec3) -> SurfaceCoords {
        let [a, b, c] = self.v;
        let x_axis = (a - b).normalize_or(Vec3::X);
        let to_c = c - a;
        let y_axis = (to_c - to_c.dot(x_axis) * x_axis).normalize_or(Vec3::Y);
        let project = |q: Vec3| ((q - a).dot(x_axis), (q - a).dot(y_axis));
        let (x, y) = project(p);
        let corners = [project(a), project(b), project(c)];
        let min_x = corners.iter().map(|c| c.0).fold(f32::INFINITY, f32::min);
        let max_x = corners
            .iter()
            .map(|c| c.0)
            .fold(f32::NEG_INFINITY, f32::max);
        let min_y = corners.iter().map(|c| c.1).fold(f32::INFINITY, f32::min);
        let max_y = corners
            .iter()
            .map(|c| c.1)
            .fold(f32::NEG_INFINITY, f32::max);
        SurfaceCoords {
            x,
            y,
            x0: min_x,
            y0: min_y,
            len_x: max_x - min_x,
            len_y: max_y - min_y,
        }
    }
}

impl Rectangle {
    /// Distance to the intersection in `(0, t_max)`, if any; both sides are hit (no
    /// culling).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let [a, b, _, d] = self.v;
        intersect_parallelogram(ray, a, b - a, d - a, 2.0, t_max)
    }

    /// Unit normal of the triangle `v0 v1 v2`; `+Z` if the rectangle is degenerate.
    pub fn normal(&self) -> Vec3 {
        let [a, b, c, _] = self.v;
        cross(b - a, c - a).normalize_or(Vec3::Z)
    }

    /// Axis-aligned box of the four corners.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.v)
    }

    /// Frame with origin `v0`, x along `v1 - v0` and y along `v3 - v0`, both in world
    /// units; the extent is `[0, |v1 - v0|] x [0, |v3 - v0|]`.
    pub fn surface_coords(&self, p: Vec3) -> SurfaceCoords {
        let [a, b, _, d] = self.v;
        let (ex, ey) = (b - a, d - a);
        SurfaceCoords {
            x: (p - a).dot(ex.normalize_or_zero()),
            y: (p - a).dot(ey.normalize_or_zero()),
            x0: 0.0,
            y0: 0.0,
            len_x: ex.length(),
            len_y: ey.length(),
        }
    }
}

impl Shape {
    /// Distance along `ray` (whose direction is unit length) to the first hit in
    /// `(0, t_max)`; `None` if the ray misses within that range.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Triangle(t) => t.intersect(ray, t_max),
            Shape::Rectangle(r) => r.intersect(ray, t_max),
        }
    }

    /// Geometric normal at `p`: outward for spheres, right-hand rule for flat shapes.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Triangle(t) => t.normal(),
            Shape::Rectangle(r) => r.normal(),
        }
    }

    /// World-space axis-aligned bounding box, which the acceleration structures build on.
    pub fn bounds(&self) -> Aabb {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Triangle(t) => t.bounds(),
            Shape::Rectangle(r) => r.bounds(),
        }
    }

    /// Texture coordinates of `p`, a point on the surface, and the shape's extent in its
    /// frame.
    pub fn surface_coords(&self, p: Vec3) -> SurfaceCoords {
        match self {
            Shape::Sphere(s) => s.surface_coords(p),
            Shape::Triangle(t) => t.surface_coords(p),
            Shape::Rectangle(r) => r.surface_coords(p),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-5 * (1.0 + b.abs())
    }

    #[test]
    fn sphere_hit_from_outside_and_inside() {
        let s = Sphere {
            center: Vec3::new(0.0, 0.0, 10.0),
            radius: 2.0,
        };
        let r = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(s.intersect(&r, f32::INFINITY), Some(8.0));
        let inside = Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z);
        assert_eq!(s.intersect(&inside, f32::INFINITY), Some(2.0));
        assert_eq!(s.intersect(&r, 7.9), None);
        let behind = Ray::new(Vec3::ZERO, -Vec3::Z);
        assert_eq!(s.intersect(&behind, f32::INFINITY), None);
        // Oblique hit: x = 1 cuts the sphere at z = 10 - sqrt(3).
        let oblique = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::Z);
        let t = s.intersect(&oblique, f32::INFINITY).unwrap();
        assert!(close(t, 10.0 - 3f32.sqrt()), "{t}");
        assert_eq!(s.normal(Vec3::new(0.0, 0.0, 8.0)), -Vec3::Z);
    }

    #[test]
    fn small_far_sphere_keeps_its_silhouette() {
        let s = Sphere {
            center: Vec3::new(0.0, 0.0, 5000.0),
            radius: 1.0,
        };
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.999, 5000.0));
        let t = s.intersect(&r, f32::INFINITY);
        assert!(t.is_some());
    }

    #[test]
    fn triangle_hit_distance_and_edges() {
        let t = Triangle {
            v: [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(4.0, 0.0, 0.0),
                Vec3::new(0.0, 4.0, 0.0),
            ],
        };
        assert_eq!(t.normal(), Vec3::Z);
        let r = Ray::new(Vec3::new(1.0, 1.0, 3.0), -Vec3::Z);
        assert_eq!(t.intersect(&r, f32::INFINITY), Some(3.0));
        // Back side hits too: the 2014 format has no back-face culling.
        let below = Ray::new(Vec3::new(1.0, 1.0, -2.0), Vec3::Z);
        assert_eq!(t.intersect(&below, f32::INFINITY), Some(2.0));
        let outside = Ray::new(Vec3::new(3.0, 3.0, 3.0), -Vec3::Z);
        assert_eq!(t.intersect(&outside, f32::INFINITY), None);
        let parallel = Ray::new(Vec3::new(1.0, 1.0, 0.0), Vec3::X);
        assert_eq!(t.intersect(&parallel, f32::INFINITY), None);
    }

    #[test]
    fn rectangle_hit_covers_both_halves() {
        let r = Rectangle {
            v: [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(4.0, 0.0, 0.0),
                Vec3::new(4.0, 2.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            ],
        };
        for (x, y) in [(3.9, 0.1), (0.1, 1.9), (2.0, 1.0)] {
            let ray = Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z);
            assert_eq!(r.intersect(&ray, f32::INFINITY), Some(5.0));
        }
        let ray = Ray::new(Vec3::new(4.1, 1.0, 5.0), -Vec3::Z);
        assert_eq!(r.intersect(&ray, f32::INFINITY), None);
        let c = r.surface_coords(Vec3::new(3.0, 0.5, 0.0));
        assert_eq!((c.x, c.y, c.len_x, c.len_y), (3.0, 0.5, 4.0, 2.0));
    }

    #[test]
    fn triangle_frame_points_x_from_v1_to_v0_and_y_toward_v2() {
        let t = Triangle {
            v: [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(-4.0, 0.0, 0.0),
                Vec3::new(-1.0, 3.0, 0.0),
            ],
        };
        let c = t.surface_coords(Vec3::new(-1.0, 1.0, 0.0));
        assert_eq!((c.x, c.y), (-1.0, 1.0));
        assert_eq!((c.x0, c.y0, c.len_x, c.len_y), (-4.0, 0.0, 4.0, 3.0));
    }

    #[test]
    fn sphere_coords_are_finite_at_the_poles_and_match_the_2014_formula() {
        let s = Sphere {
            center: Vec3::ZERO,
            radius: 2.0,
        };
        let top = s.surface_coords(Vec3::new(0.0, 0.0, 2.0));
        assert!(top.x.is_finite() && top.y.is_finite());
        assert_eq!(top.x, 0.0);
        // On the equator at azimuth pi/2: theta = pi/2 -> x = 0.5; phi/pi - 1 = -0.5 ->
        // y = asin(-0.5)/pi + 0.5 = -1/6 + 1/2 = 1/3.
        let p = s.surface_coords(Vec3::new(0.0, 2.0, 0.0));
        assert!(close(p.x, 0.5) && close(p.y, 1.0 / 3.0), "{p:?}");
    }
}
