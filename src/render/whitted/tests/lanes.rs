//! An area light's samples in lanes against `for_each_sample`, sample by sample, on
//! ordinary and degenerate lights: zero and NaN sizes, flat and NaN normals, points
//! inside or on a light, mesh lights with degenerate, NaN or non-triangle shapes, and
//! counts on either side of a chunk of lanes.

use super::*;
use crate::scene::Triangle;
use crate::scene::light::stratified::lanes::{LANES, SampleLanes};

fn bits(ls: &LightSample) -> [u32; 7] {
    [
        ls.dir.x.to_bits(),
        ls.dir.y.to_bits(),
        ls.dir.z.to_bits(),
        ls.dist.to_bits(),
        ls.e.x.to_bits(),
        ls.e.y.to_bits(),
        ls.e.z.to_bits(),
    ]
}

/// Equal bits, but that any NaN equals any NaN (the sign of a NaN made from NaN
/// inputs is not specified, and differs between the lanes and one at a time).
fn same(a: &[u32; 7], b: &[u32; 7]) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, &y)| x == y || (f32::from_bits(x).is_nan() && f32::from_bits(y).is_nan()))
}

/// Compares the samples of `light` seen from `p` both ways, and the sampler's state
/// after them; returns how many there were.
fn compare(w: &Whitted, light: &Light, p: Vec3, tag: &str) -> usize {
    let mut s1 = PixelSampler::new(5, 1, 2);
    let mut scalar = Vec::new();
    light.for_each_sample(w.scene, w.surfaces, p, &mut s1, |ls| scalar.push(bits(&ls)));
    let mut s2 = PixelSampler::new(5, 1, 2);
    let mut lanes_out = Vec::new();
    let n = light.samples.max(1);
    let mut lanes = SampleLanes::default();
    for first in (0..n).step_by(LANES) {
        let len = (n - first).min(LANES as u32) as usize;
        light.sample_lanes(w.scene, w.surfaces, p, &mut s2, first, len, &mut lanes);
        lanes_out.extend(lanes.lit().map(|ls| bits(&ls)));
    }
    assert_eq!(
        s1.next_f32().to_bits(),
        s2.next_f32().to_bits(),
        "{tag}: sampler state"
    );
    assert_eq!(scalar.len(), lanes_out.len(), "{tag}: sample count");
    for (i, (a, b)) in scalar.iter().zip(&lanes_out).enumerate() {
        assert!(same(a, b), "{tag}: sample {i}: {a:x?} vs {b:x?}");
    }
    scalar.len()
}

