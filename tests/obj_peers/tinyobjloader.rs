//! tinyobjloader's models/, tests/ and fuzzer/regressions/ files.

use prism::format::obj::GroupKind;

use super::*;

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
                // The PBR extension, as tinyobjloader's test expects it.
                let p = &m.pbr;
                assert_eq!(
                    [p.roughness, p.metallic, p.sheen, p.clearcoat],
                    [Some(0.2), Some(0.3), Some(0.4), Some(0.5)]
                );
                assert_eq!(
                    [p.clearcoat_roughness, p.anisotropy, p.anisotropy_rotation],
                    [Some(0.6), Some(0.7), Some(0.8)]
                );
                let name =
                    |t: &Option<prism::format::obj::TextureMap>| t.as_ref().unwrap().name.clone();
                assert_eq!(
                    [
                        name(&p.map_roughness),
                        name(&p.map_metallic),
                        name(&p.map_sheen)
                    ],
                    ["roughness.tex", "metallic.tex", "sheen.tex"]
                );
                assert!(
                    !o.skipped.keys().any(|k| k.starts_with("mtl:")),
                    "{:?}",
                    o.skipped
                );
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
