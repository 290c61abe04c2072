//! The PLY reader on arbitrary bytes; a mesh it accepts is finite, names only its own
//! vertices, and has one of each present attribute per vertex.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = prism::format::ply::parse(data, Path::new("mesh.ply")) {
        let n = mesh.positions.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        assert!(mesh.positions.iter().all(|p| p.is_finite()));
        for len in [mesh.normals.len(), mesh.colors.len(), mesh.texcoords.len()] {
            assert!(len == 0 || len == n);
        }
    }
});
