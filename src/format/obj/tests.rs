//! The OBJ reader, statement by statement, on small texts.

use crate::math::{cross, normalize};
use std::collections::HashMap;

use proptest::prelude::*;

use super::*;
use crate::error::Error;

fn parse_str(text: &str) -> Result<Scene> {
    parse(text, Path::new("mesh.obj"))
}

/// Parses `text` as `dir/m.obj` with the given in-memory material libraries.
fn obj_with(text: &[u8], libraries: &[(&str, &str)]) -> Result<ObjFile> {
    let files: HashMap<PathBuf, Vec<u8>> = libraries
        .iter()
        .map(|(name, text)| (Path::new("dir").join(name), text.as_bytes().to_vec()))
        .collect();
    parse_obj_with(text, Path::new("dir/m.obj"), &mut |path| {
        files
            .get(path)
            .cloned()
            .ok_or_else(|| Error::file(path, "cannot read: not found"))
    })
}

fn obj(text: &str) -> ObjFile {
    obj_with(text.as_bytes(), &[]).unwrap()
}

fn error(text: &str) -> String {
    obj_with(text.as_bytes(), &[]).unwrap_err().to_string()
}

fn messages(obj: &ObjFile) -> Vec<String> {
    obj.warnings.iter().map(|w| w.to_string()).collect()
}

fn corners(scene: &Scene, i: usize) -> [[f32; 3]; 3] {
    match scene.shapes.get(i) {
        crate::scene::Shape::Triangle(t) => t.v.map(|p| p.to_array()),
        _ => panic!("not a triangle"),
    }
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn faces_take_every_index_form_and_polygons_fan_from_the_first_vertex() {
    let text = "# a unit square and a pentagon\n\
                v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n\
                vt 0 0\nvn 0 0 1\ng square\ns off\nusemtl whatever\n\
                f 1/1 2/1/1 3//1 4\n\
                v 2 0 0\nv 3 0 0\nv 3 1 0\nv 2.5 2 0\nv 2 1 0\n\
                f -5 -4 -3 -2 -1\n";
    let scene = parse_str(text).unwrap();
    assert_eq!(scene.shapes.len(), 2 + 3);
    assert_eq!(
        corners(&scene, 0),
        [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.]]
    );
    assert_eq!(
        corners(&scene, 1),
        [[0., 0., 0.], [1., 1., 0.], [0., 1., 0.]]
    );
    assert_eq!(
        corners(&scene, 2),
        [[2., 0., 0.], [3., 0., 0.], [3., 1., 0.]]
    );
    assert_eq!(
        corners(&scene, 4),
        [[2., 0., 0.], [2.5, 2., 0.], [2., 1., 0.]]
    );
    assert_eq!(scene.materials.len(), 1);
    assert!(scene.material_of.iter().all(|&m| m == 0));
    assert!(scene.lights.is_empty());
}

#[test]
fn vertices_read_w_and_colours() {
    let o = obj("v 1 2 3\nv 4 5 6 0.5\nv 7 8 9 1 0 0.5\nv -1 -2 -3\n");
    assert_eq!(
        o.positions,
        [
            Vec3::new(1., 2., 3.),
            Vec3::new(4., 5., 6.),
            Vec3::new(7., 8., 9.),
            Vec3::new(-1., -2., -3.)
        ]
    );
    assert_eq!(
        o.colors,
        [Vec3::ONE, Vec3::ONE, Vec3::new(1., 0., 0.5), Vec3::ONE]
    );
    assert!(obj(SQUARE).colors.is_empty());
}

