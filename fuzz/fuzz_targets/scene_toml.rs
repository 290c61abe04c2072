//! The Prism scene file on arbitrary text. Inputs naming paths are skipped so the
//! fuzzer never reads files of the machine; everything else must load or fail cleanly.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if text.contains('/') || text.contains('\\') || text.contains("..") {
        return;
    }
    let _ = prism::format::scene_file::parse(text, Path::new("/nonexistent-prism/scene.toml"));
});
