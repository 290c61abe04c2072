//! The OBJ/MTL reader against the peer suites' model files (tinyobjloader, tobj, assimp)
//! and the real models in ../shared/models, asserting what
//! ../shared/models/EXPECTATIONS.md says file by file. Skipped, with a message, when
//! ../shared is not beside the repository.
//!
//! Corpus (every OBJ file in the folders below is in a table; a new file fails the
//! coverage check until it gets an entry):
//!
//! | corpus | files | load as expected | fail as expected | skipped |
//! |---|---|---|---|---|
//! | tinyobjloader models/, tests/, fuzzer/ | 49 | 44 | 5: index 0 (issue-140), relative indices out of range (2), `nan` (test-nan, C4), a coordinate glued to a NUL byte (clusterfuzz) | 0 |
//! | tobj obj/ | 8 | 7 | 1: `f 4 5 7` with 6 vertices (FaceVertexOutOfBounds) | 0 |
//! | assimp test/models/OBJ + invalid/ | 27 | 25 | 2: `3.1+e2` in number_formats.obj (strtod would stop early; Prism refuses trailing junk), index 0 in malformed.obj | 0 |
//! | cornell-box, spot | 2 named | 2 | 0 | 0 |
//!
//! Where Prism differs from tinyobjloader on purpose: issue-244's MTL lives on a search
//! path Prism does not have (a warning, no materials); `map_bump -imfchan r
//! bumpmap2.jpg -bm 1.5` keeps `bumpmap2.jpg -bm 1.5` as the name, with a warning (C2);
//! issue-319-002 gives the fan count 14, not earcut's 8 (C3 allows it); `map_Ns`,
//! `disp` and the PBR keys are counted as skipped rather than stored.

use std::path::{Path, PathBuf};

use prism::format::obj::{GroupKind, ObjFile, load_obj};
use prism::math::Vec3;

fn models() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    if root.join("EXPECTATIONS.md").exists() {
        Some(root)
    } else {
        println!(
            "skipped: {} is absent (../shared is not beside the repo)",
            root.display()
        );
        None
    }
}

/// What a file must give.
enum Expect {
    Loads(fn(&ObjFile)),
    /// The error's text after the file's path: `:line:col: message...`.
    Fails(&'static str),
}
use Expect::{Fails, Loads};

fn check(root: &Path, folder: &str, table: &[(&str, Expect)], extension: Option<&str>) {
    let dir = root.join(folder);
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| extension.is_none_or(|ext| name.ends_with(ext)))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = table.iter().map(|(name, _)| name.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed, "every file of {folder} has an entry");
    for (name, expect) in table {
        let path = dir.join(name);
        let result = load_obj(&path);
        match (expect, result) {
            (Loads(check), Ok(obj)) => {
                let check = std::panic::AssertUnwindSafe(|| check(&obj));
                if let Err(e) = std::panic::catch_unwind(check) {
                    panic!("{folder}/{name}: {e:?}\nwarnings: {:#?}", obj.warnings);
                }
            }
            (Loads(_), Err(e)) => panic!("{folder}/{name} should load: {e}"),
            (Fails(expected), Ok(_)) => panic!("{folder}/{name} should fail with {expected}"),
            (Fails(expected), Err(e)) => {
                let message = e.to_string();
                let tail = message
                    .strip_prefix(&path.display().to_string())
                    .unwrap_or(&message);
                assert!(tail.starts_with(expected), "{folder}/{name}: {message}");
            }
        }
    }
}

fn v3(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1.2e-5
}

fn names(obj: &ObjFile) -> Vec<&str> {
    obj.groups.iter().map(|g| g.name.as_str()).collect()
}

fn material_names(obj: &ObjFile) -> Vec<&str> {
    obj.materials.iter().map(|m| m.name.as_str()).collect()
}

/// The material of the first triangle of each group.
fn group_materials(obj: &ObjFile) -> Vec<Option<u32>> {
    obj.groups
        .iter()
        .map(|g| obj.triangles[g.triangles.start].material)
        .collect()
}

fn warnings_with(obj: &ObjFile, text: &str) -> usize {
    obj.warnings
        .iter()
        .filter(|w| w.message.contains(text))
        .count()
}

fn smoothing(obj: &ObjFile, group: usize) -> Vec<u32> {
    obj.triangles[obj.groups[group].triangles.clone()]
        .iter()
        .map(|t| t.smoothing)
        .collect()
}

fn cube_like(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (8, 12));
    assert_eq!(o.materials.len(), 5);
}

fn cornell_like(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (76, 36));
    assert_eq!(
        names(o),
        [
            "floor",
            "light",
            "ceiling",
            "back_wall",
            "green_wall",
            "red_wall",
            "short_block",
            "tall_block"
        ]
    );
}

