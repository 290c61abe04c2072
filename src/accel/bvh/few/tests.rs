use super::super::Leaves;
use super::*;
use crate::accel::simd::SimdLevel;
use crate::math::Vec3;
use crate::scene::{Rectangle, Shape, Shapes, Sphere, Triangle};
use proptest::prelude::*;

/// Each way the few shapes are met, as the processor runs them: the baseline's code,
/// and the AVX2 and AVX-512 builds where it has them.
fn kernels() -> Vec<(&'static str, Kernel)> {
    let mut kernels: Vec<(&'static str, Kernel)> = vec![("baseline", FewFlats::closest)];
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: only where the processor runs AVX2 and FMA.
            kernels.push(("avx2", |few, rays, t_max, hits| unsafe {
                closest_avx2(few, rays, t_max, hits)
            }));
        }
        if crate::accel::simd::avx512_supported() {
            // SAFETY: only where the processor runs AVX-512 F, VL, DQ and BW.
            kernels.push(("avx512", |few, rays, t_max, hits| unsafe {
                closest_avx512(few, rays, t_max, hits)
            }));
        }
    }
    kernels
}

type Kernel = fn(&FewFlats, &[Ray], f32, &mut [Option<Hit>]);

/// Every kernel and `Bvh::closest_many` give each ray what `Bvh::closest` gives it.
fn answers_as_single_rays(shapes: &Shapes, rays: &[Ray], t_max: f32) -> Result<(), TestCaseError> {
    let few = FewFlats::of(shapes).expect("a scene of few flat shapes");
    let best = SimdLevel::best_supported();
    for (simd, leaves) in [
        (SimdLevel::Baseline, Leaves::Indexed),
        (SimdLevel::Baseline, Leaves::Copied),
        (best, Leaves::Indexed),
        (best, Leaves::Copied),
    ] {
        let bvh = Bvh::build_with(shapes, simd, leaves);
        prop_assert!(bvh.meets_all_at_once());
        let single: Vec<_> = rays.iter().map(|r| bvh.closest(r, t_max)).collect();
        let mut many = vec![None; rays.len()];
        bvh.closest_many(rays, t_max, &mut many);
        prop_assert_eq!(&many, &single, "closest_many, {:?}, {:?}", simd, leaves);
        for (name, kernel) in kernels() {
            let mut hits = vec![None; rays.len()];
            kernel(&few, rays, t_max, &mut hits);
            prop_assert_eq!(&hits, &single, "{} kernel", name);
        }
    }
    Ok(())
}

fn triangle(v: [[f32; 3]; 3]) -> Shape {
    Shape::Triangle(Triangle {
        v: v.map(Vec3::from),
    })
}

/// A square of two triangles sharing the diagonal from (0, 0) to (1, 1) at height `y`,
/// and the same square again: four shapes that a ray down through the diagonal meets
/// at the same distance.
fn doubled_square(y: f32) -> Vec<Shape> {
    let a = [0.0, y, 0.0];
    let b = [1.0, y, 0.0];
    let c = [1.0, y, 1.0];
    let d = [0.0, y, 1.0];
    let square = [triangle([a, b, c]), triangle([a, c, d])];
    [square, square].concat()
}

#[test]
fn of_equally_near_shapes_the_lowest_index_is_met() {
    let shapes = Shapes::from(doubled_square(0.0));
    let down = |x: f32, z: f32| Ray::new(Vec3::new(x, 2.0, z), Vec3::NEG_Y);
    // On the shared diagonal, inside the first triangle, inside the second.
    let rays = [down(0.5, 0.5), down(0.7, 0.2), down(0.2, 0.7)];
    let bvh = Bvh::build(&shapes, Leaves::Indexed);
    for (name, kernel) in kernels() {
        let mut hits = [None; 3];
        kernel(bvh.few.as_ref().unwrap(), &rays, f32::INFINITY, &mut hits);
        let met: Vec<_> = hits.iter().map(|h| h.map(|h| (h.t, h.shape))).collect();
        assert_eq!(
            met,
            [Some((2.0, 0)), Some((2.0, 0)), Some((2.0, 1))],
            "{name}"
        );
    }
    answers_as_single_rays(&shapes, &rays, f32::INFINITY).unwrap();
}

