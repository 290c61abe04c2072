//! The path model held to closed forms: a diffuse object in a uniform environment (the
//! furnace), a diffuse floor under each kind of light against its analytic irradiance,
//! every BSDF's and light's sampling against its density (chi-square), BSDF albedos at
//! most one, and light-only and BSDF-only estimates against the weighed sum.

use super::*;
use crate::accel::AccelKind;
use crate::math::{cross, normalize};
use crate::scene::{Albedo, Background, Material, Rectangle, Shape, Sphere, Triangle};
use std::f32::consts::PI;

/// A scene of `shapes`, each with its own surface.
fn scene(shapes: Vec<(Shape, Surface)>, lights: Vec<Light>, background: Background) -> Scene {
    let mut s = Scene {
        lights,
        background,
        ..Scene::default()
    };
    for (i, (shape, surface)) in shapes.into_iter().enumerate() {
        s.materials.push(Material::default_white());
        s.surfaces.push(surface);
        s.push_shape(shape, i as u32);
    }
    s
}

fn matte(c: f32) -> Surface {
    Surface {
        albedo: Albedo::Color(Vec3::splat(c)),
        ..Surface::default()
    }
}

/// The mean radiance along `ray` over `n` samples.
fn mean_radiance(s: &Scene, ray: Ray, n: u32) -> Vec3 {
    weighed_radiance(s, ray, n, Weighing::PowerHeuristic)
}

/// [`mean_radiance`] with the strategies weighed by `weighing`.
fn weighed_radiance(s: &Scene, ray: Ray, n: u32, weighing: Weighing) -> Vec3 {
    estimate(s, ray, n, weighing).0
}

/// The mean radiance along `ray` over `n` samples and its standard error.
fn estimate(s: &Scene, ray: Ray, n: u32, weighing: Weighing) -> (Vec3, Vec3) {
    let depth = crate::options::MAX_PATH_DEPTH;
    let (mean, error, _) = estimate_with(s, ray, n, depth, weighing, LightSampling::Auto);
    (mean, error)
}

/// [`estimate`] by a path integrator scattering at most `max_depth` times, tracing
/// shadow rays as `how` says; and the rays it traced.
fn estimate_with(
    s: &Scene,
    ray: Ray,
    n: u32,
    max_depth: u32,
    weighing: Weighing,
    how: LightSampling,
) -> (Vec3, Vec3, u64) {
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let path = Path::new(s, &accel, &surfaces, max_depth)
        .weighing(weighing)
        .light_sampling(how);
    let mut count = RayCount::default();
    // Summed in f64: thousands of f32 additions would drift by 1e-4.
    let (mut sum, mut squares) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for i in 0..n {
        let mut sampler = PixelSampler::for_sample(11, 0, 0, i);
        let hit = accel.closest(&ray, f32::INFINITY);
        let l = path.radiance(ray, hit, &mut sampler, &mut count).as_dvec3();
        sum += l;
        squares += l * l;
    }
    let n = f64::from(n);
    let mean = sum / n;
    let variance = (squares / n - mean * mean).max(glam::DVec3::ZERO);
    (
        Vec3::from(mean.as_vec3()),
        Vec3::from((variance / n).sqrt().as_vec3()),
        count.rays,
    )
}

/// The radiance of `s` seen down -z from above each of `xs` (on the x axis) is one, to
/// four standard errors and 0.02: a furnace returns all the light.
fn assert_returns_all_the_light(s: &Scene, xs: &[f32], what: &str) {
    for &x in xs {
        let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
        let (l, error) = estimate(s, ray, 4000, Weighing::PowerHeuristic);
        assert!(
            ((l - Vec3::ONE).abs() - 4.0 * error).max_element() < 0.02,
            "{what} at x {x}: {l} ± {error}"
        );
    }
}

fn assert_near(got: Vec3, want: f32, tol: f32, what: &str) {
    assert!(
        (got - Vec3::splat(want)).abs().max_element() <= tol * want,
        "{what}: {got} against {want}"
    );
}

