//! Each object type, transform, material term, light and setting with exact values;
//! includes; every class of error with its `file:line:column`; the showcase rendered.

use super::*;
use crate::math::Vec3;
use std::path::PathBuf;

mod camera;
mod errors;
mod includes;
mod lights;
mod materials;
mod objects;
mod openpbr;
mod scenes;

/// A scene file in a fresh folder, so relative paths have somewhere to point.
struct Folder {
    dir: tempfile::TempDir,
}

impl Folder {
    fn new() -> Folder {
        Folder {
            dir: tempfile::tempdir().unwrap(),
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }

    fn load(&self, text: &str) -> SceneFile {
        let p = self.write("scene.toml", text);
        load(&p).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The error text with the folder replaced by `DIR`.
    fn error(&self, text: &str) -> String {
        let p = self.write("scene.toml", text);
        let e = load(&p).expect_err("expected an error").to_string();
        e.replace(&self.dir.path().display().to_string(), "DIR")
    }
}

fn scene(text: &str) -> SceneFile {
    Folder::new().load(text)
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!(close(a, b), "{a} != {b}");
}
