//! `prism animate` end to end: outputs, resuming, determinism and bad input.

mod common;
use common::*;
use std::fs;
use std::path::{Path, PathBuf};

fn turntable(file: &str) -> String {
    repo()
        .join("scenes/turntable")
        .join(file)
        .to_string_lossy()
        .into_owned()
}

/// Writes `anim.toml` into `dir`: the turntable scene at 32x18 with `body` after it.
fn write_anim(dir: &Path, body: &str) -> PathBuf {
    let path = dir.join("anim.toml");
    let text = format!(
        "scene = {:?}\ncamera = {:?}\n{body}",
        turntable("turntable.objx"),
        turntable("turntable.cmr")
    );
    fs::write(&path, text).unwrap();
    path
}

const SMALL: &str = "fps = 24\n[render]\nwidth = 32\nheight = 18\n";

/// The turntable's own tracks at 32x18, `frames` frames.
fn small_turntable(dir: &Path, frames: u32) -> PathBuf {
    let own = fs::read_to_string(turntable("turntable.toml")).unwrap();
    let tracks = &own[own.find("[[track]]").unwrap()..];
    write_anim(dir, &format!("frames = {frames}\n{SMALL}{tracks}"))
}

fn animate(anim: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    run(prism()
        .arg("animate")
        .arg(anim)
        .arg(out)
        .arg("--quiet")
        .args(extra))
}

/// The files in `dir`, but for a frame folder's manifest and a finished video's stamp.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != ".prism-animation" && !(n.starts_with('.') && n.ends_with(".prism")))
        .collect();
    v.sort();
    v
}

#[test]
fn shipped_animation_renders_and_the_seed_scene1_orbit_loads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let o = animate(
        &repo().join("scenes/turntable/turntable.toml"),
        &out,
        &["--frames", "10..=11"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&out), ["frame_0010.png", "frame_0011.png"]);
    assert_eq!(
        load_rgb(&out.join("frame_0010.png")).dimensions(),
        (320, 180)
    );

    if seed_scene("scene1").is_none() {
        return;
    }
    let anim = prism::anim::Animation::load(&repo().join("scenes/scene1-orbit/scene1-orbit.toml"))
        .unwrap();
    assert_eq!((anim.frames, anim.fps), (120, 24.0));
    anim.check(0..120).unwrap();
    // Frame 0 is the pose of the report's scene1 figures (docs/fidelity.md).
    let (scene, camera) = anim.pose(0).unwrap();
    let v = |x, y, z| prism::math::Vec3::new(x, y, z);
    assert!((camera.eye - v(-315.1314, -130.5317, 447.4487)).length() < 1e-3);
    assert!(
        (camera.theta_deg - 109.0).abs() < 1e-3,
        "{}",
        camera.theta_deg
    );
    assert!((camera.phi_deg - 22.5).abs() < 1e-3, "{}", camera.phi_deg);
    assert!((camera.focal_length - 360.75).abs() < 1e-3);
    let marbles = [
        v(-21.6480, -73.9106, 351.6476),
        v(-80.9512, 49.7053, 361.2462),
        v(110.8656, 0.0, 375.9221),
        v(0.0, 129.3432, 383.5757),
        v(-88.8913, 133.0352, 330.0),
    ];
    for (i, want) in marbles.iter().enumerate() {
        let name = format!("marble{i}");
        let k = (0..scene.shapes.len() as u32)
            .find(|&k| scene.material(k).name == name)
            .unwrap();
        let prism::scene::Shape::Sphere(s) = scene.shapes.get(k as usize) else {
            panic!("{name} is a sphere")
        };
        assert!((s.center - *want).length() < 2e-3, "{name}: {:?}", s.center);
    }
    // Half way round, the eye is on the other side of the z axis, at the same height.
    let (_, half) = anim.pose(60).unwrap();
    assert!((half.eye - v(315.1314, 130.5317, 447.4487)).length() < 1e-2);
}