#[test]
fn limits_are_kept_and_a_nan_limit_meets_nothing() {
    let shapes = Shapes::from(doubled_square(0.0));
    let ray = Ray::new(Vec3::new(0.7, 2.0, 0.2), Vec3::NEG_Y);
    let bvh = Bvh::build(&shapes, Leaves::Indexed);
    for (t_max, expected) in [
        (2.0, None),
        (2.0f32.next_up(), Some(Hit::world(2.0, 0))),
        (f32::NAN, None),
        (f32::INFINITY, Some(Hit::world(2.0, 0))),
    ] {
        let mut hits = [None];
        bvh.closest_many(&[ray], t_max, &mut hits);
        assert_eq!(hits[0], expected, "t_max {t_max}");
    }
}

#[test]
fn scenes_with_spheres_or_many_shapes_walk_the_tree() {
    let square = doubled_square(0.0);
    let with_sphere: Vec<Shape> = square
        .iter()
        .copied()
        .chain([Shape::Sphere(Sphere {
            center: Vec3::new(0.5, 1.0, 0.5),
            radius: 0.25,
        })])
        .collect();
    let many: Vec<Shape> = (0..=FEW_SHAPES / 4)
        .flat_map(|k| doubled_square(k as f32))
        .collect();
    assert!(many.len() > FEW_SHAPES);
    let down = Ray::new(Vec3::new(0.5, 1e3, 0.5), Vec3::NEG_Y);
    for shapes in [with_sphere, many] {
        let shapes = Shapes::from(shapes);
        let bvh = Bvh::build(&shapes, Leaves::Indexed);
        assert!(!bvh.meets_all_at_once());
        let mut hits = [None];
        bvh.closest_many(&[down], f32::INFINITY, &mut hits);
        assert_eq!(hits[0], bvh.closest(&down, f32::INFINITY));
        assert!(hits[0].is_some());
    }
    let flat = Shapes::from(square);
    assert!(Bvh::build(&flat, Leaves::Indexed).meets_all_at_once());
}

fn point() -> impl Strategy<Value = [f32; 3]> {
    prop::array::uniform3(-3.0f32..3.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Scattered rays (any direction, zero components included) from inside a cloud of
    /// up to sixty-four triangles and rectangles, in packets of every size from 1 to
    /// 16: each ray's closest hit is the single ray's, bit for bit, whatever kernel.
    #[test]
    fn scattered_rays_meet_few_shapes_as_single_rays(
        shapes in prop::collection::vec((point(), point(), point(), any::<bool>()), 1..=FEW_SHAPES),
        rays in prop::collection::vec(
            (
                prop::array::uniform3(-2.0f32..2.0),
                prop::array::uniform3(prop_oneof![4 => -1.0f32..1.0, 1 => Just(0.0f32)]),
            ),
            1..=PACKET_RAYS,
        ),
        t_max in prop_oneof![0.0f32..8.0, Just(f32::INFINITY)],
    ) {
        let shapes: Vec<Shape> = shapes
            .iter()
            .map(|&(a, b, c, rectangle)| {
                if rectangle {
                    let [a, b, d] = [a, b, c].map(Vec3::from);
                    Shape::Rectangle(Rectangle { v: [a, b, b + d - a, d] })
                } else {
                    triangle([a, b, c])
                }
            })
            .collect();
        let shapes = Shapes::from(shapes);
        let rays: Vec<Ray> = rays
            .iter()
            .filter(|(_, d)| *d != [0.0; 3])
            .map(|&(o, d)| Ray::new(Vec3::from(o), Vec3::from(d)))
            .collect();
        prop_assume!(!rays.is_empty());
        answers_as_single_rays(&shapes, &rays, t_max)?;
    }
}

/// The twelve triangles of the box from `lo` to `hi`, two a face.
fn block(lo: [f32; 3], hi: [f32; 3]) -> Vec<Shape> {
    let corner = |k: usize| {
        Vec3::new(
            if k & 1 == 0 { lo[0] } else { hi[0] },
            if k & 2 == 0 { lo[1] } else { hi[1] },
            if k & 4 == 0 { lo[2] } else { hi[2] },
        )
    };
    // Each face's corners in order round it.
    let faces = [
        [0, 1, 3, 2],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 3, 7, 5],
    ];
    faces
        .iter()
        .flat_map(|f| {
            let [a, b, c, d] = f.map(corner);
            [
                Shape::Triangle(Triangle { v: [a, b, c] }),
                Shape::Triangle(Triangle { v: [a, c, d] }),
            ]
        })
        .collect()
}

