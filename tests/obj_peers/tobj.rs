//! tobj's obj/ files.

use super::*;

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