fn single_test_triangle(o: &ObjFile) {
    assert_eq!((o.positions.len(), o.triangles.len()), (3, 1));
    assert_eq!(names(o), ["Test"]);
    assert_eq!(material_names(o), ["default"]);
}

#[test]
fn tinyobjloader_models() {
    let Some(root) = models() else { return };
    let table: Vec<(&str, Expect)> = vec![
        (
            "catmark_torus_creases0.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.texcoords.len(), o.triangles.len()),
                    (32, 4, 64)
                );
                assert_eq!(names(o), [""]);
                assert_eq!(o.skipped["t"], 8);
                // Faces name `vn` the file never writes: a warning, no normals.
                assert_eq!(warnings_with(o, "normal 1 does not exist"), 1);
                assert!(o.triangles.iter().all(|t| t.vn.is_none() && t.vt.is_some()));
            }),
        ),
        (
            "colorspace-issue-184.obj",
            Loads(|o| {
                single_test_triangle(o);
                let m = &o.materials[0];
                assert_eq!(m.tf, Some(v3(0.1, 0.2, 0.3)));
                let kd = m.map_kd.as_ref().unwrap();
                assert_eq!(
                    (kd.name.as_str(), kd.colorspace.as_deref(), kd.offset),
                    ("diffuse.jpg", Some("sRGB"), [0.1, 0.0, 0.0])
                );
                let ks = m.map_ks.as_ref().unwrap();
                assert_eq!(
                    (ks.name.as_str(), ks.colorspace.as_deref(), ks.scale),
                    ("specular.jpg", None, [0.1, 0.2, 1.0])
                );
                let bump = m.bump.as_ref().unwrap();
                assert_eq!(
                    (
                        bump.name.as_str(),
                        bump.colorspace.as_deref(),
                        bump.bump_multiplier
                    ),
                    ("bumpmap.jpg", Some("linear"), 3.0)
                );
            }),
        ),
        (
            "cornell_box.obj",
            Loads(|o| {
                cornell_like(o);
                assert_eq!(
                    material_names(o),
                    ["white", "red", "green", "blue", "light"]
                );
                let kd: Vec<_> = o.materials.iter().map(|m| m.kd.unwrap()).collect();
                assert_eq!(kd, [Vec3::ONE, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE]);
                assert_eq!(o.materials[4].ka, Some(Vec3::splat(20.0)));
                assert_eq!(
                    group_materials(o),
                    [
                        Some(0),
                        Some(4),
                        Some(0),
                        Some(0),
                        Some(2),
                        Some(1),
                        Some(0),
                        Some(0)
                    ]
                );
                // Every texture option of every material has its default.
                for m in &o.materials {
                    assert!(m.map_kd.is_none() && m.bump.is_none());
                }
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "cornell_box_multimaterial.obj",
            Loads(|o| {
                cornell_like(o);
                let tall = &o.triangles[o.groups[7].triangles.clone()];
                let ids: Vec<_> = tall.iter().map(|t| t.material.unwrap()).collect();
                assert_eq!(ids, [0, 0, 0, 0, 0, 0, 2, 2, 2, 2]);
            }),
        ),
        (
            "cube-vertex-w-component.obj",
            Loads(|o| {
                cube_like(o);
                // w is read and ignored; it is not a colour (C5).
                assert!(o.colors.is_empty());
            }),
        ),
        (
            "cube-vertexcol.obj",
            Loads(|o| {
                cube_like(o);
                assert_eq!(o.colors.len(), 8);
                assert_eq!(
                    (o.colors[0], o.colors[1], o.colors[7]),
                    (Vec3::ZERO, Vec3::Z, Vec3::ONE)
                );
                assert_eq!(o.colors[4].x, 1.0);
            }),
        ),
        (
            "cube.obj",
            Loads(|o| {
                cube_like(o);
                assert_eq!(
                    names(o),
                    [
                        "front cube",
                        "back cube",
                        "right cube",
                        "top cube",
                        "left cube",
                        "bottom cube"
                    ]
                );
                assert!(o.groups.iter().all(|g| g.kind == GroupKind::Group));
                assert_eq!(
                    group_materials(o),
                    [Some(0), Some(0), Some(1), Some(0), Some(2), Some(0)]
                );
            }),
        ),
        (
            "invalid-face-definition.obj",
            Loads(|o| {
                assert_eq!((o.triangles.len(), o.groups.len()), (0, 0));
                assert_eq!(warnings_with(o, "a face needs at least 3 vertices"), 2);
            }),
        ),
        (
            "invalid-relative-texture-index.obj",
            Fails(":2:15: texture coordinate index `-2` does not exist"),
        ),
        (
            "invalid-relative-vertex-index.obj",
            Fails(":1:3: vertex index `-4` does not exist"),
        ),
        (
            "issue-138.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.texcoords.len(), o.triangles.len()),
                    (8, 4, 12)
                );
                assert_eq!(names(o), ["test1", "test2"]);
                assert_eq!(material_names(o), ["test1", "test2"]);
                assert_eq!(o.materials[0].kd, Some(v3(0.5, 0.2, 0.2)));
                assert_eq!(
                    (o.materials[1].ns, o.materials[1].ni, o.materials[1].d),
                    (Some(10.0), Some(1.5), Some(1.0))
                );
                assert_eq!(smoothing(o, 0), [1, 1]);
                assert_eq!(smoothing(o, 1), [2, 2, 3, 3, 4, 4, 5, 5, 6, 6]);
                assert_eq!(warnings_with(o, "gives both d and Tr"), 2);
            }),
        ),
        (
            "issue-140-zero-face-idx.obj",
            Fails(":16:3: vertex index 0 does not exist: indices start at 1"),
        ),
        (
            "issue-161-inconsistent-f.obj",
            Loads(|o| {
                assert_eq!((o.triangles.len(), o.materials.len()), (12, 5));
                assert!(o.triangles.iter().all(|t| t.material.is_none()));
                assert_eq!(warnings_with(o, "usemtl names material `cube`"), 1);
            }),
        ),
        (
            "issue-162-smoothing-group.obj",
            Loads(|o| {
                assert_eq!(names(o), ["test1", "test2"]);
                assert_eq!(smoothing(o, 0), [1, 1]);
                assert_eq!(smoothing(o, 1), [0, 0, 3, 3, 4, 4, 0, 0, 6, 6]);
            }),
        ),
        (
            "issue-235-usemtl-then-o.obj",
            Loads(|o| {
                assert_eq!(names(o), ["Plane.001", "Plane"]);
                assert!(o.groups.iter().all(|g| g.kind == GroupKind::Object));
                assert_eq!(material_names(o), ["None", "None1"]);
                assert_eq!(
                    (o.materials[0].kd, o.materials[1].kd),
                    (Some(Vec3::Z), Some(Vec3::X))
                );
                let plane = o.triangles[o.groups[1].triangles.start];
                assert_eq!((plane.v[0], plane.vn.unwrap()[0]), (4, 1));
            }),
        ),
        (
            "issue-244-mtl-searchpaths.obj",
            Loads(|o| {
                // The MTL is on a search path Prism does not have: warnings only.
                assert_eq!((o.groups.len(), o.materials.len()), (2, 0));
                assert_eq!(o.triangles[o.groups[1].triangles.start].v[0], 4);
                assert_eq!(warnings_with(o, "material library skipped"), 1);
            }),
        ),
        (
            "issue-246-usemtl-whitespace.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["1"]);
                assert_eq!(o.triangles[0].material, Some(0));
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "issue-248-texres-texopt.obj",
            Loads(|o| {
                let kd = o.materials[0].map_kd.as_ref().unwrap();
                assert_eq!(
                    (kd.name.as_str(), kd.other_options.as_slice()),
                    ("input.jpg", ["-texres 512".to_owned()].as_slice())
                );
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "issue-295-trianguation-failure.obj",
            Loads(|o| {
                assert_eq!((o.triangles.len(), names(o)), (28, vec!["invalid"]));
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "issue-319-002.obj",
            Loads(|o| {
                // C3: at most n - 2 triangles per polygon, each from its own polygon's corners.
                let polygons: [&[u32]; 3] = [
                    &[1, 0, 10, 9, 8, 7, 5],
                    &[4, 6, 11, 14, 12, 13, 3, 2],
                    &[17, 18, 19, 15, 16],
                ];
                let mut next = 0;
                for corners in polygons {
                    for t in &o.triangles[next..next + corners.len() - 2] {
                        assert!(t.v.iter().all(|i| corners.contains(i)), "{t:?}");
                    }
                    next += corners.len() - 2;
                }
                assert_eq!(o.triangles.len(), next);
            }),
        ),
        (
            "issue-319-003.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 8);
                assert!(o.triangles.iter().flatten_v().all(|i| i < 10));
            }),
        ),
        (
            "issue-330.obj",
            Loads(|o| assert_eq!((o.positions.len(), o.triangles.len()), (7, 3))),
        ),
        (
            "issue-356-leading-spaces-newmtl.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["aaa"]);
                assert_eq!(o.materials[0].ka, Some(Vec3::ONE));
                assert!(o.triangles.is_empty());
            }),
        ),
        (
            "issue-92.obj",
            Loads(|o| {
                single_test_triangle(o);
                assert_eq!(o.materials[0].map_kd.as_ref().unwrap().name, "tmp.png");
            }),
        ),
        (
            "issue-95-2.obj",
            Loads(|o| assert_eq!(o.materials[0].tf, Some(v3(0.1, 0.2, 0.3)))),
        ),
        (
            "issue-95.obj",
            Loads(|o| assert_eq!(o.materials[0].tf, Some(v3(0.1, 0.2, 0.3)))),
        ),
        (
            "leading-decimal-dot-issue-201.obj",
            Loads(|o| {
                single_test_triangle(o);
                assert!(close(o.positions[0], v3(0.08, -70.0, -5.532511)));
                assert!(close(
                    v3(o.positions[1].x, o.positions[1].y, o.positions[2].x),
                    v3(0.575869, -0.666304, 0.940448)
                ));
            }),
        ),
        (
            "leading-zero-in-exponent-notation-issue-210.obj",
            Loads(|o| {
                single_test_triangle(o);
                assert!(close(o.positions[0], v3(0.08, -70.0, -5.532511)));
            }),
        ),
        (
            "line-prim.obj",
            Loads(|o| {
                assert_eq!((o.triangles.len(), o.skipped["l"]), (0, 2));
                assert_eq!(warnings_with(o, "2 `l` statements skipped"), 1);
            }),
        ),
        (
            "map-bump.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.texcoords.len(), o.triangles.len()),
                    (218, 109, 400)
                );
                assert_eq!(o.normals.len(), 82, "`s off`: no normals are made");
                assert_eq!(material_names(o), ["Material.001", "Material.003"]);
                assert_eq!(o.materials[0].bump.as_ref().unwrap().name, "bump.jpg");
            }),
        ),
        (
            "missing_material_file.obj",
            Loads(|o| {
                cornell_like(o);
                assert!(o.materials.is_empty() && o.triangles.iter().all(|t| t.material.is_none()));
                assert_eq!(warnings_with(o, "usemtl names material"), 10);
            }),
        ),
        (
            "mtl filename with whitespace issue46.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["green"]);
                assert_eq!(warnings_with(o, "material library skipped"), 2);
            }),
        ),
        (
            "mtllib-multiple-files-issue-112.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["default"]);
                assert_eq!(warnings_with(o, "material library skipped"), 2);
            }),
        ),
        (
            "no_material.obj",
            Loads(|o| {
                cornell_like(o);
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "norm-texopt.obj",
            Loads(|o| {
                let norm = o.materials[0].norm.as_ref().unwrap();
                assert_eq!(
                    (norm.name.as_str(), norm.bump_multiplier),
                    ("normalmap.jpg", 3.0)
                );
            }),
        ),
        (
            "pbr-mat-ext.obj",
            Loads(|o| {
                assert_eq!((o.triangles.len(), material_names(o)), (2, vec!["pbr"]));
                let m = &o.materials[0];
                assert_eq!((m.kd, m.ke), (Some(Vec3::ONE), Some(Vec3::splat(0.1))));
                assert_eq!(m.map_ke.as_ref().unwrap().name, "emissive.tex");
                assert_eq!(m.norm.as_ref().unwrap().name, "normalmap.tex");
                for key in [
                    "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "map_Pr", "map_Pm", "map_Ps",
                ] {
                    assert_eq!(o.skipped[&format!("mtl:{key}")], 1, "{key}");
                }
            }),
        ),
        (
            "points-prim.obj",
            Loads(|o| assert_eq!((o.triangles.len(), o.skipped["p"]), (0, 1))),
        ),
        (
            "refl.obj",
            Loads(|o| {
                assert_eq!(o.materials.len(), 5);
                assert_eq!(o.materials[0].refl.as_ref().unwrap().name, "reflection.tga");
            }),
        ),
        (
            "skin-weight.obj",
            Loads(|o| {
                cube_like(o);
                assert_eq!(o.skipped["vw"], 7);
            }),
        ),
        (
            "smoothing-group-two-squares.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 3);
                assert_eq!(warnings_with(o, "normal 1 does not exist"), 1);
                // The missing `vn` give way to smoothing-group normals: one per position.
                assert!(
                    o.triangles
                        .iter()
                        .all(|t| t.smoothing == 1 && t.vn.is_some())
                );
                assert_eq!(o.normals.len(), 5);
            }),
        ),
        (
            "smoothing-normal.obj",
            Loads(|o| {
                assert_eq!(names(o), ["front cube", "back cube"]);
                let smoothed: Vec<_> = o.triangles.iter().map(|t| t.vn.is_some()).collect();
                assert_eq!(smoothed, [true, true, true, true, false, false]);
            }),
        ),
        (
            "test-nan.obj",
            Fails(":12:3: expected a finite number for the x coordinate, found `nan`"),
        ),
        (
            "texture-filename-with-whitespace.obj",
            Loads(|o| {
                assert!(o.materials.len() > 2);
                assert_eq!(
                    o.materials[0].map_kd.as_ref().unwrap().name,
                    "texture 01.png"
                );
                let bump = o.materials[1].bump.as_ref().unwrap();
                assert_eq!(
                    (bump.name.as_str(), bump.bump_multiplier),
                    ("bump 01.png", 2.0)
                );
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "texture-options-issue-85.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["default", "bm2", "bm3"]);
                let [default, bm2, bm3] = [&o.materials[0], &o.materials[1], &o.materials[2]];
                assert!(default.map_ka.as_ref().unwrap().clamp);
                let kd = default.map_kd.as_ref().unwrap();
                assert_eq!(
                    (kd.name.as_str(), kd.offset),
                    ("diffuse.jpg", [0.1, 0.0, 0.0])
                );
                assert_eq!(default.map_ks.as_ref().unwrap().scale, [0.1, 0.2, 1.0]);
                assert_eq!(default.bump.as_ref().unwrap().bump_multiplier, 3.0);
                assert_eq!(bm2.map_kd.as_ref().unwrap().other_options, ["-blendu on"]);
                let bump2 = bm2.bump.as_ref().unwrap();
                assert_eq!(bump2.other_options, ["-imfchan r"]);
                assert_eq!(
                    (bump2.name.as_str(), bump2.bump_multiplier),
                    ("bumpmap2.jpg -bm 1.5", 1.0)
                );
                assert_eq!(warnings_with(o, "holds the option `-bm`"), 1);
                let types: Vec<_> = [&bm3.map_kd, &bm3.map_ks, &bm3.map_ka, &bm3.map_d, &bm3.bump]
                    .iter()
                    .map(|m| m.as_ref().unwrap().other_options[0].as_str())
                    .collect();
                assert_eq!(
                    types,
                    [
                        "-type sphere",
                        "-type cube_top",
                        "-type cube_left",
                        "-type cube_right",
                        "-type cube_front"
                    ]
                );
                assert_eq!((o.skipped["mtl:map_Ns"], o.skipped["mtl:disp"]), (3, 1));
            }),
        ),
        (
            "tr-and-d-issue-43.obj",
            Loads(|o| {
                assert!(o.materials.iter().all(|m| m.d == Some(0.75)));
                assert_eq!(warnings_with(o, "gives both d and Tr"), 2);
            }),
        ),
        (
            "usemtl-issue-104.obj",
            Loads(|o| {
                assert_eq!((names(o), o.triangles.len()), (vec!["floor"], 6));
                assert!(o.triangles.iter().all(|t| t.material.is_none()));
            }),
        ),
        (
            "usemtl-issue-68.obj",
            Loads(|o| {
                assert_eq!(
                    (o.triangles.len(), material_names(o)),
                    (400, vec!["Material.001", "Material.003"])
                );
            }),
        ),
    ];
    // The MTL files are checked through the OBJ files that name them.
    check(&root, "tinyobjloader/models", &table, Some(".obj"));
    check(
        &root,
        "tinyobjloader/tests",
        &[(
            "issue-177.obj",
            Loads(|o| {
                cube_like(o);
                assert!(o.warnings.is_empty());
            }),
        )],
        Some(".obj"),
    );
    check(
        &root,
        "tinyobjloader/fuzzer/regressions",
        &[(
            "clusterfuzz-testcase-minimized-fuzz_ParseFromString-4877060179886080",
            Fails(":1:3: expected a number for the x coordinate, found `3E4570711268\\u{0}`"),
        )],
        None,
    );
}