#[test]
fn texture_coordinates_and_normals_are_read_per_corner() {
    let o = obj(&format!(
        "{SQUARE}vt 0.25\nvt 0.5 0.75\nvt 1 1 9\nvn 0 0 2\nvn 0 0 1\n\
         f 1/1/1 2/2/2 3/3/1\nf 1/1 2/2 3/3\nf 1//2 2//2 3//1\nf 1/-1/-1 2/-2/-2 3/-3/-1\n"
    ));
    assert_eq!(o.texcoords, [[0.25, 0.0], [0.5, 0.75], [1.0, 1.0]]);
    assert_eq!(o.normals, [Vec3::new(0., 0., 2.), Vec3::Z]);
    let t = &o.triangles;
    assert_eq!((t[0].vt, t[0].vn), (Some([0, 1, 2]), Some([0, 1, 0])));
    assert_eq!((t[1].vt, t[1].vn), (Some([0, 1, 2]), None));
    assert_eq!((t[2].vt, t[2].vn), (None, Some([1, 1, 0])));
    assert_eq!((t[3].vt, t[3].vn), (Some([2, 1, 0]), Some([1, 0, 1])));
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
}

#[test]
fn faces_that_mix_corner_forms_lose_the_partial_attribute_once_reported() {
    let o = obj(&format!("{SQUARE}vt 0 0\nf 1/1 2 3\nf 1 2/1 3\n"));
    assert!(o.triangles.iter().all(|t| t.vt.is_none()));
    assert_eq!(
        messages(&o),
        [
            "dir/m.obj:6: a face gives texture coordinates for some corners only: it gets none \
          (this is reported for the first such face only)"
        ]
    );
}

#[test]
fn concave_polygons_are_ear_clipped_with_their_attributes() {
    // An L-shaped hexagon; corner k has vt k.
    let o = obj("v 1 1 0\nv 2 1 0\nv 2 2 0\nv 0 2 0\nv 0 0 0\nv 1 0 0\n\
         vt 0 0\nvt 1 0\nvt 2 0\nvt 3 0\nvt 4 0\nvt 5 0\n\
         f 1/1 2/2 3/3 4/4 5/5 6/6\n");
    assert_eq!(o.triangles.len(), 4);
    for t in &o.triangles {
        assert_eq!(t.vt, Some(t.v));
        let [a, b, c] = t.v.map(|i| o.positions[i as usize]);
        assert!(cross(b - a, c - a).z >= 0.0, "{t:?} is flipped");
    }
    let area: f32 = o
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.v.map(|i| o.positions[i as usize]);
            cross(b - a, c - a).z / 2.0
        })
        .sum();
    assert_eq!(area, 3.0);
}

