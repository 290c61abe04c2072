//! OpenPBR surfaces in the path model: the furnace against their directional albedo,
//! the coat's own normal, dispersion, partial presence, and paths stepped together as
//! one at a time.

use super::*;

/// The furnace for OpenPBR materials: a sphere in a uniform white environment shows,
/// at each view angle, the material's directional albedo there (the convex sphere sees
/// only the environment); clear glass, rough or thin-walled, shows exactly 1.
#[test]
fn furnace_openpbr_spheres_show_their_directional_albedo_and_clear_glass_shows_one() {
    use crate::render::bsdf::{OpenPbrBsdf, Params};
    use crate::scene::OpenPbr;
    let material = |set: &dyn Fn(&mut OpenPbr)| {
        let mut m = OpenPbr::default();
        set(&mut m);
        m
    };
    let cases: Vec<(&str, OpenPbr, Vec3, bool)> = vec![
        (
            "plastic",
            material(&|_| {}),
            Vec3::new(0.8, 0.4, 0.2),
            false,
        ),
        (
            "gold",
            material(&|m| {
                m.base_metalness.value = 1.0;
                m.specular_roughness.value = 0.4;
                m.specular_color.value = Vec3::new(1.0, 0.95, 0.8);
            }),
            Vec3::new(0.94, 0.78, 0.37),
            false,
        ),
        (
            "coated fuzz",
            material(&|m| {
                m.coat_weight.value = 1.0;
                m.coat_roughness.value = 0.2;
                m.fuzz_weight.value = 0.5;
                m.base_diffuse_roughness.value = 0.5;
            }),
            Vec3::new(0.3, 0.5, 0.7),
            false,
        ),
        (
            "rough glass",
            material(&|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.4;
            }),
            Vec3::ONE,
            true,
        ),
        (
            "thin-walled rough glass",
            material(&|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.3;
                m.geometry_thin_walled = true;
            }),
            Vec3::ONE,
            true,
        ),
    ];
    for (name, m, color, clear) in cases {
        let surface = Surface {
            albedo: Albedo::Color(color),
            openpbr: Some(Box::new(m.clone())),
            ..Surface::default()
        };
        let s = scene(
            vec![(
                Shape::Sphere(Sphere {
                    center: Vec3::ZERO,
                    radius: 1.0,
                }),
                surface,
            )],
            vec![],
            Background::Color(Vec3::ONE),
        );
        for x in [0.0f32, 0.6, 0.9] {
            let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
            let l = mean_radiance(&s, ray, 8000);
            let want = if clear {
                Vec3::ONE
            } else {
                // The albedo at the hit's view angle, by the BSDF's own samples.
                let mu = (1.0 - x * x).sqrt();
                let wo = Vec3::new(x, 0.0, mu);
                let b = OpenPbrBsdf::new(&Params::of(&m, color), wo, true);
                let n = 200_000;
                let mut sum = Vec3::ZERO;
                for i in 0..n {
                    let mut sampler = PixelSampler::for_sample(3, 0, 0, i);
                    let pick = sampler.next_f32();
                    if let Some(d) = b.sample(pick, sampler.next_2d()) {
                        sum += d.weight;
                    }
                }
                sum / n as f32
            };
            assert!(
                ((l - want).abs() / want).max_element() < 0.03,
                "{name} at x {x}: {l} against {want}"
            );
        }
    }
}

/// A clear coat over a normal-mapped base lies along the unbent normal (OpenPBR's
/// `geometry_coat_normal` default, glTF's clearcoat without its own normal texture):
/// seen head-on in a white environment over a black base it reflects the coat's
/// Fresnel at normal incidence, not at the bent normal's 30 degrees; given a coat
/// normal map of its own, it follows that one.
#[test]
fn a_coat_keeps_the_unbent_normal_under_a_base_normal_map() {
    use crate::render::optics::fresnel_dielectric;
    use crate::scene::{ImageTexture, OpenPbr, Texels, TextureSlot};
    // Tangent-space normal tilted 30 degrees toward the tangent (more, and the
    // head-on view's mirror would point into the surface).
    let tilted = |s: &mut Scene| {
        let (sin, cos) = (0.5f32, 30f32.to_radians().cos());
        let byte = |v: f32| ((0.5 + 0.5 * v) * 255.0).round() as u8;
        s.images.push(ImageTexture {
            name: "tilted".into(),
            width: 1,
            height: 1,
            texels: Texels::Rgba8 {
                texels: vec![[byte(sin), 128, byte(cos), 255]],
                srgb: false,
            },
        });
        TextureSlot::new(s.images.len() as u32 - 1)
    };
    let coated = |coat_normal: bool| {
        let mut m = OpenPbr {
            specular_weight: crate::scene::openpbr::Scalar::constant(0.0),
            coat_weight: crate::scene::openpbr::Scalar::constant(1.0),
            coat_roughness: crate::scene::openpbr::Scalar::constant(0.0),
            ..OpenPbr::default()
        };
        let mut s = scene(
            vec![(
                unit_quad(),
                Surface {
                    albedo: Albedo::Color(Vec3::ZERO),
                    ..Surface::default()
                },
            )],
            vec![],
            Background::Color(Vec3::ONE),
        );
        let slot = tilted(&mut s);
        if coat_normal {
            m.geometry_coat_normal = Some((slot, 1.0));
        }
        s.surfaces[0].normal_map = Some(slot);
        s.surfaces[0].openpbr = Some(Box::new(m));
        s
    };
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    let head_on = fresnel_dielectric(1.0, 1.0, 1.6);
    let bent = fresnel_dielectric(30f32.to_radians().cos(), 1.0, 1.6);
    let l = mean_radiance(&coated(false), ray, 64);
    // The whitted model traces the coat's own mirror as a third ray, to the same value.
    let flat = coated(false);
    let w = whitted_radiance(&flat, ray);
    assert!((w - l).abs().max_element() < 1e-6, "whitted {w}, path {l}");
    assert!(
        (l - Vec3::splat(head_on)).abs().max_element() < 1e-4,
        "{l} vs {head_on}"
    );
    let l = mean_radiance(&coated(true), ray, 64);
    assert!(
        (l - Vec3::splat(bent)).abs().max_element() < 2e-4,
        "{l} vs {bent}"
    );
}

