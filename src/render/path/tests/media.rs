//! Light through media: the walk under a subsurface and the flights through a
//! transmissive solid's scattering medium, held to the furnace, to the specification's
//! colours and extinction, and to what each lets through.

use super::*;

/// A sphere of `m` (base colour white) of radius `radius` at the origin, in a uniform
/// environment of 1.
fn furnace_of(m: crate::scene::OpenPbr, center: Vec3, radius: f32) -> Scene {
    ball_of(m, center, radius, vec![], Background::Color(Vec3::ONE))
}

/// A sphere of `m` (base colour white) under `lights` before `background`.
fn ball_of(
    m: crate::scene::OpenPbr,
    center: Vec3,
    radius: f32,
    lights: Vec<Light>,
    background: Background,
) -> Scene {
    scene(
        vec![(
            Shape::Sphere(Sphere { center, radius }),
            Surface {
                albedo: Albedo::Color(Vec3::ONE),
                openpbr: Some(Box::new(m)),
                ..Surface::default()
            },
        )],
        lights,
        background,
    )
}

/// A subsurface of white colour scatters without absorbing: whatever the interface
/// reflects and the walk brings back out add up to the light that arrived, in the
/// furnace, whichever way the ball is seen.
#[test]
fn furnace_a_white_subsurface_ball_returns_all_the_light() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::Scalar;
    let milk = OpenPbr {
        subsurface_weight: Scalar::constant(1.0),
        subsurface_color: crate::scene::openpbr::Color::constant(Vec3::ONE),
        subsurface_radius: Scalar::constant(0.3),
        ..OpenPbr::default()
    };
    let s = furnace_of(milk, Vec3::ZERO, 1.0);
    assert_returns_all_the_light(&s, &[0.0, 0.7], "white subsurface");
}

/// A medium far deeper than its free path is the semi-infinite slab the specification
/// defines `subsurface_color` by: under uniform light, with no reflection at its
/// interface, it reflects that colour, channel by channel.
#[test]
fn a_deep_subsurface_reflects_its_colour() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::{Color, Scalar};
    let color = Vec3::new(0.8, 0.5, 0.2);
    let wax = OpenPbr {
        specular_weight: Scalar::constant(0.0),
        subsurface_weight: Scalar::constant(1.0),
        subsurface_color: Color::constant(color),
        subsurface_radius: Scalar::constant(0.01),
        ..OpenPbr::default()
    };
    let s = furnace_of(wax, Vec3::new(0.0, 0.0, -1000.0), 1000.0);
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    let (l, error) = estimate(&s, ray, 6000, Weighing::PowerHeuristic);
    assert!(
        ((l - color).abs() - 4.0 * error).max_element() < 0.02,
        "{l} ± {error}, against {color}"
    );
}

/// Light walks through a slab thinner than its medium's free path and leaves on the
/// far side: a slab lit from behind glows on its dark face in the path model, where
/// the whitted model's diffuse stand-in for the medium shows nothing.
#[test]
fn a_thin_subsurface_slab_lets_light_through_from_behind() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::Scalar;
    let paper = OpenPbr {
        specular_weight: Scalar::constant(0.0),
        subsurface_weight: Scalar::constant(1.0),
        subsurface_radius: Scalar::constant(1.0),
        ..OpenPbr::default()
    };
    let face = |z: f32| {
        Shape::Rectangle(Rectangle {
            v: [
                Vec3::new(-10.0, -10.0, z),
                Vec3::new(10.0, -10.0, z),
                Vec3::new(10.0, 10.0, z),
                Vec3::new(-10.0, 10.0, z),
            ],
        })
    };
    let sheet = Surface {
        albedo: Albedo::Color(Vec3::ONE),
        openpbr: Some(Box::new(paper)),
        ..Surface::default()
    };
    let s = scene(
        vec![(face(0.0), sheet.clone()), (face(-0.05), sheet)],
        vec![area_light(
            LightKind::Quad {
                u: Vec3::new(4.0, 0.0, 0.0),
                v: Vec3::new(0.0, 4.0, 0.0),
            },
            Vec3::new(0.0, 0.0, -2.0),
            5.0,
        )],
        Background::Black,
    );
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    let (l, error) = estimate(&s, ray, 4000, Weighing::PowerHeuristic);
    assert!(
        l.min_element() > 0.1 && error.max_element() < 0.2 * l.min_element(),
        "{l} ± {error}"
    );
    // The medium's long free path in red shows: red passes more than blue.
    assert!(l.x > l.z, "{l}");
    assert_eq!(whitted_radiance(&s, ray), Vec3::ZERO);
}

