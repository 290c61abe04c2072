//! Closed-form checks of the whitted model: each scene is simple enough that optics
//! gives the radiance exactly (or, for area lights, as an integral).

use super::*;
use crate::accel::AccelKind;
use crate::math::{normalize, surface_epsilon};
use crate::scene::{Albedo, Background, Falloff, LightKind, Material, Rectangle, Shape, Sphere};
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

fn radiance_of(s: &Scene, ray: Ray) -> Vec3 {
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let w = Whitted::new(s, &accel, &surfaces, 10, 0.0);
    let mut count = RayCount::default();
    w.radiance(
        &ray,
        0,
        Vec3::ONE,
        &mut PixelSampler::new(3, 1, 2),
        &mut count,
    )
}

fn matte(c: Vec3) -> Surface {
    Surface {
        albedo: Albedo::Color(c),
        ..Surface::default()
    }
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol * b.abs().max_element().max(1e-6)
}

/// A square of side `2 half` in the plane y = `y`, normal +y (wound counter-clockwise
/// seen from above).
fn floor(y: f32, half: f32) -> Shape {
    Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-half, y, -half),
            Vec3::new(-half, y, half),
            Vec3::new(half, y, half),
            Vec3::new(half, y, -half),
        ],
    })
}

fn down_at(x: f32, z: f32) -> Ray {
    Ray::new(Vec3::new(x, 5.0, z), -Vec3::Y)
}

#[test]
fn a_diffuse_sphere_under_a_point_light_is_kd_c_i_cos_over_pi() {
    let c = Vec3::new(0.8, 0.5, 0.25);
    let ball = Shape::Sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    for theta_deg in [0.0f32, 30.0, 60.0, 89.0] {
        let theta = theta_deg.to_radians();
        let hit = Vec3::new(0.0, 0.0, 1.0);
        let mut light = Light::point(
            hit + 10.0 * Vec3::new(theta.sin(), 0.0, theta.cos()),
            Vec3::new(1.0, 0.9, 0.5),
        );
        light.intensity = 2.0;
        let surface = Surface {
            diffuse: 0.7,
            ..matte(c)
        };
        let s = scene(vec![(ball, surface)], vec![light], Background::Black);
        let l = radiance_of(&s, Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z));
        // Lambert's BRDF is the albedo over pi, as in the path model.
        let expected = 0.7 * c * Vec3::new(1.0, 0.9, 0.5) * 2.0 * theta.cos() / PI;
        assert!(close(l, expected, 1e-5), "{theta_deg}: {l} vs {expected}");
    }
}

#[test]
fn inverse_square_falloff_divides_by_the_squared_distance() {
    let mut light = Light::point(Vec3::new(0.0, 4.0, 0.0), Vec3::ONE);
    light.falloff = Falloff::InverseSquare;
    let s = scene(
        vec![(floor(0.0, 10.0), matte(Vec3::ONE))],
        vec![light],
        Background::Black,
    );
    let l = radiance_of(&s, down_at(0.0, 0.0));
    assert!(close(l, Vec3::splat(1.0 / 16.0 / PI), 1e-5), "{l}");
}

#[test]
fn a_mirror_shows_the_background_times_its_reflectance() {
    let r = Vec3::new(0.5, 0.25, 1.0);
    let mirror = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        reflection: r,
        ..Surface::default()
    };
    let sky = Vec3::new(0.2, 0.4, 0.8);
    let s = scene(
        vec![(floor(0.0, 10.0), mirror)],
        vec![],
        Background::Color(sky),
    );
    assert_eq!(radiance_of(&s, down_at(0.3, -0.2)), r * sky);
}

#[test]
fn fresnel_glass_reflects_four_percent_at_normal_incidence() {
    // A glass floor seen straight down, with nothing below but black and a white sky
    // above: only the Fresnel reflection of the sky comes back... plus what crosses
    // the floor twice, which is nothing here (black below).
    let glass = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        reflection: Vec3::ONE,
        transmission: Vec3::ONE,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let black_below = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        lit: false,
        ..Surface::default()
    };
    let s = scene(
        vec![(floor(0.0, 10.0), glass), (floor(-1.0, 10.0), black_below)],
        vec![],
        Background::Color(Vec3::ONE),
    );
    let l = radiance_of(&s, down_at(0.1, 0.1));
    assert!(close(l, Vec3::splat(0.04), 1e-5), "{l}");
}