#[test]
fn positive_indices_may_name_vertices_defined_later() {
    let scene = parse_str("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    assert_eq!(corners(&scene, 0)[2], [0., 1., 0.]);
    // A polygon naming later positions is triangulated at the end, in its place.
    let o = obj(
        "v 9 9 9\nv 9 9 8\nv 8 9 9\nf 1 2 3\nf 4 5 6 7 8 9\nf 1 3 2\n\
         v 2 1 0\nv 2 2 0\nv 0 2 0\nv 0 0 0\nv 1 0 0\nv 1 1 0\n",
    );
    let v: Vec<_> = o.triangles.iter().map(|t| t.v).collect();
    assert_eq!(v.len(), 6);
    assert_eq!((v[0], v[5]), ([0, 1, 2], [0, 2, 1]));
    // The L is ear-clipped, not fanned from its first corner (the fan crosses the notch).
    assert!(!v[1..5].contains(&[3, 6, 7]));
    assert!(v[1..5].iter().flatten().all(|&i| (3..9).contains(&i)));
}

#[test]
fn missing_texture_coordinates_and_normals_only_cost_the_face_them() {
    let o = obj(&format!(
        "{SQUARE}vt 0 0\nf 1/1/1 2/1/1 3/1/1\nf 1/2 2/1 3/1\n"
    ));
    assert_eq!((o.triangles[0].vt, o.triangles[0].vn), (Some([0; 3]), None));
    assert_eq!(o.triangles[1].vt, None);
    assert_eq!(
        messages(&o),
        [
            "dir/m.obj:7: texture coordinate 2 does not exist (the file defines 1): faces \
             naming missing texture coordinates get none (reported for the first only)",
            "dir/m.obj:6: normal 1 does not exist (the file defines 0): faces naming missing \
             normals get none (reported for the first only)",
        ]
    );
}

#[test]
fn errors_name_file_line_and_column() {
    let cases = [
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n",
            "dir/m.obj:4:7: vertex index 0 does not exist: indices start at 1",
        ),
        (
            "v 0 0 0\nf 1 -2 1\n",
            "dir/m.obj:2:5: vertex index `-2` does not exist: -1 is the last of the 1 read so far",
        ),
        (
            "v 0 0 0\nvt 0 0\nf 1/-2 1/1 1/1\n",
            "dir/m.obj:3:5: texture coordinate index `-2` does not exist: -1 is the last of the 1 read so far",
        ),
        (
            "v 0 0 0\nf 1//0 1 1\n",
            "dir/m.obj:2:6: normal index 0 does not exist: indices start at 1",
        ),
        (
            "v 0 0\n",
            "dir/m.obj:1:6: expected 3 coordinates after v (v x y z), the z coordinate is missing",
        ),
        (
            "v 0 0 0 1 1\n",
            "dir/m.obj:1:12: expected x y z, x y z w or x y z r g b after v, found 5 values: the blue of the vertex colour is missing",
        ),
        (
            "v 0 0 0 1 1 1 1\n",
            "dir/m.obj:1:15: expected x y z, x y z w or x y z r g b after v, found a 7th value `1`",
        ),
        (
            "v 0 nan 0\n",
            "dir/m.obj:1:5: expected a finite number for the y coordinate, found `nan`",
        ),
        (
            "v 0 1e39 0\n",
            "dir/m.obj:1:5: expected a finite number of magnitude at most 3.4028235e38 for the y coordinate, found `1e39`",
        ),
        (
            "v 1 2 3.1+e2\n",
            "dir/m.obj:1:7: expected a number for the z coordinate, found `3.1+e2`",
        ),
        (
            "v 0 0 0\nf 1 a 1\n",
            "dir/m.obj:2:5: expected a vertex index in the face corner `a` (i, i/t, i//n or i/t/n)",
        ),
        (
            "v 0 0 0\nf 1/x 1 1\n",
            "dir/m.obj:2:5: expected a texture coordinate index in the face corner `1/x` (i, i/t, i//n or i/t/n)",
        ),
        (
            "v 0 0 0\nf 1/1/1/1 1 1\n",
            "dir/m.obj:2:8: expected a face corner i, i/t, i//n or i/t/n, found `1/1/1/1`",
        ),
        (
            "v 0 0 0\nf 1 2 3\n",
            "dir/m.obj:2: vertex 2 does not exist: the file defines 1",
        ),
        (
            "f 1 2 \\\n 3 4\nv 0 0 0\nv 0 0 0\nv 0 0 0\n",
            "dir/m.obj:2: vertex 4 does not exist: the file defines 3",
        ),
        (
            "vt\n",
            "dir/m.obj:1:3: expected a texture coordinate after vt (vt u [v [w]]), found the end of the line",
        ),
        (
            "vt 1 2 3 4\n",
            "dir/m.obj:1:10: expected at most 3 values after vt (vt u v w), found a 4th `4`",
        ),
        (
            "vn 1 2\n",
            "dir/m.obj:1:7: expected 3 values after vn (vn x y z), the z is missing",
        ),
        (
            "vn 1 2 3 4\n",
            "dir/m.obj:1:10: expected 3 values after vn (vn x y z), found a 4th `4`",
        ),
        (
            "s\n",
            "dir/m.obj:1:2: expected a smoothing group after s (a number, 0 or off), found the end of the line",
        ),
        (
            "s on\n",
            "dir/m.obj:1:3: expected a smoothing group after s (a number, 0 or off), found `on`",
        ),
        (
            "v é 0 0\n",
            "dir/m.obj:1:3: expected a number for the x coordinate, found `é`",
        ),
        (
            "g é\nv 0 0 é\n",
            "dir/m.obj:2:7: expected a number for the z coordinate, found `é`",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(error(text), expected, "for {text:?}");
    }
}

#[test]
fn short_faces_are_dropped_with_a_warning() {
    let o = obj(&format!("{SQUARE}f 1\nf 1 2\nf\nf 1 2 3\n"));
    assert_eq!(o.triangles.len(), 1);
    assert_eq!(
        messages(&o)[0],
        "dir/m.obj:5: a face needs at least 3 vertices, found 1: the face is dropped"
    );
    assert_eq!(o.warnings.len(), 3);
}

#[test]
fn groups_own_the_triangles_that_follow_them() {
    let o = obj(&format!(
        "{SQUARE}f 1 2 3\no  first\ng back  cube\nf 1 2 3 4\ng empty\no last one\nf 1 2 3\ng\n"
    ));
    let groups: Vec<_> = o
        .groups
        .iter()
        .map(|g| (g.name.as_str(), g.kind, g.triangles.clone()))
        .collect();
    assert_eq!(
        groups,
        [
            ("", GroupKind::Group, 0..1),
            ("back cube", GroupKind::Group, 1..3),
            ("last one", GroupKind::Object, 3..4),
        ]
    );
}

#[test]
fn smoothing_groups_give_faces_averaged_normals() {
    // Two faces folded along the edge 2-3 (x = 1): the left one flat in z = 0, the right
    // one rising toward +x at 45 degrees, of equal area.
    let o = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 1\ns 1\nf 1 2 3\nf 2 4 3\ns off\nf 1 2 3\n");
    let n = |t: usize, k: usize| o.normals[o.triangles[t].vn.unwrap()[k] as usize];
    assert_eq!(o.triangles[0].smoothing, 1);
    assert_eq!(n(0, 0), Vec3::Z);
    let right = normalize(Vec3::new(-1.0, 0.0, 1.0));
    // Area-weighted: |cross| of the right face is sqrt 2, of the left 1.
    let shared = normalize(Vec3::Z + Vec3::new(-1.0, 0.0, 1.0));
    assert_eq!(n(0, 1), shared);
    assert_eq!(n(1, 0), shared);
    assert_eq!(n(1, 1), right);
    assert_eq!(o.triangles[2].vn, None);
    assert_eq!(o.triangles[2].smoothing, 0);
    assert_eq!(o.normals.len(), 4);
}

#[test]
fn materials_resolve_by_name_across_libraries() {
    let text = "usemtl early\nmtllib a.mtl b\\ c.mtl missing.mtl\nmtllib a.mtl\n\
                v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl red\nf 1 2 3\nusemtl  my blue \nf 1 2 3\n\
                usemtl nowhere\nf 1 2 3\nusemtl red\n";
    let o = obj_with(
        text.as_bytes(),
        &[
            ("a.mtl", "newmtl red\nKd 1 0 0\nnewmtl early\n"),
            (
                "b c.mtl",
                "newmtl my blue\nKd 0 0 1\nnewmtl red\nKd 0 1 0\nmap_aniso a.png\n",
            ),
        ],
    )
    .unwrap();
    let names: Vec<_> = o.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["red", "early", "my blue"]);
    assert_eq!(o.materials[0].kd, Some(Vec3::X));
    let ids: Vec<_> = o.triangles.iter().map(|t| t.material).collect();
    assert_eq!(ids, [Some(1), Some(0), Some(2), None]);
    assert_eq!(
        messages(&o),
        [
            "dir/b c.mtl:5: 1 `map_aniso` statements skipped: Prism does not use them",
            "dir/b c.mtl:3: material `red` is defined again: the first definition (dir/a.mtl:1) is kept",
            "dir/m.obj:2: material library skipped, its materials are unknown: dir/missing.mtl: cannot read: not found",
            "dir/m.obj:12: usemtl names material `nowhere`, which no material library defines: its faces get the default material",
        ]
    );
    assert_eq!(o.skipped.get("mtl:map_aniso"), Some(&1));
    // Without libraries every name is unknown, and the faces still load.
    let bare = obj(text);
    assert!(bare.triangles.iter().all(|t| t.material.is_none()));
}

