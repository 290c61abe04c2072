//! The lanes held to the path at a time: the same radiance bit for bit, and the same
//! rays traced, for every lane of every packet size and depth, and the same sums.

use super::super::Path;
use super::LANES;
use crate::accel::{Accel, AccelKind};
use crate::math::{Ray, Vec3, normalize};
use crate::render::{Integrator, PixelSampler, RayCount, WeightedColor};
use crate::scene::{
    Albedo, Background, Light, Material, MeshAttributes, Rectangle, Scene, Shape, Sphere, Surface,
    Triangle,
};
use rand_core::Rng;
use rand_pcg::Pcg32;

fn matte(albedo: Vec3) -> Surface {
    Surface {
        albedo: Albedo::Color(albedo),
        ..Surface::default()
    }
}

fn emitter(le: Vec3) -> Surface {
    Surface {
        emission: le,
        ..matte(Vec3::splat(0.3))
    }
}

/// A box open at +z with walls of several reflectances (brighter than white, coloured,
/// one without red), a black sphere, a square light under the ceiling and a small triangle light
/// on the back wall.
fn room() -> Scene {
    let mut s = Scene {
        background: Background::Black,
        ..Scene::default()
    };
    let add = |s: &mut Scene, shape: Shape, surface: Surface| {
        let m = s.materials.len() as u32;
        s.materials.push(Material::default_white());
        s.surfaces.push(surface);
        s.push_shape(shape, m);
        s.shapes.len() as u32 - 1
    };
    let quad = |s: &mut Scene, c: [Vec3; 4], surface: Surface| -> [u32; 2] {
        [
            add(
                s,
                Shape::Triangle(Triangle {
                    v: [c[0], c[1], c[2]],
                }),
                surface.clone(),
            ),
            add(
                s,
                Shape::Triangle(Triangle {
                    v: [c[0], c[2], c[3]],
                }),
                surface,
            ),
        ]
    };
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Floor, ceiling, back, left, right: normals into the room.
    quad(
        &mut s,
        [
            v(-1., -1., -1.),
            v(-1., -1., 1.),
            v(1., -1., 1.),
            v(1., -1., -1.),
        ],
        matte(Vec3::new(0.7, 0.6, 0.5)),
    );
    quad(
        &mut s,
        [
            v(-1., 1., -1.),
            v(1., 1., -1.),
            v(1., 1., 1.),
            v(-1., 1., 1.),
        ],
        matte(Vec3::splat(1.5)),
    );
    quad(
        &mut s,
        [
            v(-1., -1., -1.),
            v(1., -1., -1.),
            v(1., 1., -1.),
            v(-1., 1., -1.),
        ],
        matte(Vec3::new(0.0, 0.5, 0.5)),
    );
    quad(
        &mut s,
        [
            v(-1., -1., -1.),
            v(-1., 1., -1.),
            v(-1., 1., 1.),
            v(-1., -1., 1.),
        ],
        matte(Vec3::new(0.6, 0.1, 0.1)),
    );
    quad(
        &mut s,
        [
            v(1., -1., -1.),
            v(1., -1., 1.),
            v(1., 1., 1.),
            v(1., 1., -1.),
        ],
        matte(Vec3::new(0.1, 0.6, 0.1)),
    );
    add(
        &mut s,
        Shape::Sphere(Sphere {
            center: v(0.2, -0.5, -0.2),
            radius: 0.45,
        }),
        matte(Vec3::ZERO),
    );
    // A ramp leaning across the room: a normal along no axis, so how it is rounded
    // shows in the image.
    add(
        &mut s,
        Shape::Triangle(Triangle {
            v: [v(-0.8, -1.0, 0.5), v(0.7, -0.3, 0.1), v(-0.2, 0.4, -0.6)],
        }),
        matte(Vec3::new(0.4, 0.5, 0.3)),
    );
    let ceiling_light = quad(
        &mut s,
        [
            v(-0.3, 0.99, -0.3),
            v(0.3, 0.99, -0.3),
            v(0.3, 0.99, 0.3),
            v(-0.3, 0.99, 0.3),
        ],
        emitter(Vec3::new(8.0, 7.0, 5.0)),
    );
    let wall_light = add(
        &mut s,
        Shape::Triangle(Triangle {
            v: [
                v(-0.9, -0.2, -0.99),
                v(-0.5, -0.2, -0.99),
                v(-0.7, 0.2, -0.99),
            ],
        }),
        emitter(Vec3::new(0.5, 1.0, 3.0)),
    );
    let mut light = Light::mesh(&s, ceiling_light.map(crate::scene::ShapeId::world)).unwrap();
    light.intensity = 1.5;
    s.lights.push(light);
    s.lights
        .push(Light::mesh(&s, [crate::scene::ShapeId::world(wall_light)]).unwrap());
    // The floor's shading normals lean away from its face, and its corners have
    // colours of their own.
    let lean = |x: f32, z: f32| Vec3::new(x, 1.0, z);
    s.meshes.push(MeshAttributes::per_vertex(
        &[[0, 1, 2], [0, 2, 3]],
        vec![
            lean(0.5, 0.0),
            lean(0.0, -0.7),
            lean(-0.3, 0.3),
            lean(0.9, 0.9),
        ],
        vec![],
        vec![
            Vec3::new(1.0, 0.2, 0.2),
            Vec3::ONE,
            Vec3::new(0.3, 1.0, 0.6),
            Vec3::splat(0.5),
        ],
    ));
    s
}