trait FlattenV {
    fn flatten_v(self) -> impl Iterator<Item = u32>;
}

impl<'a, I: Iterator<Item = &'a prism::format::obj::ObjTriangle>> FlattenV for I {
    fn flatten_v(self) -> impl Iterator<Item = u32> {
        self.flat_map(|t| t.v)
    }
}

#[test]
fn tobj_models() {
    let Some(root) = models() else { return };
    let table: Vec<(&str, Expect)> = vec![
        (
            "cornell_box.obj",
            Loads(|o| {
                cornell_like(o);
                // Two mtllib lines: materials in order of appearance across both.
                assert_eq!(
                    material_names(o),
                    ["white", "red", "blue", "light", "green"]
                );
                assert_eq!(
                    group_materials(o),
                    [
                        Some(0),
                        Some(3),
                        Some(0),
                        Some(0),
                        Some(4),
                        Some(1),
                        Some(0),
                        Some(0)
                    ]
                );
                // Quads fan from their first corner. tobj lists [0,1,2,0,2,3, 4,5,6,4,6,7, ...]
                // after renumbering corners in order of use; the file says `f 8 7 6 5`.
                let floor: Vec<_> = o.triangles[..6].iter().map(|t| t.v).collect();
                assert_eq!(
                    floor,
                    [
                        [0, 1, 2],
                        [0, 2, 3],
                        [7, 6, 5],
                        [7, 5, 4],
                        [11, 10, 9],
                        [11, 9, 8]
                    ]
                );
                let [white, red, blue, light, green] = std::array::from_fn(|i| &o.materials[i]);
                assert_eq!(
                    (white.ka, white.kd, white.ks, white.ke, white.illum),
                    (
                        Some(Vec3::ZERO),
                        Some(Vec3::ONE),
                        Some(Vec3::ZERO),
                        Some(Vec3::ONE),
                        None
                    )
                );
                assert_eq!((red.kd, red.illum), (Some(Vec3::X), Some(2)));
                assert_eq!(
                    red.map_ka.as_ref().unwrap().name,
                    "this ambient texture has spaces.jpg"
                );
                assert_eq!(
                    red.bump.as_ref().unwrap().name,
                    "this normal texture has spaces.jpg"
                );
                assert_eq!(
                    red.map_d.as_ref().unwrap().name,
                    "this dissolve texture has spaces.jpg"
                );
                assert_eq!((blue.kd, blue.ns), (Some(Vec3::Z), Some(10.0)));
                assert_eq!(
                    (light.ka, light.d, light.ni),
                    (Some(Vec3::splat(20.0)), Some(0.8), Some(1.25))
                );
                assert_eq!(green.map_kd.as_ref().unwrap().name, "dummy_texture.png");
                assert_eq!(o.skipped["mtl:unknown"], 1); // crazy_unknown
                assert_eq!((o.skipped["mtl:map_Ns"], o.skipped["mtl:map_NS"]), (1, 1));
            }),
        ),
        (
            "empty_name_triangle.obj",
            Loads(|o| {
                // tobj calls the run "unnamed_object"; Prism, like tinyobjloader, "".
                assert_eq!(names(o), [""]);
                assert_eq!(o.triangles.len(), 1);
            }),
        ),
        (
            "invalid_index.obj",
            Fails(":12: vertex 7 does not exist: the file defines 6"),
        ),
        (
            "lines.obj",
            Loads(|o| {
                assert_eq!(
                    (o.triangles.len(), o.skipped["l"], o.positions.len()),
                    (0, 3, 3)
                )
            }),
        ),
        (
            "quad.obj",
            Loads(|o| {
                assert_eq!(names(o), ["Quad", "Quad_face", "Tri_v_vn"]);
                assert_eq!(
                    o.positions,
                    [
                        v3(0., 1., 0.),
                        v3(0., 0., 0.),
                        v3(1., 0., 0.),
                        v3(1., 1., 0.)
                    ]
                );
                assert_eq!(o.texcoords, [[0., 1.], [0., 0.], [1., 0.], [1., 1.]]);
                let quad: Vec<_> = o.triangles[..2]
                    .iter()
                    .map(|t| (t.v, t.vt.is_some(), t.vn.is_some()))
                    .collect();
                assert_eq!(quad, [([0, 1, 2], true, false), ([0, 2, 3], true, false)]);
                assert!(
                    o.triangles[2..4]
                        .iter()
                        .all(|t| t.vt.is_some() && t.vn.is_some())
                );
                let tri = o.triangles[4];
                assert_eq!(
                    (tri.v, tri.vt, tri.vn.map(|n| o.normals[n[0] as usize])),
                    ([0, 1, 2], None, Some(Vec3::Z))
                );
            }),
        ),
        (
            "quad_colored_merge.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.colors.len(), o.triangles.len()),
                    (6, 6, 2)
                );
            }),
        ),
        (
            "triangle.obj",
            Loads(|o| {
                assert_eq!(names(o), ["Triangle"]);
                assert_eq!(o.positions, [Vec3::ZERO, Vec3::X, Vec3::Y]);
                assert_eq!(
                    (o.triangles[0].v, o.triangles[0].material),
                    ([0, 1, 2], None)
                );
                assert!(o.colors.is_empty() && o.materials.is_empty() && o.normals.is_empty());
            }),
        ),
        (
            "triangle_colored.obj",
            Loads(|o| assert_eq!(o.colors, [Vec3::X, Vec3::Y, Vec3::Z])),
        ),
    ];
    check(&root, "tobj/obj", &table, Some(".obj"));
}

