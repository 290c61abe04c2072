//! Reading the files a scene names, safely: only regular files, never more than they
//! said they held when opened, and never more than a bound.
//!
//! Reading at most the size the file reports is what keeps `/proc` and `/sys` entries
//! (regular files of size 0 whose reads block or never end, like `/proc/kmsg`) and files
//! that grow while read from hanging Prism or filling its memory: such a file reads as
//! what its size says, usually empty.

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};

/// The folder every read is confined to, once [`restrict_reads_to`] has been called.
static READ_ROOT: OnceLock<PathBuf> = OnceLock::new();

/// Confines every later read of this process (scenes, meshes, materials, textures,
/// includes, animations) to the folder `dir`: a path that leads outside it, after `..`
/// and symbolic links are resolved, is refused. For render services that take scene
/// files from strangers. It cannot be lifted or moved once set.
pub fn restrict_reads_to(dir: &Path) -> Result<(), String> {
    let root = std::fs::canonicalize(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if !root.is_dir() {
        return Err(format!("{}: not a folder", dir.display()));
    }
    let set = READ_ROOT.get_or_init(|| root.clone());
    if *set != root {
        return Err(format!(
            "reads are already restricted to {}, not {}",
            set.display(),
            root.display()
        ));
    }
    Ok(())
}

/// The folder reads are restricted to, if they are.
pub fn read_root() -> Option<&'static Path> {
    READ_ROOT.get().map(PathBuf::as_path)
}

/// The path to open for `path`: itself, or under a restriction its resolved form, which
/// must lie inside the root (opening the resolved form means a link changed after the
/// check cannot point elsewhere).
fn allowed(path: &Path) -> Result<std::borrow::Cow<'_, Path>, String> {
    let Some(root) = read_root() else {
        return Ok(path.into());
    };
    let real = std::fs::canonicalize(path).map_err(|e| e.to_string())?;
    if real.starts_with(root) {
        Ok(real.into())
    } else {
        Err(format!(
            "outside {}, the folder reads are restricted to (--restrict-paths)",
            root.display()
        ))
    }
}

/// Whether [`recording_reads`] is running: the paths opened are then noted.
static RECORDING: AtomicBool = AtomicBool::new(false);
/// The paths noted while recording.
static READS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// One recording at a time.
static RECORDER: Mutex<()> = Mutex::new(());

/// Runs `f` and returns, with its result, every path it asked to open through this
/// module, from any thread, whether or not the file could be read (a scene's includes,
/// meshes, material libraries, textures): what a preview watches for saves. One
/// recording runs at a time; reads of other work meanwhile are noted too.
pub fn recording_reads<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let _one = RECORDER.lock().unwrap_or_else(|e| e.into_inner());
    READS.lock().unwrap_or_else(|e| e.into_inner()).clear();
    RECORDING.store(true, Ordering::SeqCst);
    let out = f();
    RECORDING.store(false, Ordering::SeqCst);
    let mut reads = std::mem::take(&mut *READS.lock().unwrap_or_else(|e| e.into_inner()));
    reads.sort();
    reads.dedup();
    (out, reads)
}

/// Opens the regular file `path` for reading, refusing directories, FIFOs, sockets and
/// devices before opening them, and paths outside a restriction.
pub fn open_regular(path: &Path) -> Result<std::fs::File, String> {
    if RECORDING.load(Ordering::Relaxed) {
        READS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(path.to_path_buf());
    }
    let path = allowed(path)?;
    // Before opening: opening a FIFO for reading blocks until someone writes to it.
    let named = std::fs::metadata(&path).map_err(|e| e.to_string())?;
    if !named.is_file() {
        return Err("not a regular file".into());
    }
    let file = std::fs::File::open(&path).map_err(|e| e.to_string())?;
    // Again on what was opened, in case the path changed in between.
    if !file.metadata().map_err(|e| e.to_string())?.is_file() {
        return Err("not a regular file".into());
    }
    Ok(file)
}

/// The bytes of the regular file `path`, at most `max` of them. The error says why,
/// without the path (callers name the file and where it was named).
pub fn read_regular(path: &Path, max: u64) -> Result<Vec<u8>, String> {
    let file = open_regular(path)?;
    let size = file.metadata().map_err(|e| e.to_string())?.len();
    if size > max {
        return Err(format!(
            "the file has {size} bytes, more than the {max} Prism reads"
        ));
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(size)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_read_whole_and_others_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        std::fs::write(&p, b"hello").unwrap();
        assert_eq!(read_regular(&p, 5).unwrap(), b"hello");
        assert!(read_regular(&p, 4).unwrap_err().contains("5 bytes"));
        assert_eq!(
            read_regular(dir.path(), 100).unwrap_err(),
            "not a regular file"
        );
        assert!(read_regular(&dir.path().join("none"), 100).is_err());
    }

    #[test]
    fn a_recording_notes_every_path_asked_for_once() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
        std::fs::write(&a, b"a").unwrap();
        let ((), reads) = recording_reads(|| {
            let _ = read_regular(&a, 10);
            let _ = read_regular(&a, 10);
            let _ = read_regular(&b, 10); // missing: noted all the same
        });
        // Other tests read files meanwhile, and are noted too: look for these two.
        assert_eq!(reads.iter().filter(|p| **p == a).count(), 1);
        assert!(reads.contains(&b));
        let _ = read_regular(&a, 10);
        assert!(!recording_reads(|| ()).1.contains(&a));
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn proc_entries_read_as_their_stated_size_without_blocking() {
        // Size 0 by its metadata, though reading it would give the environment.
        let environ = Path::new("/proc/self/environ");
        if environ.is_file() {
            assert_eq!(read_regular(environ, 1 << 20).unwrap(), b"");
        }
        // /dev/zero never ends: it is not a regular file.
        assert!(read_regular(Path::new("/dev/zero"), 1 << 20).is_err());
    }
}
