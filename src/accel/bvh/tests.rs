use super::*;
use crate::math::Vec3;
use crate::scene::{Shape, Sphere, Triangle};

#[test]
fn a_grid_of_triangles_is_hit_where_it_is_and_nowhere_else() {
    // 32 x 32 unit squares as triangle pairs in the plane z = 0.
    let mut shapes = Vec::new();
    for y in 0..32 {
        for x in 0..32 {
            let p = |dx: f32, dy: f32| Vec3::new(x as f32 + dx, y as f32 + dy, 0.0);
            shapes.push(Shape::Triangle(Triangle {
                v: [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)],
            }));
            shapes.push(Shape::Triangle(Triangle {
                v: [p(0.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
            }));
        }
    }
    let shapes = Shapes::from(shapes);
    for leaves in [Leaves::Indexed, Leaves::Copied] {
        let bvh = Bvh::build(&shapes, leaves);
        assert!(bvh.node_count() > 1);
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 2.5), Vec3::new(0.0, 0.0, -1.0));
        // (10.75, 3.25) lies in the lower-right triangle of square (10, 3).
        let hit = bvh.closest(&down(10.75, 3.25), f32::INFINITY).unwrap();
        assert_eq!(hit.t, 2.5);
        assert_eq!(hit.shape, 2 * (3 * 32 + 10));
        let hit = bvh.closest(&down(10.25, 3.75), f32::INFINITY).unwrap();
        assert_eq!(hit.shape, 2 * (3 * 32 + 10) + 1);
        assert_eq!(bvh.closest(&down(40.0, 3.0), f32::INFINITY), None);
        assert_eq!(bvh.closest(&down(10.75, 3.25), 2.0), None);
        assert!(bvh.occluded(&down(10.75, 3.25), 3.0, |_| true));
        assert!(!bvh.occluded(&down(10.75, 3.25), 2.0, |_| true));
        assert!(!bvh.occluded(&down(10.75, 3.25), 3.0, |s| s != 2 * (3 * 32 + 10)));
    }
}

#[test]
fn indexed_leaves_name_each_triangle_once_and_copied_leaves_hold_them_in_blocks() {
    // A strip of 2048 triangles.
    let shapes: Vec<Shape> = (0..2048)
        .map(|i| {
            let x = i as f32;
            Shape::Triangle(Triangle {
                v: [
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x + 1.0, 0.0, 0.0),
                    Vec3::new(x, 1.0, 0.0),
                ],
            })
        })
        .collect();
    let shapes = Shapes::from(shapes);
    let indexed = Bvh::build(&shapes, Leaves::Indexed);
    let mut named = indexed.prims.clone();
    named.sort_unstable();
    assert_eq!(named, (0..2048).collect::<Vec<u32>>());
    assert!(indexed.stored.is_empty());

    let copied = Bvh::build(&shapes, Leaves::Copied);
    assert!(copied.prims.is_empty());
    // Each leaf of up to eight triangles takes one or two blocks of four.
    assert!(copied.stored.len() >= 2048 / 4);
    assert_eq!(copied.node_count(), indexed.node_count());
    assert_eq!(
        copied.memory_bytes() - copied.nodes.capacity() * size_of::<Node8>(),
        copied.stored.capacity() * size_of::<Leaf4>()
    );
    assert!(copied.memory_bytes() > indexed.memory_bytes() + 2048 * 36);
}

#[test]
fn one_shape_and_no_shapes() {
    let one = Shapes::from(vec![Shape::Sphere(Sphere {
        center: Vec3::new(0.0, 0.0, 10.0),
        radius: 2.0,
    })]);
    let bvh = Bvh::build(&one, Leaves::Indexed);
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(bvh.closest(&ray, f32::INFINITY).map(|h| h.t), Some(8.0));
    let none = Shapes::new();
    assert!(
        Bvh::build(&none, Leaves::Indexed)
            .closest(&ray, f32::INFINITY)
            .is_none()
    );
    assert!(!Bvh::build(&none, Leaves::Indexed).occluded(&ray, f32::INFINITY, |_| true));
}

#[test]
fn coincident_shapes_beyond_a_leaf_still_build_and_tie_to_the_lowest_index() {
    let tri = Shape::Triangle(Triangle {
        v: [
            Vec3::new(-1.0, -1.0, 5.0),
            Vec3::new(1.0, -1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
        ],
    });
    let shapes = Shapes::from(vec![tri; 100]);
    let bvh = Bvh::build(&shapes, Leaves::Indexed);
    let hit = bvh.closest(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY);
    assert_eq!(hit, Some(Hit::world(5.0, 0)));
}