#[test]
fn unsupported_statements_are_counted_with_one_warning_per_kind() {
    let o = obj(&format!(
        "{SQUARE}l 1 2\nl 2 3\np 1\ncurv 0 1 1 2\nsurf 0 1 0 1 1 2 3 4\nt crease 2/1/0 1 2 4.7\n\
         vp 0.5\nfrobnicate\nxyzzy 1\nf 1 2 3\n"
    ));
    let skipped: Vec<_> = o.skipped.iter().map(|(k, &n)| (k.as_str(), n)).collect();
    assert_eq!(
        skipped,
        [
            ("curv", 1),
            ("l", 2),
            ("p", 1),
            ("surf", 1),
            ("t", 1),
            ("unknown", 2),
            ("vp", 1)
        ]
    );
    assert_eq!(
        messages(&o),
        [
            "dir/m.obj:12: unknown statement `frobnicate` skipped (the count of unknown statements is in the summary)",
            "dir/m.obj:8: 1 `curv` statements skipped: Prism renders only faces",
            "dir/m.obj:5: 2 `l` statements skipped: Prism renders only faces",
            "dir/m.obj:7: 1 `p` statements skipped: Prism renders only faces",
            "dir/m.obj:9: 1 `surf` statements skipped: Prism renders only faces",
            "dir/m.obj:10: 1 `t` statements skipped: Prism renders only faces",
            "dir/m.obj:12: 2 unknown statements skipped",
            "dir/m.obj:11: 1 `vp` statements skipped: Prism renders only faces",
        ]
    );
    assert_eq!(o.triangles.len(), 1);
}