#[test]
fn beer_absorption_through_a_slab_of_known_thickness() {
    let sigma = Vec3::new(0.5, 1.0, 2.0);
    let h = 0.75;
    // Index 1: the ray crosses straight, and without Fresnel nothing reflects.
    let slab = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::ONE,
        ior: 1.0,
        absorption: sigma,
        ..Surface::default()
    };
    let top = floor(0.0, 10.0);
    // The bottom faces down: its normal points out of the slab.
    let Shape::Rectangle(Rectangle { v }) = floor(-h, 10.0) else {
        unreachable!()
    };
    let bottom = Shape::Rectangle(Rectangle {
        v: [v[0], v[3], v[2], v[1]],
    });
    let sky = Vec3::new(1.0, 0.5, 0.25);
    let s = scene(
        vec![(top, slab.clone()), (bottom, slab)],
        vec![],
        Background::Color(sky),
    );
    let l = radiance_of(&s, down_at(0.2, 0.3));
    let expected = sky * (-sigma * h).exp();
    // The child ray starts a surface epsilon (2e-5 relative) into the slab.
    assert!(close(l, expected, 2e-4), "{l} vs {expected}");
}

#[test]
fn a_glass_slab_shifts_a_ray_sideways_by_the_closed_form() {
    // A slab of thickness h and index 1.5 between y = 0 and y = -h over a white target
    // whose edge is where the refracted ray lands; two rays either side of that edge
    // must see white and black.
    let (h, depth, n) = (1.0f32, 2.0f32, 1.5f32);
    let theta = 40f32.to_radians();
    let theta_t = (theta.sin() / n).asin();
    let glass = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::ONE,
        ior: n,
        ..Surface::default()
    };
    let Shape::Rectangle(Rectangle { v }) = floor(-h, 50.0) else {
        unreachable!()
    };
    let bottom = Shape::Rectangle(Rectangle {
        v: [v[0], v[3], v[2], v[1]],
    });
    // The ray enters at the origin heading +x and down; it lands on y = -h - depth at
    // h tan(theta_t) + depth tan(theta).
    let landing = h * theta_t.tan() + depth * theta.tan();
    let target = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(landing, -h - depth, -50.0),
            Vec3::new(landing, -h - depth, 50.0),
            Vec3::new(landing + 50.0, -h - depth, 50.0),
            Vec3::new(landing + 50.0, -h - depth, -50.0),
        ],
    });
    let white = Surface {
        albedo: Albedo::Color(Vec3::ONE),
        lit: false,
        ..Surface::default()
    };
    let s = scene(
        vec![
            (floor(0.0, 50.0), glass.clone()),
            (bottom, glass),
            (target, white),
        ],
        vec![],
        Background::Black,
    );
    let dir = Vec3::new(theta.sin(), -theta.cos(), 0.0);
    let from = |x: f32| Ray::new(Vec3::new(x, 0.0, 0.0) - 3.0 * dir, dir);
    // Moving the entry point by dx moves the landing point by dx.
    assert_eq!(radiance_of(&s, from(2e-3)), Vec3::ONE);
    assert_eq!(radiance_of(&s, from(-2e-3)), Vec3::ZERO);
    // Without refraction the ray would land h (tan theta - tan theta_t) further on.
    let shift = h * (theta.tan() - theta_t.tan());
    assert!(shift > 0.3);
}

#[test]
fn total_internal_reflection_sends_everything_to_the_mirror_ray() {
    // Inside glass, meeting its top face at 60 degrees (past the 41.8 degree critical
    // angle): the sky above is never seen; the mirror ray goes down to a lit white.
    let glass = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::ONE,
        ior: 1.5,
        fresnel: true,
        reflection: Vec3::ONE,
        ..Surface::default()
    };
    let glow = Vec3::new(0.3, 0.6, 0.9);
    let below = Surface {
        albedo: Albedo::Color(glow),
        lit: false,
        ..Surface::default()
    };
    let s = scene(
        vec![(floor(0.0, 50.0), glass), (floor(-1.0, 50.0), below)],
        vec![],
        Background::Color(Vec3::ONE),
    );
    let t = 60f32.to_radians();
    let dir = Vec3::new(t.sin(), t.cos(), 0.0);
    let l = radiance_of(&s, Ray::new(Vec3::new(0.0, -0.5, 0.0), dir));
    assert!(close(l, glow, 1e-6), "{l}");
}

