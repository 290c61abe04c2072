//! Tests of the band loop: cancellation, packets of lens rays and tiles against rays
//! traced alone, progress, and the one-tap resample without anti-aliasing.

/// `scene` with a unit sphere at the origin wearing its first material.
pub(super) fn with_unit_ball(mut scene: crate::scene::Scene) -> crate::scene::Scene {
    let ball = crate::scene::Sphere {
        center: crate::math::Vec3::ZERO,
        radius: 1.0,
    };
    scene.push_shape(crate::scene::Shape::Sphere(ball), 0);
    scene
}

/// Adds a floor of material `material` one unit below the origin, 8 units square.
pub(super) fn add_floor(scene: &mut crate::scene::Scene, material: u32) {
    use crate::math::Vec3;
    let floor = crate::scene::Shape::Rectangle(crate::scene::Rectangle {
        v: [
            Vec3::new(-4.0, -1.0, 4.0),
            Vec3::new(4.0, -1.0, 4.0),
            Vec3::new(4.0, -1.0, -4.0),
            Vec3::new(-4.0, -1.0, -4.0),
        ],
    });
    scene.push_shape(floor, material);
}

/// A glass ball on a floor under a quad light, seen through a lens: every sample of
/// a pixel differs (position, lens point, light point, bounces).
pub(super) fn scene_and_camera(
    width: u32,
    height: u32,
) -> (crate::scene::Scene, crate::scene::Camera) {
    use crate::math::Vec3;
    use crate::scene::{Camera, Light, LightKind, Material, Scene, Surface};
    let glass = Surface {
        transmission: Vec3::splat(0.8),
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let mut scene = with_unit_ball(Scene {
        materials: vec![Material::default_white(), Material::default_white()],
        surfaces: vec![glass, Surface::default()],
        lights: vec![Light {
            kind: LightKind::Quad {
                u: Vec3::new(1.5, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 1.5),
            },
            intensity: 8.0,
            ..Light::point(Vec3::new(-1.0, 3.0, 1.0), Vec3::ONE)
        }],
        ..Scene::default()
    });
    add_floor(&mut scene, 1);
    let mut camera = Camera::look_at(
        Vec3::new(0.5, 1.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        width,
        height,
    );
    camera.aperture = 0.1;
    camera.focal_length = 3.0;
    (scene, camera)
}

/// Supersampled pixel `(x, y)` of `renderer`'s path render made the slow way: each of
/// its samples traced alone, a path at a time, from its own stream, added in order.
pub(super) fn traced_alone(
    renderer: &crate::render::Renderer,
    path: &crate::render::Path,
    rays: &crate::render::CameraRays,
    (x, y): (u32, u32),
    count: &mut crate::render::RayCount,
) -> crate::math::Vec3 {
    use crate::render::Integrator;
    let streams = crate::render::PixelStreams::new(renderer.plan.seed, x, y);
    let mut acc = crate::render::WeightedColor::default();
    for i in 0..renderer.plan.spp {
        let mut sampler = streams.sample(i);
        let jitter = sampler.next_2d();
        let lens = sampler.next_2d();
        let ray = rays.through(x, y, jitter, lens);
        path.trace_camera_ray(ray, &mut sampler, &mut acc, count);
    }
    acc.mean()
}

mod bands;
mod cancel;
mod instances;
mod lens_packets;
mod sample_passes;
