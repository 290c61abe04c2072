//! Animation files end to end in the library: parsing, posing, errors, frames.

use super::*;
use crate::math::{Vec3, normalize};
use crate::scene::Shape;

fn example(file: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/example")
        .join(file);
    p.to_string_lossy().replace('\\', "/")
}

/// An animation of the example scene with `body` after its header.
fn anim_text(body: &str) -> String {
    format!(
        "scene = \"{}\"\ncamera = \"{}\"\n{body}",
        example("example.objx"),
        example("example.cmr")
    )
}

fn parse_str(body: &str) -> Result<Animation> {
    file::parse(&anim_text(body), Path::new("dir/anim.toml"))
}

fn err(body: &str) -> String {
    parse_str(body).unwrap_err().to_string()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-3
}

#[test]
fn a_rotated_object_has_known_vertices_at_a_known_frame() {
    let a = parse_str(
        "frames = 5\nfps = 4\n\
         [[track]]\ntarget = \"material:gold\"\nmotion = \"rotate\"\n\
         axis = [0, 0, 2]\ncenter = [120, 105, 0]\nkeys = [[0, 0], [1, 90]]\n",
    )
    .unwrap();
    assert_eq!((a.frames, a.fps), (5, 4.0));
    let tri = |frame| {
        let (scene, _) = a.pose(frame).unwrap();
        match scene.shapes.get(5) {
            Shape::Triangle(t) => t.v,
            _ => panic!("shape 5 is the gold triangle"),
        }
    };
    let v = tri(4);
    assert!(close(v[0], Vec3::new(165.0, 105.0, 0.0)), "{v:?}");
    assert!(close(v[1], Vec3::new(75.0, 105.0, 0.0)), "{v:?}");
    assert_eq!(v[2], Vec3::new(120.0, 105.0, 120.0), "on the axis");
    // Halfway (t = 0.5 s, 45 degrees).
    let h = 45.0 * std::f32::consts::SQRT_2 / 2.0;
    let v = tri(2);
    assert!(close(v[0], Vec3::new(120.0 + h, 105.0 - h, 0.0)), "{v:?}");
    // Frame 0 and everything else are the file's, bit for bit.
    let (scene0, camera0) = a.pose(0).unwrap();
    assert_eq!(scene0.shapes, a.scene.shapes);
    assert_eq!(camera0, a.camera);
    let (scene4, _) = a.pose(4).unwrap();
    assert_eq!(scene4.shapes.to_vec()[..5], a.scene.shapes.to_vec()[..5]);
    assert_eq!(scene4.lights, a.scene.lights);
}

#[test]
fn a_posed_camera_at_a_known_frame() {
    let a = parse_str(
        "frames = 3\nfps = 2\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"orbit\"\naxis = [0, 0, 1]\n\
         keys = [[0, 0], [1, 90]]\ninterpolation = \"smooth\"\n",
    )
    .unwrap();
    // Orbit keeping orientation: the eye (-330, 0, 120) goes round z, the view stays.
    let (_, c) = a.pose(2).unwrap();
    assert!(close(c.eye, Vec3::new(0.0, -330.0, 120.0)), "{:?}", c.eye);
    assert_eq!((c.theta_deg, c.phi_deg), (100.0, 0.0));
    // Smooth: half the angle at half the time.
    let (_, c) = a.pose(1).unwrap();
    let h = 330.0 * std::f32::consts::SQRT_2 / 2.0;
    assert!(close(c.eye, Vec3::new(-h, -h, 120.0)), "{:?}", c.eye);

    let a = parse_str(
        "frames = 3\nfps = 2\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"orbit\"\naxis = [0, 0, 1]\n\
         keys = [[0, 0], [1, 90]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = [0, 0, 120]\nfocus = true\n",
    )
    .unwrap();
    let (_, c) = a.pose(2).unwrap();
    assert!((c.theta_deg - 90.0).abs() < 1e-4 && (c.phi_deg - 90.0).abs() < 1e-4);
    assert!((c.focal_length - 330.0).abs() < 1e-3);
    let f = c.frame().forward;
    assert!(close(f, Vec3::Y), "{f:?}");

    // Rotating the camera turns its view with it; looking at an object aims at its centre.
    let a = parse_str(
        "frames = 2\nfps = 1\n[start]\neye = [-330, 0, 40]\ntheta = 90\nphi = 0\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 1]\n\
         keys = [[0, 0], [1, 90]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = \"material:glass\"\n",
    )
    .unwrap();
    let (_, c) = a.pose(0).unwrap();
    let to_glass = normalize(Vec3::new(-20.0, 40.0, 40.0) - c.eye);
    assert!(close(c.frame().forward, to_glass));
    let a = parse_str(
        "frames = 2\nfps = 1\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 1]\n\
         keys = [[0, 0], [1, 90]]\n",
    )
    .unwrap();
    let (_, c) = a.pose(1).unwrap();
    assert!((c.phi_deg - 90.0).abs() < 1e-4 && (c.theta_deg - 100.0).abs() < 1e-4);
}

