//! Hand-computed colours of the classic model.

use super::*;
use crate::accel::{Accel, AccelKind};
use crate::math::normalize;
use crate::scene::{Light, Material, Rectangle, Shape, Sphere};

const C: Vec3 = Vec3::new(0.5, 0.25, 1.0);

fn material(ka: f32, kd: f32, ks: f32, shininess: f32) -> Material {
    Material {
        name: "m".into(),
        color: C,
        ambient: ka,
        diffuse: kd,
        specular: ks,
        shininess,
        ..Material::default_white()
    }
}

/// A 20 x 20 floor at z = 0 facing +z (wound counter-clockwise seen from above).
fn floor() -> Shape {
    Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-10.0, -10.0, 0.0),
            Vec3::new(10.0, -10.0, 0.0),
            Vec3::new(10.0, 10.0, 0.0),
            Vec3::new(-10.0, 10.0, 0.0),
        ],
    })
}

fn scene(materials: Vec<Material>, shapes: Vec<(Shape, u32)>, lights: Vec<Vec3>) -> Scene {
    let mut s = Scene {
        materials,
        ..Scene::default()
    };
    for (shape, m) in shapes {
        s.push_shape(shape, m);
    }
    s.lights = lights
        .into_iter()
        .map(|position| Light::point(position, Vec3::ONE))
        .collect();
    s
}

/// Colour seen by a ray from (0, 0, 5) straight down at the floor's centre.
fn shade(s: &Scene) -> (Vec3, RayCount) {
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let classic = Classic::new(s, &accel, 1.0);
    let mut acc = WeightedColor::default();
    let mut count = RayCount::default();
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    classic.trace_camera_ray(ray, &mut PixelSampler::new(0, 0, 0), &mut acc, &mut count);
    (acc.mean(), count)
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-6, "{a} != {b}");
}

#[test]
fn lit_point_is_ambient_colour_mixed_with_diffuse_white() {
    let s = scene(
        vec![material(2.0, 1.0, 0.0, 1.0)],
        vec![(floor(), 0)],
        vec![Vec3::new(0.0, 0.0, 10.0)],
    );
    let (c, count) = shade(&s);
    assert_close(c, (2.0 * C + Vec3::ONE) / 3.0);
    // One camera ray, one shadow ray.
    assert_eq!(count.rays, 2);
}

#[test]
fn highlight_adds_white_weighted_by_phong_over_cosine() {
    // Light at 45 degrees: L = (1, 0, -1)/sqrt2, |N.L| = 1/sqrt2, R = (1, 0, 1)/sqrt2,
    // V = +z, R.V = 1/sqrt2; weight = ks (R.V)^4 / |N.L| = 0.5 (1/sqrt2)^3.
    let s = scene(
        vec![material(2.0, 1.0, 0.5, 4.0)],
        vec![(floor(), 0)],
        vec![Vec3::new(-5.0, 0.0, 5.0)],
    );
    let (c, _) = shade(&s);
    let w = 0.5 * std::f32::consts::FRAC_1_SQRT_2.powi(3);
    assert_close(c, (2.0 * C + Vec3::ONE * (1.0 + w)) / (3.0 + w));
}

#[test]
fn shadowed_point_mixes_in_black_with_weight_three() {
    let blocker = Shape::Sphere(Sphere {
        center: Vec3::new(0.0, 0.0, 8.0),
        radius: 1.0,
    });
    // The blocker is beside the camera ray's path (camera at z = 5, below it).
    let s = scene(
        vec![material(2.0, 1.0, 0.5, 4.0), material(1.0, 1.0, 0.0, 1.0)],
        vec![(floor(), 0), (blocker, 1)],
        vec![Vec3::new(0.0, 0.0, 10.0)],
    );
    let (c, _) = shade(&s);
    assert_close(c, (2.0 * C + Vec3::ONE) / 6.0);

    // A transparent blocker casts no shadow.
    let mut clear = s.clone();
    clear.materials[1].transparent = true;
    let (c, _) = shade(&clear);
    let w = 0.5; // R.V = 1, |N.L| = 1
    assert_close(c, (2.0 * C + Vec3::ONE * (1.0 + w)) / (3.0 + w));
}

