//! The full Wavefront OBJ reader (normals, texture coordinates, groups, materials) on
//! arbitrary bytes, with the libraries it names read from memory; then the scene built
//! from it. Every index it returns names an existing attribute.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

const LIBRARY: &[u8] = b"newmtl a\nKd 1 0 0\nKe 1 1 1\nnewmtl b\nillum 7\nNi 1.5\nd 0.5\n";

fuzz_target!(|data: &[u8]| {
    let path = Path::new("mesh.obj");
    let mut read = |_: &Path| Ok(LIBRARY.to_vec());
    let Ok(obj) = prism::format::obj::parse_obj_with(data, path, &mut read) else {
        return;
    };
    let (p, t, n) = (obj.positions.len(), obj.texcoords.len(), obj.normals.len());
    for tri in &obj.triangles {
        assert!(tri.v.iter().all(|&i| (i as usize) < p));
        assert!(tri.vt.iter().flatten().all(|&i| (i as usize) < t));
        assert!(tri.vn.iter().flatten().all(|&i| (i as usize) < n));
    }
    if let Ok(file) = prism::format::wavefront::from_obj(obj, path) {
        for mesh in &file.scene.meshes {
            assert!(mesh.check().is_ok());
        }
    }
});
