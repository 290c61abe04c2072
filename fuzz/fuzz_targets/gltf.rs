//! The glTF reader on arbitrary bytes (JSON or GLB, buffers in `data:` URIs): a scene it
//! builds holds finite triangles, a material for every shape and attributes that name
//! only their own vertices.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    // A folder that does not exist: external URIs are errors, never reads.
    let path = Path::new("/nonexistent/prism-fuzz/scene.gltf");
    let Ok(loaded) = prism::format::gltf::document::parse(data, path) else {
        return;
    };
    if let Ok(file) = prism::format::gltf::build(&loaded, path) {
        let scene = &file.scene;
        assert_eq!(scene.material_of.len(), scene.shapes.len());
        assert_eq!(scene.surfaces.len(), scene.materials.len());
        assert!(
            scene
                .material_of
                .iter()
                .all(|&m| (m as usize) < scene.materials.len())
        );
        assert!(scene.shapes.positions().iter().all(|p| p.is_finite()));
        for mesh in &scene.meshes {
            assert!(mesh.check().is_ok());
        }
        assert!(file.camera.is_none() == file.cameras.is_empty());
    }
});
