//! Shadow rays past shapes clear to shadows, in the scene's intersector and in one over
//! the casters.

use super::visibility::{
    glass, push_ball, push_material, random_shadow, see_through_scene, visibility_by_traversals,
};
use super::*;

/// [`see_through_scene`] and a clear glass ball of triangles (white transmission) with
/// two clear spheres inside it: shapes clear to shadows outnumber the others. Without
/// `tinted`, the scene's tinted and masked shapes are left out (every shadow ray is
/// then a plain occlusion query).
fn clear_glass_scene(tinted: bool) -> Scene {
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
    let material = push_material(&mut s, glass(Vec3::ONE));
    push_ball(&mut s, Vec3::new(0.5, 1.8, 0.0), 1.6, 24, material);
    s.push_shape(sphere_at(0.2, 1.6, 0.1, 0.5), material);
    s.push_shape(sphere_at(0.9, 2.0, -0.2, 0.4), material);
    s
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
