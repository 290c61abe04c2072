//! The OBJ/MTL reader against the peer suites' model files (tinyobjloader, tobj, assimp)
//! and the real models in ../shared/models, asserting what
//! ../shared/models/EXPECTATIONS.md says file by file. Skipped, with a message, when
//! ../shared is not beside the repository.
//!
//! Corpus (every OBJ file in the folders below is in a table; a new file fails the
//! coverage check until it gets an entry):
//!
//! | corpus | files | load as expected | fail as expected | skipped |
//! |---|---|---|---|---|
//! | tinyobjloader models/, tests/, fuzzer/ | 49 | 44 | 5: index 0 (issue-140), relative indices out of range (2), `nan` (test-nan, C4), a coordinate glued to a NUL byte (clusterfuzz) | 0 |
//! | tobj obj/ | 8 | 7 | 1: `f 4 5 7` with 6 vertices (FaceVertexOutOfBounds) | 0 |
//! | assimp test/models/OBJ + invalid/ | 27 | 25 | 2: `3.1+e2` in number_formats.obj (strtod would stop early; Prism refuses trailing junk), index 0 in malformed.obj | 0 |
//! | cornell-box, spot | 2 named | 2 | 0 | 0 |
//!
//! Where Prism differs from tinyobjloader on purpose: issue-244's MTL lives on a search
//! path Prism does not have (a warning, no materials); `map_bump -imfchan r
//! bumpmap2.jpg -bm 1.5` keeps `bumpmap2.jpg -bm 1.5` as the name, with a warning (C2);
//! issue-319-002 gives the fan count 14, not earcut's 8 (C3 allows it); `map_Ns`,
//! `disp` and the PBR keys are counted as skipped rather than stored.

mod assimp;
mod real_models;
mod tinyobjloader;
mod tobj;

use std::path::{Path, PathBuf};

use prism::format::obj::{ObjFile, load_obj};
use prism::math::Vec3;

fn models() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    if root.join("EXPECTATIONS.md").exists() {
        Some(root)
    } else {
        println!(
            "skipped: {} is absent (../shared is not beside the repo)",
            root.display()
        );
        None
    }
}

/// What a file must give.
enum Expect {
    Loads(fn(&ObjFile)),
    /// The error's text after the file's path: `:line:col: message...`.
    Fails(&'static str),
}
use Expect::{Fails, Loads};

fn check(root: &Path, folder: &str, table: &[(&str, Expect)], extension: Option<&str>) {
    let dir = root.join(folder);
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| extension.is_none_or(|ext| name.ends_with(ext)))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = table.iter().map(|(name, _)| name.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed, "every file of {folder} has an entry");
    for (name, expect) in table {
        let path = dir.join(name);
        let result = load_obj(&path);
        match (expect, result) {
            (Loads(check), Ok(obj)) => {
                let check = std::panic::AssertUnwindSafe(|| check(&obj));
                if let Err(e) = std::panic::catch_unwind(check) {
                    panic!("{folder}/{name}: {e:?}\nwarnings: {:#?}", obj.warnings);
                }
            }
            (Loads(_), Err(e)) => panic!("{folder}/{name} should load: {e}"),
            (Fails(expected), Ok(_)) => panic!("{folder}/{name} should fail with {expected}"),
            (Fails(expected), Err(e)) => {
                let message = e.to_string();
                let tail = message
                    .strip_prefix(&path.display().to_string())
                    .unwrap_or(&message);
                assert!(tail.starts_with(expected), "{folder}/{name}: {message}");
            }
        }
    }
}

fn v3(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1.2e-5
}

fn names(obj: &ObjFile) -> Vec<&str> {
    obj.groups.iter().map(|g| g.name.as_str()).collect()
}

fn material_names(obj: &ObjFile) -> Vec<&str> {
    obj.materials.iter().map(|m| m.name.as_str()).collect()
}

/// The material of the first triangle of each group.
fn group_materials(obj: &ObjFile) -> Vec<Option<u32>> {
    obj.groups
        .iter()
        .map(|g| obj.triangles[g.triangles.start].material)
        .collect()
}

fn warnings_with(obj: &ObjFile, text: &str) -> usize {
    obj.warnings
        .iter()
        .filter(|w| w.message.contains(text))
        .count()
}

fn smoothing(obj: &ObjFile, group: usize) -> Vec<u32> {
    obj.triangles[obj.groups[group].triangles.clone()]
        .iter()
        .map(|t| t.smoothing)
        .collect()
}

fn cube_like(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (8, 12));
    assert_eq!(o.materials.len(), 5);
}

fn cornell_like(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (76, 36));
    assert_eq!(
        names(o),
        [
            "floor",
            "light",
            "ceiling",
            "back_wall",
            "green_wall",
            "red_wall",
            "short_block",
            "tall_block"
        ]
    );
}

fn single_test_triangle(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (3, 1));
    assert_eq!(names(o), ["Test"]);
    assert_eq!(material_names(o), ["default"]);
}
