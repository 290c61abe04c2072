//! Standard Wavefront OBJ, geometry only: `v` positions and `f` faces.
//!
//! A face lists vertices as `i`, `i/t`, `i//n` or `i/t/n`; only `i` is used. Indices are
//! 1-based, or negative to count back from the last vertex read so far. A polygon of
//! `n > 3` vertices is fanned into the triangles `(1, k, k+1)`, in file order, so
//! triangle numbers match other renderers' (Embree's harness in `benches/` relies on
//! it). Every other statement (`vt`, `vn`, `g`, `o`, `s`, `usemtl`, `mtllib`, `l`,
//! `p`, ...) is ignored; every shape wears a matte white and the file brings no light.

use std::path::Path;

use super::text::{At, read_text, shown};
use crate::math::Vec3;
use crate::scene::{Material, Scene, Shape, Triangle};
use crate::{Error, Result};

/// An indexed triangle mesh: the file's vertices (0-based) and its triangles in file
/// order, polygons fanned.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// Reads a Wavefront OBJ file's triangles as a scene.
pub fn load(path: &Path) -> Result<Scene> {
    Ok(scene_of(&load_mesh(path)?))
}

/// Reads a Wavefront OBJ file's triangles as an indexed mesh.
pub fn load_mesh(path: &Path) -> Result<Mesh> {
    parse_mesh(&read_text(path)?, path)
}

/// Parses the text of an OBJ file into a scene; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<Scene> {
    Ok(scene_of(&parse_mesh(text, path)?))
}

/// Every triangle of `mesh` as a shape wearing a matte white.
fn scene_of(mesh: &Mesh) -> Scene {
    let mut scene = Scene {
        materials: vec![Material::default_white()],
        ..Scene::default()
    };
    scene.shapes.reserve_exact(mesh.triangles.len());
    scene.material_of.reserve_exact(mesh.triangles.len());
    for t in &mesh.triangles {
        let v = t.map(|i| mesh.vertices[i as usize]);
        scene.push_shape(Shape::Triangle(Triangle { v }), 0);
    }
    scene
}

/// Parses the text of an OBJ file into an indexed mesh whose indices are all checked.
pub fn parse_mesh(text: &str, path: &Path) -> Result<Mesh> {
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // Positive indices may name vertices defined further down, so they are checked
    // once the file is read; this keeps the line of the first face that names each
    // index beyond what was defined at the time.
    let mut forward: Vec<(u32, usize)> = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let at = At {
            path,
            line: number + 1,
        };
        let line = line.split('#').next().unwrap_or("");
        let mut tokens = line.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => vertices.push(vertex(at, tokens)?),
            Some("f") => {
                polygon.clear();
                for token in tokens {
                    let i = index(at, token, vertices.len())?;
                    if i as usize >= vertices.len() {
                        forward.push((i, at.line));
                    }
                    polygon.push(i);
                }
                if polygon.len() < 3 {
                    return Err(at.error(format!(
                        "expected at least 3 vertices after f, found {}",
                        polygon.len()
                    )));
                }
                for k in 1..polygon.len() - 1 {
                    triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                }
                if triangles.len() > crate::accel::MAX_SHAPES {
                    return Err(at.error(format!(
                        "more than {} triangles are not supported",
                        crate::accel::MAX_SHAPES
                    )));
                }
            }
            _ => {}
        }
    }
    if let Some(&(i, line)) = forward.iter().find(|(i, _)| *i as usize >= vertices.len()) {
        return Err(Error::parse(
            path,
            line,
            format!(
                "vertex {} does not exist: the file defines {}",
                i + 1,
                vertices.len()
            ),
        ));
    }
    Ok(Mesh {
        vertices,
        triangles,
    })
}

fn vertex<'a>(at: At, mut tokens: impl Iterator<Item = &'a str>) -> Result<Vec3> {
    let mut xyz = [0.0f32; 3];
    for (axis, slot) in ["x", "y", "z"].iter().zip(&mut xyz) {
        let token = tokens.next().ok_or_else(|| {
            at.error(format!(
                "expected 3 coordinates after v (v x y z), the {axis} coordinate is missing"
            ))
        })?;
        *slot = at.number(token, &format!("the {axis} coordinate"))? as f32;
    }
    // A fourth value (w) or vertex colours may follow; they do not move the vertex.
    Ok(Vec3::from_array(xyz))
}

