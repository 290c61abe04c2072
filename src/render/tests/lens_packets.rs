//! A pixel's lens rays traced as packets shade as each ray traced alone.

use crate::render::*;
use crate::scene::{Light, LightKind, Material, Surface};

/// A pixel's lens rays traced as packets (where the model allows) give the pixel
/// each ray gives traced alone, in order, from the pixel's stream.
#[test]
fn lens_rays_in_packets_shade_as_each_ray_traced_alone() {
    let glass = Surface {
        transmission: Vec3::splat(0.8),
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    // The classic model's children too: a see-through ball, a mirroring floor.
    let ball = Material {
        color: Vec3::new(0.8, 0.3, 0.2),
        reflect: 0.3,
        refract: 0.6,
        ior: 1.5,
        transparent: true,
        ..Material::default_white()
    };
    let floor = Material {
        color: Vec3::new(0.2, 0.5, 0.9),
        reflect: 0.5,
        ..Material::default_white()
    };
    let mut scene = super::with_unit_ball(Scene {
        materials: vec![ball, floor],
        surfaces: vec![glass, Surface::default()],
        ..Scene::default()
    });
    super::add_floor(&mut scene, 1);
    let mut camera = Camera::look_at(Vec3::new(0.5, 1.0, 4.0), Vec3::ZERO, Vec3::Y, 50.0, 12, 10);
    camera.aperture = 0.2;
    camera.focal_length = 3.0;
    let point = Light::point(Vec3::new(2.0, 3.0, 4.0), Vec3::ONE);
    let quad = Light {
        kind: LightKind::Quad {
            u: Vec3::new(1.0, 0.0, 0.0),
            v: Vec3::new(0.0, 0.0, 1.0),
        },
        samples: 4,
        ..Light::point(Vec3::new(-1.0, 3.0, 1.0), Vec3::ONE)
    };
    for (lights, packets) in [(vec![point.clone()], true), (vec![point, quad], false)] {
        scene.lights = lights;
        let settings = RenderSettings {
            aa: Some(1),
            spp: Some(21),
            integrator: IntegratorKind::Whitted,
            ..RenderSettings::default()
        };
        let renderer = Renderer::new(&scene, &camera, settings).unwrap();
        let plan = &renderer.plan;
        let rays = CameraRays::new(&plan.camera, 1, plan.spp);
        let accel = Accel::build(plan.accel, &scene.shapes);
        let surfaces = scene.resolved_surfaces();
        let whitted = Whitted::new(&scene, &accel, &surfaces, plan.max_depth, plan.min_weight);
        assert_eq!(whitted.lens_packets(), packets);
        assert_same_pixels(&renderer, &whitted, &accel, &rays);
        // The classic model traces lens packets whatever the lights, and their
        // shadow rays toward each light as packets too.
        let classic = Classic::new(&scene, &accel, plan.camera.medium_ior);
        assert!(classic.lens_packets());
        assert_same_pixels(&renderer, &classic, &accel, &rays);
    }
}

fn assert_same_pixels<I: Integrator>(
    renderer: &Renderer,
    integrator: &I,
    accel: &Accel,
    rays: &CameraRays,
) {
    let mut count = RayCount::default();
    let mut lit = 0;
    let camera = renderer.camera();
    for y in 0..camera.height {
        for x in 0..camera.width {
            let pixel = renderer.pixel(integrator, accel, rays, x, y, &mut count);
            let mut sampler = PixelSampler::new(renderer.plan.seed, x, y);
            let mut acc = WeightedColor::default();
            rays.for_each_ray(x, y, &mut sampler, |ray, sampler| {
                integrator.trace_camera_ray(ray, sampler, &mut acc, &mut count)
            });
            let alone = acc.mean();
            assert_eq!(
                pixel.to_array().map(f32::to_bits),
                alone.to_array().map(f32::to_bits),
                "pixel ({x}, {y})"
            );
            lit += usize::from(pixel.max_element() > 0.0);
        }
    }
    assert!(lit > 60, "{lit} pixels lit");
}
