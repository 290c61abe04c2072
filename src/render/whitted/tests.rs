//! Closed-form checks of the whitted model: each scene is simple enough that optics
//! gives the radiance exactly (or, for area lights, as an integral).

use super::*;
use crate::accel::AccelKind;
use crate::math::surface_epsilon;
use crate::scene::{Material, Rectangle, Sphere};

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
fn a_diffuse_sphere_under_a_point_light_is_kd_c_i_cos() {
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
        let expected = 0.7 * c * Vec3::new(1.0, 0.9, 0.5) * 2.0 * theta.cos();
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
    assert!(close(l, Vec3::splat(1.0 / 16.0), 1e-5), "{l}");
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
        radiance_of(&s, down_at(3.0, 0.0)),
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
    assert!(close(shadowed, tf, 1e-6), "{shadowed}");
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
        errors.push((l.x - analytic).abs() / analytic);
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
        radiance_of(&s, down_at(0.3, 0.3)).x
    };
    // Light from straight above meets the tilted normal at 45 degrees; light along the
    // tilted normal meets it head on.
    assert!(
        (lit_from(Vec3::Y) - h).abs() < 1e-5,
        "{}",
        lit_from(Vec3::Y)
    );
    assert!((lit_from(Vec3::new(0.0, 1.0, 1.0).normalize()) - 1.0).abs() < 1e-5);
    // Tilting away from the light (toward -z): darker than the flat floor would be.
    assert!(lit_from(Vec3::new(0.0, 1.0, -1.0).normalize()) < 1e-5);
}

/// Shadow-ray visibility as it was computed before the single traversal: an occlusion
/// query for the opaque surfaces, then a walk from crossing to crossing, each found by a
/// traversal of the whole scene. The reference the walk through noted spheres must
/// match bit for bit.
fn visibility_by_traversals(w: &Whitted, from: Vec3, ng: Vec3, ls: &LightSample) -> Vec3 {
    let origin = offset_origin(from, ng, ls.dir);
    let t_max = if ls.dist.is_finite() {
        ls.dist * (1.0 - 1e-4) - surface_epsilon(origin)
    } else {
        f32::INFINITY
    };
    if t_max <= 0.0 {
        return Vec3::ONE;
    }
    let ray = Ray {
        origin,
        dir: ls.dir,
    };
    let opaque = |shape: u32| {
        let s = w.surface(shape);
        !s.is_transmissive() && s.alpha_map.is_none()
    };
    if w.accel.occluded(&ray, t_max, opaque) {
        return Vec3::ZERO;
    }
    let mut vis = Vec3::ONE;
    let mut r = ray;
    let mut left = t_max;
    for _ in 0..MAX_CROSSINGS {
        let Some(hit) = w.accel.closest(&r, left) else {
            return vis;
        };
        let sp = w.scene.surface_point(hit.shape, &r, hit.t, true);
        if !w.cut_out(hit.shape, &sp) {
            vis *= w.surface(hit.shape).transmission;
            if vis.max_element() <= 0.0 {
                return Vec3::ZERO;
            }
        }
        let next = offset_origin(sp.p, sp.ng, r.dir);
        left -= (next - r.origin).length();
        if left <= 0.0 {
            return vis;
        }
        r.origin = next;
    }
    vis
}