/// The room with a wall light too bright for f32 in red, and a left wall that
/// reflects only red: light samples there are NaN in one channel.
fn blazing_room() -> Scene {
    let mut s = room();
    let wall_light = s.surfaces.len() - 1;
    s.surfaces[wall_light].emission = Vec3::new(1e38, 1.0, 3.0);
    s.lights[1].intensity = 10.0;
    for left_wall in [6, 7] {
        s.surfaces[left_wall].albedo = Albedo::Color(Vec3::new(0.6, 0.0, 0.0));
    }
    s
}

/// The room with no vertex normals or colours: its hits are flat points.
fn bare_room() -> Scene {
    let mut s = room();
    for mesh in &mut s.meshes {
        mesh.normal_indices.clear();
        mesh.color_indices.clear();
    }
    s
}

/// The bare room with a leaning panel (a rectangle) for its ball: every shape flat, so
/// the lanes read each hit's normal from their table.
fn flat_room() -> Scene {
    let mut s = bare_room();
    let ball = (0..s.shapes.len())
        .find(|&i| matches!(s.shapes.get(i), Shape::Sphere(_)))
        .expect("the room has a ball");
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    s.shapes.set(
        ball,
        Shape::Rectangle(Rectangle {
            v: [
                v(-0.1, -1.0, -0.5),
                v(0.6, -1.0, -0.2),
                v(0.6, 0.1, 0.0),
                v(-0.1, 0.1, -0.3),
            ],
        }),
    );
    let m = s.material_of[ball] as usize;
    s.surfaces[m].albedo = Albedo::Color(Vec3::new(0.5, 0.4, 0.3));
    s
}

/// The room without vertex attributes, its back wall textured: a checker of four
/// texels read at the wall's own texture coordinates.
fn textured_room() -> Scene {
    use crate::scene::TextureSlot;
    use crate::scene::image::{ImageTexture, Texels};
    let mut s = bare_room();
    s.images.push(ImageTexture {
        name: "checker".into(),
        width: 2,
        height: 2,
        texels: Texels::Rgba8 {
            texels: vec![
                [230, 40, 40, 255],
                [40, 230, 40, 255],
                [40, 40, 230, 255],
                [200; 4],
            ],
            srgb: true,
        },
    });
    for back_wall in [4, 5] {
        s.surfaces[back_wall].albedo = Albedo::Image {
            slot: TextureSlot {
                image: 0,
                scale: [3.0, 3.0],
                offset: [0.0, 0.0],
                clamp: false,
                matrix: None,
            },
            tint: Vec3::ONE,
        };
    }
    s
}

/// Camera-like rays from the open side into the room.
fn rays(rng: &mut Pcg32, n: usize) -> Vec<Ray> {
    let mut u = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    (0..n)
        .map(|_| {
            let origin = Vec3::new(u() - 0.5, u() - 0.5, 2.5);
            let target = Vec3::new(2.0 * u() - 1.0, 2.0 * u() - 1.0, -1.0);
            Ray {
                origin,
                dir: normalize(target - origin),
            }
        })
        .collect()
}

/// One way to trace lanes.
type Trace = fn(
    &Path,
    &super::LaneScene,
    &[Ray],
    &[Option<crate::accel::Hit>],
    &mut [PixelSampler],
    &mut RayCount,
    &mut [Vec3],
);

/// Each instruction set the lanes are compiled for that this processor runs.
fn variants() -> Vec<(&'static str, Trace)> {
    let mut v: Vec<(&'static str, Trace)> = vec![("baseline", |p, l, r, h, s, c, o| {
        p.radiance_lanes_in(l, r, h, s, c, o)
    })];
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the processor runs AVX2 and FMA.
            v.push(("avx2", |p, l, r, h, s, c, o| unsafe {
                p.radiance_lanes_avx2(l, r, h, s, c, o)
            }));
        }
        if crate::accel::simd::avx512_supported() {
            // SAFETY: the processor runs AVX-512 F, VL, DQ and BW.
            v.push(("avx512", |p, l, r, h, s, c, o| unsafe {
                p.radiance_lanes_avx512(l, r, h, s, c, o)
            }));
        }
    }
    v
}