#[test]
fn comments_continuations_crlf_and_byte_order_marks_are_accepted() {
    let plain = obj(&format!("{SQUARE}g a b\nf 1 2 3 4\n"));
    let variants = [
        format!("\u{feff}{}", "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\ng a b\r\nf 1 2 3 4\r\n"),
        "v 0 0 0 # corner\nv 1 0 0#\nv 1 1 0\nv 0 1 0\n# g nothing\ng a \\\n b\nf 1 \\\r\n 2 \\\n3 4 # end\n"
            .to_owned(),
        "\tv  0\t0 0  \n  v 1 0 0\nv 1 1 0\nv \\\n0 1 0\ng a b\nf 1 2 3 4".to_owned(),
    ];
    for text in variants {
        assert_eq!(obj(&text), plain, "{text:?}");
    }
}

#[test]
fn names_that_are_not_utf8_are_read_as_latin1() {
    let o = obj_with(
        b"mtllib caf\xe9.mtl\ng caf\xe9 # \xff\xfe comment\nusemtl cr\xe8me\nv 0 0 0\nf 1 1 1\n",
        &[("café.mtl", "newmtl crème\n")],
    )
    .unwrap();
    assert_eq!(o.groups[0].name, "café");
    assert_eq!(o.triangles[0].material, Some(0));
    // UTF-16 text (with its byte-order mark) reads as well.
    let utf16: Vec<u8> = [0xFEFFu16]
        .into_iter()
        .chain("v 0 0 0\r\nf 1 1 1\r\n".encode_utf16())
        .flat_map(u16::to_be_bytes)
        .collect();
    assert_eq!(obj_with(&utf16, &[]).unwrap().triangles.len(), 1);
}

