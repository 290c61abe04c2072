//! Every intersector gives the answers of brute force.

use super::*;
use crate::math::Vec3;
use crate::scene::{Rectangle, Sphere, Triangle};
use proptest::prelude::*;

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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn octree_agrees_with_brute_force(
        shapes in prop::collection::vec(shape_strategy(), 0..60),
        rays in prop::collection::vec(ray_strategy(), 32),
    ) {
        let list = Accel::build(AccelKind::List, &shapes);
        let octree = Accel::build(AccelKind::Octree, &shapes);
        for ray in &rays {
            let a = list.closest(ray, f32::INFINITY);
            let b = octree.closest(ray, f32::INFINITY);
            match (a, b) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    // Same shape tests in the same order give the same answer exactly;
                    // ties go to the lower index in both.
                    prop_assert_eq!(a, b);
                }
                _ => prop_assert!(false, "list {a:?} octree {b:?}"),
            }
            let even = |s: u32| s.is_multiple_of(2);
            for t_max in [5.0, 40.0, f32::INFINITY] {
                prop_assert_eq!(list.occluded(ray, t_max, even), octree.occluded(ray, t_max, even));
            }
        }
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
    let Accel::Octree(tree) = Accel::build(AccelKind::Octree, &shapes) else {
        unreachable!()
    };
    assert!(tree.node_count() > 8);
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    let hit = tree.closest(&ray, f32::INFINITY).unwrap();
    assert_eq!(hit, Hit { t: 4.0, shape: 0 });
}

#[test]
fn accel_names_parse_back() {
    for k in AccelKind::ALL {
        assert_eq!(k.name().parse::<AccelKind>(), Ok(k));
    }
    assert!("bsp".parse::<AccelKind>().unwrap_err().contains("expected"));
}
