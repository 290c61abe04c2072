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
    // The strip lies flat on its box: all walls, and a second tree of nothing.
    let walls = copied.indoors.as_ref().map_or(0, |i| i.memory_bytes());
    assert_eq!(
        copied.memory_bytes() - copied.nodes.capacity() * size_of::<Node8>() - walls,
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

/// Whether the ray `o + t d`, `0 <= t <= t_max`, meets the box, in exact arithmetic
/// (f64 holds every product and quotient of these f32 values closely enough: a ray
/// the margin-free test says meets is one the f32 tests must keep).
fn meets_exactly(ray: &Ray, b: &Aabb, t_max: f32) -> Option<f64> {
    let (mut near, mut far) = (0.0f64, t_max as f64);
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis] as f64, ray.dir[axis] as f64);
        let (lo, hi) = (b.min[axis] as f64, b.max[axis] as f64);
        if d == 0.0 {
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (a, c) = ((lo - o) / d, (hi - o) / d);
        near = near.max(a.min(c));
        far = far.min(a.max(c));
    }
    (near <= far).then_some(near)
}

/// Random rays (far origins, zero and tiny direction components) against boxes around
/// points on them (as thin as the tree grows them, tiny, touching the origin): neither slab test ever culls a box
/// the ray meets, the entry distance either reports never lies beyond the true one by
/// more than its rounding, and the eight-lane test (fused multiply-adds from a rounded
/// `origin * inv_dir`, the far planes pre-grown by the slack) keeps every box the
/// four-lane one keeps.
#[test]
fn the_slab_tests_never_cull_a_box_the_ray_meets() {
    use rand_core::Rng;
    let mut rng = rand_pcg::Pcg32::new(0xb0c5, 7);
    let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let (mut kept, mut handed_on) = (0, 0);
    for case in 0..20_000 {
        let scale = [1.0, 1e3, 1e6, 3e8, 1e20][case % 5];
        let component = |u: &mut dyn FnMut() -> f32| match (u() * 8.0) as u32 {
            0 => 0.0,
            1 => (u() - 0.5) * 1e-30,
            _ => u() - 0.5,
        };
        let dir = Vec3::new(
            component(&mut unit),
            component(&mut unit),
            component(&mut unit),
        );
        if dir == Vec3::ZERO {
            continue;
        }
        let dir = dir.normalize_or(Vec3::X);
        let origin = Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) * scale;
        let ray = Ray::new(origin, dir);
        let t_max = if case % 3 == 0 {
            f32::INFINITY
        } else {
            10.0 * unit() * scale
        };
        let pad = if case % 4 == 0 {
            unit() * 1e-3 * scale
        } else {
            0.0
        };
        // The origin's magnitude along the ray, axis by axis.
        let origin_in_t = (0..3)
            .filter(|&i| dir[i] != 0.0)
            .map(|i| (origin[i].abs() + pad) as f64 / dir[i].abs() as f64)
            .fold(0.0, f64::max);
        let mut node = EMPTY_NODE;
        let mut boxes = [None; WIDTH];
        for (lane, slot) in boxes.iter_mut().enumerate().take(7) {
            let t = match lane {
                0 => 0.0,
                _ => unit() * t_max.min(4.0 * scale),
            };
            let at = ray.origin + ray.dir * t;
            // The least a tree's box is grown by (`padded_bounds`): a box that thin
            // around a ray running along its face is still met.
            let least = 16.0 * f32::EPSILON * at.abs().max_element();
            let mut half = |k: u32| match (unit() * 4.0) as u32 + k {
                0 | 1 => least,
                _ => least + unit() * scale * 0.01,
            };
            let h = Vec3::new(half(0), half(0), half(1));
            let b = Aabb {
                min: at - h,
                max: at + h,
            };
            node.set_box(lane, &b);
            let grown = Aabb {
                min: b.min - Vec3::splat(pad),
                max: b.max + Vec3::splat(pad),
            };
            *slot = meets_exactly(&ray, &grown, t_max);
        }
        let four = if pad > 0.0 {
            Boxes4::<true>::padded(&ray, pad).hit(&node, t_max)
        } else {
            Boxes4::<false>::new(&ray).hit(&node, t_max)
        };
        let mut answers = vec![("four lanes", four)];
        #[cfg(target_arch = "x86_64")]
        if SimdLevel::Avx2.supported() == SimdLevel::Avx2 {
            #[target_feature(enable = "avx2,fma")]
            unsafe fn eight(
                ray: &Ray,
                pad: f32,
                node: &Node8,
                t_max: f32,
            ) -> Option<(u32, [f32; WIDTH])> {
                Some(if pad > 0.0 {
                    Boxes8::padded(ray, pad)?.hit(node, t_max)
                } else {
                    Boxes8::new(ray)?.hit(node, t_max)
                })
            }
            // SAFETY: the processor runs AVX2 and FMA.
            match unsafe { eight(&ray, pad, &node, t_max) } {
                Some(eight) => {
                    assert_eq!(eight.0 & four.0, four.0, "case {case}: {ray:?}");
                    answers.push(("eight lanes", eight));
                }
                // The four-lane test's turn: the products overflow.
                None => handed_on += 1,
            }
        }
        for (name, (mask, t)) in answers {
            assert_eq!(
                mask >> 7,
                0,
                "{name}, case {case}: the empty lane is culled"
            );
            for (lane, exact) in boxes.iter().enumerate() {
                let Some(exact) = *exact else { continue };
                kept += 1;
                assert!(
                    mask >> lane & 1 == 1,
                    "{name}, case {case}, lane {lane}: {ray:?} culled"
                );
                // Rounding the distance, and for the four-lane test the origin it
                // moves by the pad (the eight-lane one moves its planes by more than
                // its roundings).
                let moved = if name == "four lanes" {
                    origin_in_t
                } else {
                    0.0
                };
                let slack = 8.0 * f32::EPSILON as f64 * (exact.abs() + moved);
                assert!(
                    t[lane] as f64 <= exact + slack,
                    "{name}, case {case}, lane {lane}: entered at {} beyond {exact}",
                    t[lane]
                );
            }
        }
    }
    assert!(kept > 100_000, "{kept} boxes met");
    #[cfg(target_arch = "x86_64")]
    if SimdLevel::Avx2.supported() == SimdLevel::Avx2 {
        assert!(
            handed_on > 100,
            "{handed_on} rays handed to the four-lane test"
        );
    }
}