#[test]
fn orbit_keeps_or_turns_an_objects_orientation() {
    let body = |keep: bool| {
        format!(
            "frames = 2\nfps = 1\n[[track]]\ntarget = \"shape:5\"\nmotion = \"orbit\"\n\
             axis = [0, 0, 1]\nkeep_orientation = {keep}\nkeys = [[0, 0], [1, 180]]\n"
        )
    };
    let tri = |keep| match parse_str(&body(keep))
        .unwrap()
        .pose(1)
        .unwrap()
        .0
        .shapes
        .get(5)
    {
        Shape::Triangle(t) => t.v,
        _ => unreachable!(),
    };
    // Kept: moved by the centre's offset; the centre (120, 105, 60) goes to (-120, -105, 60).
    let v = tri(true);
    assert!(close(v[0], Vec3::new(-120.0, -150.0, 0.0)), "{v:?}");
    assert!(close(v[2], Vec3::new(-120.0, -105.0, 120.0)), "{v:?}");
    // Turned: a rigid half turn.
    let v = tri(false);
    assert!(close(v[0], Vec3::new(-120.0, -60.0, 0.0)), "{v:?}");
}

#[test]
fn translate_moves_a_group_with_its_light_and_duration_sets_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.objx"),
        "v 0 0 0\nv 5 0 0\ng lamp\nf 0 1\nf 1\ng\nf 1 2\n",
    )
    .unwrap();
    std::fs::copy(example("example.cmr"), dir.path().join("c.cmr")).unwrap();
    let path = dir.path().join("a.toml");
    std::fs::write(
        &path,
        "scene = \"s.objx\"\ncamera = \"c.cmr\"\nduration = 1.5\nfps = 10\n\
         [[track]]\ntarget = \"group:lamp\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [0, 0, 10]]]\n",
    )
    .unwrap();
    let a = Animation::load(&path).unwrap();
    assert_eq!(a.frames, 15);
    let (scene, _) = a.pose(5).unwrap();
    assert_eq!(scene.lights[0].position, Vec3::new(5.0, 0.0, 5.0));
    let Shape::Sphere(s) = scene.shapes.get(0) else {
        panic!()
    };
    assert_eq!(s.center, Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(
        scene.shapes.get(1),
        a.scene.shapes.get(1),
        "not in the group"
    );
    let (scene, _) = a.pose(14).unwrap();
    assert_eq!(scene.lights[0].position, Vec3::new(5.0, 0.0, 10.0), "held");
}

