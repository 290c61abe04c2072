use super::*;
use crate::accel::bvh::leaf4::{Leaf4, RayLanes};
use crate::accel::{ListAccel, PACKET_RAYS};
use crate::math::{Vec3, offset_origin};
use crate::scene::{Rectangle, Shape, Sphere, Triangle};
use rand_core::Rng;
use rand_pcg::Pcg32;

fn unit(rng: &mut Pcg32) -> f32 {
    (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
}

/// `2^k` for a whole `k` drawn from `lo..=hi`.
fn power(rng: &mut Pcg32, lo: i32, hi: i32) -> f32 {
    2f32.powi(lo + (rng.next_u32() % (hi - lo + 1) as u32) as i32)
}

/// A point on the plane `axis = plane` with in-plane coordinates `a`, `b`.
fn on_plane(axis: usize, plane: f32, a: f32, b: f32) -> Vec3 {
    let mut p = [0.0; 3];
    p[axis] = plane;
    p[(axis + 1) % 3] = a;
    p[(axis + 2) % 3] = b;
    Vec3::from_array(p)
}

/// Rays aimed at random walls (triangles and rectangles) from just inside them, at
/// every scale, with limits a hair short of the crossing, past it, infinite, NaN, zero
/// and negative: where the walls' test clears a ray, the triangle test itself finds no
/// hit. Near misses of the margin are counted, so the test is known to probe where
/// rounding decides.
#[test]
fn a_wall_meets_no_ray_its_test_clears() {
    let mut rng = Pcg32::new(0x3a11, 5);
    let (mut cleared, mut hits, mut close_calls) = (0, 0, 0);
    for _ in 0..4000 {
        let axis = rng.next_u32() as usize % 3;
        let scale = power(&mut rng, -8, 12);
        let plane = (unit(&mut rng) - 0.5) * scale * 4.0;
        let inward = if rng.next_u32() & 1 == 0 { 1.0 } else { -1.0 };
        let corner = |rng: &mut Pcg32| {
            let (a, b) = (unit(rng) * scale, unit(rng) * scale);
            on_plane(axis, plane, a, b)
        };
        let v = [corner(&mut rng), corner(&mut rng), corner(&mut rng)];
        if !usable(&v.map(|p| p.to_array()), axis) {
            continue;
        }
        // Every other wall a rectangle on the same three corners.
        let rectangle = rng.next_u32() & 1 == 1;
        let shape = if rectangle {
            let [a, b, d] = v;
            Shape::Rectangle(Rectangle {
                v: [a, b, b + d - a, d],
            })
        } else {
            Shape::Triangle(Triangle { v })
        };
        let shapes = Shapes::from(vec![shape]);
        let leaf = Leaf4::new(&shapes, &[0]);
        let face = Face {
            axis,
            plane,
            inward,
        };
        for _ in 0..64 {
            // A point of the triangle (or near it), and an origin above it.
            let (s, t) = (unit(&mut rng) * 1.2 - 0.1, unit(&mut rng) * 1.2 - 0.1);
            let target = if rectangle {
                v[0] + (v[1] - v[0]) * s + (v[2] - v[0]) * t
            } else {
                v[0] + (v[1] - v[0]) * s * (1.0 - t) + (v[2] - v[0]) * s * t
            };
            let mut normal = [0.0; 3];
            normal[axis] = inward;
            let height = scale * power(&mut rng, -50, 2) * unit(&mut rng);
            let sideways = Vec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)) - 0.5;
            let origin = target + Vec3::from_array(normal) * height + sideways * scale;
            let mut dir = (target - origin).normalize_or(Vec3::X);
            match rng.next_u32() % 8 {
                0 => dir = -dir,
                1 => {
                    // Along the plane, or barely across it.
                    let mut d = dir.to_array();
                    d[axis] = [0.0, 1e-30, -1e-30, 1e-12][rng.next_u32() as usize % 4];
                    dir = Vec3::from_array(d);
                }
                _ => {}
            }
            let crossing = (target - origin).length();
            let t_max = match rng.next_u32() % 8 {
                0 => f32::INFINITY,
                1 => [f32::NAN, 0.0, -1.0][rng.next_u32() as usize % 3],
                2 => crossing * (1.0 + power(&mut rng, -24, -4)),
                _ => crossing * (1.0 - power(&mut rng, -24, -2)),
            };
            let ray = Ray {
                origin,
                dir: Vec3::from_array(dir.to_array()),
            };
            let (met, _) = leaf.intersect_flat(&RayLanes::new(&ray), t_max);
            let hit = met & 1 == 1;
            hits += usize::from(hit);
            let o = ray.origin.to_array()[axis];
            let d = ray.dir.to_array()[axis];
            if face.clears(o, d, t_max) {
                assert!(
                    !hit,
                    "a cleared ray meets its wall: {ray:?}, t_max {t_max}, wall {v:?}"
                );
                cleared += 1;
                // Heading for the triangle and stopping within a thousandth of it.
                close_calls += usize::from(d * inward < 0.0 && t_max > crossing * 0.999);
            }
        }
    }
    assert!(cleared > 50_000, "{cleared} rays cleared");
    assert!(hits > 20_000, "{hits} rays met their wall");
    assert!(close_calls > 500, "{close_calls} close calls");
}