/// The 0-based vertex a face entry names; `defined` vertices are read so far.
fn index(at: At, token: &str, defined: usize) -> Result<u32> {
    let position = token.split('/').next().unwrap_or("");
    let value: i64 = position.parse().map_err(|_| {
        at.error(format!(
            "expected a vertex index (i, i/t, i//n or i/t/n), found {}",
            shown(token)
        ))
    })?;
    let resolved = match value {
        0 => None,
        v if v > 0 => Some(v - 1),
        v => Some(defined as i64 + v).filter(|&r| r >= 0),
    };
    resolved.and_then(|r| u32::try_from(r).ok()).ok_or_else(|| {
        at.error(format!(
            "vertex index {} does not exist: indices start at 1, and -1 is the last of \
                 the {defined} vertices read so far",
            shown(token)
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn parse_str(text: &str) -> Result<Scene> {
        parse(text, Path::new("mesh.obj"))
    }

    fn corners(scene: &Scene, i: usize) -> [[f32; 3]; 3] {
        match scene.shapes[i] {
            Shape::Triangle(t) => t.v.map(|p| p.to_array()),
            _ => panic!("not a triangle"),
        }
    }

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
    fn positive_indices_may_name_vertices_defined_later() {
        let scene = parse_str("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(corners(&scene, 0)[2], [0., 1., 0.]);
    }

    #[test]
    fn bad_faces_and_vertices_name_the_line() {
        let cases = [
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n",
                "mesh.obj:4: vertex index `0`",
            ),
            ("v 0 0 0\nf 1 -2 1\n", "mesh.obj:2: vertex index `-2`"),
            (
                "v 0 0 0\nv 1 0 0\n\nf 1 2\n",
                "mesh.obj:4: expected at least 3 vertices",
            ),
            ("v 0 0\n", "mesh.obj:1: expected 3 coordinates"),
            ("v 0 nan 0\n", "mesh.obj:1: expected a finite number"),
            ("v 0 0 0\nf 1 a 1\n", "mesh.obj:2: expected a vertex index"),
            ("v 0 0 0\nf 1 2 3\n", "mesh.obj:2: vertex 2 does not exist"),
        ];
        for (text, expected) in cases {
            let message = parse_str(text).unwrap_err().to_string();
            assert!(message.starts_with(expected), "{message:?} for {text:?}");
        }
    }

    #[test]
    fn real_models_load_with_their_face_counts() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
        let bunny = root.join("stanford-bunny/stanford-bunny.obj");
        if !bunny.exists() {
            eprintln!(
                "skipped: {} is absent (../shared is not beside the repo)",
                bunny.display()
            );
            return;
        }
        assert_eq!(load(&bunny).unwrap().shapes.len(), 69451);
        // Quads fan into two triangles each.
        let spot = load(&root.join("spot/spot_quadrangulated.obj")).unwrap();
        assert_eq!(spot.shapes.len(), 2 * 2928);
    }

    /// A line from the OBJ vocabulary with random arguments.
    fn obj_line() -> impl Strategy<Value = String> {
        let keyword = prop_oneof![4 => "v|f|vt|vn|g|o|s|usemtl|#", 1 => "\\PC{0,3}"];
        let token = prop_oneof![
            "-?[0-9]{1,2}(/[0-9]{0,2}){0,2}",
            "-?[0-9]{1,4}(\\.[0-9]{0,3})?",
            "nan|inf|1e39|-0|0|4294967296|//|/1|1//",
            "\\PC{0,4}",
        ];
        (keyword, prop::collection::vec(token, 0..6))
            .prop_map(|(k, t)| format!("{k} {}", t.join(" ")))
    }

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
            let _ = parse_str(&text);
        }

        /// Whatever the lines, a mesh that parses names only vertices it has.
        #[test]
        fn parsed_meshes_name_only_their_vertices(
            lines in prop::collection::vec(obj_line(), 0..40),
        ) {
            let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{}", lines.join("\n"));
            if let Ok(mesh) = parse_mesh(&text, Path::new("m.obj")) {
                for t in &mesh.triangles {
                    prop_assert!(t.iter().all(|&i| (i as usize) < mesh.vertices.len()));
                }
                prop_assert!(mesh.vertices.iter().all(|v| v.is_finite()));
            }
        }
    }
}