/// Glass, filters and cut-outs to cast shadow rays through: spheres (some nested and
/// overlapping, a row of more than a ray notes), a closed glass mesh whose triangles
/// share edges, a glass box of rectangles, alpha-masked shapes and opaque blockers.
fn see_through_scene(with_flat: bool) -> Scene {
    use crate::scene::{ImageTexture, Texels, TextureSlot, Triangle};
    let glass = |t: Vec3| Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: t,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let masked = |t: Vec3| Surface {
        alpha_map: Some(TextureSlot {
            scale: [3.0, 2.0],
            ..TextureSlot::new(0)
        }),
        transmission: t,
        ..matte(Vec3::new(0.3, 0.6, 0.2))
    };
    let sphere = |x: f32, y: f32, z: f32, r: f32| {
        Shape::Sphere(Sphere {
            center: Vec3::new(x, y, z),
            radius: r,
        })
    };
    let mut shapes = vec![
        (floor(0.0, 20.0), matte(Vec3::ONE)),
        (sphere(0.0, 1.0, 0.0, 1.0), glass(Vec3::new(0.9, 0.7, 0.8))),
        (sphere(0.3, 1.2, 0.1, 0.5), glass(Vec3::new(0.5, 0.9, 0.6))),
        (sphere(1.2, 1.0, -0.4, 0.8), glass(Vec3::splat(0.93))),
        (sphere(-2.0, 1.5, 1.0, 0.7), matte(Vec3::new(0.8, 0.1, 0.1))),
        (sphere(-1.0, 2.5, -1.5, 0.6), masked(Vec3::ZERO)),
        (sphere(2.5, 2.0, 1.5, 0.6), masked(Vec3::new(0.4, 0.8, 0.9))),
    ];
    // More see-through spheres in a row than one shadow ray notes.
    for i in 0..24 {
        let t = 0.5 + 0.02 * i as f32;
        shapes.push((
            sphere(-4.0 + 0.35 * i as f32, 4.0, -3.0, 0.3),
            glass(Vec3::new(t, 0.9, 1.0 - t * 0.5)),
        ));
    }
    if with_flat {
        // An octahedron of glass triangles, edge to edge.
        let (c, r) = (Vec3::new(-1.5, 1.2, 2.0), 1.1);
        let axes = [Vec3::X, Vec3::Y, Vec3::Z];
        for i in 0..8 {
            let s = |k: usize| if i >> k & 1 == 0 { 1.0 } else { -1.0 };
            let v = [0, 1, 2].map(|k| c + axes[k] * (r * s(k)));
            shapes.push((
                Shape::Triangle(Triangle { v }),
                glass(Vec3::new(0.8, 0.85, 0.6)),
            ));
        }
        // A glass box of six rectangles sharing edges.
        let (lo, hi) = (Vec3::new(1.0, 0.5, 1.5), Vec3::new(2.2, 1.7, 2.7));
        let corner = |b: usize| {
            Vec3::new(
                if b & 1 == 0 { lo.x } else { hi.x },
                if b & 2 == 0 { lo.y } else { hi.y },
                if b & 4 == 0 { lo.z } else { hi.z },
            )
        };
        for f in [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ] {
            shapes.push((
                Shape::Rectangle(Rectangle { v: f.map(corner) }),
                glass(Vec3::new(0.7, 0.9, 0.95)),
            ));
        }
        shapes.push((
            Shape::Rectangle(Rectangle {
                v: [
                    Vec3::new(-3.0, 3.0, -1.0),
                    Vec3::new(3.0, 3.0, -1.0),
                    Vec3::new(3.0, 3.5, 2.0),
                    Vec3::new(-3.0, 3.5, 2.0),
                ],
            }),
            masked(Vec3::ZERO),
        ));
    }
    let mut s = scene(shapes, Vec::new(), Background::Black);
    // A 4 x 4 mask of alternating holes.
    let texels = (0..16)
        .map(|i| [0.5, 0.5, 0.5, ((i + i / 4) % 2) as f32])
        .collect();
    s.images.push(ImageTexture {
        name: "mask".into(),
        width: 4,
        height: 4,
        texels: Texels::RgbaF32(texels),
    });
    s
}

/// A shadow ray's start, surface normal and light sample: from anywhere over the test
/// scenes toward a point of the box `toward`, the light at infinity, past the box, or
/// somewhere along the way (by `i`).
fn random_shadow(
    unit: &mut impl FnMut() -> f32,
    i: usize,
    toward: [Vec3; 2],
) -> (Vec3, Vec3, LightSample) {
    let mut point = |lo: Vec3, hi: Vec3| lo + (hi - lo) * Vec3::new(unit(), unit(), unit());
    let from = point(Vec3::new(-5.0, 0.0, -4.0), Vec3::new(5.0, 5.0, 4.0));
    let to = point(toward[0], toward[1]);
    let ng = (point(Vec3::NEG_ONE, Vec3::ONE)).normalize_or(Vec3::Y);
    let (dir, dist) = ((to - from).normalize(), (to - from).length());
    let dist = match i % 4 {
        0 => f32::INFINITY,
        1 => dist * 3.0,
        _ => dist * (0.2 + 1.6 * unit()),
    };
    let ls = LightSample {
        dir,
        dist,
        e: Vec3::ONE,
    };
    (from, ng, ls)
}

