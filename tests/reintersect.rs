//! pbrt's re-intersection test: a ray spawned from a hit on a surface, in any
//! direction, must never hit that same surface again, at any scale. Secondary rays of
//! both shading models start at `math::offset_origin`; this holds it to the promise.

use prism::math::cross;
use prism::math::{Ray, Vec3, offset_origin};
use prism::scene::{Rectangle, Shape, Sphere, Triangle};
use proptest::prelude::*;

fn unit_vector() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, 0.0f32..std::f32::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Scales from 1e-4 to 1e4, and an offset of the whole scene up to 1e4 times its size
/// (the error of a hit point grows with its coordinates, not with the shape).
fn scale() -> impl Strategy<Value = f32> {
    (-4.0f32..4.0).prop_map(|e| 10f32.powf(e))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

    #[test]
    fn rays_leaving_a_triangle_never_hit_it_again(
        a in point(), b in point(), c in point(),
        u in 0.0f32..1.0, v in 0.0f32..1.0,
        dir in unit_vector(), s in scale(), shift in point(), far in 0.0f32..1e4,
    ) {
        let place = |p: Vec3| (p + shift * far) * s;
        let tri = Triangle { v: [place(a), place(b), place(c)] };
        let shape = Shape::Triangle(tri);
        let n = cross(tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]);
        // Skip slivers whose plane f32 cannot hold.
        prop_assume!(n.length() > 1e-3 * s * s);
        let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
        let p = tri.v[0] + (tri.v[1] - tri.v[0]) * u + (tri.v[2] - tri.v[0]) * v;
        let ng = shape.normal(p);
        let ray = Ray::new(offset_origin(p, ng, dir), dir);
        prop_assert_eq!(shape.intersect(&ray, f32::INFINITY), None, "from {} toward {}", p, dir);
    }

    #[test]
    fn rays_leaving_a_sphere_never_hit_it_at_the_start(
        center in point(), r in 0.05f32..1.0, on in unit_vector(), dir in unit_vector(),
        s in scale(),
    ) {
        let sphere = Sphere { center: center * s, radius: r * s };
        let shape = Shape::Sphere(sphere);
        let p = sphere.center + on * sphere.radius;
        let ng = shape.normal(p);
        let ray = Ray::new(offset_origin(p, ng, dir), dir);
        if let Some(t) = shape.intersect(&ray, f32::INFINITY) {
            // Leaving inward, the far wall is a real hit; it must lie across the sphere.
            prop_assert!(dir.dot(ng) < 0.0, "outward ray hit its own sphere at {t}");
            prop_assert!(t > 1e-3 * sphere.radius, "re-hit at {t} of radius {}", sphere.radius);
        }
    }

    #[test]
    fn rays_leaving_a_rectangle_never_hit_it_again(
        corner in point(), e1 in unit_vector(), len1 in 0.1f32..2.0, len2 in 0.1f32..2.0,
        helper in unit_vector(), u in 0.0f32..1.0, v in 0.0f32..1.0,
        dir in unit_vector(), s in scale(),
    ) {
        let e2 = cross(e1, helper).normalize_or_zero();
        prop_assume!(e2 != Vec3::ZERO);
        let (a, x, y) = (corner * s, e1 * len1 * s, e2 * len2 * s);
        let rect = Rectangle { v: [a, a + x, a + x + y, a + y] };
        let shape = Shape::Rectangle(rect);
        let p = a + x * u + y * v;
        let ng = shape.normal(p);
        let ray = Ray::new(offset_origin(p, ng, dir), dir);
        prop_assert_eq!(shape.intersect(&ray, f32::INFINITY), None);
    }
}