/// A room: a box whose six faces are walls (the back one a rectangle, the front one
/// split into four around a window), with a leaning panel, blocks, a sphere and a
/// rectangle inside it.
fn room(rng: &mut Pcg32) -> Shapes {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.5), Vec3::new(1.0, 2.0, 1.0));
    let mut shapes = Vec::new();
    let quad = |shapes: &mut Vec<Shape>, [a, b, c, d]: [Vec3; 4]| {
        shapes.push(Shape::Triangle(Triangle { v: [a, b, c] }));
        shapes.push(Shape::Triangle(Triangle { v: [a, c, d] }));
    };
    let corner =
        |[x, y, z]: [usize; 3]| Vec3::new([lo.x, hi.x][x], [lo.y, hi.y][y], [lo.z, hi.z][z]);
    // Floor, ceiling, left and right.
    for q in [
        [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]],
        [[0, 1, 0], [0, 1, 1], [1, 1, 1], [1, 1, 0]],
        [[0, 0, 0], [0, 0, 1], [0, 1, 1], [0, 1, 0]],
        [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]],
    ] {
        quad(&mut shapes, q.map(corner));
    }
    shapes.push(Shape::Rectangle(Rectangle {
        v: [[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]].map(corner),
    }));
    // The front, with a window left open in its middle.
    for [x0, y0, x1, y1] in [
        [-1.0, 0.0, 1.0, 0.5],
        [-1.0, 1.5, 1.0, 2.0],
        [-1.0, 0.5, -0.5, 1.5],
        [0.5, 0.5, 1.0, 1.5],
    ] {
        let front = |x: f32, y: f32| Vec3::new(x, y, hi.z);
        quad(
            &mut shapes,
            [front(x0, y0), front(x1, y0), front(x1, y1), front(x0, y1)],
        );
    }
    // A panel leaning on the left wall.
    quad(
        &mut shapes,
        [
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(-0.7, 0.0, -1.0),
            Vec3::new(-0.7, 1.0, -0.4),
            Vec3::new(-1.0, 1.0, -0.4),
        ],
    );
    for _ in 0..40 {
        let a = Vec3::new(
            unit(rng) * 1.8 - 0.9,
            unit(rng) * 1.8,
            unit(rng) * 2.2 - 1.4,
        );
        let inside = |p: Vec3| p.clamp(lo + 0.01, hi - 0.01);
        let mut near = || inside(a + (Vec3::new(unit(rng), unit(rng), unit(rng)) - 0.5) * 0.6);
        let (b, c) = (near(), near());
        shapes.push(Shape::Triangle(Triangle { v: [a, b, c] }));
    }
    shapes.push(Shape::Sphere(Sphere {
        center: Vec3::new(0.4, 0.3, 0.2),
        radius: 0.3,
    }));
    let r = |x: f32, y: f32| Vec3::new(x, y, -0.5);
    shapes.push(Shape::Rectangle(Rectangle {
        v: [r(0.2, 1.0), r(0.6, 1.0), r(0.6, 1.3), r(0.2, 1.3)],
    }));
    Shapes::from(shapes)
}

/// Shadow rays in a room, from points on its shapes (moved off them as the
/// integrators move them) toward points inside it, on its walls and outside its
/// window, and toward the sky: every answer, one ray at a time, sixteen scattered or
/// as a packet, is the brute-force one, with every leaf layout and instruction set.
#[test]
fn shadow_rays_in_a_room_are_answered_as_brute_force_answers() {
    let mut rng = Pcg32::new(0x400e, 9);
    let shapes = room(&mut rng);
    let list = ListAccel::new(&shapes);
    let mut through_walls = [0usize; 2];
    for leaves in [Leaves::Indexed, Leaves::Copied] {
        for simd in [SimdLevel::Baseline, SimdLevel::Avx2] {
            let bvh = Bvh::build_with(&shapes, simd, leaves);
            let indoors = bvh.indoors.as_ref().expect("the room's walls");
            assert_eq!(indoors.walls.faces.len(), 6);
            // Four sides of two triangles, the back's rectangle, the front's four quads.
            assert_eq!(indoors.tree.shape_count(), shapes.len() - 17);
            for _ in 0..300 {
                let n = 1 + rng.next_u32() as usize % PACKET_RAYS;
                let mut rays = Vec::new();
                let mut limits = Vec::new();
                for _ in 0..n {
                    let (ray, t_max) = shadow_ray(&mut rng, &shapes);
                    rays.push(ray);
                    limits.push(t_max);
                }
                let many = bvh.occluded_many(&rays, &limits);
                let odd = |s: u32| s % 2 == 1;
                let packet = bvh.occluded_packet(&rays, &limits, odd);
                for (i, (ray, &t_max)) in rays.iter().zip(&limits).enumerate() {
                    let truth = list.occluded(ray, t_max, |_| true);
                    assert_eq!(bvh.occluded(ray, t_max, |_| true), truth, "{ray:?} {t_max}");
                    assert_eq!(many >> i & 1 == 1, truth, "scattered {ray:?} {t_max}");
                    let odd_truth = list.occluded(ray, t_max, odd);
                    assert_eq!(packet >> i & 1 == 1, odd_truth, "packet {ray:?} {t_max}");
                    through_walls[usize::from(indoors.clear(ray, t_max))] += 1;
                }
            }
        }
    }
    // Rays toward points inside the room (half of them) walk the tree without the
    // walls; those toward the walls, out of the window and to the sky need the whole.
    let [whole, inner] = through_walls;
    assert!(inner > 4000 && whole > 2000, "{inner} inside, {whole} not");
}

