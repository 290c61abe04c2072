//! Ctrl-C and SIGTERM during `prism render` and `prism animate`: the work stops, no
//! partial or temporary file is left, the exit code is 128 + the signal, and a rerun of
//! the animation resumes.
#![cfg(unix)]

mod common;
use common::*;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn send(child: &Child, signal: &str) {
    let ok = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "kill -{signal} failed");
}

/// Waits for `child`, killing it after a minute so a broken handler cannot hang CI.
fn wait(mut child: Child) -> Option<i32> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.code();
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("prism did not stop after the signal");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn leftovers(dir: &Path) -> Vec<String> {
    let mut names = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            if e.file_type().unwrap().is_dir() {
                stack.push(e.path());
            } else if name.ends_with(".part") {
                names.push(name);
            }
        }
    }
    names
}

#[test]
fn a_signal_during_a_render_stops_it_with_no_output() {
    for (signal, code) in [("INT", 130), ("TERM", 143)] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("big.png");
        // Far longer than the test waits: 1600x900 with 64 lens rays per pixel.
        let child = prism()
            .arg("render")
            .args([example("example.objx"), example("example.cmr"), out.clone()])
            .args(["--width", "1600", "--dof-rays", "64", "--quiet"])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(500));
        send(&child, signal);
        assert_eq!(wait(child), Some(code), "SIG{signal}");
        assert!(!out.exists(), "SIG{signal} left an output");
        assert!(
            leftovers(dir.path()).is_empty(),
            "{:?}",
            leftovers(dir.path())
        );
    }
}

#[test]
fn a_signal_during_an_animation_keeps_whole_frames_and_a_rerun_finishes() {
    let dir = tempfile::tempdir().unwrap();
    let anim = dir.path().join("anim.toml");
    let turntable = repo().join("scenes/turntable");
    std::fs::write(
        &anim,
        format!(
            "scene = {:?}\ncamera = {:?}\nframes = 40\nfps = 24\n[render]\nwidth = 320\n\
             height = 180\nspp = 16\n",
            turntable.join("turntable.objx"),
            turntable.join("turntable.cmr"),
        ),
    )
    .unwrap();
    let out = dir.path().join("film.gif");
    let child = prism()
        .arg("animate")
        .arg(&anim)
        .arg(&out)
        .arg("--quiet")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    send(&child, "INT");
    let mut child = child;
    let mut said = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut said).unwrap();
    assert_eq!(wait(child), Some(130));
    assert!(said.contains("finished frames are kept in"), "{said}");
    assert!(!said.contains("nothing was written"), "{said}");
    assert!(!out.exists(), "no video from an interrupted run");
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
    // Every frame written is whole.
    let frames = dir.path().join("film.gif.frames");
    if frames.is_dir() {
        for e in std::fs::read_dir(&frames).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "png") {
                image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            }
        }
    }
    // The rerun completes the film.
    let o = run(prism().arg("animate").arg(&anim).arg(&out).arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_file());
}

/// Resident memory of a running process, from /proc (Linux only; `None` elsewhere).
fn resident_kib(child: &Child) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{}/status", child.id())).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[test]
fn a_million_frame_gif_renders_in_bounded_memory_and_stops_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["example.objx", "example.mtlx", "example.cmr", "checker.ppm"] {
        std::fs::copy(example(f), dir.path().join(f)).unwrap();
    }
    let anim = dir.path().join("long.toml");
    std::fs::write(
        &anim,
        "scene = \"example.objx\"\ncamera = \"example.cmr\"\nframes = 1000000\nfps = 24\n\
         [render]\nwidth = 8\nheight = 8\naa = 1\nspp = 1\n",
    )
    .unwrap();
    let out = dir.path().join("long.gif");
    let child = prism()
        .args(["animate", "--quiet"])
        .args([&anim, &out])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    // Hundreds of frames are done by now; memory must not grow with the film's length.
    if let Some(kib) = resident_kib(&child) {
        assert!(kib < 256 * 1024, "{kib} KiB resident");
    }
    send(&child, "INT");
    assert_eq!(wait(child), Some(130));
    assert!(!out.exists());
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

/// A FIFO, `/dev/zero` or a folder named as a scene, a material library or a texture:
/// refused by type at once (exit 2), never opened and waited on.
#[test]
fn fifos_devices_and_folders_in_a_scene_are_refused_without_waiting() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        skipped("mkfifo is not available");
        return;
    }
    let scene = std::fs::read_to_string(example("example.objx")).unwrap();
    let materials = std::fs::read_to_string(example("example.mtlx")).unwrap();
    for f in ["example.cmr", "checker.ppm"] {
        std::fs::copy(example(f), dir.path().join(f)).unwrap();
    }
    for bad in ["pipe", "/dev/zero", "."] {
        for what in ["scene", "material library", "texture"] {
            // The scene names its library, the library its texture: one of the three is
            // the bad file.
            let library = if what == "material library" {
                bad
            } else {
                "lib.mtlx"
            };
            let texture = if what == "texture" {
                bad
            } else {
                "checker.ppm"
            };
            std::fs::write(
                dir.path().join("lib.mtlx"),
                materials.replace("checker.ppm", texture),
            )
            .unwrap();
            std::fs::write(
                dir.path().join("ok.objx"),
                scene.replace("example.mtlx", library),
            )
            .unwrap();
            let scene_path = dir
                .path()
                .join(if what == "scene" { bad } else { "ok.objx" });
            refused_at_once(&scene_path, &dir.path().join("example.cmr"), what, bad);
        }
    }
}

/// Renders `scene_path` expecting a refusal (exit 2, no output) within seconds.
fn refused_at_once(scene_path: &Path, camera: &Path, what: &str, bad: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let child = prism()
        .args(["render", "--quiet"])
        .arg(scene_path)
        .args([camera, &out])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    assert_eq!(wait(child), Some(2), "{what} {bad}");
    assert!(start.elapsed() < Duration::from_secs(10), "{what} {bad}");
    assert!(!out.exists());
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