#[test]
fn transparent_surfaces_tint_shadows() {
    let tf = Vec3::new(1.0, 0.5, 0.0);
    let filter = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: tf,
        ior: 1.0,
        ..Surface::default()
    };
    let light = Light::point(Vec3::new(0.0, 4.0, 0.0), Vec3::ONE);
    let s = scene(
        vec![
            (floor(0.0, 10.0), matte(Vec3::ONE)),
            (floor(2.0, 1.0), filter),
        ],
        vec![light],
        Background::Black,
    );
    // Under the filter: tinted; beside it: full.
    assert!(close(
        radiance_of(&s, down_at(3.0, 0.0)) * PI,
        Vec3::splat(0.8),
        1e-5
    ));
    let shadowed = {
        let accel = Accel::build(AccelKind::List, &s.shapes);
        let surfaces = s.resolved_surfaces();
        let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
        let mut count = RayCount::default();
        // Start below the filter so the camera ray does not cross it.
        let ray = Ray::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y);
        w.radiance(
            &ray,
            0,
            Vec3::ONE,
            &mut PixelSampler::new(0, 0, 0),
            &mut count,
        )
    };
    assert!(close(shadowed * PI, tf, 1e-6), "{shadowed}");
}

#[test]
fn an_area_light_converges_to_the_analytic_irradiance_of_a_disk() {
    // A disk of radius r at height h facing down onto a white floor: irradiance at the
    // point below its centre is Le pi r^2 / (h^2 + r^2).
    let (r, h, le) = (1.5f32, 2.0f32, 3.0f32);
    let mut light = Light::point(Vec3::new(0.0, h, 0.0), Vec3::ONE);
    light.intensity = le;
    light.kind = LightKind::Disk {
        normal: -Vec3::Y,
        radius: r,
    };
    let analytic = le * std::f32::consts::PI * r * r / (h * h + r * r);
    let mut errors = Vec::new();
    for samples in [4u32, 64, 1024] {
        light.samples = samples;
        let s = scene(
            vec![(floor(0.0, 10.0), matte(Vec3::ONE))],
            vec![light.clone()],
            Background::Black,
        );
        let l = radiance_of(&s, down_at(0.0, 0.0));
        // A white Lambert floor reflects radiance E / pi.
        errors.push((l.x * PI - analytic).abs() / analytic);
    }
    assert!(errors[2] < 2e-3, "{errors:?}");
    assert!(errors[2] <= errors[0], "{errors:?}");
}

#[test]
fn a_quad_light_half_hidden_casts_a_half_shadow() {
    // A 2 x 2 quad light straight above; an opaque wall covering exactly the half of it
    // with x < 0 as seen from the origin: half the samples are blocked, so the point
    // gets half the light of the unblocked quad (by symmetry), up to sampling noise.
    let mut light = Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE);
    light.kind = LightKind::Quad {
        u: Vec3::new(2.0, 0.0, 0.0),
        v: Vec3::new(0.0, 0.0, 2.0),
    };
    light.samples = 256;
    let blocker = Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-5.0, 1.0, -5.0),
            Vec3::new(-5.0, 1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::new(0.0, 1.0, -5.0),
        ],
    });
    let open = scene(
        vec![(floor(0.0, 10.0), matte(Vec3::ONE))],
        vec![light.clone()],
        Background::Black,
    );
    let half = scene(
        vec![
            (floor(0.0, 10.0), matte(Vec3::ONE)),
            (blocker, matte(Vec3::ONE)),
        ],
        vec![light],
        Background::Black,
    );
    let full = radiance_of(&open, down_at(0.0, 0.0)).x;
    let shaded = {
        let accel = Accel::build(AccelKind::List, &half.shapes);
        let surfaces = half.resolved_surfaces();
        let w = Whitted::new(&half, &accel, &surfaces, 10, 0.0);
        let ray = Ray::new(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y);
        let mut count = RayCount::default();
        w.radiance(
            &ray,
            0,
            Vec3::ONE,
            &mut PixelSampler::new(3, 1, 2),
            &mut count,
        )
        .x
    };
    assert!(full > 0.0);
    assert!((shaded / full - 0.5).abs() < 0.03, "{shaded} / {full}");
}