#[test]
fn bad_input_is_an_error_with_file_and_line() {
    let cases: &[(&str, usize, &str)] = &[
        (
            "frames = 0\n",
            3,
            "expected between 1 and 1000000 frames, found 0",
        ),
        ("duration = 0.01\nfps = 10\n", 3, "frames, found 0"),
        (
            "fps = 24\n",
            1,
            "expected `frames = N` or `duration = SECONDS`",
        ),
        ("frames = 2\nduration = 1\n", 3, "not both"),
        (
            "frames = 2\nfps = -1\n",
            4,
            "expected fps between 0.01 and 1000",
        ),
        (
            "frames = 2\nfps = 0.0004\n",
            4,
            "expected fps between 0.01 and 1000",
        ),
        (
            "frames = 2\nfps = 1001\n",
            4,
            "expected fps between 0.01 and 1000",
        ),
        ("frames = 2\nspeed = 3\n", 4, "unknown field `speed`"),
        (
            "frames = 2\n[render]\nwidth = 0\n",
            4,
            "image width must be between 1",
        ),
        ("frames = 2\n[render]\nfilter = \"sinc\"\n", 5, "unknown"),
        (
            "frames = 2\n\n[[track]]\ntarget = \"material:nothing\"\nmotion = \"translate\"\n\
             keys = [[0, [0, 0, 0]]]\n",
            6,
            "unknown target `material:nothing`: no shape wears material `nothing`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"shape:6\"\nmotion = \"translate\"\nkeys = [[0, [1, 2, 3]]]\n",
            5,
            "unknown target `shape:6`: the scene has 6 shapes",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"group:g\"\nmotion = \"translate\"\nkeys = [[0, [1, 2, 3]]]\n",
            5,
            "the scene has no `g g` or `o g`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"lamp\"\nmotion = \"translate\"\nkeys = [[0, [1, 2, 3]]]\n",
            5,
            "expected camera, shape:N, material:NAME, group:NAME, object:NAME or light:NAME",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 1]\n\
             keys = [\n  [0, 0],\n  [2, 10],\n  [1, 20],\n]\n",
            11,
            "key times must increase: 1 s comes after 2 s",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 0]\nkeys = [[0, 0]]\n",
            7,
            "the axis must not be zero",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\nkeys = [[0, 0]]\n",
            6,
            "motion `rotate` needs `axis`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"translate\"\nkeys = [[0, 5]]\n",
            7,
            "expected [time, [x, y, z]]",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"spin\"\n",
            6,
            "unknown motion `spin`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"shape:1\"\nmotion = \"look_at\"\nat = [0, 0, 0]\n",
            6,
            "only the camera can look_at",
        ),
        ("frames = [2\n", 3, ""),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = [0, 0, 0]\n\
             keys = [[0, 1]]\n",
            8,
            "`keys` does not apply to motion `look_at`, which takes `at`, `focus`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\n\
             interpolation = \"smooth\"\nat = [0, 0, 0]\n",
            7,
            "`interpolation` does not apply to motion `look_at`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 1]\n\
             keep_orientation = false\nkeys = [[0, 1]]\n",
            8,
            "`keep_orientation` does not apply to motion `rotate`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"shape:1\"\nmotion = \"translate\"\n\
             axis = [0, 0, 1]\nkeys = [[0, [1, 2, 3]]]\n",
            7,
            "`axis` does not apply to motion `translate`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"shape:1\"\nmotion = \"orbit\"\n\
             axis = [0, 0, 1]\nfocus = true\nkeys = [[0, 1]]\n",
            8,
            "`focus` does not apply to motion `orbit`",
        ),
        (
            "frames = 2\n[start]\nfocal_length = -1\n",
            4,
            "expected start.focal_length >= 0, found -1",
        ),
        (
            "frames = 2\n[start]\neye = [1e31, 0, 0]\n",
            4,
            "magnitude at most 1e30 for start.eye",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [nan, 0, 1]\nkeys = [[0, 0]]\n",
            7,
            "expected finite numbers of magnitude at most 1e30 for the axis",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"rotate\"\naxis = [0, 0, 1]\nkeys = [[0, inf]]\n",
            8,
            "expected finite numbers",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"translate\"\nkeys = [[0, [0, 0, 1e31]]]\n",
            7,
            "at most 1e30",
        ),
    ];
    for &(body, line, words) in cases {
        let e = err(body);
        assert!(
            e.starts_with(&format!("dir/anim.toml:{line}: ")) && e.contains(words),
            "{body:?} gave {e}"
        );
    }
}

#[test]
fn a_camera_on_its_look_at_point_is_refused_before_rendering() {
    let a = parse_str(
        "frames = 5\nfps = 1\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [4, [660, 0, 0]]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = [0, 0, 120]\n",
    )
    .unwrap();
    assert!(a.check(0..2).is_ok());
    let e = a.check(0..5).unwrap_err().to_string();
    assert!(
        e.starts_with("dir/anim.toml:9: frame 2: at 2 s the camera's eye (0, 0, 120) is on the point it looks at"),
        "{e}"
    );
    assert!(a.pose(2).is_err());
}

