//! Shadow rays through glass: the one traversal and its walks against the walk by
//! traversals, tinted glass meshes, and the limits on crossings.

use super::*;
use crate::math::normalize;
use crate::scene::{ImageTexture, Texels, TextureSlot, Triangle};

/// Glass that transmits `t` per crossing.
pub(super) fn glass(t: Vec3) -> Surface {
    Surface {
        albedo: Albedo::Color(Vec3::ZERO),
        transmission: t,
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    }
}

/// Adds `surface` to `s` as a material of its own; its index.
pub(super) fn push_material(s: &mut Scene, surface: Surface) -> u32 {
    s.materials.push(Material::default_white());
    s.surfaces.push(surface);
    s.materials.len() as u32 - 1
}

/// Adds a ball of triangles edge to edge (`rings` of latitude, twice as many of
/// longitude) around `c`, of radius `r`.
pub(super) fn push_ball(s: &mut Scene, c: Vec3, r: f32, rings: u32, material: u32) {
    let at = |i: u32, j: u32| {
        let (theta, phi) = (
            std::f32::consts::PI * i as f32 / rings as f32,
            std::f32::consts::TAU * j as f32 / (2 * rings) as f32,
        );
        c + r * Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    for i in 0..rings {
        for j in 0..2 * rings {
            let (a, b, d, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            s.push_shape(Shape::Triangle(Triangle { v: [a, b, d] }), material);
            s.push_shape(Shape::Triangle(Triangle { v: [a, d, e] }), material);
        }
    }
}

/// The six faces of the box from `lo` to `hi`, each wound counter-clockwise seen from
/// outside.
fn box_faces(lo: Vec3, hi: Vec3) -> [[Vec3; 4]; 6] {
    let corner = |b: usize| {
        Vec3::new(
            if b & 1 == 0 { lo.x } else { hi.x },
            if b & 2 == 0 { lo.y } else { hi.y },
            if b & 4 == 0 { lo.z } else { hi.z },
        )
    };
    [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ]
    .map(|f| f.map(corner))
}

/// A pane cut out by a 4 x 4 mask of alternating holes (image 0 of the scene, see
/// [`mask_image`]), transmitting `t` where it is not cut.
fn masked(t: Vec3) -> Surface {
    Surface {
        alpha_map: Some(TextureSlot {
            scale: [3.0, 2.0],
            ..TextureSlot::new(0)
        }),
        transmission: t,
        ..matte(Vec3::new(0.3, 0.6, 0.2))
    }
}

/// The mask [`masked`] reads.
fn mask_image() -> ImageTexture {
    ImageTexture {
        name: "mask".into(),
        width: 4,
        height: 4,
        texels: Texels::RgbaF32(
            (0..16)
                .map(|i| [0.5, 0.5, 0.5, ((i + i / 4) % 2) as f32])
                .collect(),
        ),
    }
}

/// A rectangle across the scenes' space, to carry a cut-out surface.
fn cut_out_pane() -> Shape {
    Shape::Rectangle(Rectangle {
        v: [
            Vec3::new(-3.0, 3.0, -1.0),
            Vec3::new(3.0, 3.0, -1.0),
            Vec3::new(3.0, 3.5, 2.0),
            Vec3::new(-3.0, 3.5, 2.0),
        ],
    })
}

/// `rays` random shadow rays toward the box `toward`: for every intersector, the
/// visibility is that of the walk by traversals bit for bit, and more than `tinted` of
/// them are tinted (neither all light nor none).
fn assert_visibility_is_the_walks(
    s: &Scene,
    unit: &mut impl FnMut() -> f32,
    rays: usize,
    toward: [Vec3; 2],
    tinted: usize,
    label: &str,
) {
    let surfaces = s.resolved_surfaces();
    for kind in AccelKind::ALL {
        let accel = Accel::build(kind, &s.shapes);
        let w = Whitted::new(s, &accel, &surfaces, 10, 0.0);
        let (mut seen, mut count) = (0, RayCount::default());
        for i in 0..rays {
            let (from, ng, ls) = random_shadow(unit, i, toward);
            let (dir, dist) = (ls.dir, ls.dist);
            let expected = visibility_by_traversals(&w, from, ng, &ls);
            let got = w.visibility(from, ng, &ls, &mut count);
            assert_eq!(
                got.to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits),
                "{label} {kind}: from {from} dir {dir} dist {dist}: {got} against {expected}"
            );
            if expected != Vec3::ZERO && expected != Vec3::ONE {
                seen += 1;
            }
        }
        assert!(
            seen > tinted,
            "{label} {kind}: only {seen} tinted shadow rays"
        );
    }
}

/// Shadow-ray visibility as it was computed before the single traversal: an occlusion
/// query for the opaque surfaces, then a walk from crossing to crossing, each found by a
/// traversal of the whole scene. The reference the walk through noted spheres must
/// match bit for bit.
pub(super) fn visibility_by_traversals(
    w: &Whitted,
    from: Vec3,
    ng: Vec3,
    ls: &LightSample,
) -> Vec3 {
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
    let opaque = |shape: crate::scene::ShapeId| {
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
        let sp = w.scene.surface_point(hit.id(), &r, hit.t, true);
        if !w.cut_out(hit.id(), &sp) {
            vis *= w.surface(hit.id()).transmission;
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
pub(super) fn see_through_scene(with_flat: bool) -> Scene {
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
        for v in box_faces(Vec3::new(1.0, 0.5, 1.5), Vec3::new(2.2, 1.7, 2.7)) {
            shapes.push((
                Shape::Rectangle(Rectangle { v }),
                glass(Vec3::new(0.7, 0.9, 0.95)),
            ));
        }
        shapes.push((cut_out_pane(), masked(Vec3::ZERO)));
    }
    let mut s = scene(shapes, Vec::new(), Background::Black);
    s.images.push(mask_image());
    s
}

/// A shadow ray's start, surface normal and light sample: from anywhere over the test
/// scenes toward a point of the box `toward`, the light at infinity, past the box, or
/// somewhere along the way (by `i`).
pub(super) fn random_shadow(
    unit: &mut impl FnMut() -> f32,
    i: usize,
    toward: [Vec3; 2],
) -> (Vec3, Vec3, LightSample) {
    let mut point = |lo: Vec3, hi: Vec3| lo + (hi - lo) * Vec3::new(unit(), unit(), unit());
    let from = point(Vec3::new(-5.0, 0.0, -4.0), Vec3::new(5.0, 5.0, 4.0));
    let to = point(toward[0], toward[1]);
    let ng = (point(Vec3::NEG_ONE, Vec3::ONE)).normalize_or(Vec3::Y);
    let (dir, dist) = (normalize(to - from), (to - from).length());
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
        let toward = [Vec3::new(-3.0, 0.0, -3.5), Vec3::new(3.0, 4.5, 3.0)];
        let label = format!("flat {with_flat}");
        let s = see_through_scene(with_flat);
        assert_visibility_is_the_walks(&s, &mut unit, 20_000, toward, 2_000, &label);
    }
}

/// A closed box of twelve tinted glass triangles (each face two, sharing a diagonal),
/// from `lo` to `hi`.
fn glass_box_mesh(s: &mut Scene, lo: Vec3, hi: Vec3, transmission: Vec3) {
    let material = push_material(s, glass(transmission));
    for [a, b, c, d] in box_faces(lo, hi) {
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
            let dir = normalize(dir);
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
    use rand_core::Rng;
    let mut rng = rand_pcg::Pcg32::new(0xf1a7, 5);
    let mut unit = move || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let mut s = scene(
        vec![
            (floor(0.0, 20.0), matte(Vec3::ONE)),
            (cut_out_pane(), masked(Vec3::new(0.4, 0.8, 0.9))),
        ],
        Vec::new(),
        Background::Black,
    );
    s.images.push(mask_image());
    glass_box_mesh(
        &mut s,
        Vec3::new(1.2, 0.5, 1.0),
        Vec3::new(2.4, 1.9, 2.5),
        Vec3::new(0.7, 0.9, 0.95),
    );
    let tinted = push_material(&mut s, glass(Vec3::new(0.9, 0.6, 0.8)));
    push_ball(&mut s, Vec3::new(-0.8, 1.6, 0.0), 1.4, 12, tinted);
    let toward = [Vec3::new(-3.0, 0.0, -2.0), Vec3::new(3.0, 4.0, 3.0)];
    assert_visibility_is_the_walks(&s, &mut unit, 20_000, toward, 3_000, "flat");
}

/// Two tinted panes, coincident, a hair apart or well apart, crossed square on and at a
/// slant: each tints once where the ray meets them more than a surface epsilon apart,
/// and as one pane where closer, on every intersector.
#[test]
fn panes_a_hair_apart_tint_as_one_and_panes_apart_as_two() {
    let pane = |x: f32| {
        let c = |y: f32, z: f32| Vec3::new(x, y, z);
        [
            Triangle {
                v: [c(-5.0, -5.0), c(5.0, -5.0), c(5.0, 5.0)],
            },
            Triangle {
                v: [c(-5.0, -5.0), c(5.0, 5.0), c(-5.0, 5.0)],
            },
        ]
    };
    // Off the panes' diagonals; the surface epsilon there is 2.6e-5.
    let at = Vec3::new(0.0, 0.3, 0.2);
    for (gap, tint) in [(0.0, 0.5), (1e-6, 0.5), (1e-4, 0.25), (0.1, 0.25)] {
        let mut s = scene(
            vec![(floor(-20.0, 40.0), matte(Vec3::ONE))],
            Vec::new(),
            Background::Black,
        );
        let half = push_material(&mut s, glass(Vec3::splat(0.5)));
        for x in [0.0, gap] {
            for t in pane(x) {
                s.push_shape(Shape::Triangle(t), half);
            }
        }
        let surfaces = s.resolved_surfaces();
        for degrees in [0.0f32, 60.0, 80.0, 85.0] {
            let a = degrees.to_radians();
            let dir = Vec3::new(a.cos(), a.sin(), 0.0);
            let ls = LightSample {
                dir,
                dist: 4.0,
                e: Vec3::ONE,
            };
            for kind in AccelKind::ALL {
                let accel = Accel::build(kind, &s.shapes);
                let w = Whitted::new(&s, &accel, &surfaces, 10, 0.0);
                let vis = w.visibility(at - 2.0 * dir, dir, &ls, &mut RayCount::default());
                assert_eq!(
                    vis,
                    Vec3::splat(tint),
                    "{kind}: gap {gap}, {degrees} degrees"
                );
            }
        }
    }
}

/// The visibility of a shadow ray from `from` toward a point light at `to`, for every
/// intersector, with and without an intersector over the scene's casters: one answer,
/// checked against each.
fn shadow_answers(s: &Scene, from: Vec3, to: Vec3) -> Vec<(String, Vec3)> {
    let surfaces = s.resolved_surfaces();
    let casters = Casters::of(s, &surfaces).expect("clear shapes outnumber the rest");
    let ls = LightSample {
        dir: normalize(to - from),
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
    for (t, crossings) in [(1.0f32, 0), (0.9, 2)] {
        let mut shapes = vec![(sphere_at(0.0, 0.0, 0.0, 0.3), matte(Vec3::ONE))];
        // Clear shells around it, so that casters are built: the tinted one outermost.
        for r in [0.6, 0.9, 1.2] {
            shapes.push((sphere_at(0.0, 0.0, 0.0, r), glass(Vec3::ONE)));
        }
        shapes.push((sphere_at(0.0, 0.0, 0.0, 1.5), glass(Vec3::splat(t))));
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
