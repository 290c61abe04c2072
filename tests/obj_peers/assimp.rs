//! assimp's test/models/OBJ and invalid/ files, and its concave polygon's triangulation.

use super::*;

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