#[test]
fn frame_k_is_the_still_render_of_the_posed_scene_for_any_thread_count() {
    let mut a = parse_str(
        "frames = 4\nfps = 2\n[render]\nwidth = 32\nheight = 18\naa = 2\ndof_rays = 3\n\
         [[track]]\ntarget = \"material:red\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1.5, [0, 90, 30]]]\ninterpolation = \"smooth\"\n",
    )
    .unwrap();
    let (scene, camera) = a.pose(2).unwrap();
    let still = Renderer::new(&scene, &camera, a.settings.clone())
        .unwrap()
        .render(&())
        .unwrap()
        .0;
    assert_eq!((still.width, still.height), (32, 18));
    for threads in [1, 2, 3] {
        a.settings.threads = Some(threads);
        let (frame, _) = a.render_frame(2, &()).unwrap();
        assert_eq!(frame, still, "{threads} threads");
    }
    let (frame0, _) = a.render_frame(0, &()).unwrap();
    assert_ne!(frame0, still, "the ball moved");
    assert_eq!(a.frame_size().unwrap(), (32, 18));
}

#[test]
fn spp_is_the_samples_key_and_dof_rays_its_older_name() {
    let new = parse_str("frames = 2\n[render]\nspp = 3\n").unwrap();
    let old = parse_str("frames = 2\n[render]\ndof_rays = 3\n").unwrap();
    assert_eq!((new.settings.spp, old.settings.spp), (Some(3), Some(3)));
}

/// An animation file's `[render]` lies over its scene file's, resolved as a still's
/// job is: the scene's model, samples and development hold unless the animation says.
#[test]
fn an_animation_takes_its_scene_files_render_settings_under_its_own() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.toml"),
        "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\n\
         [render]\nwidth = 40\nheight = 20\nspp = 2\nintegrator = \"classic\"\n\
         exposure = 1\ntonemap = \"aces\"\n\
         [[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
    )
    .unwrap();
    let path = dir.path().join("anim.toml");
    let text = "scene = \"scene.toml\"\nframes = 2\n[render]\nwidth = 32\n";
    std::fs::write(&path, text).unwrap();
    let a = file::parse(text, &path).unwrap();
    assert_eq!(
        a.settings.integrator,
        crate::render::IntegratorKind::Classic
    );
    assert_eq!(a.settings.spp, Some(2));
    // A side the animation gives replaces the scene's size: the height follows the aspect.
    assert_eq!((a.settings.width, a.settings.height), (Some(32), None));
    assert_eq!(a.frame_size().unwrap(), (32, 16));
    let d = a.output.develop;
    assert_eq!(
        (d.exposure, d.tonemap, d.transfer),
        (
            1.0,
            crate::film::ToneMap::Aces,
            crate::film::Transfer::Classic
        )
    );
}

#[test]
fn a_camera_only_animation_shares_one_intersector_and_renders_the_same_frames() {
    let a = parse_str(
        "frames = 3\nfps = 1\n[render]\nwidth = 32\nheight = 18\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"orbit\"\naxis = [0, 0, 1]\n\
         center = [0, 0, 0]\nkeys = [[0, 0], [2, 30]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = \"material:red\"\n",
    )
    .unwrap();
    let still = a.still_geometry().unwrap().expect("no shape moves");
    assert_eq!(still.shape_count(), a.scene.shapes.len());
    let mut posed = a.scene.clone();
    for k in 0..3 {
        let (fresh, _) = a.render_frame(k, &()).unwrap();
        let (shared, _) = a.render_frame_in(k, &mut posed, Some(&still), &()).unwrap();
        assert_eq!(shared, fresh, "frame {k}");
    }
    // A track that moves shapes gets an intersector per frame.
    let moving = parse_str(
        "frames = 2\nfps = 1\n[[track]]\ntarget = \"material:red\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [0, 10, 0]]]\n",
    )
    .unwrap();
    assert!(moving.still_geometry().unwrap().is_none());
}