#[test]
fn assimp_models_load_or_fail_cleanly() {
    let Some(root) = models() else { return };
    // (file, positions, triangles) for those that load.
    macro_rules! loads {
        ($v:expr, $t:expr) => {
            Loads(|o| assert_eq!((o.positions.len(), o.triangles.len()), ($v, $t)))
        };
    }
    let table: Vec<(&str, Expect)> = vec![
        ("WusonOBJ.obj", loads!(2117, 3732)),
        ("box.obj", loads!(8, 12)),
        // UTF-16 big-endian with a byte-order mark and CRLF.
        ("box_UTF16BE.obj", loads!(8, 12)),
        // One face of 936 corners over 8 positions: it crosses itself, so a fan.
        (
            "box_longline.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 10 + 934);
                assert_eq!(
                    o.warnings
                        .iter()
                        .filter(|w| w.message.contains("split as a fan"))
                        .count(),
                    1
                );
            }),
        ),
        (
            "box_mat_with_spaces.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 12);
                assert_eq!(o.triangles[0].material, Some(0));
                assert_eq!(o.materials[0].name, "Material name with many, many spaces");
            }),
        ),
        ("box_without_lineending.obj", loads!(8, 12)),
        (
            "concave_polygon.obj",
            Loads(|o| {
                assert_eq!((o.positions.len(), o.triangles.len()), (64, 64));
                assert!(o.warnings.is_empty());
            }),
        ),
        (
            "cube_mtllib_after_g.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 12);
                assert_eq!(
                    o.warnings
                        .iter()
                        .filter(|w| w.message.contains("cube_mtllib_after_g.mat"))
                        .count(),
                    1
                );
            }),
        ),
        (
            "cube_usemtl.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["mtl", "mtl2"]);
                assert_eq!(
                    o.warnings
                        .iter()
                        .filter(|w| w.message.contains("`mtl3`"))
                        .count(),
                    2
                );
            }),
        ),
        (
            "cube_with_vertexcolors.obj",
            Loads(|o| assert_eq!((o.colors.len(), o.triangles.len()), (8, 12))),
        ),
        (
            "cube_with_vertexcolors_uni.obj",
            Loads(|o| assert_eq!((o.colors.len(), o.triangles.len()), (8, 12))),
        ),
        ("empty_mat.obj", loads!(130, 256)),
        (
            "mtl_different_folder.obj",
            Loads(|o| assert_eq!(material_names(o), ["Whatever"])),
        ),
        ("multiple_spaces.obj", loads!(4, 1)),
        (
            "number_formats.obj",
            Fails(":11:14: expected a number for the z coordinate, found `3.1+e2`"),
        ),
        // Colours on some vertices: the others are white.
        (
            "only_a_part_of_vertexcolors.obj",
            Loads(|o| {
                assert_eq!(
                    o.colors,
                    [Vec3::ONE, Vec3::Z, Vec3::ONE, v3(1.0, 0.6, 0.3), Vec3::ONE]
                );
            }),
        ),
        ("point_cloud.obj", loads!(3, 0)),
        (
            "regr01.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.triangles.len(), o.groups.len()),
                    (2108, 2710, 55)
                );
                assert_eq!(o.materials[8].name, "Terraindæk");
            }),
        ),
        (
            "regr_3429812.obj",
            Loads(|o| assert_eq!(names(o), ["rectangle", "triangle1", "triangle2"])),
        ),
        (
            "space_in_material_name.obj",
            Loads(|o| {
                assert_eq!(material_names(o), ["Hard Shiny Plastic White"]);
                assert!(o.triangles.iter().all(|t| t.material == Some(0)));
            }),
        ),
        (
            "spider.obj",
            Loads(|o| {
                assert_eq!(
                    (o.positions.len(), o.triangles.len(), o.materials.len()),
                    (762, 1368, 5)
                );
                let tex = o.materials.iter().find_map(|m| m.map_kd.as_ref()).unwrap();
                assert!(tex.path.exists(), "{}", tex.path.display());
            }),
        ),
        (
            "testline.obj",
            Loads(|o| assert_eq!((o.triangles.len(), o.skipped["l"]), (0, 6))),
        ),
        (
            "testmixed.obj",
            Loads(|o| {
                assert_eq!(
                    (o.triangles.len(), o.skipped["l"], o.skipped["p"]),
                    (12, 6, 6)
                )
            }),
        ),
        (
            "testpoints.obj",
            Loads(|o| assert_eq!((o.triangles.len(), o.skipped["p"]), (0, 6))),
        ),
    ];
    check(&root, "assimp/test/models/OBJ", &table, Some(".obj"));
    let invalid: Vec<(&str, Expect)> = vec![
        ("empty.obj", loads!(0, 0)),
        (
            "malformed.obj",
            Fails(":28:3: vertex index 0 does not exist"),
        ),
        (
            "malformed2.obj",
            Loads(|o| {
                assert_eq!(o.triangles.len(), 10);
                assert_eq!(names(o), ["-1"]);
            }),
        ),
    ];
    check(&root, "assimp/test/models/invalid", &invalid, Some(".obj"));
}