#[test]
fn one_traversal_gives_the_visibility_of_the_walk_by_traversals() {
    use rand_core::Rng;
    let mut rng = rand_pcg::Pcg32::new(0x5eed, 7);
    let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    for with_flat in [false, true] {
        let s = see_through_scene(with_flat);
        let surfaces = s.resolved_surfaces();
        for kind in AccelKind::ALL {
            let accel = Accel::build(kind, &s.shapes);
            let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
            let (mut tinted, mut count) = (0, RayCount::default());
            for i in 0..20_000 {
                let (from, ng, ls) = random_shadow(
                    &mut unit,
                    i,
                    [Vec3::new(-3.0, 0.0, -3.5), Vec3::new(3.0, 4.5, 3.0)],
                );
                let dir = ls.dir;
                let dist = ls.dist;
                let expected = visibility_by_traversals(&w, from, ng, &ls);
                let got = w.visibility(from, ng, &ls, &mut count);
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    expected.to_array().map(f32::to_bits),
                    "{kind} flat {with_flat}: from {from} dir {dir} dist {dist}: {got} against {expected}"
                );
                if expected != Vec3::ZERO && expected != Vec3::ONE {
                    tinted += 1;
                }
            }
            assert!(tinted > 2_000, "{kind}: only {tinted} tinted shadow rays");
        }
    }
}

