//! Every intersector gives the answers of brute force.

use super::*;
use crate::math::Vec3;
use crate::scene::{Rectangle, Shape, Shapes, Sphere, Triangle};
use proptest::prelude::*;

fn bvh(b: Bvh<'_>) -> Accel<'_> {
    Accel::from(Intersector::Bvh(b))
}

fn v(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn shape_strategy() -> impl Strategy<Value = Shape> {
    let p = || prop::array::uniform3(-50.0f32..50.0);
    prop_oneof![
        (p(), 0.5f32..10.0).prop_map(|(c, r)| Shape::Sphere(Sphere {
            center: v(c),
            radius: r
        })),
        (p(), p(), p()).prop_map(|(a, b, c)| Shape::Triangle(Triangle {
            v: [v(a), v(b), v(c)]
        })),
        (p(), p(), 0.5f32..20.0).prop_map(|(a, d, h)| {
            // A rectangle from a corner, an edge direction and a height along a
            // perpendicular: always a true rectangle.
            let a = v(a);
            let e1 = v(d).normalize_or(Vec3::X) * 15.0;
            let e2 = e1.any_orthonormal_vector() * h;
            Shape::Rectangle(Rectangle {
                v: [a, a + e1, a + e1 + e2, a + e2],
            })
        }),
    ]
}

fn ray_strategy() -> impl Strategy<Value = Ray> {
    (
        prop::array::uniform3(-80.0f32..80.0),
        prop::array::uniform3(-1.0f32..1.0),
    )
        .prop_filter("direction", |(_, d)| v(*d).length() > 1e-3)
        .prop_map(|(o, d)| Ray::new(v(o), v(d)))
}

/// Every fast intersector against brute force: the same closest hit (the same shape
/// tests give the same distance bit for bit, and ties go to the lower index in all) and
/// the same shadow answer.
fn agree_with_brute_force(shapes: &[Shape], rays: &[Ray]) -> Result<(), TestCaseError> {
    agree_on(&Shapes::from(shapes), rays)
}

fn agree_on(shapes: &Shapes, rays: &[Ray]) -> Result<(), TestCaseError> {
    let list = Accel::build(AccelKind::List, shapes);
    let fast = [
        ("octree", Accel::build(AccelKind::Octree, shapes)),
        (
            "bvh sse2",
            bvh(Bvh::build_with(
                shapes,
                SimdLevel::Baseline,
                Leaves::Indexed,
            )),
        ),
        (
            "bvh avx2",
            bvh(Bvh::build_with(shapes, SimdLevel::Avx2, Leaves::Indexed)),
        ),
        (
            "bvh copied sse2",
            bvh(Bvh::build_with(shapes, SimdLevel::Baseline, Leaves::Copied)),
        ),
        (
            "bvh copied avx2",
            bvh(Bvh::build_with(shapes, SimdLevel::Avx2, Leaves::Copied)),
        ),
    ];
    for (kind, fast) in &fast {
        // Packets of every size from 1 to 8: the single-ray answers, bit for bit.
        let mut start = 0;
        for size in (1..=PACKET_RAYS).cycle() {
            if start >= rays.len() {
                break;
            }
            let chunk = &rays[start..(start + size).min(rays.len())];
            start += size;
            for t_max in [5.0, 40.0, f32::INFINITY] {
                let mut hits = vec![None; chunk.len()];
                fast.closest_packet(chunk, t_max, &mut hits);
                let limits: Vec<f32> = (0..chunk.len())
                    .map(|i| t_max / (1 + i % 3) as f32)
                    .collect();
                let even = |s: ShapeId| s.shape.is_multiple_of(2);
                let blocked = fast.occluded_packet(chunk, &limits, even);
                for (i, ray) in chunk.iter().enumerate() {
                    prop_assert_eq!(
                        hits[i],
                        list.closest(ray, t_max),
                        "{} packet of {}, ray {}",
                        kind,
                        size,
                        i
                    );
                    prop_assert_eq!(
                        blocked >> i & 1 == 1,
                        list.occluded(ray, limits[i], even),
                        "{} shadow packet of {}, ray {}",
                        kind,
                        size,
                        i
                    );
                }
            }
        }
        for ray in rays {
            for t_max in [5.0, 40.0, f32::INFINITY] {
                let (a, b) = (list.closest(ray, t_max), fast.closest(ray, t_max));
                prop_assert_eq!(a, b, "{} closest, t_max {}, ray {:?}", kind, t_max, ray);
                let even = |s: ShapeId| s.shape.is_multiple_of(2);
                prop_assert_eq!(
                    list.occluded(ray, t_max, even),
                    fast.occluded(ray, t_max, even),
                    "{} occluded, t_max {}",
                    kind,
                    t_max
                );
            }
        }
    }
    Ok(())
}

/// A ray from a random point towards a random point of a random shape's box, so most
/// rays hit something (uniform random rays mostly miss small scenes).
fn aimed_rays(shapes: &[Shape], picks: &[(usize, [f32; 3], [f32; 3])]) -> Vec<Ray> {
    picks
        .iter()
        .filter(|_| !shapes.is_empty())
        .map(|&(i, o, f)| {
            let b = shapes[i % shapes.len()].bounds();
            let target = b.min + b.extent() * v(f);
            Ray::new(v(o), target - v(o))
        })
        .filter(|r| r.dir.is_finite())
        .collect()
}

/// `shape` with every coordinate (and radius) multiplied by `k`.
fn scaled(shape: &Shape, k: f32) -> Shape {
    match *shape {
        Shape::Sphere(s) => Shape::Sphere(Sphere {
            center: s.center * k,
            radius: s.radius * k,
        }),
        Shape::Triangle(t) => Shape::Triangle(Triangle {
            v: t.v.map(|p| p * k),
        }),
        Shape::Rectangle(r) => Shape::Rectangle(Rectangle {
            v: r.v.map(|p| p * k),
        }),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Coordinates up to about 1.8e38, where the scene's extent overflows f32: the
    /// octree's cells must still be finite (they once became NaN and hid everything).
    #[test]
    fn intersectors_agree_at_extreme_magnitudes(
        shapes in prop::collection::vec(shape_strategy(), 1..40),
        picks in prop::collection::vec(
            (0usize..1000, prop::array::uniform3(-80.0f32..80.0), prop::array::uniform3(0.0f32..1.0)),
            16,
        ),
        exponent in 30.0f32..36.5,
    ) {
        let k = 10f32.powf(exponent);
        let big: Vec<Shape> = shapes.iter().map(|s| scaled(s, k)).collect();
        let rays: Vec<Ray> = aimed_rays(&shapes, &picks)
            .into_iter()
            .map(|r| Ray { origin: r.origin * k, dir: r.dir })
            .collect();
        agree_with_brute_force(&big, &rays)?;
    }

    #[test]
    fn intersectors_agree_with_brute_force_on_random_rays(
        shapes in prop::collection::vec(shape_strategy(), 0..60),
        rays in prop::collection::vec(ray_strategy(), 32),
    ) {
        agree_with_brute_force(&shapes, &rays)?;
    }

    /// Camera-like packets: every ray from one eye, toward nearby points.
    #[test]
    fn packets_from_one_eye_agree_with_brute_force(
        shapes in prop::collection::vec(shape_strategy(), 1..300),
        eye in prop::array::uniform3(-80.0f32..80.0),
        target in prop::array::uniform3(-20.0f32..20.0),
        jitter in prop::collection::vec(prop::array::uniform3(-3.0f32..3.0), 40),
    ) {
        let rays: Vec<Ray> = jitter
            .iter()
            .map(|j| Ray::new(v(eye), v(target) + v(*j) - v(eye)))
            .filter(|r| r.dir.is_finite())
            .collect();
        agree_with_brute_force(&shapes, &rays)?;
    }

    /// Lens-like packets: origins spread over a small disk, directions all in one
    /// octant (so the BVH tests nodes once against the packet's frustum).
    #[test]
    fn packets_through_a_lens_agree_with_brute_force(
        shapes in prop::collection::vec(shape_strategy(), 1..300),
        eye in prop::array::uniform3(-80.0f32..80.0),
        focus in prop::array::uniform3(-20.0f32..20.0),
        lens in prop::collection::vec((prop::array::uniform3(-2.0f32..2.0), prop::array::uniform3(-1.0f32..1.0)), 40),
    ) {
        let rays: Vec<Ray> = lens
            .iter()
            .map(|(o, j)| {
                let origin = v(eye) + v(*o);
                Ray::new(origin, v(focus) + v(*j) - origin)
            })
            .filter(|r| r.dir.is_finite())
            .collect();
        agree_with_brute_force(&shapes, &rays)?;
    }

    #[test]
    fn intersectors_agree_with_brute_force_on_aimed_rays(
        shapes in prop::collection::vec(shape_strategy(), 1..200),
        picks in prop::collection::vec(
            (0usize..1000, prop::array::uniform3(-80.0f32..80.0), prop::array::uniform3(0.0f32..1.0)),
            32,
        ),
    ) {
        agree_with_brute_force(&shapes, &aimed_rays(&shapes, &picks))?;
    }

    /// A tessellated grid stored as a mesh: every triangle shares its edges and its
    /// corners, and rays through vertices and along edges test the ties.
    #[test]
    fn intersectors_agree_on_shared_edges(
        n in 1usize..12,
        picks in prop::collection::vec((0i32..24, 0i32..24, -3i32..4, -3i32..4), 32),
    ) {
        let positions: Vec<Vec3> = (0..=n)
            .flat_map(|y| (0..=n).map(move |x| Vec3::new(x as f32, y as f32, 0.0)))
            .collect();
        let mut triangles = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let p = |dx: usize, dy: usize| ((y + dy) * (n + 1) + x + dx) as u32;
                triangles.push([p(0, 0), p(1, 0), p(1, 1)]);
                triangles.push([p(0, 0), p(1, 1), p(0, 1)]);
            }
        }
        let mut shapes = Shapes::new();
        shapes.push_mesh(&positions, &triangles);
        let rays: Vec<Ray> = picks
            .iter()
            .map(|&(x, y, dx, dy)| {
                let target = Vec3::new(x as f32 * 0.5, y as f32 * 0.5, 0.0);
                let origin = target + Vec3::new(dx as f32, dy as f32, 7.0);
                Ray::new(origin, target - origin)
            })
            .collect();
        agree_on(&shapes, &rays)?;
    }
}

#[test]
fn octree_splits_crowded_cells() {
    let shapes: Vec<Shape> = (0..64)
        .map(|i| {
            Shape::Sphere(Sphere {
                center: Vec3::new(
                    (i % 4) as f32 * 10.0,
                    (i / 4 % 4) as f32 * 10.0,
                    (i / 16) as f32 * 10.0,
                ),
                radius: 1.0,
            })
        })
        .collect();
    let shapes = Shapes::from(shapes);
    let Intersector::Octree(tree) = Intersector::build(AccelKind::Octree, &shapes) else {
        unreachable!()
    };
    assert!(tree.node_count() > 8);
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    let hit = tree.closest(&ray, f32::INFINITY).unwrap();
    assert_eq!(hit, Hit::world(4.0, 0));
}

#[test]
fn accel_names_parse_back() {
    for k in AccelKind::ALL {
        assert_eq!(k.name().parse::<AccelKind>(), Ok(k));
    }
    assert!("bsp".parse::<AccelKind>().unwrap_err().contains("expected"));
}

/// A shape with a NaN coordinate is never hit and hides no other shape, whichever
/// intersector: every seventh triangle of a grid is broken, and rays aimed at the others
/// find them.
#[test]
fn shapes_with_a_nan_coordinate_hide_no_other_shape() {
    let mut shapes = Vec::new();
    for i in 0..900 {
        let (x, y) = ((i % 30) as f32, (i / 30) as f32);
        let mut corners = [v([x, y, 0.0]), v([x + 1.0, y, 0.0]), v([x, y + 1.0, 0.0])];
        if i % 7 == 3 {
            corners[i % 3][(i / 7) % 3] = f32::NAN;
        }
        shapes.push(Shape::Triangle(Triangle { v: corners }));
    }
    let shapes = Shapes::from(shapes);
    for kind in AccelKind::ALL {
        let accel = Accel::build(kind, &shapes);
        for i in 0..900u32 {
            let (x, y) = ((i % 30) as f32 + 0.25, (i / 30) as f32 + 0.25);
            let ray = Ray::new(v([x, y, 3.0]), -Vec3::Z);
            let expected = (i % 7 != 3).then_some(Hit::world(3.0, i));
            assert_eq!(
                accel.closest(&ray, f32::INFINITY),
                expected,
                "{kind} triangle {i}"
            );
            assert_eq!(accel.occluded(&ray, 4.0, |_| true), expected.is_some());
        }
    }
}
