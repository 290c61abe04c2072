use super::*;
use crate::accel::bvh::Leaves;
use crate::math::Vec3;
use crate::scene::{Shape, Shapes, Sphere, Triangle};
use rand_core::Rng;

/// Random triangles and a few spheres in a box of side 10, as `Shapes`.
fn scene(rng: &mut rand_pcg::Pcg32, triangles: usize) -> Shapes {
    let mut unit = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let point =
        |unit: &mut dyn FnMut() -> f32| Vec3::new(unit(), unit(), unit()) * 10.0 - Vec3::splat(5.0);
    let mut shapes: Vec<Shape> = (0..triangles)
        .map(|_| {
            let a = point(&mut unit);
            let b = a + (point(&mut unit) * 0.2);
            let c = a + (point(&mut unit) * 0.2);
            Shape::Triangle(Triangle { v: [a, b, c] })
        })
        .collect();
    for _ in 0..3 {
        shapes.push(Shape::Sphere(Sphere {
            center: point(&mut unit),
            radius: 0.3 + unit(),
        }));
    }
    Shapes::from(shapes)
}

/// Scattered shadow rays, as a pixel's paths cast them toward a light: from random
/// points to random points, with limits short of, at, past and beyond their ends,
/// NaN, zero and negative among them; each ray's answer is the single ray's, with both
/// leaf layouts, at every instruction set, for trees of one level and of several.
#[test]
fn scattered_shadow_rays_are_answered_as_single_rays() {
    let mut rng = rand_pcg::Pcg32::new(0x5ca7, 11);
    let (mut blocked, mut clear) = (0, 0);
    for triangles in [30, 60, 400] {
        let shapes = scene(&mut rng, triangles);
        for leaves in [Leaves::Indexed, Leaves::Copied] {
            for simd in [
                crate::accel::SimdLevel::Baseline,
                crate::accel::SimdLevel::Avx2,
            ] {
                let bvh = Bvh::build_with(&shapes, simd, leaves);
                for _ in 0..200 {
                    let n = 1 + rng.next_u32() as usize % PACKET_RAYS;
                    let mut unit = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
                    let mut rays = Vec::new();
                    let mut limits = Vec::new();
                    for k in 0..n {
                        let from = Vec3::new(unit(), unit(), unit()) * 12.0 - Vec3::splat(6.0);
                        let to = Vec3::new(unit(), unit(), unit()) * 12.0 - Vec3::splat(6.0);
                        let d = to - from;
                        let len = d.length();
                        rays.push(Ray::new(from, d / len));
                        limits.push(match k % 7 {
                            0 => f32::NAN,
                            1 => 0.0,
                            2 => -1.0,
                            3 => f32::INFINITY,
                            _ => len * (0.5 + unit()),
                        });
                    }
                    let many = bvh.occluded_many(&rays, &limits);
                    for k in 0..n {
                        let single = bvh.occluded(&rays[k], limits[k], |_| true);
                        assert_eq!(many >> k & 1 == 1, single, "ray {k} of {n}: {:?}", rays[k]);
                        if single {
                            blocked += 1;
                        } else {
                            clear += 1;
                        }
                    }
                    assert_eq!(many >> n, 0, "no bit past the rays");
                }
            }
        }
    }
    assert!(
        blocked > 1000 && clear > 1000,
        "{blocked} blocked, {clear} clear"
    );
}