#[test]
fn furnace_a_diffuse_sphere_in_a_uniform_environment_shows_its_albedo_times_the_light() {
    for albedo in [0.5, 1.0] {
        let s = scene(
            vec![(
                Shape::Sphere(Sphere {
                    center: Vec3::ZERO,
                    radius: 1.0,
                }),
                matte(albedo),
            )],
            vec![],
            Background::Color(Vec3::splat(2.0)),
        );
        for x in [0.0, 0.5, 0.9] {
            let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
            let l = mean_radiance(&s, ray, 8000);
            assert_near(l, 2.0 * albedo, 0.03, &format!("albedo {albedo}, x {x}"));
        }
    }
}

/// A pane cut out everywhere is not there: camera rays, BSDF rays and shadow rays all
/// pass it, and the furnace still shows the sphere's albedo times the light. (Scenes
/// with cut-outs take their own way through the path loop.)
#[test]
fn a_pane_cut_out_everywhere_leaves_the_furnace_as_it_was() {
    use crate::scene::{ImageTexture, Texels, TextureSlot};
    let pane = Surface {
        alpha_map: Some(TextureSlot::new(0)),
        ..matte(0.9)
    };
    let mut s = scene(
        vec![
            (
                Shape::Sphere(Sphere {
                    center: Vec3::ZERO,
                    radius: 1.0,
                }),
                matte(0.5),
            ),
            (
                Shape::Rectangle(Rectangle {
                    v: [
                        Vec3::new(-4.0, -4.0, 3.0),
                        Vec3::new(4.0, -4.0, 3.0),
                        Vec3::new(4.0, 4.0, 3.0),
                        Vec3::new(-4.0, 4.0, 3.0),
                    ],
                }),
                pane,
            ),
        ],
        vec![],
        Background::Color(Vec3::splat(2.0)),
    );
    s.images.push(ImageTexture {
        name: "holes".into(),
        width: 2,
        height: 2,
        texels: Texels::RgbaF32(vec![[1.0, 1.0, 1.0, 0.0]; 4]),
    });
    for x in [0.0, 0.9] {
        let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
        let l = mean_radiance(&s, ray, 8000);
        assert_near(l, 1.0, 0.03, &format!("x {x}"));
    }
}

/// A floor of albedo 0.8 at y = 0, seen straight down at its origin.
fn floor_under(lights: Vec<Light>, extra: Vec<(Shape, Surface)>) -> Vec3 {
    let mut shapes = vec![(
        Shape::Rectangle(Rectangle {
            v: [
                Vec3::new(-50.0, 0.0, -50.0),
                Vec3::new(-50.0, 0.0, 50.0),
                Vec3::new(50.0, 0.0, 50.0),
                Vec3::new(50.0, 0.0, -50.0),
            ],
        }),
        matte(0.8),
    )];
    shapes.extend(extra);
    let s = scene(shapes, lights, Background::Black);
    mean_radiance(&s, Ray::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y), 6000)
}

fn area_light(kind: LightKind, at: Vec3, radiance: f32) -> Light {
    Light {
        position: at,
        color: Vec3::ONE,
        intensity: radiance,
        kind,
        falloff: crate::scene::Falloff::None,
        samples: 1,
        camera_visible: true,
    }
}

/// Form factor from a point to a rectangle `a` x `b` parallel to it at height `h`,
/// with one corner straight above the point.
fn corner_form_factor(a: f32, b: f32, h: f32) -> f32 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