#[test]
fn an_intersector_over_other_shapes_is_refused() {
    let a = parse_str("frames = 1\nfps = 1\n[render]\nwidth = 8\nheight = 6\n").unwrap();
    let empty = crate::scene::Shapes::new();
    let accel = crate::accel::Accel::build(crate::accel::AccelKind::Bvh, &empty);
    let renderer = Renderer::new(&a.scene, &a.camera, a.settings.clone()).unwrap();
    let e = renderer.render_with(&accel, &()).unwrap_err().to_string();
    assert!(e.contains("built over 0 shapes"), "{e}");
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    /// A `[[track]]` with fields drawn from the file's vocabulary and odd values.
    fn track() -> impl Strategy<Value = String> {
        let target = "camera|shape:[0-9]|material:(gold|red|glass|x)|group:g|lamp";
        let motion = "translate|rotate|orbit|look_at|spin";
        let number = prop_oneof![
            "-?[0-9]{1,3}(\\.[0-9])?",
            Just("nan".to_string()),
            Just("inf".to_string()),
            Just("1e300".to_string()),
        ];
        let vector = (number.clone(), number.clone(), number.clone())
            .prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]"));
        let value = prop_oneof![number.clone(), vector.clone()];
        let key = (number.clone(), value).prop_map(|(t, v)| format!("[{t}, {v}]"));
        (
            target,
            motion,
            prop::option::of(vector.clone()),
            prop::option::of(vector),
            prop::collection::vec(key, 0..4),
            prop::option::of("\"material:glass\"|[0, 0, 40]|\"camera\""),
        )
            .prop_map(|(t, m, axis, center, keys, at)| {
                let mut s = format!("[[track]]\ntarget = \"{t}\"\nmotion = \"{m}\"\n");
                if let Some(a) = axis {
                    s += &format!("axis = {a}\n");
                }
                if let Some(c) = center {
                    s += &format!("center = {c}\n");
                }
                if !keys.is_empty() {
                    s += &format!("keys = [{}]\n", keys.join(", "));
                }
                if let Some(a) = at {
                    s += &format!("at = {a}\nfocus = true\n");
                }
                s
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn arbitrary_tracks_parse_or_fail_cleanly_and_pose_every_frame(
            tracks in prop::collection::vec(track(), 0..4),
            frames in 1u32..4,
        ) {
            let body = format!("frames = {frames}\nfps = 2\n{}", tracks.join(""));
            if let Ok(a) = parse_str(&body) {
                for k in 0..frames {
                    if let Ok((scene, camera)) = a.pose(k) {
                        prop_assert!(camera.eye.is_finite());
                        prop_assert_eq!(scene.shapes.len(), a.scene.shapes.len());
                    }
                }
            }
        }
    }
}

#[test]
fn a_reused_posed_scene_equals_a_fresh_pose_at_every_frame() {
    let a = parse_str(
        "frames = 6\nfps = 2\n\
         [[track]]\ntarget = \"shape:1\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [2, [10, 0, 0]]]\n\
         [[track]]\ntarget = \"shape:2\"\nmotion = \"orbit\"\naxis = [0, 0, 1]\n\
         keys = [[0, 0], [2, 90]]\n",
    )
    .unwrap();
    let mut posed = a.scene.clone();
    for k in [3, 0, 5, 1, 1, 4] {
        let camera = a.pose_into(k, &mut posed).unwrap();
        let (fresh, fresh_camera) = a.pose(k).unwrap();
        assert_eq!(posed.shapes, fresh.shapes, "frame {k}");
        assert_eq!(posed.lights, fresh.lights, "frame {k}");
        assert_eq!(camera, fresh_camera, "frame {k}");
    }
}

/// Posing stores transforms only for what moves (per-shape arrays sized to the scene
/// made checking 400 frames of a 300 000-shape scene take seconds); the posed scene
/// still moves exactly its target.
#[test]
fn a_big_scene_moves_only_its_target_at_every_frame() {
    let mut a = parse_str(
        "frames = 400\nfps = 24\n\
         [[track]]\ntarget = \"shape:1\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [10, [10, 0, 0]]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = \"shape:1\"\n",
    )
    .unwrap();
    // 300 000 more triangles, none of them moving.
    let t = a.scene.shapes.get(0);
    let m = a.scene.material_of[0];
    for _ in 0..300_000 {
        a.scene.push_shape(t, m);
    }
    a.check(0..400).unwrap();
    let mut posed = a.scene.clone();
    for k in [0, 120, 399] {
        a.pose_into(k, &mut posed).unwrap();
        let moved: Vec<usize> = (0..posed.shapes.len())
            .filter(|&i| posed.shapes.get(i) != a.scene.shapes.get(i))
            .collect();
        let expected: Vec<usize> = if k == 0 { vec![] } else { vec![1] };
        assert_eq!(moved, expected, "frame {k}");
    }
}

/// Mesh triangles share corners: moving one must move its own corners only, frame
/// after frame in the same posed scene, without the scene growing.
#[test]
fn moving_one_triangle_of_a_mesh_leaves_its_neighbour_in_place() {
    let mut a = parse_str(
        "frames = 2\nfps = 1\n\
         [[track]]\ntarget = \"shape:1\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [10, 0, 0]]]\n",
    )
    .unwrap();
    let quad = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    ];
    a.scene.shapes = crate::scene::Shapes::new();
    a.scene.shapes.push_mesh(&quad, &[[0, 1, 2], [0, 2, 3]]);
    a.scene.material_of.truncate(2);
    let mut posed = a.scene.clone();
    for k in [1, 1, 0, 1] {
        a.pose_into(k, &mut posed).unwrap();
        let shift = Vec3::new(10.0 * k as f32, 0.0, 0.0);
        assert_eq!(posed.shapes.get(0), a.scene.shapes.get(0), "frame {k}");
        let Shape::Triangle(moved) = posed.shapes.get(1) else {
            panic!("shape 1 is a triangle")
        };
        assert_eq!(moved.v, [quad[0], quad[2], quad[3]].map(|p| p + shift));
        assert!(posed.shapes.positions().len() <= 4 + 3, "frame {k}");
    }
}

