use super::super::{BoxTest, Boxes4, EMPTY_NODE, Leaves};
use super::*;
use crate::accel::simd::SimdLevel;
use crate::math::{Aabb, Vec3};
use crate::scene::{Shape, Shapes};
use proptest::prelude::*;

/// Both instruction sets, each with both leaf layouts.
fn levels_and_layouts() -> [(SimdLevel, Leaves); 4] {
    let best = SimdLevel::best_supported();
    [
        (SimdLevel::Baseline, Leaves::Indexed),
        (SimdLevel::Baseline, Leaves::Copied),
        (best, Leaves::Indexed),
        (best, Leaves::Copied),
    ]
}

#[test]
fn lane_bits_sets_the_bit_of_each_flagged_lane() {
    for pattern in [0u32, 1, 0x8000, 0xffff, 0xa5c3, 0x1248, 0x7ffe] {
        let flags: [u32; PACKET_RAYS] = std::array::from_fn(|i| lane_flag(pattern >> i & 1 == 1));
        assert_eq!(lane_bits(&flags), pattern);
    }
    let eight: [u32; WIDTH] = std::array::from_fn(|i| lane_flag(i % 3 == 0));
    assert_eq!(lane_bits(&eight), 0b0100_1001);
}

fn node_of(boxes: &[Aabb]) -> Node8 {
    let mut node = EMPTY_NODE;
    for (lane, b) in boxes.iter().enumerate() {
        node.set_box(lane, b);
    }
    node
}

/// Rays from `base` plus each ray's share of `spread`, their directions turned into
/// the octant of `signs` (not normalised: the box test takes any direction), and
/// boxes from corners and sizes, those with a NaN left out.
fn packet_and_boxes(
    signs: [bool; 3],
    base: [f32; 3],
    spread: [f32; 3],
    rays: &[([f32; 3], [f32; 3])],
    boxes: &[([f32; 3], [f32; 3])],
) -> (Vec<Ray>, Vec<Aabb>) {
    let rays = rays
        .iter()
        .map(|(o, d)| Ray {
            origin: Vec3::from(std::array::from_fn::<f32, 3, _>(|a| {
                base[a] + o[a] * spread[a]
            })),
            dir: Vec3::from(std::array::from_fn::<f32, 3, _>(|a| {
                if signs[a] { -d[a] } else { d[a] }
            })),
        })
        .collect();
    let boxes = boxes
        .iter()
        .map(|(lo, size)| Aabb {
            min: Vec3::from(*lo),
            max: Vec3::from(*lo) + Vec3::from(*size),
        })
        .filter(|b| !b.min.is_nan() && !b.max.is_nan())
        .collect();
    (rays, boxes)
}

/// Every box of `boxes` a ray of `rays` enters before `bound` (by the single-ray
/// test) is entered by the rays' frustum, no later.
fn frustum_holds_for(rays: &[Ray], boxes: &[Aabb], bound: f32) -> Result<(), TestCaseError> {
    let node = node_of(boxes);
    let lanes = Rays::new(rays);
    let Some(frustum) = Frustum::of(&lanes, rays.len()) else {
        return Ok(());
    };
    let (mask, t) = frustum.enter(&node, bound);
    for ray in rays {
        let (ray_mask, ray_t) = Boxes4::<false>::new(ray).hit(&node, bound);
        prop_assert_eq!(ray_mask & !mask, 0, "a box the ray enters is culled");
        for lane in 0..WIDTH {
            if ray_mask >> lane & 1 == 1 {
                prop_assert!(
                    t[lane] <= ray_t[lane],
                    "lane {}: {} > {}",
                    lane,
                    t[lane],
                    ray_t[lane]
                );
            }
        }
    }
    Ok(())
}

/// A direction component: mostly ordinary, sometimes zero (a 1e30 inverse), tiny,
/// subnormal or huge.
fn component() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => 0.0f32..1.0,
        2 => Just(0.0f32),
        1 => 1e-30f32..1e-20,
        1 => Just(1e-45f32),
        1 => 1e30f32..f32::MAX,
    ]
}

/// A coordinate: mostly near the origin, sometimes huge or infinite.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => -6.0f32..6.0,
        1 => Just(0.0f32),
        1 => -1e30f32..1e30,
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
    ]
}

fn sphere_row() -> Shapes {
    let spheres: Vec<Shape> = (0..100)
        .map(|i| {
            Shape::Sphere(Sphere {
                center: Vec3::new(i as f32 * 2.0, 0.0, 0.0),
                radius: 0.5,
            })
        })
        .collect();
    Shapes::from(spheres)
}