#[test]
fn a_diffuse_floor_under_each_area_light_converges_to_the_analytic_irradiance() {
    // Lambert: L = rho / pi E.
    let (rho, le, h) = (0.8, 3.0, 2.0);
    let disk = floor_under(
        vec![area_light(
            LightKind::Disk {
                normal: -Vec3::Y,
                radius: 1.0,
            },
            Vec3::new(0.0, h, 0.0),
            le,
        )],
        vec![],
    );
    // E = pi L R^2 / (h^2 + R^2).
    assert_near(disk, rho * le / (h * h + 1.0), 0.02, "disk");

    let quad_e = PI * le * 4.0 * corner_form_factor(1.0, 1.0, h);
    let quad = floor_under(
        vec![area_light(
            LightKind::Quad {
                u: Vec3::new(2.0, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 2.0),
            },
            Vec3::new(0.0, h, 0.0),
            le,
        )],
        vec![],
    );
    assert_near(quad, rho / PI * quad_e, 0.02, "quad");

    // A sphere of radius R at distance d: E = pi L (R / d)^2.
    let sphere = floor_under(
        vec![area_light(
            LightKind::Sphere { radius: 0.5 },
            Vec3::new(0.0, h, 0.0),
            le,
        )],
        vec![],
    );
    assert_near(sphere, rho * le * 0.25 / (h * h), 0.02, "sphere");

    // The same square as two emissive triangles facing down: a mesh light.
    let y = h;
    let corners = [
        Vec3::new(-1.0, y, -1.0),
        Vec3::new(1.0, y, -1.0),
        Vec3::new(1.0, y, 1.0),
        Vec3::new(-1.0, y, 1.0),
    ];
    let emitter = Surface {
        emission: Vec3::splat(le),
        ..matte(0.0)
    };
    let tris = vec![
        (
            Shape::Triangle(Triangle {
                v: [corners[0], corners[1], corners[2]],
            }),
            emitter.clone(),
        ),
        (
            Shape::Triangle(Triangle {
                v: [corners[0], corners[2], corners[3]],
            }),
            emitter,
        ),
    ];
    assert!(cross(corners[1] - corners[0], corners[2] - corners[0]).y < 0.0);
    let mut probe = scene(vec![], vec![], Background::Black);
    for (shape, _) in &tris {
        probe.shapes.push(*shape);
    }
    // Shapes 1 and 2 of the floor scene.
    let mut light = Light::mesh(&probe.shapes, &[0, 1]).unwrap();
    if let LightKind::Mesh { shapes, .. } = &mut light.kind {
        *shapes = vec![1, 2];
    }
    let mesh = floor_under(vec![light], tris);
    assert_near(mesh, rho / PI * quad_e, 0.02, "mesh");
}

#[test]
fn a_point_light_over_a_diffuse_floor_gives_the_inverse_square_law_exactly() {
    let light = Light {
        falloff: crate::scene::Falloff::InverseSquare,
        intensity: 5.0,
        ..Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE)
    };
    let l = floor_under(vec![light], vec![]);
    assert_near(l, 0.8 / PI * 5.0 / 4.0, 1e-5, "point");
}

#[test]
fn a_light_hidden_from_the_camera_is_its_light_alone_no_object_no_shadow() {
    // A sphere light straight ahead of the camera, over a mirror floor: the camera ray
    // sees it unless it is hidden; hidden, it still lights the floor and shows in it.
    let sphere = |visible: bool| Light {
        camera_visible: visible,
        ..area_light(
            LightKind::Sphere { radius: 0.5 },
            Vec3::new(0.0, 1.0, -3.0),
            7.0,
        )
    };
    let seen = |visible: bool| {
        let s = scene(
            vec![],
            vec![sphere(visible)],
            Background::Color(Vec3::splat(0.25)),
        );
        mean_radiance(&s, Ray::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Z), 4)
    };
    assert_near(seen(true), 7.0, 1e-6, "the light seen");
    assert_near(
        seen(false),
        0.25,
        1e-6,
        "the background behind the hidden light",
    );
    let lit = |visible: bool| floor_under(vec![sphere(visible)], vec![]);
    assert_near(lit(false), lit(true).x, 1e-3, "the same light");
    // Hidden, it casts no shadow: a dark sphere light between a point light and the
    // floor blocks it only while it is an object of the scene.
    let lamp = Light {
        falloff: crate::scene::Falloff::InverseSquare,
        intensity: 5.0,
        ..Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE)
    };
    let blocker = |visible: bool| Light {
        intensity: 0.0,
        ..sphere(visible)
    };
    let shaded = |visible: bool| {
        let mut b = blocker(visible);
        b.position = Vec3::new(0.0, 1.5, 0.0);
        floor_under(vec![lamp.clone(), b], vec![])
    };
    assert_near(
        shaded(false),
        0.8 / PI * 5.0 / 4.0,
        1e-5,
        "no shadow of a hidden light",
    );
    assert_near(
        shaded(true),
        0.0,
        1e-6,
        "the shadow of a light that is an object",
    );
    let mirror = Surface {
        reflection: Vec3::ONE,
        albedo: Albedo::Color(Vec3::ZERO),
        ..Surface::default()
    };
    let floor = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-50.0, 0.0, -50.0),
            Vec3::new(-50.0, 0.0, 50.0),
            Vec3::new(50.0, 0.0, 50.0),
            Vec3::new(50.0, 0.0, -50.0),
        ],
    });
    let s = scene(
        vec![(floor, mirror)],
        vec![sphere(false)],
        Background::Black,
    );
    let down = normalize(Vec3::new(0.0, -1.0, -1.5));
    let reflected = mean_radiance(&s, Ray::new(Vec3::new(0.0, 1.0, 0.0), down), 4);
    assert_near(reflected, 7.0, 1e-4, "the hidden light in the mirror");
}