#[test]
fn lanes_give_each_path_the_radiance_and_rays_of_the_path_at_a_time() {
    let mut rng = Pcg32::new(7, 0xa02b_db2e_3f0c_4d6d);
    let (mut lit, mut total) = (0, 0);
    let rooms = [
        (room(), false, true),
        (blazing_room(), false, true),
        (bare_room(), true, true),
        (flat_room(), true, true),
        (textured_room(), true, false),
    ];
    for (s, flat, untextured) in rooms {
        let accel = Accel::build(AccelKind::Bvh, &s.shapes);
        let surfaces = s.resolved_surfaces();
        for max_depth in [0, 1, 2, 6, crate::options::MAX_PATH_DEPTH] {
            let path = Path::new(&s, &accel, &surfaces, max_depth);
            let lights = path
                .lanes
                .as_ref()
                .expect("a Lambertian room lit by meshes");
            assert_eq!(lights.flat, flat);
            assert_eq!(lights.untextured, untextured);
            // A flat room's hits read their normals and plain surfaces from the table.
            let all_flat =
                (0..s.shapes.len()).all(|i| !matches!(s.shapes.get(i), Shape::Sphere(_)));
            let table = if flat && all_flat { s.shapes.len() } else { 0 };
            assert_eq!(lights.flat_hits.len(), table);
            for n in [1, 5, LANES - 1, LANES] {
                for packet in 0..24u32 {
                    let rays = rays(&mut rng, n);
                    let hits: Vec<_> = rays
                        .iter()
                        .map(|r| accel.closest(r, f32::INFINITY))
                        .collect();
                    let streams =
                        |k: usize| PixelSampler::for_sample(3, packet, max_depth, k as u32);
                    let mut alone = RayCount::default();
                    let want: Vec<Vec3> = (0..n)
                        .map(|k| path.radiance(rays[k], hits[k], &mut streams(k), &mut alone))
                        .collect();
                    for (variant, trace) in variants() {
                        let mut samplers: Vec<_> = (0..n).map(streams).collect();
                        let mut together = RayCount::default();
                        let mut got = [Vec3::ZERO; LANES];
                        trace(
                            &path,
                            lights,
                            &rays,
                            &hits,
                            &mut samplers,
                            &mut together,
                            &mut got,
                        );
                        for k in 0..n {
                            assert_eq!(
                                got[k].to_array().map(f32::to_bits),
                                want[k].to_array().map(f32::to_bits),
                                "{variant}: lane {k} of {n}, depth {max_depth}: {} against {}",
                                got[k],
                                want[k]
                            );
                        }
                        assert_eq!(
                            together.rays, alone.rays,
                            "{variant}: rays, {n} lanes, depth {max_depth}"
                        );
                    }
                    lit += want.iter().filter(|l| l.max_element() > 0.0).count();
                    total += n;
                }
            }
        }
    }
    // Most paths carry light: the comparison is not of zeros.
    assert!(lit * 2 > total, "{lit} lit paths of {total}");
}

#[test]
fn lanes_take_lambertian_scenes_lit_by_meshes_only() {
    let s = room();
    let surfaces = s.resolved_surfaces();
    assert!(Path::lanes_apply(&s, &surfaces).is_some());
    // A highlight, a mirror, a cut-out, another kind of light, an environment: each
    // keeps the path at a time.
    let mut shiny = surfaces.clone();
    shiny[0].specular = Vec3::splat(0.2);
    assert!(Path::lanes_apply(&s, &shiny).is_none());
    let mut mirror = surfaces.clone();
    mirror[3].reflection = Vec3::ONE;
    assert!(Path::lanes_apply(&s, &mirror).is_none());
    let mut openpbr = surfaces.clone();
    openpbr[1].openpbr = Some(Box::default());
    assert!(Path::lanes_apply(&s, &openpbr).is_none());
    let mut point_lit = room();
    point_lit.lights.push(Light::point(Vec3::ZERO, Vec3::ONE));
    assert!(Path::lanes_apply(&point_lit, &surfaces).is_none());
    let mut sky = room();
    sky.background = Background::Color(Vec3::splat(0.5));
    assert!(Path::lanes_apply(&sky, &surfaces).is_none());
}

#[test]
fn the_lanes_maximum_of_three_is_glams_even_with_nans() {
    let values = [
        f32::NAN,
        -1.0,
        -0.0,
        0.0,
        2.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ];
    for x in values {
        for y in values {
            for z in values {
                let glam = Vec3::new(x, y, z).max_element();
                let lanes = super::max_element([x, y, z]);
                assert_eq!(lanes.to_bits(), glam.to_bits(), "{x} {y} {z}");
            }
        }
    }
}

