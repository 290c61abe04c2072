//! The Wavefront OBJ reader on arbitrary text; a mesh it accepts names only its own
//! vertices.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(mesh) = prism::format::obj::parse_mesh(text, Path::new("mesh.obj")) {
        let n = mesh.vertices.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
    }
});