/// The 66-gon: its triangles cover exactly its area, and none lies outside it.
#[test]
fn assimp_concave_polygon_is_triangulated_inside_its_outline() {
    let Some(root) = models() else { return };
    let path = root.join("assimp/test/models/OBJ/concave_polygon.obj");
    let obj = load_obj(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let face: Vec<u32> = text
        .lines()
        .find(|l| l.starts_with("f "))
        .unwrap()
        .split_whitespace()
        .skip(1)
        .map(|c| c.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
        .collect();
    assert_eq!(face.len(), 66);
    assert_eq!(obj.triangles.len(), 64);
    // The polygon lies in a plane: measure in it, with the Newell normal.
    let p = |i: u32| obj.positions[i as usize].as_dvec3();
    let normal: glam::DVec3 = (0..face.len())
        .map(|k| p(face[k]).cross(p(face[(k + 1) % face.len()])))
        .sum::<glam::DVec3>()
        / 2.0;
    let area = normal.length();
    let unit = normal / area;
    let mut covered = 0.0;
    for t in &obj.triangles {
        let [a, b, c] = t.v.map(p);
        let signed = (b - a).cross(c - a).dot(unit) / 2.0;
        assert!(signed >= -1e-9, "{t:?} is wound against the polygon");
        covered += signed;
        if signed > 1e-9 {
            assert!(
                inside(
                    &face.iter().map(|&i| p(i)).collect::<Vec<_>>(),
                    unit,
                    (a + b + c) / 3.0
                ),
                "{t:?} lies outside"
            );
        }
    }
    assert!((covered - area).abs() < 1e-6 * area, "{covered} vs {area}");
}

/// Even-odd test of `q` against a planar polygon, projected along its normal's largest axis.
fn inside(polygon: &[glam::DVec3], normal: glam::DVec3, q: glam::DVec3) -> bool {
    let axis = normal.abs().max_position();
    let (u, v) = [(1, 2), (2, 0), (0, 1)][axis];
    let mut inside = false;
    for k in 0..polygon.len() {
        let (a, b) = (polygon[k], polygon[(k + polygon.len() - 1) % polygon.len()]);
        let (ax, ay, bx, by) = (a[u], a[v], b[u], b[v]);
        if (ay > q[v]) != (by > q[v]) && q[u] < (bx - ax) * (q[v] - ay) / (by - ay) + ax {
            inside = !inside;
        }
    }
    inside
}

#[test]
fn cornell_box_and_spot_load_with_their_counts() {
    let Some(root) = models() else { return };
    let cornell = load_obj(&root.join("cornell-box/CornellBox-Original.obj")).unwrap();
    assert_eq!((cornell.positions.len(), cornell.triangles.len()), (72, 36));
    assert_eq!(
        material_names(&cornell),
        [
            "leftWall",
            "rightWall",
            "floor",
            "ceiling",
            "backWall",
            "shortBox",
            "tallBox",
            "light"
        ]
    );
    let light = &cornell.materials[7];
    assert_eq!(
        (light.ke, light.kd),
        (Some(v3(17.0, 12.0, 4.0)), Some(Vec3::splat(0.78)))
    );
    assert!(cornell.triangles.iter().all(|t| t.material.is_some()));
    // `usemtl shortBox` comes before `g shortBox`, so the blocks' faces are in the
    // groups written before them; their materials are right.
    assert_eq!(
        names(&cornell),
        [
            "floor",
            "ceiling",
            "backWall",
            "rightWall",
            "leftWall",
            "shortBox",
            "light"
        ]
    );
    assert!(cornell.warnings.is_empty(), "{:?}", cornell.warnings);

    // Spot has no material library upstream (README): texture coordinates only.
    let spot = load_obj(&root.join("spot/spot_triangulated.obj")).unwrap();
    assert_eq!(
        (
            spot.positions.len(),
            spot.texcoords.len(),
            spot.triangles.len()
        ),
        (2930, 3225, 5856)
    );
    assert!(
        spot.triangles
            .iter()
            .all(|t| t.vt.is_some() && t.vn.is_none())
    );
    assert!(spot.materials.is_empty() && spot.warnings.is_empty());
}