/// Clear glass holding a medium that scatters without absorbing (white
/// `transmission_color`, `transmission_scatter` above zero) loses no light: in the
/// furnace a ball of it shows one, smooth or rough, whichever way the medium scatters.
#[test]
fn furnace_glass_holding_a_white_scattering_medium_returns_all_the_light() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::{Color, Scalar};
    for (roughness, g) in [(0.0, 0.0), (0.0, 0.7), (0.3, -0.5)] {
        let milky = OpenPbr {
            transmission_weight: Scalar::constant(1.0),
            transmission_depth: Scalar::constant(0.5),
            transmission_scatter: Color::constant(Vec3::ONE),
            transmission_scatter_anisotropy: Scalar::constant(g),
            specular_roughness: Scalar::constant(roughness),
            ..OpenPbr::default()
        };
        let s = furnace_of(milky, Vec3::ZERO, 1.0);
        let what = format!("roughness {roughness}, g {g}");
        assert_returns_all_the_light(&s, &[0.0, 0.8], &what);
    }
}

/// Light seen straight through a solid's scattering medium is dimmed by its whole
/// extinction, absorption and scattering together, as the specification builds it:
/// `transmission_color` (0.5, 0.7, 0.9) after a depth of 1 with a grey scatter of 0.9
/// leaves absorption below zero in every channel, so grey is added until blue's is
/// zero. Seen through a chord of 1 of an index-matched ball, a small light of radiance
/// 1 shows exp(-σt).
#[test]
fn a_light_seen_through_a_scattering_medium_is_dimmed_by_its_extinction() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::{Color, Scalar};
    let color = Vec3::new(0.5, 0.7, 0.9);
    let scatter = Vec3::splat(0.9);
    let fog = OpenPbr {
        transmission_weight: Scalar::constant(1.0),
        transmission_color: Color::constant(color),
        transmission_depth: Scalar::constant(1.0),
        transmission_scatter: Color::constant(scatter),
        specular_ior: Scalar::constant(1.0),
        specular_roughness: Scalar::constant(0.0),
        ..OpenPbr::default()
    };
    let s = ball_of(
        fog,
        Vec3::ZERO,
        0.5,
        vec![area_light(
            LightKind::Quad {
                u: Vec3::new(0.02, 0.0, 0.0),
                v: Vec3::new(0.0, 0.02, 0.0),
            },
            Vec3::new(0.0, 0.0, -2.0),
            1.0,
        )],
        Background::Black,
    );
    let mu_t = -Vec3::new(color.x.ln(), color.y.ln(), color.z.ln());
    let mu_a = mu_t - scatter;
    let sigma_t = mu_a - Vec3::splat(mu_a.min_element()) + scatter;
    let want = (-sigma_t).exp();
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    let (l, error) = estimate(&s, ray, 20_000, Weighing::PowerHeuristic);
    assert!(
        ((l - want).abs() - 4.0 * error).max_element() < 0.003,
        "{l} ± {error}, against {want}"
    );
    // Beer's absorption alone would leave the colour itself.
    assert!((l - color).abs().min_element() > 0.2, "{l}");
}

/// Lit from the side against black, clear glass shows the black behind it where a
/// milky one glows with the light its medium scatters toward the viewer.
#[test]
fn a_milky_ball_lit_from_the_side_glows_where_clear_glass_shows_black() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::{Color, Scalar};
    let radiance = |scatter: f32| {
        let glass = OpenPbr {
            transmission_weight: Scalar::constant(1.0),
            transmission_depth: Scalar::constant(0.5),
            transmission_scatter: Color::constant(Vec3::splat(scatter)),
            specular_roughness: Scalar::constant(0.0),
            ..OpenPbr::default()
        };
        let s = ball_of(
            glass,
            Vec3::ZERO,
            1.0,
            vec![area_light(
                LightKind::Quad {
                    u: Vec3::new(0.0, 0.0, 2.0),
                    v: Vec3::new(0.0, 2.0, 0.0),
                },
                Vec3::new(3.0, 0.0, 0.0),
                5.0,
            )],
            Background::Black,
        );
        estimate(
            &s,
            Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z),
            4000,
            Weighing::PowerHeuristic,
        )
    };
    let (clear, _) = radiance(0.0);
    let (milky, error) = radiance(1.0);
    assert_eq!(clear, Vec3::ZERO);
    assert!(
        milky.min_element() > 0.05 && error.max_element() < 0.25 * milky.min_element(),
        "{milky} ± {error}"
    );
}