/// A shadow ray from a point on a random shape of `shapes` toward a point in or
/// beyond the room, or toward the sky, and its limit.
fn shadow_ray(rng: &mut Pcg32, shapes: &Shapes) -> (Ray, f32) {
    let shape = shapes.get(rng.next_u32() as usize % shapes.len());
    let (s, t) = (unit(rng), unit(rng));
    let (from, normal) = match shape {
        Shape::Triangle(tri) => {
            let [a, b, c] = tri.v;
            let p = a + (b - a) * s * (1.0 - t) + (c - a) * s * t;
            (p, crate::math::cross(b - a, c - a).normalize_or(Vec3::Y))
        }
        Shape::Sphere(sp) => {
            let d = (Vec3::new(unit(rng), unit(rng), unit(rng)) - 0.5).normalize_or(Vec3::Y);
            (sp.center + d * sp.radius, d)
        }
        Shape::Rectangle(r) => (
            r.v[0] + (r.v[1] - r.v[0]) * s + (r.v[3] - r.v[0]) * t,
            Vec3::Z,
        ),
    };
    let to = match rng.next_u32() % 6 {
        // Outside the room, seen through the window or not.
        0 => Vec3::new(
            unit(rng) * 4.0 - 2.0,
            unit(rng) * 3.0,
            1.2 + unit(rng) * 2.0,
        ),
        // A point on one of the walls.
        1 => Vec3::new(-1.0, unit(rng) * 2.0, unit(rng) * 2.5 - 1.5),
        2 => {
            let dir = (Vec3::new(unit(rng), unit(rng), unit(rng)) - 0.5).normalize_or(Vec3::Y);
            let ray = Ray {
                origin: offset_origin(from, normal, dir),
                dir,
            };
            return (
                ray,
                [f32::INFINITY, f32::NAN, 0.0][rng.next_u32() as usize % 3],
            );
        }
        _ => Vec3::new(
            unit(rng) * 1.9 - 0.95,
            unit(rng) * 1.9 + 0.05,
            unit(rng) * 2.4 - 1.45,
        ),
    };
    let d = to - from;
    let dist = d.length();
    let dir = d / dist;
    let origin = offset_origin(from, normal, dir);
    let t_max = dist * (1.0 - 1e-4) - crate::math::surface_epsilon(origin);
    (Ray { origin, dir }, t_max)
}

/// Walls are found only flat on the box's faces, only where usable, and only in a
/// scene small enough for a second tree.
#[test]
fn walls_are_triangles_flat_on_the_scene_box() {
    let mut rng = Pcg32::new(0x3a12, 1);
    let shapes = room(&mut rng);
    let (walls, others) = Walls::of(&shapes).unwrap();
    assert_eq!(walls.faces.len(), 6);
    // The leaning panel touches the floor and the left wall but lies on neither.
    for i in 17..21u32 {
        assert!(others.contains(&i), "shape {i}");
    }
    // A sliver on the floor is not a wall: its edges are nearly parallel.
    let sliver = Triangle {
        v: [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.5, 0.0, 1e-3),
        ],
    };
    let floor = Triangle {
        v: [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ],
    };
    let top = Sphere {
        center: Vec3::new(0.5, 1.0, 0.5),
        radius: 0.25,
    };
    let shapes = Shapes::from(vec![
        Shape::Triangle(sliver),
        Shape::Sphere(top),
        Shape::Triangle(floor),
    ]);
    let (walls, others) = Walls::of(&shapes).unwrap();
    assert_eq!(others, vec![0, 1]);
    assert_eq!(
        walls.faces,
        vec![Face {
            axis: 1,
            plane: 0.0,
            inward: 1.0
        }]
    );
    // Nothing flat on the box: no walls.
    let shapes = Shapes::from(vec![Shape::Sphere(top)]);
    assert!(Walls::of(&shapes).is_none());
    // Too many shapes for a second tree.
    let many = vec![Shape::Triangle(floor); INDOOR_SHAPES + 1];
    let shapes = Shapes::from(many);
    assert!(Indoors::of(&shapes, SimdLevel::Baseline, Leaves::Indexed).is_none());
}