#[test]
fn checker_alternates_in_world_cubes() {
    let a = Vec3::new(1.0, 0.0, 0.0);
    let b = Vec3::new(0.0, 0.0, 1.0);
    let checker = Surface {
        albedo: Albedo::Checker { a, b, scale: 1.0 },
        lit: false,
        ..Surface::default()
    };
    let s = scene(vec![(floor(0.0, 10.0), checker)], vec![], Background::Black);
    // The floor lies on the cube face y = 0; it is read just below (inside it, against
    // its normal), in the row y in [-1, 0), whatever the rounding of each hit.
    assert_eq!(radiance_of(&s, down_at(0.5, 0.5)), b);
    assert_eq!(radiance_of(&s, down_at(1.5, 0.5)), a);
    assert_eq!(radiance_of(&s, down_at(-0.5, 0.5)), a);
    assert_eq!(radiance_of(&s, down_at(-0.5, -0.5)), b);
    // Rays hitting at slightly different heights of the same cell agree.
    for i in 0..200 {
        let x = 0.01 + i as f32 * 0.00491;
        let dir = Vec3::new(0.3, -1.0, 0.2);
        let ray = Ray::new(Vec3::new(x, 0.0, 0.37) - dir * 5.3, dir);
        assert_eq!(radiance_of(&s, ray), b, "{x}");
    }
}

#[test]
fn recursion_stops_at_max_depth_between_parallel_mirrors() {
    let mirror = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        reflection: Vec3::ONE,
        emission: Vec3::splat(1.0),
        ..Surface::default()
    };
    let Shape::Rectangle(Rectangle { v }) = floor(1.0, 10.0) else {
        unreachable!()
    };
    let ceiling = Shape::Rectangle(Rectangle {
        v: [v[0], v[3], v[2], v[1]],
    });
    let s = scene(
        vec![(floor(0.0, 10.0), mirror.clone()), (ceiling, mirror)],
        vec![],
        Background::Black,
    );
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    for depth in [0u32, 3, 7] {
        let w = Whitted::new(&s, &accel, &surfaces, depth, 0.0);
        let mut count = RayCount::default();
        let ray = Ray::new(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y);
        let l = w.radiance(
            &ray,
            0,
            Vec3::ONE,
            &mut PixelSampler::new(0, 0, 0),
            &mut count,
        );
        // Each surface met emits 1: depth + 1 of them.
        assert_eq!(l, Vec3::splat((depth + 1) as f32));
        assert_eq!(count.rays, u64::from(depth) + 1);
    }
}

#[test]
fn a_normal_map_tilts_the_shading_normal_in_the_tangent_frame() {
    use crate::scene::{ImageTexture, Texels, TextureSlot};
    // One texel: the normal tilted 45 degrees toward the tangent (dP/du: +z on this
    // floor), encoded as (n + 1) / 2.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let texel = [(h + 1.0) / 2.0, 0.5, (h + 1.0) / 2.0, 1.0];
    let bumpy = Surface {
        normal_map: Some(TextureSlot::new(0)),
        ..matte(Vec3::ONE)
    };
    let lit_from = |dir: Vec3| {
        let mut s = scene(
            vec![(floor(0.0, 10.0), bumpy.clone())],
            vec![Light {
                kind: LightKind::Directional { direction: -dir },
                ..Light::point(Vec3::ZERO, Vec3::ONE)
            }],
            Background::Black,
        );
        s.images.push(ImageTexture {
            name: "n".into(),
            width: 1,
            height: 1,
            texels: Texels::RgbaF32(vec![texel]),
        });
        radiance_of(&s, down_at(0.3, 0.3)).x * PI
    };
    // Light from straight above meets the tilted normal at 45 degrees; light along the
    // tilted normal meets it head on.
    assert!(
        (lit_from(Vec3::Y) - h).abs() < 1e-5,
        "{}",
        lit_from(Vec3::Y)
    );
    assert!((lit_from(normalize(Vec3::new(0.0, 1.0, 1.0))) - 1.0).abs() < 1e-5);
    // Tilting away from the light (toward -z): darker than the flat floor would be.
    assert!(lit_from(normalize(Vec3::new(0.0, 1.0, -1.0))) < 1e-5);
}

