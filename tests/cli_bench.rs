//! `prism bench` and `prism convert` end to end.

mod common;
use common::*;
use std::fs;

#[test]
fn bench_json_has_every_figure() {
    for accel in ["bvh", "bvh-copied", "octree", "list"] {
        let o = run(prism()
            .args(["bench", "--json", "--seconds", "0", "--threads", "2"])
            .args([example("example.objx"), example("example.cmr")])
            .args(["--accel", accel]));
        assert!(o.status.success(), "{}", stderr(&o));
        let json = String::from_utf8(o.stdout).unwrap();
        assert_eq!(json.lines().count(), 1, "{json}");
        for key in [
            "build_s",
            "primitives",
            "bytes",
            "primary_mrays",
            "shadow_mrays",
            "frame_s",
            "hit_fraction",
        ] {
            assert!(json.contains(&format!("\"{key}\":")), "{key} in {json}");
        }
        assert!(json.contains(&format!("\"accel\":\"{accel}\"")), "{json}");
        // The example has 3 rectangles, 2 spheres and a triangle.
        assert!(json.contains("\"primitives\":6,"), "{json}");
        assert!(json.contains("\"threads\":2,"), "{json}");
    }
}

#[test]
fn bench_table_and_bad_arguments() {
    let o = run(prism()
        .args(["bench", "--seconds", "0", "--no-frame"])
        .args([example("example.objx"), example("example.cmr")]));
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8(o.stdout).unwrap();
    assert!(table.contains("Mrays/s") && table.contains("bytes per primitive"));
    assert!(!table.contains("classic frame"));

    let o = run(prism()
        .args(["bench", "--accel", "kd"])
        .args([example("example.objx"), example("example.cmr")]));
    assert_eq!(o.status.code(), Some(2));
    let o = run(prism()
        .args(["bench", "--seconds=-1"])
        .args([example("example.objx"), example("example.cmr")]));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--seconds"), "{}", stderr(&o));
}

#[test]
fn bench_dump_writes_the_rays_for_another_ray_tracer() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("quad.obj");
    // A quad facing the example camera and, behind it, a triangle it hides in part.
    fs::write(
        &obj,
        "v 0 -60 20\nv 0 60 20\nv 0 60 140\nv 0 -60 140\nf 1 2 3 4\n\
         v 100 -150 0\nv 100 150 0\nv 100 0 200\nf 5 6 7\n",
    )
    .unwrap();
    let dump = dir.path().join("dump");
    let o = run(prism()
        .args([
            "bench",
            "--json",
            "--width",
            "40",
            "--threads",
            "2",
            "--dump",
        ])
        .args([&dump, &obj, &example("example.cmr")]));
    assert!(o.status.success(), "{}", stderr(&o));
    let json = String::from_utf8(o.stdout).unwrap();
    assert_eq!(
        json.trim(),
        fs::read_to_string(dump.join("meta.json")).unwrap().trim()
    );
    let number = |key: &str| -> usize {
        let at = json.find(&format!("\"{key}\":")).expect(key) + key.len() + 3;
        json[at..]
            .split([',', '}'])
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert_eq!(number("width"), 40);
    assert_eq!(number("triangles"), 3);
    let (rays, shadow) = (number("rays"), number("shadow_rays"));
    assert_eq!(rays, 40 * number("height"));
    assert!(shadow > 0 && shadow < rays, "{json}");
    for (file, bytes) in [
        ("triangles.f32", 3 * 36),
        ("rays.f32", 24 * rays),
        ("hits.bin", 8 * rays),
        ("shadow.f32", 28 * shadow),
        ("occluded.u8", shadow),
    ] {
        assert_eq!(
            fs::metadata(dump.join(file)).unwrap().len(),
            bytes as u64,
            "{file}"
        );
    }

    // Spheres cannot be exported: refused, and nothing written.
    let refused = dir.path().join("refused");
    let o = run(prism().args(["bench", "--dump"]).args([
        &refused,
        &example("example.objx"),
        &example("example.cmr"),
    ]));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a triangle"), "{}", stderr(&o));
    assert!(!refused.exists());
}

#[test]
fn convert_writes_a_2014_scene_that_renders_like_the_obj() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("quad.obj");
    fs::write(
        &obj,
        "# a quad facing the example camera\n\
         v 0 -60 20\nv 0 60 20\nv 0 60 140\nv 0 -60 140\n\
         vn 1 0 0\nf 1//1 2//1 3//1 4//1\n",
    )
    .unwrap();
    let objx = dir.path().join("quad.objx");
    let o = run(prism().arg("convert").args([&obj, &objx]));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = fs::read_to_string(&objx).unwrap();
    assert!(text.contains("\nf 0 1 2\nf 0 2 3\n"), "{text}");

    let render = |scene: &std::path::Path, name: &str| {
        let out = dir.path().join(name);
        let o = run(prism()
            .args([scene.to_path_buf(), example("example.cmr"), out.clone()])
            // The same model for both: an OBJ is whitted by default, a 2014 file classic.
            .args(["--width", "48", "--aa", "1", "--integrator", "classic"]));
        assert!(o.status.success(), "{}", stderr(&o));
        load_rgb(&out)
    };
    let (a, b) = (render(&obj, "a.ppm"), render(&objx, "b.ppm"));
    assert_eq!(a, b);
    assert!(
        a.pixels().any(|p| p.0 != [0, 0, 0]),
        "the quad must be seen"
    );
}

#[test]
fn convert_refuses_a_bad_mesh_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("bad.obj");
    fs::write(&obj, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let objx = dir.path().join("bad.objx");
    let o = run(prism().arg("convert").args([&obj, &objx]));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.obj:3: vertex 7 does not exist"),
        "{}",
        stderr(&o)
    );
    assert!(!objx.exists());
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn convert_refuses_to_overwrite_its_input_or_write_another_format() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("cube.obj");
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    fs::write(&obj, text).unwrap();
    let o = run(prism().arg("convert").args([&obj, &obj]));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(".objx"), "{}", stderr(&o));
    // Named .objx, but the same file through a link.
    let link = dir.path().join("cube.objx");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&obj, &link).unwrap();
        let o = run(prism().arg("convert").args([&obj, &link]));
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains("is the input file"), "{}", stderr(&o));
    }
    assert_eq!(fs::read_to_string(&obj).unwrap(), text);
}