/// Smooth lobes of every kind, seen from several directions.
fn smooth_bsdfs() -> Vec<(&'static str, Terms)> {
    let base = Terms {
        diffuse: Vec3::ZERO,
        highlight: Highlight::None,
        reflection: Vec3::ZERO,
        transmission: Vec3::ZERO,
        fresnel: false,
        eta_i: 1.0,
        eta_t: 1.5,
    };
    vec![
        (
            "lambert",
            Terms {
                diffuse: Vec3::new(0.9, 0.5, 0.1),
                ..base
            },
        ),
        (
            "phong 20",
            Terms {
                diffuse: Vec3::splat(0.3),
                highlight: Highlight::Phong {
                    ks: Vec3::splat(0.6),
                    exponent: 20.0,
                },
                ..base
            },
        ),
        (
            "phong 1 white",
            Terms {
                highlight: Highlight::Phong {
                    ks: Vec3::ONE,
                    exponent: 1.0,
                },
                ..base
            },
        ),
        (
            "blinn 50",
            Terms {
                diffuse: Vec3::splat(0.5),
                highlight: Highlight::Blinn {
                    ks: Vec3::splat(0.5),
                    exponent: 50.0,
                },
                ..base
            },
        ),
        (
            "blinn 2 white",
            Terms {
                highlight: Highlight::Blinn {
                    ks: Vec3::ONE,
                    exponent: 2.0,
                },
                ..base
            },
        ),
        (
            "ggx metal 0.3",
            Terms {
                highlight: Highlight::Ggx {
                    f0: Vec3::new(0.95, 0.64, 0.54),
                    alpha: 0.09,
                },
                ..base
            },
        ),
        (
            "ggx white metal rough",
            Terms {
                highlight: Highlight::Ggx {
                    f0: Vec3::ONE,
                    alpha: 0.8,
                },
                ..base
            },
        ),
        (
            "ggx white dielectric",
            Terms {
                diffuse: Vec3::ONE,
                highlight: Highlight::Ggx {
                    f0: Vec3::splat(0.04),
                    alpha: 0.25,
                },
                ..base
            },
        ),
    ]
}

/// Directions `wo` from normal incidence to grazing, about +z.
fn views() -> Vec<Vec3> {
    [1.0f32, 0.8, 0.5, 0.2, 0.05]
        .iter()
        .map(|&c| Vec3::new((1.0 - c * c).sqrt(), 0.0, c))
        .collect()
}

