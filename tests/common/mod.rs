//! Helpers shared by the end-to-end tests.
#![allow(dead_code)]

pub mod python_env;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn example(file: &str) -> PathBuf {
    repo().join("scenes/example").join(file)
}

/// The 2014 seed scenes, present beside the repository in CI and on developer machines;
/// `None` (after saying why) in a plain clone.
pub fn seed_scene(name: &str) -> Option<PathBuf> {
    let dir = repo().join("../shared/seed-scenes/Ray-Tracing").join(name);
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipped: {} is absent (it sits beside the repository in CI)",
            dir.display()
        );
        None
    }
}

pub fn run(cmd: &mut Command) -> Output {
    cmd.output().expect("prism runs")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn load_rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}