/// [`see_through_scene`] and a clear glass ball of triangles (white transmission) with
/// two clear spheres inside it: shapes clear to shadows outnumber the others. Without
/// `tinted`, the scene's tinted and masked shapes are left out (every shadow ray is
/// then a plain occlusion query).
fn clear_glass_scene(tinted: bool) -> Scene {
    use crate::scene::Triangle;
    let mut s = if tinted {
        see_through_scene(true)
    } else {
        scene(
            vec![
                (floor(0.0, 20.0), matte(Vec3::ONE)),
                (
                    sphere_at(-2.0, 1.5, 1.0, 0.7),
                    matte(Vec3::new(0.8, 0.1, 0.1)),
                ),
            ],
            Vec::new(),
            Background::Black,
        )
    };
    let clear = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::ONE,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let material = s.materials.len() as u32;
    s.materials.push(Material::default_white());
    s.surfaces.push(clear);
    let (c, r) = (Vec3::new(0.5, 1.8, 0.0), 1.6);
    let at = |i: u32, j: u32| {
        let (theta, phi) = (
            std::f32::consts::PI * i as f32 / 24.0,
            std::f32::consts::TAU * j as f32 / 48.0,
        );
        c + r * Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    for i in 0..24 {
        for j in 0..48 {
            let (a, b, d, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            s.push_shape(Shape::Triangle(Triangle { v: [a, b, d] }), material);
            s.push_shape(Shape::Triangle(Triangle { v: [a, d, e] }), material);
        }
    }
    s.push_shape(sphere_at(0.2, 1.6, 0.1, 0.5), material);
    s.push_shape(sphere_at(0.9, 2.0, -0.2, 0.4), material);
    s
}

fn sphere_at(x: f32, y: f32, z: f32, r: f32) -> Shape {
    Shape::Sphere(Sphere {
        center: Vec3::new(x, y, z),
        radius: r,
    })
}

#[test]
fn casters_are_the_shapes_not_clear_to_shadows_when_clear_ones_outnumber_them() {
    for tinted in [false, true] {
        let s = clear_glass_scene(tinted);
        let surfaces = s.resolved_surfaces();
        let casters = Casters::of(&s, &surfaces).expect("clear shapes outnumber the rest");
        let expected: Vec<u32> = (0..s.shapes.len() as u32)
            .filter(|&i| !surfaces[s.material_of[i as usize] as usize].is_clear_to_shadows())
            .collect();
        assert_eq!(casters.scene_index(), expected);
        assert_eq!(casters.shapes().len(), expected.len());
        assert_eq!(Casters::count(&s, &surfaces), Some(expected.len()));
        // Within what the memory estimate adds for them.
        assert!(casters.shapes().memory_bytes() <= s.shapes.memory_bytes());
        for (k, &i) in expected.iter().enumerate() {
            assert_eq!(casters.shapes().get(k), s.shapes.get(i as usize));
        }
    }
    // No clear shape, or no more clear shapes than casters: the scene's intersector.
    let s = see_through_scene(true);
    assert!(Casters::of(&s, &s.resolved_surfaces()).is_none());
    assert_eq!(Casters::count(&s, &s.resolved_surfaces()), None);
    let clear = Surface {
        transmission: Vec3::ONE,
        ..Surface::default()
    };
    let half = scene(
        vec![
            (floor(0.0, 20.0), matte(Vec3::ONE)),
            (sphere_at(0.0, 1.0, 0.0, 1.0), clear),
        ],
        Vec::new(),
        Background::Black,
    );
    assert!(Casters::of(&half, &half.resolved_surfaces()).is_none());
}

/// Shadow rays let by the shapes clear to shadows, in the scene's intersector or in one
/// over the casters, see what the walk from crossing to crossing sees (which multiplies
/// by one at each clear crossing), bit for bit.
#[test]
fn shadows_past_clear_shapes_are_those_of_the_walk_by_traversals() {
    use rand_core::Rng;
    let mut rng = rand_pcg::Pcg32::new(0xc1ea, 11);
    let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    for tinted in [false, true] {
        let s = clear_glass_scene(tinted);
        let surfaces = s.resolved_surfaces();
        let casters = Casters::of(&s, &surfaces).unwrap();
        for kind in AccelKind::ALL {
            let accel = Accel::build(kind, &s.shapes);
            let caster_accel = Accel::build(kind, casters.shapes());
            let plain = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
            let with_casters =
                Whitted::new(&s, &accel, &surfaces, 10, 0.0).with_casters(&caster_accel, &casters);
            let (mut through_clear, mut count) = (0, RayCount::default());
            for i in 0..4_000 {
                let (from, ng, ls) = random_shadow(
                    &mut unit,
                    i,
                    [Vec3::new(-1.0, 0.5, -1.5), Vec3::new(2.0, 3.5, 1.5)],
                );
                let dir = ls.dir;
                let dist = ls.dist;
                let expected = visibility_by_traversals(&plain, from, ng, &ls).to_array();
                for (w, name) in [(&plain, "plain"), (&with_casters, "casters")] {
                    let got = w.visibility(from, ng, &ls, &mut count).to_array();
                    assert_eq!(
                        got.map(f32::to_bits),
                        expected.map(f32::to_bits),
                        "{kind} {name} tinted {tinted}: from {from} dir {dir} dist {dist}"
                    );
                }
                let t = if dist.is_finite() { dist } else { 100.0 };
                let segment = Ray::new(offset_origin(from, ng, dir), dir);
                if expected != [0.0; 3] && accel.closest(&segment, t).is_some() {
                    through_clear += 1;
                }
            }
            assert!(
                through_clear > 500,
                "{kind}: {through_clear} lit rays crossed glass"
            );
        }
    }
}

/// A closed box of twelve tinted glass triangles (each face two, sharing a diagonal),
/// from `lo` to `hi`.
fn glass_box_mesh(s: &mut Scene, lo: Vec3, hi: Vec3, transmission: Vec3) {
    use crate::scene::Triangle;
    let material = s.materials.len() as u32;
    s.materials.push(Material::default_white());
    s.surfaces.push(Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    });
    let corner = |b: usize| {
        Vec3::new(
            if b & 1 == 0 { lo.x } else { hi.x },
            if b & 2 == 0 { lo.y } else { hi.y },
            if b & 4 == 0 { lo.z } else { hi.z },
        )
    };
    for f in [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ] {
        let [a, b, c, d] = f.map(corner);
        s.push_shape(Shape::Triangle(Triangle { v: [a, b, c] }), material);
        s.push_shape(Shape::Triangle(Triangle { v: [a, c, d] }), material);
    }
}

/// Shadow rays through a tinted glass box of triangles are tinted once per side they
/// cross, also where they enter through the diagonal two triangles of a face share or
/// through an edge of the box, where two or four triangles meet the ray at one point.
#[test]
fn a_tinted_glass_mesh_tints_once_per_side_even_through_its_edges() {
    let t = Vec3::new(0.8, 0.5, 0.9);
    let mut s = scene(
        vec![(floor(-5.0, 20.0), matte(Vec3::ONE))],
        Vec::new(),
        Background::Black,
    );
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    glass_box_mesh(&mut s, lo, hi, t);
    let twice = Vec3::ONE * t * t;
    let surfaces = s.resolved_surfaces();
    // Where each ray enters the box, and its direction (into the box).
    let entries = [
        (Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 0.1, 0.2)), // a face's middle
        (Vec3::new(-1.0, 1.3, 0.3), Vec3::new(1.0, 0.2, -0.1)), // on the face's diagonal
        (Vec3::new(-1.0, 0.7, -0.3), Vec3::new(1.0, -0.1, 0.3)), // the same diagonal
        (Vec3::new(-1.0, 2.0, 0.2), Vec3::new(1.0, -0.7, 0.1)), // an edge of the box
        (Vec3::new(0.4, 2.0, 1.0), Vec3::new(-0.2, -0.6, -1.0)), // another edge
        (Vec3::new(-0.3, 0.0, -0.3), Vec3::new(0.2, 1.0, 0.3)), // the bottom's diagonal
    ];
    for kind in AccelKind::ALL {
        let accel = Accel::build(kind, &s.shapes);
        let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
        for (at, dir) in entries {
            let dir = dir.normalize();
            let from = at - 4.0 * dir;
            // The light 3 past the entry, beyond the box; the opaque floor below every
            // ray, and so no blocker.
            let ls = LightSample {
                dir,
                dist: 7.0,
                e: Vec3::ONE,
            };
            let vis = w.visibility(from, dir, &ls, &mut RayCount::default());
            assert_eq!(vis, twice, "{kind}: entering at {at} toward {dir}");
        }
    }
}

