//! What a new user meets first: sizes that keep their aspect, thread counts refused
//! before threads start, the help, the line a finished render prints, and animations
//! developed as their file says.

mod common;
use common::*;
use std::fs;

#[test]
fn width_alone_keeps_the_aspect_of_the_scene_files_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let scene = repo().join("scenes/showcase/showcase.toml");
    let o = run(prism()
        .arg("render")
        .arg(&scene)
        .arg(&out)
        .args(["--width", "320", "--aa", "1", "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    // The file says 640 x 360: 320 wide keeps 16:9.
    assert_eq!(load_rgb(&out).dimensions(), (320, 180));
    let o = run(prism()
        .arg("render")
        .arg(&scene)
        .arg(&out)
        .args(["--height", "90", "--aa", "1", "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(load_rgb(&out).dimensions(), (160, 90));
}

#[test]
fn too_many_threads_are_refused_before_any_starts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.png");
    let start = std::time::Instant::now();
    let o = run(prism()
        .arg("render")
        .arg(repo().join("scenes/showcase/showcase.toml"))
        .arg(&out)
        .args(["--threads", "100000"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("thread count must be at most"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    assert!(start.elapsed().as_secs() < 10, "took {:?}", start.elapsed());
    let o = run(prism()
        .args(["bench"])
        .arg(example("example.objx"))
        .arg(example("example.cmr"))
        .args(["--threads", "100000"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn help_says_what_prism_is_and_a_render_says_what_it_wrote() {
    let o = run(prism().arg("--help"));
    let help = String::from_utf8(o.stdout).unwrap();
    assert!(help.starts_with("Prism: a ray tracer"), "{help}");
    for command in ["render", "animate", "info", "bench", "convert"] {
        assert!(help.contains(command), "{command} missing");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("e.png");
    let o = run(prism()
        .args([example("example.objx"), example("example.cmr"), out.clone()])
        .args(["--width", "48"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    let line = e.lines().find(|l| l.starts_with("wrote ")).expect(&e);
    assert!(
        line.contains("e.png (48x27, ") && line.contains(" s: ") && line.contains("Mrays/s"),
        "{line}"
    );
    let o = run(prism()
        .args([example("example.objx"), example("example.cmr"), out.clone()])
        .args(["--width", "48", "--quiet"]));
    assert!(
        o.status.success() && !stderr(&o).contains("wrote "),
        "{}",
        stderr(&o)
    );
}

#[test]
fn an_animation_is_developed_with_its_files_tone_map() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    // A white ball under a light bright enough that the tone map matters.
    fs::write(
        &scene,
        "[camera]\nfrom = [0, 0, 4]\nat = [0, 0, 0]\n[render]\nwidth = 32\nheight = 18\n\
         tonemap = \"reinhard\"\n[animation]\nframes = 1\n\
         [[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = { color = [1, 1, 1] }\n\
         [[light]]\ntype = \"point\"\nposition = [2, 2, 4]\nintensity = 6\n",
    )
    .unwrap();
    let frames = dir.path().join("f");
    let o = run(prism()
        .arg("animate")
        .arg(&scene)
        .arg(&frames)
        .arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let still = dir.path().join("still.png");
    let o = run(prism().arg("render").arg(&scene).arg(&still).arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let clamped = dir.path().join("clamped.png");
    let o = run(prism().arg("render").arg(&scene).arg(&clamped).args([
        "--tonemap",
        "clamp",
        "--quiet",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let frame = load_rgb(&frames.join("frame_0000.png"));
    assert_eq!(frame, load_rgb(&still));
    assert_ne!(frame, load_rgb(&clamped));
}
