//! The animation file reader on arbitrary text. The scene and camera it names are read
//! from disk, so the harness lays out the turntable example in a folder of its own and
//! passes over inputs that name other folders.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

static FOLDER: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();

fn lay_out() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let turntable = dir.path().join("turntable");
    std::fs::create_dir_all(dir.path().join("example")).unwrap();
    std::fs::create_dir_all(&turntable).unwrap();
    let files: [(&str, &[u8]); 4] = [
        (
            "example/checker.ppm",
            include_bytes!("../../scenes/example/checker.ppm"),
        ),
        (
            "turntable/turntable.objx",
            include_bytes!("../../scenes/turntable/turntable.objx"),
        ),
        (
            "turntable/turntable.mtlx",
            include_bytes!("../../scenes/turntable/turntable.mtlx"),
        ),
        (
            "turntable/turntable.cmr",
            include_bytes!("../../scenes/turntable/turntable.cmr"),
        ),
    ];
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    (dir, turntable.join("animation.toml"))
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if text.contains(['/', '\\']) {
        return;
    }
    let (_, path) = FOLDER.get_or_init(lay_out);
    let _ = prism::anim::file::parse(text, path);
});