/// Flat see-through shapes alone (a tinted glass ball of triangles, a glass box of
/// triangles, a cut-out pane, an opaque floor): the crossings a shadow ray gathers on
/// its one traversal give what the walk by traversals gives, bit for bit.
#[test]
fn flat_crossings_gathered_on_one_traversal_are_those_of_the_walk() {
    use crate::scene::{ImageTexture, Texels, TextureSlot, Triangle};
    use rand_core::Rng;
    let mut rng = rand_pcg::Pcg32::new(0xf1a7, 5);
    let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let masked = Surface {
        alpha_map: Some(TextureSlot {
            scale: [3.0, 2.0],
            ..TextureSlot::new(0)
        }),
        transmission: Vec3::new(0.4, 0.8, 0.9),
        ..matte(Vec3::new(0.3, 0.6, 0.2))
    };
    let mut s = scene(
        vec![
            (floor(0.0, 20.0), matte(Vec3::ONE)),
            (
                Shape::Rectangle(Rectangle {
                    v: [
                        Vec3::new(-3.0, 3.0, -1.0),
                        Vec3::new(3.0, 3.0, -1.0),
                        Vec3::new(3.0, 3.5, 2.0),
                        Vec3::new(-3.0, 3.5, 2.0),
                    ],
                }),
                masked,
            ),
        ],
        Vec::new(),
        Background::Black,
    );
    s.images.push(ImageTexture {
        name: "mask".into(),
        width: 4,
        height: 4,
        texels: Texels::RgbaF32(
            (0..16)
                .map(|i| [0.5, 0.5, 0.5, ((i + i / 4) % 2) as f32])
                .collect(),
        ),
    });
    glass_box_mesh(
        &mut s,
        Vec3::new(1.2, 0.5, 1.0),
        Vec3::new(2.4, 1.9, 2.5),
        Vec3::new(0.7, 0.9, 0.95),
    );
    // A ball of tinted glass triangles, edge to edge.
    let material = s.materials.len() as u32;
    s.materials.push(Material::default_white());
    s.surfaces.push(Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::new(0.9, 0.6, 0.8),
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    });
    let (c, r) = (Vec3::new(-0.8, 1.6, 0.0), 1.4);
    let at = |i: u32, j: u32| {
        let (theta, phi) = (
            std::f32::consts::PI * i as f32 / 12.0,
            std::f32::consts::TAU * j as f32 / 24.0,
        );
        c + r * Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    for i in 0..12 {
        for j in 0..24 {
            let (a, b, d, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            s.push_shape(Shape::Triangle(Triangle { v: [a, b, d] }), material);
            s.push_shape(Shape::Triangle(Triangle { v: [a, d, e] }), material);
        }
    }
    let surfaces = s.resolved_surfaces();
    for kind in AccelKind::ALL {
        let accel = Accel::build(kind, &s.shapes);
        let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
        let (mut tinted, mut count) = (0, RayCount::default());
        for i in 0..20_000 {
            let (from, ng, ls) = random_shadow(
                &mut unit,
                i,
                [Vec3::new(-3.0, 0.0, -2.0), Vec3::new(3.0, 4.0, 3.0)],
            );
            let (dir, dist) = (ls.dir, ls.dist);
            let expected = visibility_by_traversals(&w, from, ng, &ls);
            let got = w.visibility(from, ng, &ls, &mut count);
            assert_eq!(
                got.to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits),
                "{kind}: from {from} dir {dir} dist {dist}: {got} against {expected}"
            );
            if expected != Vec3::ZERO && expected != Vec3::ONE {
                tinted += 1;
            }
        }
        assert!(tinted > 3_000, "{kind}: only {tinted} tinted shadow rays");
    }
}

