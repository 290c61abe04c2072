//! A scene of instances answers every query as its flattened twin does, bit for bit.

use super::super::{Accel, AccelKind, Hit};
use crate::math::{Ray, Vec3};
use crate::scene::{Instance, Object, Scene, Shape, ShapeId, Shapes, Triangle};
use glam::{Affine3A, Quat};
use proptest::prelude::*;

/// An object of `n` random triangles near the origin, on a seeded generator.
fn object(seed: u64, n: usize) -> Object {
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    };
    let mut shapes = Shapes::new();
    for _ in 0..n {
        let c = Vec3::new(next(), next(), next()) * 3.0;
        let t = Triangle {
            v: [0; 3].map(|_| c + Vec3::new(next(), next(), next())),
        };
        shapes.push(Shape::Triangle(t));
    }
    Object {
        name: format!("o{seed}"),
        material_of: vec![0; shapes.len()],
        shapes,
        meshes: Vec::new(),
    }
}

/// A transform from a scale (negative components mirror), an axis-angle and a move.
fn transform(scale: [f32; 3], axis: [f32; 3], angle: f32, at: [f32; 3]) -> Affine3A {
    let axis = glam::Vec3::from_array(axis).normalize_or(glam::Vec3::Y);
    Affine3A::from_scale_rotation_translation(
        glam::Vec3::from_array(scale),
        Quat::from_axis_angle(axis, angle),
        glam::Vec3::from_array(at),
    )
}

fn scene_of(objects: Vec<Object>, placed: &[(u32, Affine3A)], world: usize) -> Scene {
    let mut scene = Scene {
        objects,
        ..Scene::default()
    };
    let own = object(99, world);
    for i in 0..own.shapes.len() {
        scene.push_shape(own.shapes.get(i), 0);
    }
    scene.instances = placed.iter().map(|&(o, m)| Instance::new(o, m)).collect();
    scene
}

/// Index in the flattened twin of the shape `id` names.
fn flat_index(scene: &Scene, id: ShapeId) -> u32 {
    if id.is_world() {
        return id.shape;
    }
    let before: usize = scene.instances[..id.instance as usize]
        .iter()
        .map(|i| scene.objects[i.object() as usize].shapes.len())
        .sum();
    (scene.shapes.len() + before) as u32 + id.shape
}

fn agree(scene: &Scene, rays: &[Ray]) -> Result<(), TestCaseError> {
    let flat = scene.flattened();
    let reference = Accel::build(AccelKind::List, &flat.shapes);
    for kind in [AccelKind::Bvh, AccelKind::List, AccelKind::Octree] {
        let placed = Accel::build_scene(kind, scene);
        for ray in rays {
            for t_max in [f32::INFINITY, 6.0] {
                let want = reference.closest(ray, t_max);
                let got = placed.closest(ray, t_max);
                let got_flat = got.map(|h| Hit::world(h.t, flat_index(scene, h.id())));
                prop_assert_eq!(got_flat, want, "{:?} {:?} {}", kind, ray, t_max);
                let want_blocked = reference.occluded(ray, t_max, |s| s.shape % 3 != 1);
                let got_blocked = placed.occluded(ray, t_max, |s| flat_index(scene, s) % 3 != 1);
                prop_assert_eq!(got_blocked, want_blocked);
            }
        }
        // Packets and loose rays answer as single rays.
        let mut hits = vec![None; rays.len().min(8)];
        placed.closest_many(&rays[..hits.len()], f32::INFINITY, &mut hits);
        for (hit, ray) in hits.iter().zip(rays) {
            prop_assert_eq!(*hit, placed.closest(ray, f32::INFINITY));
        }
    }
    Ok(())
}

fn rays(seed: u64, n: usize) -> Vec<Ray> {
    let o = object(seed, n);
    (0..n)
        .map(|i| {
            let Shape::Triangle(t) = o.shapes.get(i) else {
                unreachable!()
            };
            let origin = t.v[0] * 8.0;
            // Aimed at the middle of the scene, or anywhere.
            let dir = if i % 2 == 0 { -origin + t.v[1] } else { t.v[2] };
            Ray::new(origin, crate::math::normalize(dir + Vec3::splat(1e-3)))
        })
        .collect()
}