/// Dispersion splits a path by colour: each path carries one channel, three times its
/// share, so a clear dispersive glass ball in a white furnace still shows 1 in every
/// channel, while each channel refracts at its own index.
#[test]
fn a_dispersive_glass_ball_passes_the_furnace_channel_by_channel() {
    use crate::render::bsdf::Params;
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::Scalar;
    let glass = OpenPbr {
        transmission_weight: Scalar::constant(1.0),
        specular_roughness: Scalar::constant(0.0),
        transmission_dispersion_scale: Scalar::constant(1.0),
        transmission_dispersion_abbe_number: Scalar::constant(20.0),
        ..OpenPbr::default()
    };
    assert!(glass.disperses());
    let p = Params::of(&glass, Vec3::ONE);
    let iors = [0, 1, 2].map(|c| p.for_channel(&glass, c).specular_ior);
    assert!(iors[0] < iors[1] && iors[1] < iors[2], "{iors:?}");
    let s = scene(
        vec![(
            Shape::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            }),
            Surface {
                albedo: Albedo::Color(Vec3::ONE),
                openpbr: Some(Box::new(glass)),
                ..Surface::default()
            },
        )],
        vec![],
        Background::Color(Vec3::ONE),
    );
    for x in [0.0f32, 0.7] {
        let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
        let (l, error) = estimate(&s, ray, 6000, Weighing::PowerHeuristic);
        assert!(
            (l - Vec3::ONE).abs().max_element() < 0.04 + 4.0 * error.max_element(),
            "at x {x}: {l} ± {error}"
        );
    }
}

/// `geometry_opacity`: a surface present a third of the time lets the rest of the light
/// straight through. A black, unreflecting quad before a white environment shows
/// exactly what passes, in both physical models; shadow rays are dimmed alike.
#[test]
fn a_partly_present_surface_lets_the_rest_of_the_light_through() {
    use crate::scene::OpenPbr;
    use crate::scene::openpbr::Scalar;
    let veil = OpenPbr {
        specular_weight: Scalar::constant(0.0),
        geometry_opacity: Scalar::constant(0.3),
        ..OpenPbr::default()
    };
    let s = scene(
        vec![(
            unit_quad(),
            Surface {
                albedo: Albedo::Color(Vec3::ZERO),
                openpbr: Some(Box::new(veil)),
                ..Surface::default()
            },
        )],
        vec![],
        Background::Color(Vec3::ONE),
    );
    let ray = Ray::new(Vec3::new(0.2, 0.1, 5.0), -Vec3::Z);
    let l = mean_radiance(&s, ray, 16);
    assert!((l - Vec3::splat(0.7)).abs().max_element() < 1e-6, "{l}");
    assert_eq!(
        s.resolved_surfaces()[0].transmission,
        Vec3::splat(0.7),
        "shadows pass 0.7"
    );
    let w = whitted_radiance(&s, ray);
    assert!(
        (w - Vec3::splat(0.7)).abs().max_element() < 1e-6,
        "whitted {w}"
    );
}

/// A 2 x 2 square about the origin in the plane z = 0; its tangent (dP/du) is its first
/// edge, +x.
fn unit_quad() -> Shape {
    Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
    })
}

