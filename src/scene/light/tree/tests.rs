//! The light tree held to what sampling needs of it: every draw's odds are what
//! [`LightTree::pmf`] retraces, the odds sum to at most one and match the draws'
//! frequencies, and no light that reaches a point is left out there.
//!
//! The odds may sum to less than one: a node's bounds are looser than its children's,
//! so a walk can reach a node from which no child can light the point, and draws
//! nothing. That loses no light (every light that reaches the point has odds), only a
//! sample, as in pbrt.

use super::*;
use crate::math::normalize;
use crate::scene::{ConeEdge, Material, Shape, ShapeId, Triangle};
use rand_core::Rng;
use rand_pcg::Pcg32;

fn rng(seed: u64) -> Pcg32 {
    Pcg32::new(seed, 0xa02b_dbf7_bb3c_0a7b)
}

fn unit(r: &mut Pcg32) -> f32 {
    (r.next_u32() >> 8) as f32 / (1u32 << 24) as f32
}

fn in_box(r: &mut Pcg32, half: f32) -> Vec3 {
    Vec3::new(unit(r), unit(r), unit(r)) * (2.0 * half) - Vec3::splat(half)
}

fn direction(r: &mut Pcg32) -> Vec3 {
    loop {
        let v = in_box(r, 1.0);
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

/// Forty lights of every kind the tree holds, scattered in a box of side 20, a
/// glowing mesh among them, and lights drawn beside the tree (a sun, a point light
/// without falloff), with surfaces resolved.
fn many_lights() -> (Scene, Vec<Surface>) {
    let mut r = rng(7);
    let mut scene = Scene::default();
    let glowing = Surface {
        emission: Vec3::new(2.0, 1.0, 0.5),
        ..Surface::default()
    };
    scene.materials.push(Material::default_white());
    scene.surfaces.push(glowing);
    for _ in 0..6 {
        let c = in_box(&mut r, 8.0);
        let v = [c, c + in_box(&mut r, 1.0), c + in_box(&mut r, 1.0)];
        scene.push_shape(Shape::Triangle(Triangle { v }), 0);
    }
    let inverse_square = |light: Light| Light {
        falloff: Falloff::InverseSquare,
        ..light
    };
    for k in 0..40 {
        let at = in_box(&mut r, 10.0);
        let color = Vec3::new(0.2 + unit(&mut r), 0.2 + unit(&mut r), 0.2 + unit(&mut r));
        let kind = match k % 6 {
            0 => LightKind::Point,
            1 => LightKind::Spot {
                direction: direction(&mut r),
                cos_inner: 0.9,
                cos_outer: 0.7,
                edge: ConeEdge::Smooth,
            },
            2 => LightKind::Quad {
                u: in_box(&mut r, 1.0),
                v: in_box(&mut r, 1.0),
            },
            3 => LightKind::Disk {
                normal: direction(&mut r),
                radius: 0.3 + unit(&mut r),
            },
            4 => LightKind::Sphere {
                radius: 0.1 + unit(&mut r),
            },
            // A spot whose cones are named the other way round.
            _ => LightKind::Spot {
                direction: direction(&mut r),
                cos_inner: 0.5,
                cos_outer: 0.8,
                edge: ConeEdge::Squared,
            },
        };
        scene.lights.push(inverse_square(Light {
            kind,
            intensity: 1.0 + 4.0 * unit(&mut r),
            ..Light::point(at, color)
        }));
    }
    let mesh = Light::mesh(&scene, (0..6).map(ShapeId::world)).expect("a glowing mesh");
    scene.lights.push(mesh);
    scene.lights.push(Light {
        kind: LightKind::Directional {
            direction: normalize(Vec3::new(0.3, -1.0, 0.2)),
        },
        ..Light::point(Vec3::ZERO, Vec3::ONE)
    });
    scene
        .lights
        .push(Light::point(Vec3::new(1.0, 2.0, 3.0), Vec3::ONE));
    let surfaces = scene.resolved_surfaces();
    (scene, surfaces)
}

#[test]
fn every_draw_has_the_odds_its_light_retraces_and_the_odds_sum_to_at_most_one() {
    let (scene, surfaces) = many_lights();
    let tree = LightTree::new(&scene, &surfaces, true);
    assert_eq!(
        tree.apart,
        vec![41, 42],
        "the sun and the light without falloff"
    );
    // Those two and the environment are each sampled at every vertex.
    assert!(tree.samples_apart_each());
    assert_eq!(tree.environment_pmf(), 1.0);
    let mut r = rng(11);
    let mut drawn = 0.0;
    for _ in 0..200 {
        let (p, n) = (in_box(&mut r, 12.0), direction(&mut r));
        assert_eq!((tree.pmf(p, n, 41), tree.pmf(p, n, 42)), (1.0, 1.0));
        let total: f64 = (0..41).map(|k| f64::from(tree.pmf(p, n, k))).sum();
        assert!(total < 1.0 + 1e-5, "at {p}: odds sum to {total}");
        drawn += total;
        for _ in 0..20 {
            let Some((picked, pmf)) = tree.sample(p, n, unit(&mut r)) else {
                continue;
            };
            assert!(matches!(picked, Picked::Light(k) if k < 41), "{picked:?}");
            let retraced = match picked {
                Picked::Light(k) => tree.pmf(p, n, k),
                Picked::Environment => tree.environment_pmf(),
            };
            assert_eq!(pmf.to_bits(), retraced.to_bits(), "{picked:?} at {p}");
            assert!(pmf > 0.0);
        }
    }
    // Here a draw from the tree finds a light 88 % of the time.
    assert!(
        drawn / 200.0 > 0.85,
        "a draw finds a light {} of the time",
        drawn / 200.0
    );
}

#[test]
fn lights_are_drawn_as_often_as_their_odds_say() {
    let (scene, surfaces) = many_lights();
    let tree = LightTree::new(&scene, &surfaces, false);
    let (p, n) = (Vec3::new(0.5, -1.0, 2.0), Vec3::Y);
    let draws = 200_000;
    let mut seen = vec![0u32; scene.lights.len()];
    let mut none = 0u32;
    for i in 0..draws {
        // Stratified numbers: the frequencies settle as 1/draws.
        let u = (i as f32 + 0.5) / draws as f32;
        match tree.sample(p, n, u) {
            Some((Picked::Light(k), _)) => seen[k as usize] += 1,
            Some((Picked::Environment, _)) => panic!("no environment to draw"),
            None => none += 1,
        }
    }
    // The lights beside the tree (41 and 42) are sampled at every vertex, not drawn.
    let total: f32 = (0..41).map(|k| tree.pmf(p, n, k)).sum();
    let nothing = none as f32 / draws as f32;
    assert!(
        (nothing - (1.0 - total)).abs() < 1e-3,
        "{nothing} drew nothing"
    );
    assert_eq!(seen[41..], [0, 0]);
    for (k, &count) in seen.iter().enumerate().take(41) {
        let pmf = tree.pmf(p, n, k as u32);
        let frequency = count as f32 / draws as f32;
        assert!(
            (frequency - pmf).abs() < 1e-4 + 0.01 * pmf,
            "light {k}: drawn {frequency}, odds {pmf}"
        );
    }
}

/// Where a light's sample brings light to a point, the tree draws that light there:
/// otherwise the estimate would lose its light (a biased image).
#[test]
fn no_light_that_reaches_a_point_has_zero_odds_there() {
    let (scene, surfaces) = many_lights();
    let tree = LightTree::new(&scene, &surfaces, false);
    let mut r = rng(23);
    let mut reached = 0;
    for _ in 0..3000 {
        let (p, n) = (in_box(&mut r, 14.0), direction(&mut r));
        for (k, light) in scene.lights.iter().enumerate() {
            let u = (unit(&mut r), unit(&mut r));
            let Some(inc) = light.sample_incident(&scene, &surfaces, p, u) else {
                continue;
            };
            if inc.li.max_element() <= 0.0 || inc.dir.dot(n).abs() < 1e-4 {
                continue;
            }
            reached += 1;
            assert!(
                tree.pmf(p, n, k as u32) > 0.0,
                "light {k} ({}) reaches {p} (normal {n}) along {} but has no odds",
                light.kind_name(),
                inc.dir
            );
        }
    }
    assert!(reached > 50_000, "{reached}");
}

#[test]
fn and_some_lights_that_cannot_reach_a_point_are_never_drawn_there() {
    // A quad facing down is never drawn above it, nor a spot behind its cone.
    let mut scene = Scene::default();
    let down = Light {
        kind: LightKind::Quad {
            u: Vec3::X,
            v: Vec3::Z,
        },
        ..Light::point(Vec3::ZERO, Vec3::ONE)
    };
    let spot = Light {
        kind: LightKind::Spot {
            direction: -Vec3::Y,
            cos_inner: 0.95,
            cos_outer: 0.9,
            edge: ConeEdge::Smooth,
        },
        falloff: Falloff::InverseSquare,
        ..Light::point(Vec3::new(10.0, 0.0, 0.0), Vec3::ONE)
    };
    scene.lights = vec![down, spot];
    let tree = LightTree::new(&scene, &[], false);
    let above = Vec3::new(0.2, 1.0, 0.1);
    assert_eq!(tree.pmf(above, Vec3::Y, 0), 0.0);
    assert_eq!(tree.pmf(Vec3::new(10.0, 1.0, 0.0), Vec3::Y, 1), 0.0);
    assert_eq!(tree.pmf(Vec3::new(0.0, -1.0, 0.0), Vec3::Y, 0), 1.0);
}

#[test]
fn a_merged_cone_holds_both_cones() {
    let mut r = rng(31);
    for _ in 0..2000 {
        let cone = |r: &mut Pcg32| DirectionCone {
            w: direction(r),
            cos_theta: 2.0 * unit(r) - 1.0,
        };
        let (a, b) = (cone(&mut r), cone(&mut r));
        let merged = a.union(b);
        for c in [a, b] {
            // The cone's edge in a few directions around its axis.
            let (t1, t2) = c.w.any_orthonormal_pair();
            let sin = (1.0 - c.cos_theta * c.cos_theta).max(0.0).sqrt();
            for k in 0..8 {
                let phi = k as f32 * std::f32::consts::FRAC_PI_4;
                let edge = c.w * c.cos_theta + (t1 * phi.cos() + t2 * phi.sin()) * sin;
                // Up to the rounding of the edge itself.
                assert!(
                    merged.w.dot(normalize(edge)) >= merged.cos_theta - 1e-5,
                    "{a:?} and {b:?} merged to {merged:?}, which leaves out {edge}"
                );
            }
        }
    }
}

#[test]
fn ten_thousand_lights_in_one_spot_still_fit_the_trails() {
    let scene = Scene {
        lights: (0..10_000)
            .map(|_| Light {
                falloff: Falloff::InverseSquare,
                ..Light::point(Vec3::ONE, Vec3::ONE)
            })
            .collect(),
        ..Scene::default()
    };
    let tree = LightTree::new(&scene, &[], false);
    let p = Vec3::new(3.0, 0.0, 0.0);
    let pmf = tree.pmf(p, Vec3::ZERO, 1234);
    assert!((pmf * 10_000.0 - 1.0).abs() < 1e-3, "{pmf}");
    let (picked, odds) = tree.sample(p, Vec3::ZERO, 0.5).expect("a light");
    assert!(matches!(picked, Picked::Light(_)));
    assert!((odds * 10_000.0 - 1.0).abs() < 1e-3, "{odds}");
}

#[test]
fn a_few_lights_beside_the_tree_are_each_sampled_and_many_drawn_uniformly() {
    let far = |x: f32| Light::point(Vec3::new(x, 0.0, 0.0), Vec3::ONE);
    let lit = |x: f32| Light {
        falloff: Falloff::InverseSquare,
        ..far(x)
    };
    // A light without falloff and a sky: each sampled, the tree (empty) draws nothing.
    let few = Scene {
        lights: vec![far(0.0)],
        ..Scene::default()
    };
    let tree = LightTree::new(&few, &[], true);
    assert!(tree.samples_apart_each());
    assert_eq!(tree.sample(Vec3::X, Vec3::Y, 0.2), None);
    assert_eq!(
        (tree.pmf(Vec3::X, Vec3::Y, 0), tree.environment_pmf()),
        (1.0, 1.0)
    );
    // Five and a sky beside a tree of one: each of the six as likely as the tree.
    let many = Scene {
        lights: vec![far(0.0), far(1.0), far(2.0), far(3.0), far(4.0), lit(5.0)],
        ..Scene::default()
    };
    let tree = LightTree::new(&many, &[], true);
    assert!(!tree.samples_apart_each());
    let sixth = 6.0 / 7.0 / 6.0;
    assert_eq!(
        tree.sample(Vec3::X, Vec3::Y, 0.2),
        Some((Picked::Light(1), sixth))
    );
    assert_eq!(
        tree.sample(Vec3::X, Vec3::Y, 0.84),
        Some((Picked::Environment, sixth))
    );
    assert_eq!(
        tree.sample(Vec3::new(1.0, 1.0, 0.0), Vec3::Y, 0.9),
        Some((Picked::Light(5), 1.0 - 6.0f32 / 7.0))
    );
    assert_eq!(
        (tree.pmf(Vec3::X, Vec3::Y, 3), tree.environment_pmf()),
        (sixth, sixth)
    );
    let empty = LightTree::new(&Scene::default(), &[], false);
    assert_eq!(empty.sample(Vec3::X, Vec3::Y, 0.3), None);
}
