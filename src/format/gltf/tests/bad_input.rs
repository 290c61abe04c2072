//! Files that are wrong or too large: errors that name the JSON path, before anything large is read.

use super::*;

#[test]
fn bad_files_are_errors_naming_the_json_path() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let base = |f: &dyn Fn(&mut Value)| {
        let mut b = Builder::default();
        b.mesh(&tri, Some(&[0, 1, 2]), 4, None);
        let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
        f(&mut doc);
        doc
    };
    let cases: Vec<(Value, &str)> = vec![
        (
            base(&|d| {
                d["accessors"][1]["count"] = json!(4);
            }),
            "meshes[0].primitives[0].indices: 4 elements of 2 bytes from byte 0 need more than",
        ),
        (
            base(&|d| {
                d["bufferViews"][0]["byteLength"] = json!(400);
            }),
            "past the end of buffer 0",
        ),
        (
            base(&|d| {
                d["buffers"][0]["byteLength"] = json!(4000);
            }),
            "buffers[0]: byteLength is 4000 but the data holds",
        ),
        (
            base(&|d| {
                d["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
            }),
            "scenes[0] lists nodes[0] as a root, but it is a child of nodes[1]",
        ),
        (
            base(&|d| {
                d["nodes"] = json!([{"mesh": 0, "children": [2]}, {"children": [2]}, {}]);
                d["scenes"] = json!([{"nodes": [0, 1]}]);
            }),
            "nodes[2] has two parents",
        ),
        (
            base(&|d| {
                d["buffers"][0]["uri"] = json!("http://example.com/b.bin");
            }),
            "buffers[0]: the URI `http://example.com/b.bin` is not a file",
        ),
        (
            base(&|d| {
                d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(9);
            }),
            "meshes[0].primitives[0].attributes",
        ),
    ];
    for (doc, expected) in cases {
        let (_dir, path) = write(&doc);
        let e = crate::format::load(&path).expect_err(expected).to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(e.contains(expected), "{e}\nexpected: {expected}");
    }
    // An index past the vertices, and a NaN position.
    let mut b = Builder::default();
    b.mesh(&tri, Some(&[0, 1, 7]), 4, None);
    let doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).err().unwrap().to_string();
    assert!(
        e.contains("meshes[0].primitives[0].indices: index 7 is past the primitive's 3 vertices"),
        "{e}"
    );
    let mut b = Builder::default();
    b.mesh(
        &[0.0, f32::NAN, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        None,
        4,
        None,
    );
    let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    doc["accessors"][0].as_object_mut().unwrap().remove("min");
    doc["accessors"][0].as_object_mut().unwrap().remove("max");
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).err().unwrap().to_string();
    assert!(
        e.contains("attributes.POSITION: vertex 0 is not finite"),
        "{e}"
    );
}

#[test]
fn an_unknown_extension_is_an_error_listing_the_formats_and_dialect() {
    let e = crate::format::load(Path::new("/nonexistent/model.fbx"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("cannot tell the scene format from the extension `.fbx`"),
        "{e}"
    );
    assert!(
        e.contains(".gltf, .glb") && e.contains("--dialect obj|gltf|ply|toml|objx"),
        "{e}"
    );
}

#[test]
fn a_large_accessor_named_by_many_primitives_is_refused_before_it_is_read_again() {
    // A sparse POSITION accessor of 2^24 vertices with no bytes behind it (200 MB once
    // decoded), named by 30 primitives: past the decoding budget at the 22nd, whose
    // counts are checked before it is read.
    let mut b = Builder::default();
    b.mesh(&[0.0; 9], Some(&[0, 1, 2]), 4, None);
    let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    doc["accessors"][0] = json!({"componentType": 5126, "count": 1 << 24, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                   "values": {"bufferView": 0}}});
    let prim = doc["meshes"][0]["primitives"][0].clone();
    doc["meshes"][0]["primitives"] = json!(vec![prim; 30]);
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("would decode to more than 4294967296 bytes"),
        "{e}"
    );
}