/// The visibility of a shadow ray from `from` toward a point light at `to`, for every
/// intersector, with and without an intersector over the scene's casters: one answer,
/// checked against each.
fn shadow_answers(s: &Scene, from: Vec3, to: Vec3) -> Vec<(String, Vec3)> {
    let surfaces = s.resolved_surfaces();
    let casters = Casters::of(s, &surfaces).expect("clear shapes outnumber the rest");
    let ls = LightSample {
        dir: (to - from).normalize(),
        dist: (to - from).length(),
        e: Vec3::ONE,
    };
    let mut answers = Vec::new();
    for kind in AccelKind::ALL {
        let accel = Accel::build(kind, &s.shapes);
        let caster_accel = Accel::build(kind, casters.shapes());
        let plain = Whitted::new(s, &accel, &surfaces, 10, 0.0);
        let with_casters =
            Whitted::new(s, &accel, &surfaces, 10, 0.0).with_casters(&caster_accel, &casters);
        for (w, name) in [(plain, "plain"), (with_casters, "casters")] {
            let vis = w.visibility(from, ls.dir, &ls, &mut RayCount::default());
            answers.push((format!("{kind} {name}"), vis));
        }
    }
    answers
}

/// Clear glass changes nothing a shadow ray carries, however many panes it crosses: a
/// row of more clear panes than the tinting limit counts still lets the tinted glass
/// behind it tint, a flat pane or a sphere.
#[test]
fn clear_panes_past_the_crossing_limit_leave_the_tint_behind_them() {
    use crate::scene::Triangle;
    let clear = Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::ONE,
        ..Surface::default()
    };
    let half = Surface {
        transmission: Vec3::splat(0.5),
        ..clear.clone()
    };
    let pane = |x: f32| {
        let c = |y: f32, z: f32| Vec3::new(x, y, z);
        [
            Shape::Triangle(Triangle {
                v: [c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0)],
            }),
            Shape::Triangle(Triangle {
                v: [c(-1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0)],
            }),
        ]
    };
    let panes = MAX_CROSSINGS as usize + 6;
    for tinted_sphere in [false, true] {
        let mut shapes = Vec::new();
        for i in 0..panes {
            for t in pane(0.1 * i as f32) {
                shapes.push((t, clear.clone()));
            }
        }
        let tint = if tinted_sphere {
            shapes.push((sphere_at(9.0, 0.0, 0.0, 0.5), half.clone()));
            0.25
        } else {
            for t in pane(9.0) {
                shapes.push((t, half.clone()));
            }
            0.5
        };
        let s = scene(shapes, Vec::new(), Background::Black);
        // Off the panes' diagonals, square through every one of them.
        let (from, to) = (Vec3::new(-1.0, 0.3, 0.2), Vec3::new(12.0, 0.3, 0.2));
        for (name, vis) in shadow_answers(&s, from, to) {
            assert_eq!(
                vis,
                Vec3::splat(tint),
                "{name}, tinted sphere {tinted_sphere}"
            );
        }
    }
}

/// An opaque ball inside clear glass, and one inside tinted glass: shadow rays through
/// the ball are stopped, and those beside it keep all of the light, or the glass's tint
/// once per crossing.
#[test]
fn an_opaque_ball_inside_glass_stops_the_shadow_rays_through_it() {
    let glass = |t: f32| Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: Vec3::splat(t),
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    for (t, crossings) in [(1.0f32, 0), (0.9, 2)] {
        let mut shapes = vec![(sphere_at(0.0, 0.0, 0.0, 0.3), matte(Vec3::ONE))];
        // Clear shells around it, so that casters are built: the tinted one outermost.
        for r in [0.6, 0.9, 1.2] {
            shapes.push((sphere_at(0.0, 0.0, 0.0, r), glass(1.0)));
        }
        shapes.push((sphere_at(0.0, 0.0, 0.0, 1.5), glass(t)));
        let s = scene(shapes, Vec::new(), Background::Black);
        let tint = (0..crossings).fold(1.0f32, |v, _| v * t);
        for (y, expected) in [(0.0, 0.0), (0.1, 0.0), (0.45, tint), (-1.0, tint)] {
            let (from, to) = (Vec3::new(-3.0, y, 0.05), Vec3::new(3.0, y, 0.05));
            for (name, vis) in shadow_answers(&s, from, to) {
                assert_eq!(
                    vis,
                    Vec3::splat(expected),
                    "{name}: glass {t}, ray at y = {y}"
                );
            }
        }
    }
}

