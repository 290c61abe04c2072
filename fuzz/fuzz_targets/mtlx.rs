//! The 2014 material reader on arbitrary text, in a folder of its own that holds one
//! texture (`checker.ppm`). Inputs naming other folders are passed over, so textures
//! are only ever looked up inside that folder.
#![no_main]
use libfuzzer_sys::fuzz_target;
use prism::format::mtlx;
use std::sync::OnceLock;

static FOLDER: OnceLock<tempfile::TempDir> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if text.contains(['/', '\\']) {
        return;
    }
    let folder = FOLDER.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let checker = include_bytes!("../../scenes/example/checker.ppm");
        std::fs::write(dir.path().join("checker.ppm"), checker).unwrap();
        dir
    });
    let path = folder.path().join("materials.mtlx");
    let _ = mtlx::parse(text, &path, &mut mtlx::MaterialLibrary::new());
});