#[test]
fn frames_resume_and_do_not_depend_on_threads() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 5);
    let a = dir.path().join("a");
    let o = animate(&anim, &a, &["--frames", "1..3", "--threads", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&a), ["frame_0001.png", "frame_0002.png"]);
    // Rerun: the two frames present are skipped, the other three rendered.
    let o = animate(&anim, &a, &["--threads", "2", "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("frames 3 rendered, 2 skipped"), "{stdout}");
    assert_eq!(names(&a).len(), 5);
    // A fresh run with another thread count and a %04d pattern gives the same files.
    let b = dir.path().join("b");
    fs::create_dir(&b).unwrap();
    let o = animate(&anim, &b.join("shot%04d.png"), &["--threads", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..5 {
        assert_eq!(
            fs::read(a.join(format!("frame_{k:04}.png"))).unwrap(),
            fs::read(b.join(format!("shot{k:04}.png"))).unwrap(),
            "frame {k}"
        );
    }
    assert_ne!(
        fs::read(a.join("frame_0000.png")).unwrap(),
        fs::read(a.join("frame_0002.png")).unwrap(),
        "the scene moves"
    );
}

#[test]
fn a_frame_where_the_tracks_come_back_is_the_still_render_of_the_files() {
    let dir = tempfile::tempdir().unwrap();
    let anim = write_anim(
        dir.path(),
        &format!(
            "frames = 3\n{SMALL}aa = 2\nspp = 3\n\
             [[track]]\ntarget = \"group:pyramid\"\nmotion = \"translate\"\n\
             keys = [[0, [0, 0, 0]], [0.0416666, [0, -40, 10]], [0.0833333, [0, 0, 0]]]\n"
        ),
    );
    let frames = dir.path().join("f");
    let o = animate(&anim, &frames, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let still = dir.path().join("still.png");
    let o = run(prism()
        .args([
            "render",
            &turntable("turntable.objx"),
            &turntable("turntable.cmr"),
        ])
        .arg(&still)
        .args([
            "--width",
            "32",
            "--height",
            "18",
            "--aa",
            "2",
            "--dof-rays",
            "3",
        ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let still = load_rgb(&still);
    assert_eq!(load_rgb(&frames.join("frame_0000.png")), still);
    // Frame 2 is at 2/24 s, past the last key (0.0833333 s): the pyramid is back.
    assert_eq!(load_rgb(&frames.join("frame_0002.png")), still);
    assert_ne!(load_rgb(&frames.join("frame_0001.png")), still);
}

#[test]
fn mp4_has_the_frames_size_and_rate_and_plays() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 7);
    let mp4 = dir.path().join("t.mp4");
    let o = animate(&anim, &mp4, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The frames it was made from are gone; only the video is left.
    assert_eq!(names(dir.path()), ["anim.toml", "t.mp4"]);
    let size = fs::metadata(&mp4).unwrap().len();
    let file = std::io::BufReader::new(fs::File::open(&mp4).unwrap());
    let reader = mp4::Mp4Reader::read_header(file, size).unwrap();
    let track = reader.tracks().get(&1).unwrap();
    assert_eq!((track.width(), track.height()), (32, 18));
    assert_eq!(track.sample_count(), 7);
    assert!((track.frame_rate() - 24.0).abs() < 1e-9);
    // The container lasts as long as the stream: 7 frames at 24 fps.
    let movie = &reader.moov.mvhd;
    assert_eq!(movie.duration as f64 / movie.timescale as f64, 7.0 / 24.0);

    let probe = std::process::Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries", "stream=codec_name,width,height,r_frame_rate,nb_read_frames,color_space,color_primaries,color_transfer,pix_fmt:format=duration"])
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(&mp4)
        .output();
    match probe {
        Err(e) => skipped(format_args!(
            "the ffprobe check: ffprobe cannot run here ({e})"
        )),
        Ok(p) => {
            let text = String::from_utf8_lossy(&p.stdout);
            assert!(p.status.success(), "{}", String::from_utf8_lossy(&p.stderr));
            for line in [
                "codec_name=h264",
                "width=32",
                "height=18",
                "r_frame_rate=24/1",
                "nb_read_frames=7",
                "color_space=smpte170m",
                "pix_fmt=yuv420p",
                "duration=0.291667",
            ] {
                assert!(text.lines().any(|l| l == line), "{line} not in\n{text}");
            }
        }
    }
}

#[test]
fn gif_decodes_to_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 4);
    let gif_path = dir.path().join("t.gif");
    let o = run(prism().arg("animate").arg(&anim).arg(&gif_path));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("GIF delays are whole hundredths of a second: frames last 4 or 5"),
        "{}",
        stderr(&o)
    );
    let file = fs::File::open(&gif_path).unwrap();
    let mut decoder = gif::DecodeOptions::new().read_info(file).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (32, 18));
    let mut n = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width, frame.height), (32, 18));
        assert_eq!(frame.delay, [4, 4, 5, 4][n], "frame {n}");
        n += 1;
    }
    assert_eq!(n, 4);
}