#[test]
fn every_bsdf_reflects_at_most_what_it_receives_and_its_samples_agree_with_eval() {
    let mut s = PixelSampler::for_sample(5, 0, 0, 0);
    for (name, terms) in smooth_bsdfs() {
        for wo in views() {
            let bsdf = PhongBsdf::new(&terms, wo, Vec3::Z, Vec3::Z);
            // The albedo two ways: the mean sample weight, and f cos integrated over
            // the hemisphere by stratified uniform directions.
            let n = 200_000;
            let mut by_samples = Vec3::ZERO;
            for _ in 0..n {
                let pick = s.next_f32();
                if let Some(sm) = bsdf.sample(pick, s.next_2d()) {
                    by_samples += sm.weight;
                }
            }
            by_samples /= n as f32;
            let k = 400;
            let mut by_eval = Vec3::ZERO;
            for i in 0..k {
                for j in 0..k {
                    let z = (i as f32 + 0.5) / k as f32;
                    let phi = (j as f32 + 0.5) / k as f32 * 2.0 * PI;
                    let r = (1.0 - z * z).sqrt();
                    let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    by_eval += bsdf.eval(wi) * z;
                }
            }
            by_eval *= 2.0 * PI / (k * k) as f32;
            assert!(
                by_eval.max_element() <= 1.0 + 2e-3,
                "{name} at {wo}: albedo {by_eval}"
            );
            assert!(
                (by_samples - by_eval).abs().max_element() <= 0.01 + 0.02 * by_eval.max_element(),
                "{name} at {wo}: sampled {by_samples}, integrated {by_eval}"
            );
        }
    }
}

/// Pearson's chi-square of `n` directions drawn by `draw` against `pdf`, over bins of
/// the sphere in (z, phi), expected counts integrated from the density; bins expecting
/// fewer than five are pooled. Returns the statistic over its degrees of freedom.
fn chi_square(
    n: u32,
    sub: u32,
    mut draw: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) -> f32 {
    const ZB: usize = 24;
    const PB: usize = 48;
    let mut observed = vec![0f64; ZB * PB];
    for _ in 0..n {
        if let Some(d) = draw() {
            let z = ((d.z * 0.5 + 0.5) * ZB as f32).clamp(0.0, ZB as f32 - 1.0) as usize;
            let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            let p = ((phi / (2.0 * PI)) * PB as f32).min(PB as f32 - 1.0) as usize;
            observed[z * PB + p] += 1.0;
        }
    }
    let mut expected = vec![0f64; ZB * PB];
    for (b, e) in expected.iter_mut().enumerate() {
        let (zi, pi) = (b / PB, b % PB);
        let mut sum = 0.0f64;
        for a in 0..sub {
            for c in 0..sub {
                let z = -1.0 + 2.0 * (zi as f32 + (a as f32 + 0.5) / sub as f32) / ZB as f32;
                let phi = 2.0 * PI * (pi as f32 + (c as f32 + 0.5) / sub as f32) / PB as f32;
                let r = (1.0 - z * z).max(0.0).sqrt();
                sum += f64::from(pdf(Vec3::new(r * phi.cos(), r * phi.sin(), z)));
            }
        }
        let area = 2.0 / ZB as f64 * 2.0 * std::f64::consts::PI / PB as f64;
        *e = sum / f64::from(sub * sub) * area * f64::from(n);
    }
    let (mut chi2, mut bins, mut pool_o, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
    for (o, e) in observed.iter().zip(&expected) {
        if *e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            bins += 1;
        }
    }
    if pool_e >= 5.0 {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        bins += 1;
    }
    (chi2 / (bins.max(2) - 1) as f64) as f32
}

#[test]
fn every_bsdf_draws_directions_by_its_density() {
    let mut s = PixelSampler::for_sample(6, 0, 0, 0);
    for (name, terms) in smooth_bsdfs() {
        for wo in [views()[1], views()[3]] {
            let bsdf = PhongBsdf::new(&terms, wo, Vec3::Z, Vec3::Z);
            let mut draw = || {
                let pick = s.next_f32();
                bsdf.sample(pick, s.next_2d()).map(|sm| sm.wi)
            };
            // Draws that fail (below the surface) keep their share of the density
            // outside the hemisphere, where `pdf` is zero: count them as such.
            let stat = chi_square(400_000, 8, &mut draw, |wi| bsdf.pdf(wi));
            assert!(stat < 1.5, "{name} at {wo}: chi-square / dof {stat}");
        }
    }
}