/// A pixel's paths stepped together ([`Path::radiance_wave`]) give each path the
/// radiance and the ray count of [`Path::radiance`], bit for bit, in a scene of every
/// kind of OpenPBR lobe and delta (coat over a subsurface, rough metal, dispersive
/// glass holding a scattering medium, partial presence), a cut-out, a quad light, a
/// point light and an environment.
#[test]
fn paths_stepped_together_give_each_the_radiance_of_the_path_at_a_time() {
    use crate::scene::openpbr::Scalar;
    use crate::scene::{ImageTexture, OpenPbr, Texels, TextureSlot};
    use rand_core::Rng;
    let openpbr = |m: OpenPbr| Surface {
        albedo: Albedo::Color(Vec3::new(0.8, 0.6, 0.3)),
        openpbr: Some(Box::new(m)),
        ..Surface::default()
    };
    let ball = |x: f32, y: f32| {
        Shape::Sphere(Sphere {
            center: Vec3::new(x, y, 0.0),
            radius: 0.5,
        })
    };
    let coated = OpenPbr {
        subsurface_weight: Scalar::constant(0.7),
        subsurface_radius: Scalar::constant(0.2),
        coat_weight: Scalar::constant(1.0),
        coat_roughness: Scalar::constant(0.0),
        base_diffuse_roughness: Scalar::constant(0.5),
        ..OpenPbr::default()
    };
    let metal = OpenPbr {
        base_metalness: Scalar::constant(1.0),
        specular_roughness: Scalar::constant(0.4),
        ..OpenPbr::default()
    };
    let glass = OpenPbr {
        transmission_weight: Scalar::constant(1.0),
        specular_roughness: Scalar::constant(0.0),
        transmission_dispersion_scale: Scalar::constant(1.0),
        transmission_color: crate::scene::openpbr::Color::constant(Vec3::new(0.9, 0.8, 0.7)),
        transmission_depth: Scalar::constant(0.5),
        transmission_scatter: crate::scene::openpbr::Color::constant(Vec3::splat(0.6)),
        ..OpenPbr::default()
    };
    let veil = OpenPbr {
        geometry_opacity: Scalar::constant(0.4),
        ..OpenPbr::default()
    };
    let pane = Surface {
        alpha_map: Some(TextureSlot::new(0)),
        ..matte(0.7)
    };
    let floor = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-3.0, -3.0, -0.5),
            Vec3::new(3.0, -3.0, -0.5),
            Vec3::new(3.0, 3.0, -0.5),
            Vec3::new(-3.0, 3.0, -0.5),
        ],
    });
    let mut s = scene(
        vec![
            (ball(-0.6, 0.6), openpbr(coated)),
            (ball(0.6, 0.6), openpbr(metal)),
            (ball(-0.6, -0.6), openpbr(glass)),
            (ball(0.6, -0.6), openpbr(veil)),
            (unit_quad(), pane),
            (floor, matte(0.5)),
        ],
        vec![
            area_light(
                LightKind::Quad {
                    u: Vec3::X,
                    v: -Vec3::Y,
                },
                Vec3::new(0.0, 0.0, 3.0),
                4.0,
            ),
            Light {
                falloff: crate::scene::Falloff::InverseSquare,
                ..area_light(LightKind::Point, Vec3::new(2.0, 1.0, 2.0), 5.0)
            },
        ],
        Background::Color(Vec3::splat(0.3)),
    );
    // A checkerboard of holes: half the pane is cut out.
    s.images.push(ImageTexture {
        name: "holes".into(),
        width: 2,
        height: 2,
        texels: Texels::RgbaF32([0.0, 1.0, 1.0, 0.0].map(|a| [1.0, 1.0, 1.0, a]).to_vec()),
    });
    let accel = Accel::build(AccelKind::Bvh, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let path = Path::new(&s, &accel, &surfaces, crate::options::MAX_PATH_DEPTH);
    assert!(
        path.lanes.is_none(),
        "the vectorised lanes take Lambertian scenes"
    );
    let mut rng = rand_pcg::Pcg32::new(11, 0x2545_f491_4f6c_dd1d);
    let mut u = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let mut lit = 0;
    for round in 0..64 {
        let n = 1 + round % lanes::LANES;
        let rays: Vec<Ray> = (0..n)
            .map(|_| {
                let origin = Vec3::new(u() - 0.5, u() - 0.5, 4.0);
                let target = Vec3::new(3.0 * u() - 1.5, 3.0 * u() - 1.5, 0.0);
                Ray::new(origin, normalize(target - origin))
            })
            .collect();
        let hits: Vec<_> = rays
            .iter()
            .map(|r| accel.closest(r, f32::INFINITY))
            .collect();
        let samplers = || -> Vec<PixelSampler> {
            (0..n)
                .map(|k| PixelSampler::for_sample(3, round as u32, 7, k as u32))
                .collect()
        };
        let mut alone_count = RayCount::default();
        let mut one = samplers();
        let alone: Vec<_> = (0..n)
            .map(|k| path.radiance(rays[k], hits[k], &mut one[k], &mut alone_count))
            .map(|l| l.to_array().map(f32::to_bits))
            .collect();
        let mut wave_count = RayCount::default();
        let mut together = [Vec3::ZERO; lanes::LANES];
        path.radiance_wave(
            &rays,
            &hits,
            &mut samplers(),
            &mut wave_count,
            &mut together,
        );
        let together: Vec<_> = together[..n]
            .iter()
            .map(|l| l.to_array().map(f32::to_bits))
            .collect();
        assert_eq!(alone, together, "round {round}");
        assert_eq!(alone_count.rays, wave_count.rays, "round {round}");
        lit += alone.iter().filter(|l| **l != [0; 3]).count();
    }
    assert!(lit > 400, "{lit} of 544 paths found light");
}
