//! The 2014 camera reader on arbitrary text.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = prism::format::cmr::parse(text, Path::new("camera.cmr"));
    }
});
