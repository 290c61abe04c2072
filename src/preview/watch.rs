//! Noticing a saved file: every file the scene read (its includes, meshes, material
//! libraries, textures, wherever they are) and the scene file's folder are looked at a
//! few times a second, and a change in any file's size or time of change reads the
//! scene again. Polling needs no watcher
//! service and sees files on every file system alike; the look is bounded in files and
//! depth, so a scene beside a huge tree costs no more than a glance.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Files looked at, at most (the first found, in name order).
const MAX_FILES: usize = 4096;
/// Folder levels below the scene's folder looked into.
const MAX_DEPTH: usize = 3;

/// What the watched files were like: each file's path, size and time of change.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Snapshot(Vec<(PathBuf, u64, Option<SystemTime>)>);

impl Snapshot {
    /// The files under `dir` now (hidden ones and build folders left out), and the
    /// files `reads` names wherever they are (a mesh beside the repository; a file
    /// missing now is noted as missing, so its return is a change).
    pub fn of(dir: &Path, reads: &[PathBuf]) -> Snapshot {
        let mut files = Vec::new();
        visit(dir, 0, &mut files);
        for path in reads.iter().take(MAX_FILES) {
            let meta = std::fs::metadata(path).ok();
            files.push((
                path.clone(),
                meta.as_ref().map_or(u64::MAX, |m| m.len()),
                meta.and_then(|m| m.modified().ok()),
            ));
        }
        Snapshot(files)
    }
}

fn visit(dir: &Path, depth: usize, out: &mut Vec<(PathBuf, u64, Option<SystemTime>)>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.flatten().collect();
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        if out.len() >= MAX_FILES {
            return;
        }
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') || name == "target" || name == "node_modules" {
            continue;
        }
        let Ok(meta) = entry.metadata() else {
            continue;
        };
        if meta.is_dir() {
            if depth < MAX_DEPTH {
                visit(&entry.path(), depth + 1, out);
            }
        } else if meta.is_file() {
            out.push((entry.path(), meta.len(), meta.modified().ok()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_file_changes_the_snapshot_and_a_hidden_one_does_not() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("scene.toml"), "a").unwrap();
        std::fs::create_dir(dir.path().join("meshes")).unwrap();
        std::fs::write(dir.path().join("meshes/m.obj"), "v 0 0 0").unwrap();
        let before = Snapshot::of(dir.path(), &[]);
        assert_eq!(before.0.len(), 2);
        std::fs::write(dir.path().join(".scene.toml.swp"), "x").unwrap();
        assert_eq!(Snapshot::of(dir.path(), &[]), before);
        std::fs::write(dir.path().join("meshes/m.obj"), "v 0 0 1\n").unwrap();
        assert_ne!(Snapshot::of(dir.path(), &[]), before);
    }
}