#[test]
fn a_nan_limit_blocks_nothing_and_hides_no_other_ray() {
    let shapes = sphere_row();
    let rays: Vec<Ray> = (0..PACKET_RAYS)
        .map(|k| {
            let k = k as f32;
            Ray::new(
                Vec3::new(-5.0, 0.001 * k, 0.0),
                Vec3::new(1.0, 0.0001 * k, 0.0001),
            )
        })
        .collect();
    for nan_lane in [0, 8, 15] {
        let mut t_max = [100.0f32; PACKET_RAYS];
        t_max[nan_lane] = f32::NAN;
        for (simd, leaves) in levels_and_layouts() {
            let bvh = Bvh::build_with(&shapes, simd, leaves);
            let blocked = bvh.occluded_packet(&rays, &t_max, |_| true);
            assert_eq!(
                blocked,
                0xffff & !(1 << nan_lane),
                "{simd:?}, NaN in lane {nan_lane}"
            );
            for (i, ray) in rays.iter().enumerate() {
                assert_eq!(blocked >> i & 1 == 1, bvh.occluded(ray, t_max[i], |_| true));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Every box a ray of the packet enters is entered by the frustum, no later
    /// than the ray enters it: the frustum never culls what a leaf would hit.
    #[test]
    fn the_frustum_enters_every_box_a_ray_enters_and_no_later(
        signs in prop::array::uniform3(any::<bool>()),
        base in prop::array::uniform3(-4.0f32..4.0),
        spread in 0.0f32..2.0,
        rays in prop::collection::vec(
            (prop::array::uniform3(0.0f32..1.0), prop::array::uniform3(0.0f32..1.0)),
            1..=PACKET_RAYS,
        ),
        boxes in prop::collection::vec(
            (prop::array::uniform3(-6.0f32..6.0), prop::array::uniform3(0.0f32..3.0)),
            WIDTH,
        ),
        bound in 0.5f32..40.0,
    ) {
        let (rays, boxes) = packet_and_boxes(signs, base, [spread; 3], &rays, &boxes);
        frustum_holds_for(&rays, &boxes, bound)?;
    }

    /// The same on hard cases: zero, tiny and huge direction components, origins
    /// spread apart on each axis, infinite coordinates, padding lanes and bounds of
    /// every kind.
    #[test]
    fn the_frustum_enters_every_box_on_hard_cases_too(
        signs in prop::array::uniform3(any::<bool>()),
        base in prop::array::uniform3(coordinate()),
        spread in prop::array::uniform3(prop_oneof![Just(0.0f32), 0.0f32..2.0, 0.0f32..1e6]),
        rays in prop::collection::vec(
            (prop::array::uniform3(0.0f32..1.0), prop::array::uniform3(component())),
            1..=PACKET_RAYS,
        ),
        boxes in prop::collection::vec(
            (
                prop::array::uniform3(coordinate()),
                prop::array::uniform3(prop_oneof![0.0f32..3.0, Just(0.0f32), Just(f32::INFINITY)]),
            ),
            0..=WIDTH,
        ),
        bound in prop_oneof![0.5f32..40.0, Just(f32::INFINITY), Just(0.0f32), -1.0f32..0.0],
    ) {
        let (rays, boxes) = packet_and_boxes(signs, base, spread, &rays, &boxes);
        frustum_holds_for(&rays, &boxes, bound)?;
    }

    /// Coherent packets (one octant, origins spread, zero direction components)
    /// against a scene of spheres: each ray's closest hit and shadow answer, with
    /// a limit of its own, are the single ray's, on both instruction sets.
    #[test]
    fn coherent_packets_answer_as_single_rays(
        spheres in prop::collection::vec((prop::array::uniform3(-20.0f32..20.0), 0.2f32..3.0), 17..120),
        signs in prop::array::uniform3(any::<bool>()),
        base in prop::array::uniform3(-25.0f32..25.0),
        spread in prop::array::uniform3(prop_oneof![Just(0.0f32), 0.0f32..3.0, 0.0f32..30.0]),
        rays in prop::collection::vec(
            (
                prop::array::uniform3(0.0f32..1.0),
                prop::array::uniform3(prop_oneof![3 => 0.0f32..1.0, 1 => Just(0.0f32), 1 => 0.0f32..1e-6]),
            ),
            1..=PACKET_RAYS,
        ),
        limits in prop::collection::vec(prop_oneof![0.0f32..60.0, Just(f32::INFINITY)], PACKET_RAYS),
        t_max in prop_oneof![0.0f32..60.0, Just(f32::INFINITY)],
    ) {
        let shapes: Vec<Shape> = spheres
            .iter()
            .map(|(c, r)| Shape::Sphere(Sphere { center: Vec3::from(*c), radius: *r }))
            .collect();
        let shapes = Shapes::from(shapes);
        let rays: Vec<Ray> = rays
            .iter()
            .map(|(o, d)| {
                let origin = Vec3::from(std::array::from_fn::<f32, 3, _>(|a| base[a] + o[a] * spread[a]));
                let dir = Vec3::from(std::array::from_fn::<f32, 3, _>(|a| if signs[a] { -d[a] } else { d[a] }));
                Ray::new(origin, dir)
            })
            .filter(|r| r.dir.is_finite() && r.dir != Vec3::ZERO)
            .collect();
        prop_assume!(!rays.is_empty());
        let limits = &limits[..rays.len()];
        let blocks = |s: u32| !s.is_multiple_of(3);
        for (simd, leaves) in levels_and_layouts() {
            let bvh = Bvh::build_with(&shapes, simd, leaves);
            let mut hits = vec![None; rays.len()];
            bvh.closest_packet(&rays, t_max, &mut hits);
            let blocked = bvh.occluded_packet(&rays, limits, blocks);
            for (i, ray) in rays.iter().enumerate() {
                prop_assert_eq!(hits[i], bvh.closest(ray, t_max), "closest, {:?}, ray {}", simd, i);
                prop_assert_eq!(blocked >> i & 1 == 1, bvh.occluded(ray, limits[i], blocks), "occluded, {:?}, ray {}", simd, i);
            }
        }
    }
}