#[test]
fn lanes_give_the_samples_of_for_each_sample_on_odd_lights() {
    let tri = |v: [Vec3; 3]| Shape::Triangle(Triangle { v });
    let emitter = Surface {
        emission: Vec3::new(2.0, 1.8, 1.5),
        ..matte(Vec3::ZERO)
    };
    let shapes = vec![
        (
            tri([
                Vec3::new(-0.5, 3.0, -0.5),
                Vec3::new(0.5, 3.0, -0.5),
                Vec3::new(0.5, 3.0, 0.5),
            ]),
            emitter.clone(),
        ),
        // degenerate: zero area
        (
            tri([
                Vec3::new(0.0, 3.0, 0.0),
                Vec3::new(1.0, 3.0, 0.0),
                Vec3::new(2.0, 3.0, 0.0),
            ]),
            emitter.clone(),
        ),
        (sphere_at(0.0, 3.0, 0.0, 0.3), emitter.clone()),
        (
            tri([
                Vec3::new(-0.5, 3.0, -0.5),
                Vec3::new(0.5, 3.0, 0.5),
                Vec3::new(-0.5, 3.0, 0.5),
            ]),
            emitter.clone(),
        ),
        // NaN corner
        (
            tri([
                Vec3::new(f32::NAN, 3.0, -0.5),
                Vec3::new(0.5, 3.0, 0.5),
                Vec3::new(-0.5, 3.0, 0.5),
            ]),
            emitter.clone(),
        ),
    ];
    let s = scene(shapes, vec![], Background::Black);
    let accel = Accel::build(AccelKind::List, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
    let at = |kind: LightKind, pos: Vec3| {
        let mut l = Light::point(pos, Vec3::new(1.0, 0.9, 0.8));
        l.kind = kind;
        l
    };
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let c = Vec3::new(0.3, 3.0, -0.2);
    let mut kinds = vec![
        (
            "quad",
            LightKind::Quad {
                u: Vec3::new(1.5, 0.0, 0.2),
                v: Vec3::new(0.0, 0.3, 1.2),
            },
        ),
        (
            "quad flipped",
            LightKind::Quad {
                v: Vec3::new(1.5, 0.0, 0.2),
                u: Vec3::new(0.0, 0.3, 1.2),
            },
        ),
        (
            "quad zero",
            LightKind::Quad {
                u: Vec3::ZERO,
                v: Vec3::new(0.0, 0.3, 1.2),
            },
        ),
        (
            "quad line",
            LightKind::Quad {
                u: Vec3::X,
                v: Vec3::X,
            },
        ),
        (
            "quad nan",
            LightKind::Quad {
                u: Vec3::new(nan, 0.0, 0.0),
                v: Vec3::Z,
            },
        ),
        (
            "quad inf",
            LightKind::Quad {
                u: Vec3::new(inf, 0.0, 0.0),
                v: Vec3::Z,
            },
        ),
        (
            "quad huge",
            LightKind::Quad {
                u: Vec3::new(3e19, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 3e19),
            },
        ),
        (
            "disk",
            LightKind::Disk {
                normal: Vec3::new(0.2, -1.0, 0.1),
                radius: 0.5,
            },
        ),
        (
            "disk up",
            LightKind::Disk {
                normal: Vec3::Y,
                radius: 0.5,
            },
        ),
        (
            "disk zero normal",
            LightKind::Disk {
                normal: Vec3::ZERO,
                radius: 0.5,
            },
        ),
        (
            "disk nan normal",
            LightKind::Disk {
                normal: Vec3::new(nan, 1.0, 0.0),
                radius: 0.5,
            },
        ),
        (
            "disk zero radius",
            LightKind::Disk {
                normal: -Vec3::Y,
                radius: 0.0,
            },
        ),
        (
            "disk nan radius",
            LightKind::Disk {
                normal: -Vec3::Y,
                radius: nan,
            },
        ),
        (
            "disk inf radius",
            LightKind::Disk {
                normal: -Vec3::Y,
                radius: inf,
            },
        ),
        (
            "disk neg radius",
            LightKind::Disk {
                normal: -Vec3::Y,
                radius: -1.0,
            },
        ),
        ("sphere", LightKind::Sphere { radius: 0.4 }),
        ("sphere zero", LightKind::Sphere { radius: 0.0 }),
        ("sphere nan", LightKind::Sphere { radius: nan }),
        ("sphere inf", LightKind::Sphere { radius: inf }),
        ("sphere big", LightKind::Sphere { radius: 2.9999 }),
        (
            "mesh",
            LightKind::Mesh {
                shapes: worlds(&[0, 3]),
                cdf: vec![0.5, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh degenerate",
            LightKind::Mesh {
                shapes: worlds(&[0, 1, 3]),
                cdf: vec![0.4, 0.5, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh non-tri",
            LightKind::Mesh {
                shapes: worlds(&[0, 2, 3]),
                cdf: vec![0.3, 0.6, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh non-tri first",
            LightKind::Mesh {
                shapes: worlds(&[2, 0, 2, 3, 2]),
                cdf: vec![0.2, 0.4, 0.6, 0.8, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh nan",
            LightKind::Mesh {
                shapes: worlds(&[0, 4]),
                cdf: vec![0.5, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh empty",
            LightKind::Mesh {
                shapes: worlds(&[]),
                cdf: vec![],
                area: 0.0,
            },
        ),
        (
            "mesh nan cdf",
            LightKind::Mesh {
                shapes: worlds(&[0, 3]),
                cdf: vec![nan, 1.0],
                area: 1.0,
            },
        ),
        (
            "mesh zero area",
            LightKind::Mesh {
                shapes: worlds(&[0, 3]),
                cdf: vec![0.5, 1.0],
                area: 0.0,
            },
        ),
    ];
    kinds.push((
        "mesh many",
        LightKind::Mesh {
            shapes: worlds(&[0, 3, 0, 3, 0, 3, 0, 3]),
            cdf: (1..=8).map(|k| k as f32 / 8.0).collect(),
            area: 1.0,
        },
    ));
    let points = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.7, 1.2, -0.3),
        Vec3::new(0.3, 5.0, -0.2),   // above: behind downward emitters
        Vec3::new(0.3, 3.0, -0.2),   // at the centre
        Vec3::new(0.0, 3.0, 0.0),    // on the mesh plane
        Vec3::new(0.3, 3.0, 1e-8),   // in the plane
        Vec3::new(1e20, -1e20, 0.0), // far: d2 overflows
        Vec3::new(nan, 0.0, 0.0),
        Vec3::new(inf, 0.0, 0.0),
        Vec3::new(0.3, 3.0 - 0.4, -0.2), // on the sphere
    ];
    let mut compared = 0;
    for (name, kind) in &kinds {
        for pos in [
            c,
            Vec3::ZERO + Vec3::new(0.0, 3.0, 0.0),
            Vec3::new(nan, 3.0, 0.0),
        ] {
            for samples in [0u32, 1, 2, 15, 16, 17, 31, 33, 100] {
                for (pi, &p) in points.iter().enumerate() {
                    let mut light = at(kind.clone(), pos);
                    light.samples = samples;
                    let tag = format!("{name} pos {pos} n {samples} p#{pi} {p}");
                    compared += compare(&w, &light, p, &tag);
                }
            }
        }
    }
    assert!(compared > 50_000, "{compared} samples compared");
}

/// Shapes of the scene's own, by index.
fn worlds(indices: &[u32]) -> Vec<crate::scene::ShapeId> {
    indices
        .iter()
        .map(|&i| crate::scene::ShapeId::world(i))
        .collect()
}
