//! An area light's shadow rays from one point as packets, against one at a time.

use super::visibility::see_through_scene;
use super::*;
use crate::scene::Triangle;

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
        light(
            LightKind::Disk {
                normal: Vec3::new(0.2, -1.0, 0.1),
                radius: 0.5,
            },
            23,
        ),
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
        (
            sphere_at(-1.0, 0.5, 0.8, 0.4),
            Surface {
                specular: Vec3::splat(0.4),
                shininess: 30.0,
                ..matte(Vec3::new(0.6, 0.6, 0.3))
            },
        ),
    ];
    // A square of two emissive triangles facing down, lighting the scene as a mesh
    // light of many samples (more than one packet's worth).
    let emitter = Surface {
        emission: Vec3::new(2.0, 1.8, 1.5),
        ..matte(Vec3::ZERO)
    };
    let corner = |x: f32, z: f32| Vec3::new(x, 3.2, z);
    let mut opaque = opaque;
    let first_emitter = opaque.len() as u32;
    for v in [
        [corner(-0.5, -0.5), corner(0.5, -0.5), corner(0.5, 0.5)],
        [corner(-0.5, -0.5), corner(0.5, 0.5), corner(-0.5, 0.5)],
    ] {
        opaque.push((Shape::Triangle(Triangle { v }), emitter.clone()));
    }
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
    for (_, s) in &mut cases {
        let mut mesh =
            Light::mesh(s, [first_emitter, first_emitter + 1].map(ShapeId::world)).unwrap();
        mesh.samples = 19;
        s.lights.push(mesh);
    }
    cases.push(("see-through", see_through_scene(true)));
    cases[3].1.lights = lights;
    let mut count = RayCount::default();
    for (name, s) in &cases {
        let surfaces = s.resolved_surfaces();
        for kind in [AccelKind::Bvh, AccelKind::BvhCopied, AccelKind::List] {
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
            // Packets are traced, also where a first sample goes alone to see whether the
            // rest should (tinted and see-through scenes); never with the switch off.
            assert!(packets.packets_traced() > 100, "{name} {kind}: few packets");
            assert_eq!(single.packets_traced(), 0);
        }
    }
}