#[test]
fn odd_sizes_are_refused_for_mp4_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let anim = write_anim(
        dir.path(),
        "frames = 2\n[render]\nwidth = 33\nheight = 18\n",
    );
    let o = animate(&anim, &dir.path().join("t.mp4"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("even width and height, found 33x18"),
        "{}",
        stderr(&o)
    );
    assert_eq!(names(dir.path()), ["anim.toml"]);
}

#[test]
fn bad_input_exits_2_with_file_and_line_and_writes_nothing() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "frames = 2\n[[track]]\ntarget = \"group:nothing\"\nmotion = \"translate\"\nkeys = [[0, [0, 0, 1]]]\n",
            "t.mp4",
            "anim.toml:5: unknown target `group:nothing`",
        ),
        (
            "frames = 2\n[[track]]\ntarget = \"camera\"\nmotion = \"translate\"\n\
             keys = [[1, [0, 0, 1]], [0.5, [0, 0, 2]]]\n",
            "frames",
            "anim.toml:7: key times must increase: 0.5 s comes after 1 s",
        ),
        (
            "frames = 0\n",
            "t.gif",
            "anim.toml:3: expected between 1 and",
        ),
        (
            "frames = 2\n",
            "t.avi",
            "t.avi: unknown output extension `avi`",
        ),
        (
            "frames = 3\nfps = 1\n[[track]]\ntarget = \"camera\"\nmotion = \"translate\"\n\
             keys = [[0, [0, 0, 0]], [2, [330, 0, -100]]]\n\
             [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = [0, 0, 50]\n",
            "t.mp4",
            "anim.toml:9: frame 2: at 2 s the camera's eye (0, 0, 50) is on the point it looks at",
        ),
    ];
    for (body, out, message) in cases {
        let dir = tempfile::tempdir().unwrap();
        let anim = write_anim(dir.path(), body);
        let o = animate(&anim, &dir.path().join(out), &[]);
        assert_eq!(o.status.code(), Some(2), "{body}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.starts_with("error: ") && e.contains(message),
            "{body}: {e}"
        );
        assert_eq!(names(dir.path()), ["anim.toml"], "{body}: nothing written");
    }
    let dir = tempfile::tempdir().unwrap();
    let anim = write_anim(dir.path(), "frames = 2\n");
    let o = animate(&anim, &dir.path().join("f"), &["--frames", "1..5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--frames 1..5"), "{}", stderr(&o));
    assert_eq!(names(dir.path()), ["anim.toml"]);
}

