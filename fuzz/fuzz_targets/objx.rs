//! The 2014 scene reader on arbitrary text. Every `mtllib` is served the same material
//! file from memory, so `usemtl` finds names and nothing is read from disk.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

const LIBRARY: &str = "newmtl red 200 40 30 10 1 15 8.5 1 0.2 0 0\n\
                       newmtl glass 230 240 255 0.1 0.1 20 20 1.5 0.2 1 1\n\
                       newmtl light 255 255 255 0 0 0 0 0 0 0 0\n";

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("/nonexistent/prism-fuzz/scene.objx");
    let _ = prism::format::objx::parse(text, path, |_| Ok(LIBRARY.to_owned()));
});