#[test]
fn every_area_light_draws_directions_by_its_density() {
    let p = Vec3::new(0.3, -0.2, 0.1);
    let lights = [
        LightKind::Quad {
            u: Vec3::new(1.5, 0.0, 0.3),
            v: Vec3::new(0.0, 0.4, 1.0),
        },
        LightKind::Disk {
            normal: normalize(Vec3::new(-1.0, 0.2, 0.1)),
            radius: 0.8,
        },
        LightKind::Sphere { radius: 0.6 },
    ];
    let empty = Scene::default();
    for kind in lights {
        let light = area_light(kind, Vec3::new(1.5, 0.5, 0.2), 1.0);
        let mut s = PixelSampler::for_sample(7, 0, 0, 0);
        let mut draw = || {
            light
                .sample_incident(&empty, &[], p, s.next_2d())
                .map(|inc| inc.dir)
        };
        // The density of a direction: where it meets the light, if it does.
        let pdf = |d: Vec3| {
            light
                .hit(&Ray::new(p, d), f32::INFINITY)
                .map_or(0.0, |(t, n)| light.pdf_incident(p, p + d * t, n))
        };
        // A light's density ends at its edges: the bins it crosses are integrated finely.
        let stat = chi_square(200_000, 32, &mut draw, pdf);
        assert!(stat < 1.5, "{}: chi-square / dof {stat}", light.kind_name());
    }
}

#[test]
fn an_environment_image_is_drawn_by_its_brightness() {
    let up = Vec3::Y;
    let forward = Vec3::Z;
    let sun = normalize(Vec3::new(0.3, 0.6, -0.5));
    let sky = |d: Vec3| Vec3::splat(0.2 + 50.0 * d.dot(sun).max(0.0).powi(40));
    let dist = environment::ImageDistribution::new(128, 64, up, forward, sky);
    let mut s = PixelSampler::for_sample(8, 0, 0, 0);
    let mut draw = || dist.sample(s.next_2d()).map(|(d, _)| d);
    let stat = chi_square(400_000, 8, &mut draw, |d| dist.pdf(d));
    assert!(stat < 1.5, "chi-square / dof {stat}");
    // Its density integrates to one over the sphere.
    let k = 512;
    let mut total = 0.0f64;
    for i in 0..k {
        for j in 0..2 * k {
            let z = -1.0 + 2.0 * (i as f32 + 0.5) / k as f32;
            let phi = PI * (j as f32 + 0.5) / k as f32;
            let r = (1.0 - z * z).sqrt();
            total += f64::from(dist.pdf(Vec3::new(r * phi.cos(), z, r * phi.sin())));
        }
    }
    let total = total * 4.0 * std::f64::consts::PI / (2 * k * k) as f64;
    assert!((total - 1.0).abs() < 0.01, "{total}");
}

#[test]
fn light_sampling_alone_and_bsdf_sampling_alone_agree_with_their_weighed_sum() {
    // A glossy floor under a disk light, beside a diffuse wall, in a dim sky: light
    // that each strategy finds well and light it finds badly.
    let glossy = Surface {
        specular: Vec3::splat(0.4),
        shininess: 30.0,
        ..matte(0.4)
    };
    let s = scene(
        vec![
            (
                Shape::Rectangle(Rectangle {
                    v: [
                        Vec3::new(-5.0, 0.0, -5.0),
                        Vec3::new(-5.0, 0.0, 5.0),
                        Vec3::new(5.0, 0.0, 5.0),
                        Vec3::new(5.0, 0.0, -5.0),
                    ],
                }),
                glossy,
            ),
            (
                Shape::Sphere(Sphere {
                    center: Vec3::new(-1.5, 1.0, 0.0),
                    radius: 1.0,
                }),
                matte(0.7),
            ),
        ],
        vec![area_light(
            LightKind::Disk {
                normal: normalize(Vec3::new(-0.3, -1.0, 0.0)),
                radius: 0.7,
            },
            Vec3::new(1.0, 2.5, 0.0),
            4.0,
        )],
        Background::Color(Vec3::new(0.1, 0.15, 0.3)),
    );
    for target in [Vec3::new(0.5, 0.0, 0.3), Vec3::new(-0.8, 0.0, 1.2)] {
        let from = Vec3::new(-2.0, 1.5, 3.0);
        let ray = Ray::new(from, target - from);
        let (mis, mis_error) = estimate(&s, ray, 40_000, Weighing::PowerHeuristic);
        for weighing in [Weighing::LightsOnly, Weighing::BsdfOnly] {
            let (alone, error) = estimate(&s, ray, 40_000, weighing);
            // Within four standard errors (of the two, taken as independent: they
            // share their random streams, so the bound is loose, not tight).
            let bound = (error * error + mis_error * mis_error).sqrt() * 4.0;
            assert!(
                (alone - mis).abs().cmple(bound).all(),
                "{weighing:?} at {target}: {alone} against {mis}, bound {bound}"
            );
            // Each strategy alone is noisier than the two weighed.
            assert!(
                error.max_element() > mis_error.max_element(),
                "{weighing:?}"
            );
        }
    }
}

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

