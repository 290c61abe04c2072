//! One shadow ray a vertex against one a light: the same expectation, fewer rays.

use super::*;

/// A floor under six lights of every kind (a sphere casting part of the quad light's
/// shadow, a glowing triangle among them) in a grey environment.
fn many_lights_floor() -> Scene {
    let glowing = Shape::Triangle(Triangle {
        v: [
            Vec3::new(-1.5, 2.5, 0.5),
            Vec3::new(-0.5, 2.5, 1.5),
            Vec3::new(-1.5, 2.5, 1.5),
        ],
    });
    let mut s = lights_floor();
    s.materials.push(Material::default_white());
    s.surfaces.push(Surface {
        emission: Vec3::new(3.0, 2.0, 1.0),
        ..matte(0.0)
    });
    s.push_shape(glowing, 2);
    let mesh = Light::mesh(&s, [crate::scene::ShapeId::world(2)]).expect("a mesh light");
    s.lights.push(mesh);
    s
}

/// The floor of [`many_lights_floor`] under its five lights that are not geometry.
fn lights_floor() -> Scene {
    let floor = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-50.0, 0.0, -50.0),
            Vec3::new(-50.0, 0.0, 50.0),
            Vec3::new(50.0, 0.0, 50.0),
            Vec3::new(50.0, 0.0, -50.0),
        ],
    });
    let blocker = Shape::Sphere(Sphere {
        center: Vec3::new(0.3, 1.0, 0.0),
        radius: 0.3,
    });
    scene(
        vec![(floor, matte(0.8)), (blocker, matte(0.5))],
        vec![
            Light {
                falloff: crate::scene::Falloff::InverseSquare,
                intensity: 5.0,
                ..Light::point(Vec3::new(1.0, 2.0, 0.0), Vec3::ONE)
            },
            area_light(
                LightKind::Quad {
                    u: Vec3::new(2.0, 0.0, 0.0),
                    v: Vec3::new(0.0, 0.0, 2.0),
                },
                Vec3::new(0.5, 2.0, 0.0),
                3.0,
            ),
            area_light(
                LightKind::Sphere { radius: 0.4 },
                Vec3::new(-2.0, 1.5, 1.0),
                8.0,
            ),
            area_light(
                LightKind::Disk {
                    normal: -Vec3::Y,
                    radius: 0.5,
                },
                Vec3::new(0.0, 3.0, -2.0),
                2.0,
            ),
            Light {
                falloff: crate::scene::Falloff::InverseSquare,
                intensity: 1.0,
                color: Vec3::new(1.0, 0.5, 0.2),
                ..Light::point(Vec3::new(-1.0, 0.5, -1.0), Vec3::ONE)
            },
        ],
        Background::Color(Vec3::splat(0.2)),
    )
}

/// One shadow ray a vertex, toward a light sample chosen by its contribution or
/// toward a light the tree draws, is unbiased: the floor under six lights, part in a
/// shadow, converges to what a shadow ray toward every light gives, direct light alone
/// and with bounces (where the BSDF's rays meet the lights and the environment, weighed
/// by the odds the tree would have drawn them with); and a direct-light vertex traces
/// one shadow ray where it traced six.
#[test]
fn one_shadow_ray_a_vertex_converges_to_a_shadow_ray_toward_every_light() {
    let s = many_lights_floor();
    for (x, max_depth) in [
        (0.0, 0),
        (0.4, 0),
        (-1.0, 0),
        (0.0, crate::options::MAX_PATH_DEPTH),
    ] {
        let ray = Ray::new(
            Vec3::new(x, 1.5, 0.6),
            normalize(Vec3::new(0.0, -1.0, -0.2)),
        );
        let mis = Weighing::PowerHeuristic;
        let (all, all_error, all_rays) =
            estimate_with(&s, ray, 20_000, max_depth, mis, LightSampling::All);
        for way in [LightSampling::One, LightSampling::Tree] {
            let n = if way == LightSampling::Tree {
                80_000
            } else {
                20_000
            };
            let (one, one_error, one_rays) = estimate_with(&s, ray, n, max_depth, mis, way);
            let error = (all_error * all_error + one_error * one_error).sqrt();
            assert!(
                ((one - all).abs() - 4.0 * error).max_element() < 1e-3 * all.max_element(),
                "x {x}, depth {max_depth}, {way}: {one} ± {one_error}, all {all} ± {all_error}"
            );
            if max_depth == 0 {
                // The camera ray and a shadow ray toward each light with light to give
                // (the environment's samples below the floor give none).
                assert!(all_rays >= 20_000 * 6, "{all_rays}");
                // The tree's draw, and the environment beside the tree sampled too.
                let most = if way == LightSampling::Tree { 3 } else { 2 };
                assert!(one_rays <= u64::from(n) * most, "{way}: {one_rays}");
            }
        }
    }
}

#[test]
fn auto_light_sampling_draws_one_light_from_the_tree_above_sixteen_lights() {
    let lights = LightSampling::AUTO_ALL_UP_TO;
    assert!(!LightSampling::Auto.traces_one(lights));
    assert!(LightSampling::Auto.traces_one(lights + 1));
    assert!(!LightSampling::Auto.draws_from_tree(lights));
    assert!(LightSampling::Auto.draws_from_tree(lights + 1));
    assert!(!LightSampling::One.draws_from_tree(lights + 1));
    assert!(LightSampling::One.traces_one(1));
    assert!(!LightSampling::All.traces_one(1000));
    // Lambertian lanes trace a ray toward every light: a scene that traces one
    // takes the path at a time.
    let mut s = many_lights_floor();
    s.background = Background::Black;
    s.lights.retain(|l| matches!(l.kind, LightKind::Point));
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let path = Path::new(&s, &accel, &surfaces, 4);
    assert!(path.lanes.is_none() || !path.one_shadow_ray);
    assert!(path.light_sampling(LightSampling::One).lanes.is_none());
}

/// Where the path goes no further (direct light alone: a depth of 0), no BSDF sample
/// can find a light, so the lights' samples count in full: weighed by the power
/// heuristic they lost the share a BSDF sample would have found, 18 % of the floor's
/// light here.
#[test]
fn the_last_vertex_counts_its_light_samples_in_full() {
    let s = many_lights_floor();
    let ray = Ray::new(
        Vec3::new(0.0, 1.5, 0.6),
        normalize(Vec3::new(0.0, -1.0, -0.2)),
    );
    for way in [LightSampling::All, LightSampling::One, LightSampling::Tree] {
        let weighed = estimate_with(&s, ray, 2_000, 0, Weighing::PowerHeuristic, way).0;
        let alone = estimate_with(&s, ray, 2_000, 0, Weighing::LightsOnly, way).0;
        assert_eq!(weighed, alone, "{way}");
    }
}