#[test]
fn mirror_child_adds_its_own_weighted_terms() {
    // Floor reflects with ratio 0.5 into a ceiling at z = 10 facing down.
    let ceiling = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-10.0, -10.0, 10.0),
            Vec3::new(-10.0, 10.0, 10.0),
            Vec3::new(10.0, 10.0, 10.0),
            Vec3::new(10.0, -10.0, 10.0),
        ],
    });
    let mut mirror = material(1.0, 1.0, 0.0, 1.0);
    mirror.reflect = 0.5;
    let mut red = material(1.0, 0.0, 0.0, 1.0);
    red.color = Vec3::X;
    let s = scene(vec![mirror, red], vec![(floor(), 0), (ceiling, 1)], vec![]);
    let (c, count) = shade(&s);
    // Floor: (C, 1), (W, 1); ceiling seen with intensity 0.5: (red, 0.5).
    assert_close(c, (C + Vec3::ONE + 0.5 * Vec3::X) / 2.5);
    assert_eq!(count.rays, 2);
}

#[test]
fn weak_and_deep_rays_stop() {
    let mut m = material(1.0, 1.0, 0.0, 1.0);
    m.reflect = 0.09; // child intensity below 0.1: not traced
    let s = scene(vec![m], vec![(floor(), 0)], vec![]);
    assert_eq!(shade(&s).1.rays, 1);

    // Two facing mirrors: camera ray plus four bounces (depth 1..=4).
    let ceiling = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-10.0, -10.0, 10.0),
            Vec3::new(-10.0, 10.0, 10.0),
            Vec3::new(10.0, 10.0, 10.0),
            Vec3::new(10.0, -10.0, 10.0),
        ],
    });
    let mut mirror = material(1.0, 1.0, 0.0, 1.0);
    mirror.reflect = 1.0;
    let s = scene(vec![mirror], vec![(floor(), 0), (ceiling, 0)], vec![]);
    assert_eq!(shade(&s).1.rays, 5);
}

#[test]
fn nothing_hit_is_black() {
    let s = scene(vec![material(1.0, 1.0, 0.0, 1.0)], vec![], vec![Vec3::Z]);
    assert_eq!(shade(&s).0, Vec3::ZERO);
}

#[test]
fn snell_bends_toward_the_normal_entering_water() {
    // Normal points into the water (down); a ray going down at 45 degrees enters.
    let n = -Vec3::Z;
    let d = normalize(Vec3::new(1.0, 0.0, -1.0));
    let (t, ior) = refract(d, n, 1.0, 1.33).unwrap();
    assert_eq!(ior, 1.33);
    let sin_t = std::f32::consts::FRAC_1_SQRT_2 / 1.33;
    assert!((t.x - sin_t).abs() < 1e-6, "{t}");
    assert!((t.z + (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-6, "{t}");
    // Straight through at normal incidence.
    let (t, _) = refract(-Vec3::Z, n, 1.0, 1.33).unwrap();
    assert_close(t, -Vec3::Z);
}

#[test]
fn leaving_a_denser_medium_past_the_critical_angle_reflects_totally() {
    let n = -Vec3::Z; // into the water; a ray going up leaves it
    let steep = Vec3::new(0.5, 0.0, 0.75f32.sqrt()); // 30 degrees from the normal
    let (t, ior) = refract(steep, n, 1.33, 1.33).unwrap();
    assert_eq!(ior, 1.0);
    assert!((t.x - 0.5 * 1.33).abs() < 1e-6);
    let grazing = Vec3::new(0.75f32.sqrt(), 0.0, 0.5); // 60 degrees: sin * 1.33 > 1
    assert_eq!(refract(grazing, n, 1.33, 1.33), None);
}

#[test]
fn total_internal_reflection_sends_the_refracted_share_to_the_mirror_ray() {
    // Camera inside water (index 1.33) looking up at 60 degrees at a water surface
    // whose normal points down into the water: the refracted child reflects back
    // down and sees the floor.
    let surface = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-50.0, -50.0, 5.0),
            Vec3::new(-50.0, 50.0, 5.0),
            Vec3::new(50.0, 50.0, 5.0),
            Vec3::new(50.0, -50.0, 5.0),
        ],
    });
    let mut water = material(0.0, 0.0, 0.0, 1.0);
    water.refract = 1.0;
    water.ior = 1.33;
    water.transparent = true;
    let mut floor_m = material(1.0, 0.0, 0.0, 1.0);
    floor_m.color = Vec3::Y;
    let big_floor = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-50.0, -50.0, 0.0),
            Vec3::new(50.0, -50.0, 0.0),
            Vec3::new(50.0, 50.0, 0.0),
            Vec3::new(-50.0, 50.0, 0.0),
        ],
    });
    let s = scene(
        vec![water, floor_m],
        vec![(surface, 0), (big_floor, 1)],
        vec![],
    );
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let classic = Classic::new(&s, &accel, 1.33);
    let mut acc = WeightedColor::default();
    let mut count = RayCount::default();
    let ray = Ray::new(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(0.75f32.sqrt(), 0.0, 0.5),
    );
    classic.trace_camera_ray(ray, &mut PixelSampler::new(0, 0, 0), &mut acc, &mut count);
    assert_eq!(count.rays, 2);
    assert_close(acc.mean(), Vec3::Y);
}