/// `[render] denoise` asks for denoised frames; a folder of frames made without it is
/// not resumed by a run with it, before anything is rendered (nor the other way).
#[test]
fn denoise_is_a_render_key_and_denoised_frames_are_another_folder() {
    let size = "frames = 2\n[render]\nwidth = 8\nheight = 8\n";
    let plain = parse_str(size).unwrap();
    assert!(!plain.denoise);
    // Resolved as a still's job is: a Prism that cannot denoise refuses the file.
    let asked = parse_str(&format!("{size}denoise = true\n"));
    if crate::film::denoise::AVAILABLE {
        assert!(asked.unwrap().denoise);
    } else {
        assert!(matches!(asked, Err(crate::Error::Denoise(_))));
    }
    let denoised = Animation {
        denoise: true,
        ..plain.clone()
    };
    assert!(plain.frame_job(0).map(|j| !j.denoise).unwrap());
    assert!(denoised.frame_job(0).map(|j| j.denoise).unwrap());
    let dir = tempfile::tempdir().unwrap();
    let output = output::Output::from_path(&dir.path().join("frames")).unwrap();
    let observer = job::FrameObserver {
        frame_start: &|_, _| {},
        rows: &|_| {},
        frame_done: &|_, _| {},
    };
    let report = job::render_frames(&plain, 0..1, output.frames(), &observer).unwrap();
    assert_eq!(report.rendered, 1);
    for (anim, frames) in [(&denoised, 1..2), (&plain, 1..2)] {
        let got = job::render_frames(anim, frames, output.frames(), &observer);
        if anim.denoise {
            let e = got.unwrap_err().to_string();
            assert!(e.contains("another version of the animation"), "{e}");
        } else {
            assert_eq!(got.unwrap().rendered, 1);
        }
    }
}

/// A named instance object is a group of its instances: a track moves each of them.
#[test]
fn a_track_moves_the_instances_of_a_named_instance_object() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[camera]\nfrom = [0, 0, 8]\nat = [0, 0, 0]\n[render]\nwidth = 24\nheight = 16\n\
         [[light]]\ntype = \"point\"\nposition = [0, 0, 5]\n\
         [[object]]\nname = \"pair\"\ntype = \"instance\"\nfile = \"tri.obj\"\n\
         transforms = [[[1, 0, 0, -2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]\n\
         [[object]]\nname = \"still\"\ntype = \"instance\"\nfile = \"tri.obj\"\n",
    )
    .unwrap();
    let path = dir.path().join("a.toml");
    std::fs::write(
        &path,
        "scene = \"s.toml\"\nduration = 1\nfps = 4\n\
         [[track]]\ntarget = \"object:pair\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [0, 2, 0]]]\n",
    )
    .unwrap();
    let a = Animation::load(&path).unwrap();
    assert!(a.still_geometry().unwrap().is_none(), "the instances move");
    let (scene, _) = a.pose(2).unwrap();
    assert_eq!(scene.instances.len(), 3);
    let moved = |i: usize| scene.instances[i].to_world().translation;
    assert_eq!(moved(0), glam::Vec3A::new(-2.0, 1.0, 0.0));
    assert_eq!(moved(1), glam::Vec3A::new(1.0, 1.0, 0.0));
    assert_eq!(moved(2), glam::Vec3A::ZERO, "not in the group");
}