#[test]
fn a_video_resumes_from_its_frames() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 5);
    let gif_path = dir.path().join("t.gif");
    // Two frames rendered and kept, as an interrupted run leaves them.
    let o = animate(&anim, &gif_path, &["--frames", "0..2", "--keep-frames"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        names(&dir.path().join("t.gif.frames")),
        ["frame_0000.png", "frame_0001.png"]
    );
    let o = animate(&anim, &gif_path, &["--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("frames 3 rendered, 2 skipped"), "{stdout}");
    assert!(stdout.contains("encoded 5 frames"), "{stdout}");
    // 5 frames at 24 fps: 21 hundredths in all.
    assert!(stdout.contains("fps 23.8"), "{stdout}");
    assert_eq!(names(dir.path()), ["anim.toml", "t.gif"]);
    let count = |path: &Path| {
        let file = fs::File::open(path).unwrap();
        let mut decoder = gif::DecodeOptions::new().read_info(file).unwrap();
        let mut n = 0;
        while decoder.read_next_frame().unwrap().is_some() {
            n += 1;
        }
        n
    };
    assert_eq!(count(&gif_path), 5);
}

#[test]
fn a_video_split_across_runs_is_encoded_by_the_run_that_completes_it() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 5);
    let gif_path = dir.path().join("split.gif");
    let frames = dir.path().join("split.gif.frames");
    // One machine's share: its frames stay, and no film is made yet.
    let o = run(prism()
        .arg("animate")
        .arg(&anim)
        .arg(&gif_path)
        .args(["--frames", "1..=3"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("2 of the animation's 5 frames are not in"),
        "{}",
        stderr(&o)
    );
    assert!(!gif_path.exists());
    assert_eq!(
        names(&frames),
        ["frame_0001.png", "frame_0002.png", "frame_0003.png"]
    );
    let o = animate(&anim, &gif_path, &["--frames", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!gif_path.exists());
    // The last share completes the frames: the whole film is encoded, the frames go.
    let o = animate(&anim, &gif_path, &["--frames", "4..", "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("encoded 5 frames"), "{stdout}");
    assert_eq!(names(dir.path()), ["anim.toml", "split.gif"]);
}

#[test]
fn a_frame_folder_of_another_animation_is_not_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 3);
    let out = dir.path().join("f");
    let o = animate(&anim, &out, &["--frames", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join(".prism-animation").is_file());
    // A temporary file left by a crash (an hour ago) is removed at the next start; a
    // fresh one may be another machine's frame being written, and stays.
    let hour_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    let old = fs::File::create(out.join(".prism-x1y2.part")).unwrap();
    old.set_modified(hour_ago).unwrap();
    drop(old);
    fs::write(out.join(".prism-new.part"), b"half a frame").unwrap();
    let o = animate(&anim, &out, &["--frames", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        names(&out),
        [".prism-new.part", "frame_0000.png", "frame_0001.png"]
    );
    fs::remove_file(out.join(".prism-new.part")).unwrap();
    // The animation changes (a longer film moves differently): its frames are refused.
    let text = fs::read_to_string(&anim).unwrap();
    fs::write(&anim, text.replace("frames = 3", "frames = 4")).unwrap();
    let o = animate(&anim, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("holds frames of another version of the animation")
            && e.contains("delete the folder"),
        "{e}"
    );
    assert_eq!(names(&out), ["frame_0000.png", "frame_0001.png"]);
}

#[test]
fn a_scene_file_animates_itself_and_frame_0_is_its_still() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bounce.toml");
    fs::write(
        &scene,
        "[camera]\nfrom = [0, 1, 5]\nat = [0, 0.5, 0]\nfov = 50\n\
         [render]\nwidth = 32\nheight = 18\n\
         [animation]\nframes = 3\nfps = 2\n\
         [[material]]\nname = \"red\"\ncolor = [0.8, 0.1, 0.1]\n\
         [[object]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.5\n\
         material = \"red\"\n\
         [[object]]\ntype = \"plane\"\n\
         [[light]]\nname = \"sun\"\ntype = \"directional\"\ndirection = [-1, -2, -1]\n\
         [[track]]\ntarget = \"object:ball\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [1, 0, 0]]]\n",
    )
    .unwrap();
    let frames = dir.path().join("frames");
    let o = animate(&scene, &frames, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        names(&frames),
        ["frame_0000.png", "frame_0001.png", "frame_0002.png"]
    );
    let still = dir.path().join("still.png");
    let o = run(prism().arg("render").arg(&scene).arg(&still).arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let first = load_rgb(&frames.join("frame_0000.png"));
    assert_eq!(first, load_rgb(&still), "frame 0 is the scene at rest");
    // Half a second later the ball has moved half a unit to the right.
    assert_ne!(first, load_rgb(&frames.join("frame_0001.png")));
    // A scene file without [animation] says what is missing.
    let plain = dir.path().join("plain.toml");
    fs::write(&plain, "[[object]]\ntype = \"sphere\"\nradius = 1\n").unwrap();
    let o = animate(&plain, &dir.path().join("p"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("[animation]"), "{}", stderr(&o));
}

#[test]
fn animation_files_must_be_regular_and_errors_name_the_right_line_among_many_tracks() {
    let dir = tempfile::tempdir().unwrap();
    let o = animate(dir.path(), &dir.path().join("out"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    #[cfg(unix)]
    {
        let fifo = dir.path().join("anim.fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let o = animate(&fifo, &dir.path().join("out"), &[]);
            assert_eq!(o.status.code(), Some(2), "a FIFO must not block");
        }
    }
    // 20 000 tracks, the last one naming nothing: the error has its line (line lookup
    // was once quadratic in the file's size).
    let track = "[[track]]\ntarget = \"camera\"\nmotion = \"translate\"\nkeys = [[0, [0, 0, 0]]]\n";
    let mut body = format!("frames = 1\n{SMALL}");
    for _ in 0..20_000 {
        body.push_str(track);
    }
    body.push_str(
        "[[track]]\ntarget = \"group:nowhere\"\nmotion = \"translate\"\nkeys = [[0, [0, 0, 0]]]\n",
    );
    let anim = write_anim(dir.path(), &body);
    let o = animate(&anim, &dir.path().join("out"), &[]);
    assert_eq!(o.status.code(), Some(2));
    // scene, camera, frames, 4 lines of SMALL, 4 per track: the bad target's line.
    let line = 2 + 1 + 4 + 20_000 * 4 + 2;
    assert!(
        stderr(&o).contains(&format!("anim.toml:{line}: unknown target")),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_rerun_of_a_finished_video_does_no_work() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 3);
    let gif = dir.path().join("t.gif");
    let o = animate(&anim, &gif, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let made = fs::metadata(&gif).unwrap().modified().unwrap();
    let o = run(prism().arg("animate").arg(&anim).arg(&gif).arg("--stats"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("nothing to do"), "{}", stderr(&o));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("rendered"));
    assert_eq!(fs::metadata(&gif).unwrap().modified().unwrap(), made);
    // Another animation into the same file is made again.
    let other = small_turntable(dir.path(), 4);
    let o = animate(&other, &gif, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let frames = gif::DecodeOptions::new()
        .read_info(fs::File::open(&gif).unwrap())
        .unwrap()
        .into_iter()
        .count();
    assert_eq!(frames, 4);
}

/// A glTF scene animates with its own camera, its node names as groups: frame 0 is
/// the still render of the file, the gold sphere moves in frame 1.
#[test]
fn a_gltf_scene_animates_its_nodes_with_its_own_camera() {
    let dir = tempfile::tempdir().unwrap();
    let glb = repo().join("scenes/blender/blender-export.glb");
    let anim = dir.path().join("anim.toml");
    fs::write(
        &anim,
        format!(
            "scene = {:?}\nframes = 2\nfps = 24\n[render]\nwidth = 48\nheight = 30\n\
             [[track]]\ntarget = \"group:Gold\"\nmotion = \"translate\"\n\
             keys = [[0, [0, 0, 0]], [0.0416666, [0, 0.5, 0]]]\n",
            glb.to_string_lossy()
        ),
    )
    .unwrap();
    let frames = dir.path().join("f");
    let o = animate(&anim, &frames, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let still = dir.path().join("still.png");
    let o = run(prism()
        .arg("render")
        .arg(&glb)
        .arg(&still)
        .args(["--width", "48", "--height", "30", "--aa", "1", "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let still = load_rgb(&still);
    assert_eq!(load_rgb(&frames.join("frame_0000.png")), still);
    assert_ne!(load_rgb(&frames.join("frame_0001.png")), still);
    // A scene without a camera of its own still needs a 2014 one.
    let obj = dir.path().join("tri.obj");
    fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    fs::write(
        &anim,
        format!("scene = {:?}\nframes = 1\n", obj.to_string_lossy()),
    )
    .unwrap();
    let o = animate(&anim, &dir.path().join("g"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the scene has no camera of its own"),
        "{}",
        stderr(&o)
    );
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}

/// `--denoise` in a Prism without Open Image Denoise is refused before any frame is
/// rendered: exit 2, the reason and how to build it, no frame folder.
#[cfg(not(feature = "oidn"))]
#[test]
fn without_oidn_denoised_frames_are_refused_before_the_first() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 2);
    let out = dir.path().join("f");
    let o = animate(&anim, &out, &["--denoise"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.starts_with(
            "error: cannot denoise: this Prism was built without Intel Open Image Denoise"
        ) && e.contains("--features oidn"),
        "{e}"
    );
    assert!(!out.exists());
    // So is an animation file that asks for it.
    let text = fs::read_to_string(&anim).unwrap();
    fs::write(
        &anim,
        text.replace("[render]\n", "[render]\ndenoise = true\n"),
    )
    .unwrap();
    let o = animate(&anim, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!out.exists());
}

/// `--denoise` writes every frame denoised (other pixels than the plain run's, the same
/// size) into a folder of its own kind, which a denoised run resumes.
#[cfg(feature = "oidn")]
#[test]
fn denoised_frames_are_written_whole_and_resume() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small_turntable(dir.path(), 2);
    let (plain, denoised) = (dir.path().join("plain"), dir.path().join("denoised"));
    let o = animate(&anim, &plain, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = animate(&anim, &denoised, &["--denoise", "--frames", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = animate(&anim, &denoised, &["--denoise", "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("frames 1 rendered, 1 skipped"), "{stdout}");
    assert_eq!(names(&denoised), names(&plain));
    for name in names(&plain) {
        let (a, b) = (
            load_rgb(&plain.join(&name)),
            load_rgb(&denoised.join(&name)),
        );
        assert_eq!(a.dimensions(), b.dimensions());
        assert_ne!(a, b, "{name}");
    }
    // The plain folder is not resumed by a denoised run.
    let o = animate(&anim, &plain, &["--denoise"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}