#[test]
fn loading_reads_only_regular_files_and_libraries_beside_the_obj() {
    let dir = tempfile::tempdir().unwrap();
    let e = load_obj(dir.path()).unwrap_err().to_string();
    assert!(e.ends_with("cannot read: not a regular file"), "{e}");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/m.mtl"), "newmtl m\nmap_Kd t.png\n").unwrap();
    std::fs::write(
        dir.path().join("sub/a.obj"),
        "mtllib m.mtl\nusemtl m\nv 0 0 0\nf 1 1 1\n",
    )
    .unwrap();
    let o = load_obj(&dir.path().join("sub/a.obj")).unwrap();
    assert_eq!(o.triangles[0].material, Some(0));
    assert_eq!(
        o.materials[0].map_kd.as_ref().unwrap().path,
        dir.path().join("sub/t.png")
    );
    // The geometry-only readers ignore material libraries.
    let mesh = load_mesh(&dir.path().join("sub/a.obj")).unwrap();
    assert_eq!(mesh.triangles, [[0, 0, 0]]);
}

#[test]
fn real_models_load_with_their_face_counts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    let bunny = root.join("stanford-bunny/stanford-bunny.obj");
    if !bunny.exists() {
        crate::util::skipped(format_args!(
            "{} is absent (../shared is not beside the repo)",
            bunny.display()
        ));
        return;
    }
    assert_eq!(load(&bunny).unwrap().shapes.len(), 69451);
    // Quads fan into two triangles each.
    let spot = load(&root.join("spot/spot_quadrangulated.obj")).unwrap();
    assert_eq!(spot.shapes.len(), 2 * 2928);
}

/// A line from the OBJ vocabulary with random arguments.
fn obj_line() -> impl Strategy<Value = String> {
    let keyword = prop_oneof![
        6 => "v|f|vt|vn|g|o|s|usemtl|mtllib|#|l|p|t",
        1 => "\\PC{0,3}"
    ];
    let token = prop_oneof![
        "-?[0-9]{1,2}(/-?[0-9]{0,2}){0,2}",
        "-?[0-9]{1,4}(\\.[0-9]{0,3})?",
        "nan|inf|1e39|-0|0|off|4294967296|//|/1|1//|\\\\",
        "\\PC{0,4}",
    ];
    (keyword, prop::collection::vec(token, 0..8)).prop_map(|(k, t)| format!("{k} {}", t.join(" ")))
}

proptest! {
    #![proptest_config(ProptestConfig {
        rng_seed: proptest::test_runner::RngSeed::Fixed(2024),
        ..ProptestConfig::default()
    })]

    #[test]
    fn arbitrary_text_never_panics(text in prop::collection::vec(any::<u8>(), 0..300)) {
        let _ = obj_with(&text, &[("a", "newmtl a\n")]);
        let _ = super::super::mtl::parse(&text, Path::new("x.mtl"));
    }

    /// Whatever the lines, a file that parses names only what it has.
    #[test]
    fn parsed_files_name_only_what_they_hold(
        lines in prop::collection::vec(obj_line(), 0..40),
    ) {
        let text = format!("mtllib a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n{}", lines.join("\n"));
        if let Ok(o) = obj_with(text.as_bytes(), &[("a", "newmtl 1\nnewmtl 2\n")]) {
            for t in &o.triangles {
                prop_assert!(t.v.iter().all(|&i| (i as usize) < o.positions.len()));
                prop_assert!(t.vt.iter().flatten().all(|&i| (i as usize) < o.texcoords.len()));
                prop_assert!(t.vn.iter().flatten().all(|&i| (i as usize) < o.normals.len()));
                prop_assert!(t.material.is_none_or(|m| (m as usize) < o.materials.len()));
            }
            prop_assert!(o.colors.is_empty() || o.colors.len() == o.positions.len());
            prop_assert!(o.positions.iter().all(|v| v.is_finite()));
            prop_assert!(o.normals.iter().all(|v| v.is_finite()));
            let mut end = 0;
            for g in &o.groups {
                prop_assert!(g.triangles.start >= end && g.triangles.start < g.triangles.end);
                end = g.triangles.end;
            }
            prop_assert!(end <= o.triangles.len());
        }
    }
}
