//! A scene of instances renders as its flattened twin, bit for bit, in every model.

use crate::math::Vec3;
use crate::options::LightSampling;
use crate::render::{IntegratorKind, RenderSettings, Renderer};
use crate::scene::openpbr::Scalar;
use crate::scene::{
    Camera, Instance, Light, LightKind, Material, MeshAttributes, Object, OpenPbr, Scene, ShapeId,
    Shapes, Surface,
};
use glam::{Affine3A, Quat};

/// An octahedron with smooth normals, texture coordinates and colours, wearing
/// `material`.
fn gem(material: u32) -> Object {
    let positions = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let mut shapes = Shapes::new();
    shapes.push_mesh(&positions, &triangles);
    let normals = positions.iter().map(|p| *p * 0.8 + Vec3::Y * 0.2).collect();
    let uv = positions
        .iter()
        .map(|p| [p.x * 0.5 + 0.5, p.z * 0.5 + 0.5])
        .collect();
    let colors = positions.iter().map(|p| p.abs() * 0.5 + 0.5).collect();
    Object {
        name: "gem".into(),
        material_of: vec![material; triangles.len()],
        meshes: vec![MeshAttributes::per_vertex(&triangles, normals, uv, colors)],
        shapes,
    }
}

fn scene(metal: bool) -> Scene {
    let m = OpenPbr {
        base_metalness: Scalar::constant(1.0),
        specular_roughness: Scalar::constant(0.3),
        ..OpenPbr::default()
    };
    let mut scene = Scene {
        materials: vec![Material::default_white(); 2],
        surfaces: vec![
            Surface::from_classic(&Material::default_white()),
            if metal {
                Surface {
                    openpbr: Some(Box::new(m)),
                    ..Surface::default()
                }
            } else {
                Surface::from_classic(&Material::default_white())
            },
        ],
        lights: vec![Light::point(Vec3::new(1.0, 5.0, 3.0), Vec3::splat(30.0))],
        objects: vec![gem(1)],
        ..Scene::default()
    };
    super::add_floor(&mut scene, 0);
    scene.instances = (0..7)
        .map(|k| {
            let f = k as f32;
            let mirror = if k % 3 == 1 { -1.0 } else { 1.0 };
            Instance::new(
                0,
                Affine3A::from_scale_rotation_translation(
                    glam::Vec3::new(mirror * 0.5, 0.4 + 0.1 * f, 0.45),
                    Quat::from_rotation_y(f * 0.9) * Quat::from_rotation_x(0.3),
                    glam::Vec3::new(f - 3.0, -0.5 + 0.1 * f, (f * 1.7).sin()),
                ),
            )
        })
        .collect();
    scene
}

fn render(scene: &Scene, integrator: IntegratorKind) -> Vec<[f32; 3]> {
    render_with(scene, integrator, LightSampling::default())
}

fn render_with(
    scene: &Scene,
    integrator: IntegratorKind,
    light_sampling: LightSampling,
) -> Vec<[f32; 3]> {
    let camera = Camera::look_at(Vec3::new(0.0, 2.0, 7.0), Vec3::ZERO, Vec3::Y, 45.0, 48, 32);
    let settings = RenderSettings {
        spp: Some(4),
        integrator,
        light_sampling,
        ..RenderSettings::default()
    };
    let renderer = Renderer::new(scene, &camera, settings).unwrap();
    renderer.render(&()).unwrap().0.pixels
}

fn same_bits(a: &[[f32; 3]], b: &[[f32; 3]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits))
}

/// The gems with their upper halves glowing (material 2), lit by nothing else:
/// the glow of the first four is one light (as glTF lights a material), each of the
/// other three's its own (as the scene file lights an instance).
fn glowing_scene() -> Scene {
    let mut scene = scene(false);
    scene.materials.push(Material::default_white());
    scene.surfaces.push(Surface {
        emission: Vec3::new(4.0, 3.0, 2.0),
        ..Surface::from_classic(&Material::default_white())
    });
    for m in &mut scene.objects[0].material_of[..4] {
        *m = 2;
    }
    let glowing = |i: u32| (0..4).map(move |shape| ShapeId { instance: i, shape });
    let shared = Light::mesh(&scene, (0..4).flat_map(glowing)).unwrap();
    let own: Vec<Light> = (4..7)
        .map(|i| Light::mesh(&scene, glowing(i)).unwrap())
        .collect();
    scene.lights = std::iter::once(shared).chain(own).collect();
    scene
}

#[test]
fn glowing_instances_light_as_their_flattened_twin_bit_for_bit() {
    let scene = glowing_scene();
    let flat = scene.flattened();
    let LightKind::Mesh { shapes, .. } = &flat.lights[0].kind else {
        panic!()
    };
    // The copies' indices: the floor is shape 0, each gem 8 shapes.
    assert_eq!(shapes[..5], [1, 2, 3, 4, 9].map(ShapeId::world));
    let dark = Scene {
        lights: Vec::new(),
        ..scene.clone()
    };
    for (integrator, sampling) in [
        (IntegratorKind::Path, LightSampling::All),
        (IntegratorKind::Path, LightSampling::One),
        (IntegratorKind::Path, LightSampling::Tree),
        (IntegratorKind::Whitted, LightSampling::All),
    ] {
        let placed = render_with(&scene, integrator, sampling);
        let twin = render_with(&flat, integrator, sampling);
        assert!(same_bits(&placed, &twin), "{integrator:?}, {sampling:?}");
        // The lights are sampled: the whitted model sees the floor lit only
        // through them; the path model finds the same light either way, but
        // with other numbers.
        let unlit = render_with(&dark, integrator, sampling);
        let sum = |p: &[[f32; 3]]| p.iter().map(|c| c[0] + c[1] + c[2]).sum::<f32>();
        match integrator {
            IntegratorKind::Whitted => assert!(sum(&placed) > 1.5 * sum(&unlit)),
            _ => assert!(!same_bits(&placed, &unlit), "{sampling:?}"),
        }
    }
}

/// Smooth instances in a scene whose own meshes are flat, traced in the path
/// model's lanes: the placed normals are interpolated there too.
#[test]
fn lanes_shade_placed_vertex_normals_as_the_flattened_twin() {
    let scene = glowing_scene();
    assert!(scene.meshes.is_empty());
    let flat = scene.flattened();
    let placed = render_with(&scene, IntegratorKind::Path, LightSampling::All);
    let twin = render_with(&flat, IntegratorKind::Path, LightSampling::All);
    assert!(same_bits(&placed, &twin));
}

#[test]
fn instances_render_as_their_flattened_twin_bit_for_bit() {
    for metal in [false, true] {
        let scene = scene(metal);
        let flat = scene.flattened();
        assert_eq!(flat.shapes.len(), 1 + 7 * 8);
        for integrator in [
            IntegratorKind::Path,
            IntegratorKind::Whitted,
            IntegratorKind::Classic,
        ] {
            let placed = render(&scene, integrator);
            let twin = render(&flat, integrator);
            assert!(same_bits(&placed, &twin), "{integrator:?}, metal {metal}");
            // The gems are seen: pixels differ from the floor-only render.
            let bare = Scene {
                instances: Vec::new(),
                ..scene.clone()
            };
            assert_ne!(render(&bare, integrator), placed, "{integrator:?}");
        }
    }
}