/// The whitted model's radiance along `ray` in `s` (one sample, four bounces).
fn whitted_radiance(s: &Scene, ray: Ray) -> Vec3 {
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let whitted = crate::render::whitted::Whitted::new(s, &accel, &surfaces, 4, 0.0);
    let mut sampler = PixelSampler::for_sample(1, 0, 0, 0);
    whitted.radiance(&ray, 0, Vec3::ONE, &mut sampler, &mut RayCount::default())
}

/// A pixel's paths stepped together ([`Path::radiance_wave`]) give each path the
/// radiance and the ray count of [`Path::radiance`], bit for bit, in a scene of every
/// kind of OpenPBR lobe and delta (coat over a subsurface, rough metal, dispersive
/// glass holding a scattering medium, partial presence), a cut-out, a quad light, a point light and an environment.
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

/// A floor under five lights of every kind (a sphere casting part of the quad light's
/// shadow) in a grey environment.
fn many_lights_floor() -> Scene {
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

/// One shadow ray a vertex, toward a light sample chosen by its contribution, is
/// unbiased: the floor under five lights, part in a shadow, converges to what a
/// shadow ray toward every light gives, direct light alone and with bounces; and a
/// direct-light vertex traces one shadow ray where it traced five.
#[test]
fn one_shadow_ray_a_vertex_converges_to_a_shadow_ray_toward_every_light() {
    let s = many_lights_floor();
    for (x, max_depth) in [(0.0, 0), (0.4, 0), (0.0, crate::options::MAX_PATH_DEPTH)] {
        let ray = Ray::new(
            Vec3::new(x, 1.5, 0.6),
            normalize(Vec3::new(0.0, -1.0, -0.2)),
        );
        let mis = Weighing::PowerHeuristic;
        let (all, all_error, all_rays) =
            estimate_with(&s, ray, 20_000, max_depth, mis, LightSampling::All);
        let (one, one_error, one_rays) =
            estimate_with(&s, ray, 20_000, max_depth, mis, LightSampling::One);
        let error = (all_error * all_error + one_error * one_error).sqrt();
        assert!(
            ((one - all).abs() - 4.0 * error).max_element() < 1e-3 * all.max_element(),
            "x {x}, depth {max_depth}: one {one} ± {one_error}, all {all} ± {all_error}"
        );
        if max_depth == 0 {
            // The camera ray and a shadow ray toward each light with light to give
            // (the environment's samples below the floor give none).
            assert!(all_rays >= 20_000 * 5, "{all_rays}");
            assert!(one_rays <= 20_000 * 2, "{one_rays}");
        }
    }
}

#[test]
fn auto_light_sampling_traces_one_shadow_ray_above_sixteen_lights() {
    let lights = LightSampling::AUTO_ALL_UP_TO;
    assert!(!LightSampling::Auto.traces_one(lights));
    assert!(LightSampling::Auto.traces_one(lights + 1));
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