proptest::proptest! {
    /// A rectangle's frame gives the normal and texture coordinates the shape computes
    /// from its corners, bit for bit, on any rectangle and at any point.
    #[test]
    fn rectangle_frames_equal_the_shape_to_the_bit(
        a in proptest::array::uniform3(-1e3f32..1e3),
        u in proptest::array::uniform3(-1e2f32..1e2),
        w in proptest::array::uniform3(-1e2f32..1e2),
        p in proptest::array::uniform3(-1e3f32..1e3),
    ) {
        let (a, u, w, p) = (Vec3::from(a), Vec3::from(u), Vec3::from(w), Vec3::from(p));
        // v: perpendicular to u in the plane of u and w, so the corners make a rectangle.
        let v = w - u * (w.dot(u) / u.length_squared().max(1e-12));
        let r = Rectangle { v: [a, a + u, a + u + v, a + v] };
        let frame = RectangleFrame::of(&r);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        proptest::prop_assert_eq!(bits(frame.normal), bits(r.normal()));
        let (got, want) = (frame.coords(p), r.surface_coords(p));
        let fields = |c: SurfaceCoords| [c.x, c.y, c.x0, c.y0, c.len_x, c.len_y].map(f32::to_bits);
        proptest::prop_assert_eq!(fields(got), fields(want));
    }
}

#[test]
fn shading_reads_rectangle_frames_by_their_place_among_the_other_shapes() {
    // A sphere before the floor: the floor is the second of the other shapes.
    let mut s = scene(
        vec![material(1.0, 1.0, 0.0, 1.0)],
        vec![
            (
                Shape::Sphere(Sphere {
                    center: Vec3::new(50.0, 50.0, 50.0),
                    radius: 1.0,
                }),
                0,
            ),
            (floor(), 0),
        ],
        vec![Vec3::new(0.0, 0.0, 10.0)],
    );
    s.push_shape(floor(), 0);
    let accel = Accel::build(AccelKind::Bvh, &s.shapes);
    let classic = Classic::new(&s, &accel, 1.0);
    assert!(classic.rectangle(0).is_none());
    for shape in [1, 2] {
        let frame = classic.rectangle(shape).expect("a rectangle");
        let Shape::Rectangle(r) = s.shapes.get(shape as usize) else {
            unreachable!()
        };
        assert_eq!(frame.normal, r.normal());
        assert_eq!(frame.normal, Vec3::Z);
    }
}