#[test]
fn instances_meet_rays_as_their_flattened_twin_does() {
    let objects = vec![object(1, 40), object(2, 3), object(3, 200)];
    let mut placed = Vec::new();
    for k in 0..30u32 {
        let f = k as f32;
        let mirror = if k % 4 == 1 { -1.0 } else { 1.0 };
        placed.push((
            k % 3,
            transform(
                [mirror * (0.5 + 0.1 * f), 1.0 + 0.05 * f, 0.7],
                [f.sin(), 1.0, f.cos()],
                f * 0.7,
                [(f * 1.3).sin() * 12.0, (f * 0.9).cos() * 8.0, f - 15.0],
            ),
        ));
    }
    let scene = scene_of(objects, &placed, 20);
    let rays = rays(7, 400);
    agree(&scene, &rays).unwrap();
    let flat = scene.flattened();
    let list = Accel::build(AccelKind::List, &flat.shapes);
    let hits = rays
        .iter()
        .filter(|r| list.closest(r, f32::INFINITY).is_some())
        .count();
    assert!(hits > 100, "only {hits} of 400 rays meet the scene");
    let instanced = rays
        .iter()
        .filter_map(|r| Accel::build_scene(AccelKind::Bvh, &scene).closest(r, f32::INFINITY))
        .filter(|h| h.instance != crate::scene::NO_INSTANCE)
        .count();
    assert!(instanced > 50, "only {instanced} rays meet an instance");
}

/// Two instances of one object at the same place: ties go to the earlier, as the
/// flattened twin's lower index.
#[test]
fn coincident_instances_tie_to_the_earlier_one() {
    let m = transform([1.0, 1.0, 1.0], [0.0, 1.0, 0.0], 0.3, [0.0, 0.0, 0.0]);
    let scene = scene_of(vec![object(5, 30)], &[(0, m), (0, m)], 0);
    let accel = Accel::build_scene(AccelKind::Bvh, &scene);
    let mut met = 0;
    for ray in rays(11, 200) {
        if let Some(hit) = accel.closest(&ray, f32::INFINITY) {
            assert_eq!(hit.instance, 0);
            met += 1;
        }
    }
    assert!(met > 20);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random objects, random transforms (mirrors, shears of non-uniform scale under
    /// rotation, far moves), random rays: the two-level structure gives the flat one's
    /// answers.
    #[test]
    fn two_levels_answer_as_one(
        seeds in prop::collection::vec((1u64..1000, 1usize..60), 1..4),
        placements in prop::collection::vec(
            (0u32..4, prop::array::uniform3(-3.0f32..3.0), prop::array::uniform3(-1.0f32..1.0),
             -6.0f32..6.0, prop::array::uniform3(-40.0f32..40.0)),
            1..20),
        world in 0usize..20,
        ray_seed in 0u64..1000,
    ) {
        let objects: Vec<Object> = seeds.iter().map(|&(s, n)| object(s, n)).collect();
        let placed: Vec<(u32, Affine3A)> = placements
            .iter()
            .filter(|p| p.1.iter().all(|s| s.abs() > 0.05))
            .map(|&(o, s, a, angle, at)| {
                (o % objects.len() as u32, transform(s, a, angle, at))
            })
            .collect();
        let scene = scene_of(objects, &placed, world);
        agree(&scene, &rays(ray_seed, 60))?;
    }
}

/// An instance costs its transform in twelve floats and, in the top structure, its box
/// in six, its index and its share of the tree (whose nodes hold six floats a box too).
#[test]
fn an_instance_holds_under_100_bytes() {
    // Its object and mirror bit, and its transform in twelve floats.
    assert_eq!(size_of::<Instance>(), 4 + 48);
    let placed: Vec<(u32, Affine3A)> = (0..4096)
        .map(|k| {
            let at = [(k % 64) as f32 * 3.0, 0.0, (k / 64) as f32 * 3.0];
            (0, transform([1.0; 3], [0.0, 1.0, 0.0], k as f32, at))
        })
        .collect();
    let scene = scene_of(vec![object(1, 8)], &placed, 0);
    let top = super::Instances::build(&scene.objects, &scene.instances);
    let tree = crate::accel::Bvh::build(&scene.objects[0].shapes, crate::accel::Leaves::Indexed);
    let per_instance = (top.memory_bytes() - tree.memory_bytes()) / placed.len();
    println!("the top structure holds {per_instance} bytes an instance");
    assert!(size_of::<Instance>() + per_instance < 100, "{per_instance}");
}
