//! Samples traced in packets across pixels, held to each sample traced alone.

use crate::accel::Accel;
use crate::film::Image;
use crate::math::Vec3;
use crate::options::Filter;
use crate::render::*;
use crate::scene::{Light, Material, Scene, Shape, ShapeId, Surface, Triangle};

/// A unit ball on a floor, lit by a glowing triangle above them: every surface
/// Lambertian and the light a mesh, so the paths go in lanes.
fn lambertian_scene() -> Scene {
    let matte = |r: f32| Surface {
        albedo: crate::scene::Albedo::Color(Vec3::new(r, 0.6, 0.5)),
        ..Surface::default()
    };
    let mut scene = super::super::tests::with_unit_ball(Scene {
        materials: vec![Material::default_white(); 3],
        surfaces: vec![
            matte(0.8),
            matte(0.3),
            Surface {
                emission: Vec3::new(4.0, 3.5, 3.0),
                ..matte(0.2)
            },
        ],
        ..Scene::default()
    });
    super::super::tests::add_floor(&mut scene, 1);
    let glow = Triangle {
        v: [
            Vec3::new(-1.0, 2.5, -1.0),
            Vec3::new(1.0, 2.5, 0.5),
            Vec3::new(-0.5, 2.5, 1.5),
        ],
    };
    scene.push_shape(Shape::Triangle(glow), 2);
    let glow = ShapeId::world(scene.shapes.len() as u32 - 1);
    scene.lights.push(Light::mesh(&scene, [glow]).unwrap());
    scene
}

/// A glass ball on a floor under a quad light, seen through a lens: the paths step
/// together as a wave, each with its own BSDF.
fn glass_scene() -> Scene {
    super::super::tests::scene_and_camera(1, 1).0
}

fn camera(width: u32, height: u32) -> Camera {
    super::super::tests::scene_and_camera(width, height).1
}

fn settings(spp: u32, region: Option<Region>) -> RenderSettings {
    RenderSettings {
        spp: Some(spp),
        aa: Some(1),
        filter: Filter::Area,
        region,
        threads: Some(2),
        integrator: IntegratorKind::Path,
        ..RenderSettings::default()
    }
}

/// The image of `renderer` (one traced pixel to each output pixel) made the slow way:
/// each sample of each pixel traced alone.
fn traced_alone(scene: &Scene, renderer: &Renderer) -> Vec<[f32; 3]> {
    let plan = &renderer.plan;
    let rays = CameraRays::new(&plan.camera, 1, plan.spp);
    let accel = Accel::build(plan.accel, &scene.shapes);
    let surfaces = scene.resolved_surfaces();
    let path = Path::new(scene, &accel, &surfaces, plan.max_depth);
    let mut count = RayCount::default();
    let r = renderer.region();
    let mut pixels = Vec::new();
    for y in r.y..r.y + r.height {
        for x in r.x..r.x + r.width {
            let p = super::super::tests::traced_alone(renderer, &path, &rays, (x, y), &mut count);
            // `+ 0`, as the one-tap resample adds.
            pixels.push((p + Vec3::ZERO).to_array());
        }
    }
    pixels
}

fn bits(pixels: &[[f32; 3]]) -> Vec<u32> {
    pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

/// One, two, three, sixteen and twenty-one samples a pixel, in packets that hold
/// several pixels' samples or a pixel's samples split across two packets, whole frames
/// and a region whose tiles are cut at its edges: every pixel as its samples traced
/// alone give it, in lanes (a Lambertian scene lit by a mesh) and in waves (glass).
#[test]
fn packets_across_pixels_shade_each_sample_as_traced_alone() {
    let region = Region {
        x: 3,
        y: 2,
        width: 13,
        height: 9,
    };
    for (name, scene) in [("lanes", lambertian_scene()), ("wave", glass_scene())] {
        let camera = camera(18, 14);
        {
            let accel = Accel::build(crate::accel::AccelKind::Bvh, &scene.shapes);
            let surfaces = scene.resolved_surfaces();
            let path = Path::new(&scene, &accel, &surfaces, 8);
            assert_eq!(path.steps_in_lanes(), name == "lanes", "{name}");
        }
        for spp in [1, 2, 3, 16, 21] {
            for region in [None, Some(region)] {
                let renderer = Renderer::new(&scene, &camera, settings(spp, region)).unwrap();
                let (image, _) = renderer.render(&()).unwrap();
                let want = traced_alone(&scene, &renderer);
                let case = format!("{name}, {spp} spp, {region:?}");
                assert_eq!(bits(&image.pixels), bits(&want), "{case}");
                assert!(image.pixels.iter().flatten().any(|&v| v > 0.0), "{case}");
            }
        }
    }
}

/// Passes of one, one, two and seventeen samples (the first ones in packets of
/// sixteen pixels) sum to what each sample traced alone gives, and each pass's image
/// is a whole render of its samples.
#[test]
fn passes_in_packets_across_pixels_sum_each_sample_as_traced_alone() {
    for scene in [lambertian_scene(), glass_scene()] {
        let camera = camera(17, 11);
        let renderer = Renderer::new(&scene, &camera, settings(21, None)).unwrap();
        let accel = renderer.build_accel().unwrap();
        let mut sums = renderer.sample_sums().unwrap();
        let mut last: Option<Image> = None;
        for to in [1, 2, 4, 21] {
            let (image, _) = renderer.render_samples(&accel, &mut sums, to, &()).unwrap();
            let whole = Renderer::new(&scene, &camera, settings(to, None)).unwrap();
            assert_eq!(
                bits(&image.pixels),
                bits(&traced_alone(&scene, &whole)),
                "{to}"
            );
            last = Some(image);
        }
        assert!(last.unwrap().pixels.iter().flatten().any(|&v| v > 0.0));
    }
}
