//! glTF through the `prism` command: `info` of the bundled Blender export, camera
//! choice, and bad input refused with exit 2 and no output.

mod common;
use common::*;
use std::fs;

fn blender() -> std::path::PathBuf {
    repo().join("scenes/blender/blender-export.glb")
}

#[test]
fn info_of_the_blender_export_lists_its_camera_lights_and_objects() {
    let o = run(prism().args(["info", "--json"]).arg(blender()));
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["dialect"], "gltf");
    assert_eq!(json["triangles"], 1934);
    assert_eq!(
        json["light_kinds"],
        serde_json::json!(["point", "directional"])
    );
    assert_eq!(
        json["object_names"],
        serde_json::json!(["Floor", "Glass", "Gold", "Box"])
    );
    let cameras = json["cameras"].as_array().unwrap();
    assert_eq!(cameras.len(), 1);
    assert_eq!(cameras[0]["name"], "Camera");
    assert_eq!(cameras[0]["projection"], "perspective");
    let at = cameras[0]["position"].as_array().unwrap();
    assert!(
        (at[1].as_f64().unwrap() - 3.2).abs() < 1e-6
            && (at[2].as_f64().unwrap() - 6.5).abs() < 1e-6
    );
    // Blender's floor, 8 m square at y = 0, and the spheres above it.
    let b = &json["bounds"];
    assert_eq!(b[0][0], -4.0);
    assert_eq!(b[1][2], 4.0);
}

#[test]
fn the_camera_aspect_ratio_sizes_the_output_and_bad_choices_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.png");
    let o = run(prism().arg("render").arg(blender()).arg(&out).args([
        "--width",
        "80",
        "--camera-name",
        "Camera",
        "--quiet",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let img = load_rgb(&out);
    // aspectRatio 1.6: 80 x 50.
    assert_eq!(img.dimensions(), (80, 50));
    let missing = dir.path().join("m.png");
    let o = run(prism()
        .arg("render")
        .arg(blender())
        .arg(&missing)
        .args(["--camera-index", "4"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("no camera has index 4: the scene's cameras are 0: `Camera`"),
        "{}",
        stderr(&o)
    );
    assert!(!missing.exists());
}

#[test]
fn unknown_extensions_and_broken_files_exit_2_with_their_reason() {
    let dir = tempfile::tempdir().unwrap();
    let fbx = dir.path().join("model.fbx");
    fs::write(&fbx, "Kaydara FBX Binary").unwrap();
    let out = dir.path().join("o.png");
    let o = run(prism().arg("render").arg(&fbx).arg(&out));
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("cannot tell the scene format from the extension `.fbx`"),
        "{e}"
    );
    assert!(e.contains("--dialect"), "{e}");
    assert!(!out.exists());
    // A GLB cut short, read as glTF by --dialect whatever its name.
    let bytes = fs::read(blender()).unwrap();
    let cut = dir.path().join("cut.bin");
    fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = run(prism()
        .arg("render")
        .arg(&cut)
        .arg(&out)
        .args(["--dialect", "gltf"]));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the GLB header states"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    // The whole file, by --dialect: it renders.
    let whole = dir.path().join("scene.bin");
    fs::write(&whole, &bytes).unwrap();
    let o = run(prism().arg("render").arg(&whole).arg(&out).args([
        "--dialect",
        "gltf",
        "--width",
        "32",
        "--quiet",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
}