/// A room of ten wall triangles holding three blocks, as a scene file lists them.
fn room_of_blocks() -> Vec<Shape> {
    let room = block([-2.0, 0.0, -2.0], [2.0, 3.0, 2.0]);
    let blocks = [
        block([-1.2, 0.0, -1.0], [-0.4, 0.9, -0.2]),
        block([0.3, 0.0, 0.2], [1.1, 1.8, 1.0]),
        block([-0.3, 2.0, -0.3], [0.3, 2.6, 0.3]),
    ];
    room[..10].iter().copied().chain(blocks.concat()).collect()
}

#[test]
fn a_room_s_blocks_are_runs_of_their_own() {
    let shapes = Shapes::from(room_of_blocks());
    let few = FewFlats::of(&shapes).unwrap();
    let ends: Vec<u32> = few.runs.iter().map(|r| r.end).collect();
    assert!(ends.len() > 1, "{ends:?}");
    assert_eq!(ends.last(), Some(&(shapes.len() as u32)));
    // No run mixes a wall with a block, nor two blocks.
    let mut start = 0;
    for &end in &ends {
        let group = |i: u32| if i < 10 { 0 } else { 1 + (i - 10) / 12 };
        assert_eq!(group(start), group(end - 1), "run {start}..{end}");
        start = end;
    }
    // A tiny scene is one run, met by every batch.
    let tiny = Shapes::from(block([0.0; 3], [1.0; 3]));
    let few = FewFlats::of(&tiny).unwrap();
    assert_eq!(few.runs.len(), 1);
    assert_eq!(few.runs[0].bounds, None);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Rays from anywhere in a room of blocks toward the blocks' corners and edges, a
    /// hair off or exactly, and toward random points: each ray's closest hit is the
    /// single ray's, bit for bit, though the batch passes over runs none of its rays
    /// enters.
    #[test]
    fn rays_past_a_room_s_blocks_meet_them_as_single_rays(
        rays in prop::collection::vec(
            (
                (-1.99f32..1.99, 0.01f32..2.99, -1.99f32..1.99),
                0usize..108,
                0usize..3,
                prop::array::uniform3(prop_oneof![2 => Just(0.0f32), 1 => -1e-6f32..1e-6]),
                any::<bool>(),
            ),
            1..=PACKET_RAYS,
        ),
    ) {
        let shapes = room_of_blocks();
        let targets: Vec<Vec3> = shapes[10..]
            .iter()
            .flat_map(|s| match s {
                Shape::Triangle(t) => t.v,
                _ => unreachable!(),
            })
            .collect();
        let shapes = Shapes::from(shapes);
        let rays: Vec<Ray> = rays
            .iter()
            .map(|&((x, y, z), target, edge, jitter, on_edge)| {
                let o = Vec3::new(x, y, z);
                // A corner, or the middle of an edge to the next corner.
                let a = targets[target % targets.len()];
                let b = targets[(target / 3) * 3 + (target + 1 + edge) % 3];
                let aim = if on_edge { (a + b) * 0.5 } else { a } + Vec3::from(jitter);
                Ray::new(o, aim - o)
            })
            .filter(|r| r.dir != Vec3::ZERO)
            .collect();
        prop_assume!(!rays.is_empty());
        answers_as_single_rays(&shapes, &rays, f32::INFINITY)?;
    }
}
