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
             height = 180\ndof_rays = 16\n",
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
    assert_eq!(wait(child), Some(130));
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
