//! The path model held to closed forms: a diffuse object in a uniform environment (the
//! furnace), a diffuse floor under each kind of light against its analytic irradiance,
//! every BSDF's and light's sampling against its density (chi-square), BSDF albedos at
//! most one, and light-only and BSDF-only estimates against the weighed sum; OpenPBR
//! surfaces (`openpbr`), media (`media`) and the ways of testing light samples
//! (`light_sampling`) in their own files, on the helpers here.

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
    let mut light = Light::mesh(&probe, [0, 1].map(ShapeId::world)).unwrap();
    if let LightKind::Mesh { shapes, .. } = &mut light.kind {
        *shapes = vec![ShapeId::world(1), ShapeId::world(2)];
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

/// The whitted model's radiance along `ray` in `s` (one sample, four bounces).
fn whitted_radiance(s: &Scene, ray: Ray) -> Vec3 {
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let whitted = crate::render::whitted::Whitted::new(s, &accel, &surfaces, 4, 0.0);
    let mut sampler = PixelSampler::for_sample(1, 0, 0, 0);
    whitted.radiance(&ray, 0, Vec3::ONE, &mut sampler, &mut RayCount::default())
}

mod light_sampling;
mod media;
mod openpbr;