/// An area light's shadow rays from one point go as a packet, and give the radiance of
/// the rays one at a time bit for bit: over opaque shapes, past clear glass, and through
/// tinted glass and cut-outs (where the packet's met rays are settled one by one).
#[test]
fn area_light_shadow_packets_give_the_single_ray_radiance() {
    let light = |kind: LightKind, samples: u32| {
        let mut l = Light::point(Vec3::new(0.3, 3.0, -0.2), Vec3::new(1.0, 0.9, 0.8));
        l.kind = kind;
        l.samples = samples;
        l
    };
    let lights = vec![
        light(
            LightKind::Quad {
                u: Vec3::new(1.5, 0.0, 0.2),
                v: Vec3::new(0.0, 0.3, 1.2),
            },
            37,
        ),
        light(LightKind::Sphere { radius: 0.4 }, 16),
        Light::point(Vec3::new(-2.0, 4.0, 1.0), Vec3::splat(0.5)),
    ];
    let glass = |t: Vec3| Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: t,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let opaque = vec![
        (floor(0.0, 10.0), matte(Vec3::new(0.9, 0.8, 0.7))),
        (
            sphere_at(0.0, 1.0, 0.0, 0.6),
            matte(Vec3::new(0.2, 0.5, 0.9)),
        ),
        (sphere_at(0.9, 0.4, 0.5, 0.3), matte(Vec3::ONE)),
    ];
    let mut clear = opaque.clone();
    clear.push((sphere_at(-0.8, 1.3, -0.4, 0.5), glass(Vec3::ONE)));
    let mut tinted = clear.clone();
    tinted.push((
        sphere_at(0.7, 1.6, -0.6, 0.45),
        glass(Vec3::new(0.5, 0.8, 0.9)),
    ));
    let mut cases: Vec<(&str, Scene)> = [("opaque", opaque), ("clear", clear), ("tinted", tinted)]
        .into_iter()
        .map(|(name, shapes)| (name, scene(shapes, lights.clone(), Background::Black)))
        .collect();
    cases.push(("see-through", see_through_scene(true)));
    cases[3].1.lights = lights;
    let mut count = RayCount::default();
    for (name, s) in &cases {
        let surfaces = s.resolved_surfaces();
        for kind in [AccelKind::Bvh, AccelKind::List] {
            let accel = Accel::build(kind, &s.shapes);
            let packets = Whitted::new(s, &accel, &surfaces, 10, 0.0);
            let single = Whitted::new(s, &accel, &surfaces, 10, 0.0).one_shadow_ray_at_a_time();
            // Floor points in light, half shadow, shadow and tinted shadow all differ.
            let mut floor = std::collections::HashSet::new();
            for k in 0..400u32 {
                let (x, z) = ((k % 20) as f32 * 0.2 - 2.0, (k / 20) as f32 * 0.2 - 2.0);
                let ray = Ray::new(Vec3::new(x, 5.0, z), Vec3::new(0.1, -1.0, 0.05));
                let mut radiance = |w: &Whitted| {
                    let mut sampler = PixelSampler::new(7, k, 3);
                    w.radiance(&ray, 0, Vec3::ONE, &mut sampler, &mut count)
                };
                let (a, b) = (radiance(&packets), radiance(&single));
                assert_eq!(
                    a.to_array().map(f32::to_bits),
                    b.to_array().map(f32::to_bits),
                    "{name} {kind} ray {k}: {a} against {b}"
                );
                let first = single.accel.closest(&ray, f32::INFINITY).map(|h| h.shape);
                if first == Some(0) {
                    floor.insert(a.to_array().map(f32::to_bits));
                }
            }
            assert!(floor.len() > 40, "{name}: {} floor radiances", floor.len());
        }
    }
}