fn sphere_at(x: f32, y: f32, z: f32, r: f32) -> Shape {
    Shape::Sphere(Sphere {
        center: Vec3::new(x, y, z),
        radius: r,
    })
}

mod casters;
mod lanes;
mod packets;
mod visibility;

/// The floor: colour 0.5 under a 10 W/sr point light 2 m above, seen from
/// above, is `0.5 / pi * 10 / 4` in both physical models, and every lobe, Phong or
/// OpenPBR, gathers the same direct light in both (they share one BSDF). (A subsurface
/// is the exception by design: the path model walks light under it to where it
/// leaves, which is not direct light at the hit.)
#[test]
fn whitted_and_path_gather_the_same_direct_light_for_every_lobe() {
    use crate::render::path::Path;
    use crate::scene::OpenPbr;
    let openpbr = |set: &dyn Fn(&mut OpenPbr)| {
        let mut m = OpenPbr::default();
        set(&mut m);
        Surface {
            albedo: Albedo::Color(Vec3::new(0.8, 0.5, 0.3)),
            openpbr: Some(Box::new(m)),
            ..Surface::default()
        }
    };
    let surfaces: Vec<(&str, Surface)> = vec![
        ("lambert", matte(Vec3::splat(0.5))),
        (
            "phong",
            Surface {
                specular: Vec3::splat(0.3),
                shininess: 20.0,
                ..matte(Vec3::splat(0.5))
            },
        ),
        ("openpbr default", openpbr(&|_| {})),
        (
            "openpbr rough diffuse",
            openpbr(&|m| m.base_diffuse_roughness.value = 0.8),
        ),
        (
            "openpbr metal",
            openpbr(&|m| {
                m.base_metalness.value = 1.0;
                m.specular_roughness.value = 0.5;
            }),
        ),
        (
            "openpbr rough glass",
            openpbr(&|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.6;
            }),
        ),
        (
            "openpbr coat",
            openpbr(&|m| {
                m.coat_weight.value = 1.0;
                m.coat_roughness.value = 0.3;
            }),
        ),
        (
            "openpbr coloured coat",
            openpbr(&|m| {
                m.coat_weight.value = 0.8;
                m.coat_roughness.value = 0.3;
                m.coat_color.value = Vec3::new(0.5, 0.8, 0.9);
            }),
        ),
    ];
    let mut light = Light::point(Vec3::new(0.3, 2.0, 0.0), Vec3::ONE);
    light.intensity = 10.0;
    light.falloff = Falloff::InverseSquare;
    for (name, surface) in surfaces {
        let s = scene(
            vec![(floor(0.0, 10.0), surface)],
            vec![light.clone()],
            Background::Black,
        );
        let accel = Accel::build(AccelKind::List, &s.shapes);
        let resolved = s.resolved_surfaces();
        let ray = Ray::new(
            Vec3::new(-0.5, 3.0, 0.2),
            normalize(Vec3::new(0.5, -3.0, -0.2)),
        );
        let whitted = Whitted::new(&s, &accel, &resolved, 0, 0.0).radiance(
            &ray,
            0,
            Vec3::ONE,
            &mut PixelSampler::new(0, 0, 0),
            &mut RayCount::default(),
        );
        let path = Path::new(&s, &accel, &resolved, 0).radiance(
            ray,
            accel.closest(&ray, f32::INFINITY),
            &mut PixelSampler::new(0, 0, 0),
            &mut RayCount::default(),
        );
        assert!(whitted.max_element() > 0.0, "{name}: black");
        assert!(close(whitted, path, 1e-6), "{name}: {whitted} vs {path}");
    }
    // The numbers: 0.5 / pi * 10 / 2^2 straight below the light.
    let mut light = Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE);
    light.intensity = 10.0;
    light.falloff = Falloff::InverseSquare;
    let s = scene(
        vec![(floor(0.0, 10.0), matte(Vec3::splat(0.5)))],
        vec![light],
        Background::Black,
    );
    let l = radiance_of(&s, down_at(0.0, 0.0));
    assert!(close(l, Vec3::splat(0.5 / PI * 10.0 / 4.0), 1e-6), "{l}");
}