/// A tile's camera rays shaded as a packet (hits, shadow rays and children found
/// ahead) give each pixel what the ray traced alone gives, bit for bit, and count the
/// same rays: over a mirroring floor with an opaque ball's shadows and highlights, and a
/// glass ball whose rays refract and reflect.
#[test]
fn camera_packets_shade_as_each_ray_traced_alone() {
    let mut floor_material = material(1.0, 1.0, 0.8, 20.0);
    floor_material.reflect = 0.4;
    let mut glass = material(0.2, 0.1, 0.9, 60.0);
    glass.reflect = 0.2;
    glass.refract = 0.7;
    glass.ior = 1.5;
    glass.transparent = true;
    let ball = |x: f32, y: f32, r: f32| {
        Shape::Sphere(Sphere {
            center: Vec3::new(x, y, r),
            radius: r,
        })
    };
    let s = scene(
        vec![floor_material, material(1.0, 1.0, 0.5, 8.0), glass],
        vec![
            (floor(), 0),
            (ball(-2.5, 1.0, 1.5), 1),
            (ball(2.5, -1.0, 2.0), 2),
        ],
        vec![Vec3::new(-6.0, 4.0, 9.0), Vec3::new(5.0, 6.0, 12.0)],
    );
    let accel = Accel::build(AccelKind::Bvh, &s.shapes);
    let classic = Classic::new(&s, &accel, 1.0);
    let eye = Vec3::new(0.0, -3.0, 14.0);
    let (w, h) = (32, 32);
    let ray_at = |x: u32, y: u32| {
        let target = Vec3::new(
            (x as f32 + 0.5) / w as f32 * 18.0 - 9.0,
            (y as f32 + 0.5) / h as f32 * 18.0 - 9.0,
            0.0,
        );
        Ray::new(eye, normalize(target - eye))
    };
    let (mut shadowed, mut in_glass) = (0, 0);
    let (mut packed_count, mut alone_count) = (RayCount::default(), RayCount::default());
    for ty in (0..h).step_by(4) {
        for tx in (0..w).step_by(4) {
            let rays: Vec<Ray> = (0..16).map(|i| ray_at(tx + i % 4, ty + i / 4)).collect();
            let mut hits = [None; PACKET_RAYS];
            accel.closest_packet(&rays, f32::INFINITY, &mut hits);
            let mut samplers: Vec<PixelSampler> = (0..16)
                .map(|i| PixelSampler::new(0, tx + i % 4, ty + i / 4))
                .collect();
            let mut packed = [WeightedColor::default(); 16];
            classic.trace_camera_packet(
                &rays,
                &hits,
                &mut samplers,
                &mut packed,
                &mut packed_count,
            );
            for (i, ray) in rays.iter().enumerate() {
                let mut alone = WeightedColor::default();
                let mut sampler = PixelSampler::new(0, tx + i as u32 % 4, ty + i as u32 / 4);
                classic.trace_camera_ray(*ray, &mut sampler, &mut alone, &mut alone_count);
                assert_eq!(
                    (
                        packed[i].sum.to_array().map(f32::to_bits),
                        packed[i].weight.to_bits()
                    ),
                    (
                        alone.sum.to_array().map(f32::to_bits),
                        alone.weight.to_bits()
                    ),
                    "tile ({tx}, {ty}) ray {i}"
                );
                // What the tiles cover, so that the comparison means something.
                let Some(hit) = hits[i] else { continue };
                let p = ray.at(hit.t);
                if hit.shape == 0 {
                    let (shadow, t_max) = from_light(s.lights[0].position, p).unwrap();
                    shadowed += usize::from(accel.occluded(&shadow, t_max, |k| k.shape == 1));
                }
                in_glass += usize::from(hit.shape == 2);
            }
        }
    }
    assert_eq!(packed_count.rays, alone_count.rays);
    assert!(
        shadowed > 10,
        "{shadowed} floor points in the ball's shadow"
    );
    assert!(in_glass > 10, "{in_glass} rays on the glass ball");
}