#[test]
fn a_packet_of_samples_adds_up_as_one_path_at_a_time_adds_it() {
    let s = room();
    let accel = Accel::build(AccelKind::Bvh, &s.shapes);
    let surfaces = s.resolved_surfaces();
    let lanes = Path::new(&s, &accel, &surfaces, crate::options::MAX_PATH_DEPTH);
    let mut alone = Path::new(&s, &accel, &surfaces, crate::options::MAX_PATH_DEPTH);
    alone.lanes = None;
    let mut rng = Pcg32::new(9, 0x1d3b_5a79_c2e4_f601);
    for n in [2, LANES, 2 * LANES + 3] {
        let rays = rays(&mut rng, n);
        let hits: Vec<_> = rays
            .iter()
            .map(|r| accel.closest(r, f32::INFINITY))
            .collect();
        let sums = |path: &Path| {
            let mut samplers: Vec<_> = (0..n)
                .map(|k| PixelSampler::for_sample(5, 1, 2, k as u32))
                .collect();
            let mut acc = WeightedColor::default();
            let mut count = RayCount::default();
            path.trace_camera_packet(
                &rays,
                &hits,
                &mut samplers,
                std::slice::from_mut(&mut acc),
                &mut count,
            );
            (acc.sum.to_array().map(f32::to_bits), acc.weight, count.rays)
        };
        assert_eq!(sums(&lanes), sums(&alone), "{n} samples");
    }
}

#[test]
fn a_few_triangles_are_picked_in_every_lane_as_the_search_picks_one() {
    use super::{MeshLight, V3};
    use crate::scene::light::sampling::{MeshTriangle, pick_triangle, triangle_point};
    let mut rng = Pcg32::new(11, 0x5851_f42d_4c95_7f2d);
    let mut unit = || (rng.next_u32() >> 8) as f32 / (1 << 24) as f32;
    let mut checked = 0;
    for round in 0..400 {
        let count = 1 + round % super::FEW_TRIANGLES;
        let triangles: Vec<MeshTriangle> = (0..count)
            .map(|_| MeshTriangle {
                v: [0; 3].map(|_| Vec3::new(unit(), unit(), unit()) * 4.0 - 2.0),
                normal: normalize(Vec3::new(unit() - 0.5, unit() - 0.5, 1.0)),
                le: Vec3::new(unit(), unit(), unit()),
            })
            .collect();
        // Areas with zeros among them (a repeated entry), and a total that rounds
        // below 1 in some rounds, so the last triangle is clamped to as well.
        let areas: Vec<f32> = (0..count)
            .map(|k| {
                if k > 0 && (round + k) % 3 == 0 {
                    0.0
                } else {
                    unit() + 0.01
                }
            })
            .collect();
        let total: f32 = areas.iter().sum::<f32>() * if round % 2 == 0 { 1.0 } else { 1.001 };
        let cdf: Vec<f32> = areas
            .iter()
            .scan(0.0, |acc, a| {
                *acc += a;
                Some(*acc / total)
            })
            .collect();
        let light = MeshLight::new(1.0, cdf.clone(), triangles);
        assert!(light.few);
        let a: [f32; LANES] = std::array::from_fn(|i| match i {
            0 => 0.0,
            1 => 1.0 - f32::EPSILON / 2.0,
            2 => cdf[0],
            _ => unit(),
        });
        let b: [f32; LANES] = std::array::from_fn(|i| if i == 3 { 0.0 } else { unit() });
        let (mut y, mut normal, mut le) = (V3::ZERO, V3::ZERO, V3::ZERO);
        light.points(&a, &b, &mut y, &mut normal, &mut le);
        for i in 0..LANES {
            let (k, su) = pick_triangle(&cdf, count, a[i]);
            let tri = &light.triangles[k];
            let want = triangle_point(tri.v, su, b[i]);
            assert_eq!(
                y.get(i).to_array().map(f32::to_bits),
                want.to_array().map(f32::to_bits)
            );
            assert_eq!(normal.get(i), tri.normal);
            assert_eq!(le.get(i), tri.le);
            checked += 1;
        }
    }
    assert_eq!(checked, 400 * LANES);
    // A light of many triangles, or of an unordered cdf, takes the search.
    let many = |n: usize| {
        MeshLight::new(
            1.0,
            (1..=n).map(|k| k as f32 / n as f32).collect(),
            vec![
                MeshTriangle {
                    v: [Vec3::ZERO; 3],
                    normal: Vec3::Z,
                    le: Vec3::ONE
                };
                n
            ],
        )
    };
    assert!(many(super::FEW_TRIANGLES).few);
    assert!(!many(super::FEW_TRIANGLES + 1).few);
    let mut unordered = many(2);
    unordered = MeshLight::new(1.0, vec![0.7, 0.5], unordered.triangles);
    assert!(!unordered.few);
}
