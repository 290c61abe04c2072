//! A scene file given as data rather than text (Python's `scene_from_dict`): the same
//! schema, as a JSON-like value, with mesh objects that carry their arrays.

use super::{SceneFile, parse_with_meshes};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::{Material, MeshAttributes, MeshMaterials, Scene, SceneBuilder, Surface};
use std::collections::HashMap;
use std::path::Path;

/// A triangle mesh handed over as arrays: `vertices` (x, y, z each), `faces` (three
/// vertex indices each), and optionally a normal and a texture coordinate per vertex.
#[derive(Clone, Debug, Default)]
pub struct ArrayMesh {
    /// Vertex positions in the mesh's own frame (the object's transform places them);
    /// every coordinate finite.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles as indices into `vertices`, each below its length.
    pub faces: Vec<[u32; 3]>,
    /// One normal per vertex, interpolated across faces; `None` for flat faces.
    pub normals: Option<Vec<[f32; 3]>>,
    /// One texture coordinate per vertex, v running up the image (as OBJ's do);
    /// `None` when the mesh has none.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// One linear RGB colour per vertex, multiplied into the albedo; `None` for none.
    pub colors: Option<Vec<[f32; 3]>>,
}

impl ArrayMesh {
    /// The mesh as a scene of its own, in a matte white (a scene file object's
    /// `material` replaces it), or what is wrong with the arrays.
    fn scene(&self) -> std::result::Result<Scene, String> {
        let n = self.vertices.len();
        if let Some(i) = self
            .vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(format!("vertex {i} is not finite"));
        }
        if let Some((f, &bad)) = self
            .faces
            .iter()
            .enumerate()
            .find_map(|(f, t)| t.iter().find(|&&i| i as usize >= n).map(|i| (f, i)))
        {
            return Err(format!(
                "face {f} names vertex {bad}, past the {n} vertices"
            ));
        }
        if self.faces.len() > crate::scene::MAX_SHAPES {
            return Err(format!("more than {} faces", crate::scene::MAX_SHAPES));
        }
        for (what, len) in [
            ("normals", self.normals.as_ref().map(Vec::len)),
            ("uvs", self.uvs.as_ref().map(Vec::len)),
            ("colors", self.colors.as_ref().map(Vec::len)),
        ] {
            if let Some(len) = len
                && len != n
            {
                return Err(format!("{len} {what} for {n} vertices: one per vertex"));
            }
        }
        if let Some(i) = self
            .colors
            .iter()
            .flatten()
            .position(|c| !c.iter().all(|v| v.is_finite() && *v >= 0.0))
        {
            return Err(format!(
                "colour {i} is not a finite, non-negative linear RGB"
            ));
        }
        let mut b = SceneBuilder::new();
        let white = b.add_material(Material::default_white(), Surface::default());
        let attributes = MeshAttributes::per_vertex(
            &self.faces,
            self.normals
                .iter()
                .flatten()
                .map(|&v| Vec3::from_array(v))
                .collect(),
            self.uvs.clone().unwrap_or_default(),
            self.colors
                .iter()
                .flatten()
                .map(|&c| Vec3::from_array(c))
                .collect(),
        );
        let positions: Vec<Vec3> = self.vertices.iter().map(|&v| Vec3::from_array(v)).collect();
        b.add_mesh(
            &positions,
            &self.faces,
            MeshMaterials::All(white),
            Some(attributes),
        );
        Ok(b.finish())
    }
}

/// The scene a scene-file `value` describes, its relative paths resolved against
/// `folder`; a mesh object whose `file` is a key of `meshes` takes those arrays.
/// Errors quote the offending entry: a value has no lines of its own.
pub fn from_value(
    value: &serde_json::Value,
    folder: &Path,
    meshes: &HashMap<String, ArrayMesh>,
    transforms: HashMap<String, Vec<[[f64; 4]; 4]>>,
) -> Result<SceneFile> {
    let origin = folder.join("<scene dict>");
    let data = |place: String, message: String| Error::Data {
        place,
        message: crate::error::bounded(message),
    };
    let text = toml::to_string(value).map_err(|e| {
        data(
            "scene".into(),
            format!("not a scene: {e} (the scene file's schema: tables, arrays, numbers, strings, booleans)"),
        )
    })?;
    let mut scenes = HashMap::new();
    for (name, mesh) in meshes {
        let scene = mesh
            .scene()
            .map_err(|e| data(format!("mesh {}", crate::util::text::shown(name)), e))?;
        scenes.insert(name.clone(), scene);
    }
    let given = super::InMemory {
        meshes: scenes,
        transforms,
    };
    parse_with_meshes(&text, &origin, given).map_err(|e| match e {
        Error::ParseAt {
            path,
            line,
            message,
            ..
        } if path == origin => {
            let entry = text
                .lines()
                .nth(line.saturating_sub(1))
                .unwrap_or("")
                .trim();
            // The table the entry is in, and which of its kind (`object[2]`).
            let tables: Vec<&str> = text
                .lines()
                .take(line)
                .filter(|l| l.starts_with('['))
                .collect();
            let place = match tables.last() {
                Some(t) => {
                    let nth = tables.iter().filter(|u| *u == t).count() - 1;
                    match t.strip_prefix("[[").and_then(|t| t.strip_suffix("]]")) {
                        Some(kind) => format!("{kind}[{nth}]"),
                        None => t.trim_matches(['[', ']']).to_string(),
                    }
                }
                None => "scene".into(),
            };
            data(
                place,
                format!("{}: {message}", crate::util::text::shown(entry)),
            )
        }
        e => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn quad() -> ArrayMesh {
        ArrayMesh {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            faces: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
            uvs: None,
            colors: None,
        }
    }

    #[test]
    fn a_value_with_array_meshes_equals_the_same_scene_from_files() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("quad.obj"),
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n",
        )
        .unwrap();
        let scene = |file: &str| {
            json!({
                "camera": {"from": [0.5, 0.5, 3], "at": [0.5, 0.5, 0], "fov": 40},
                "render": {"width": 32, "height": 24},
                "material": [{"name": "red", "color": [0.8, 0.1, 0.1]}],
                "object": [
                    {"type": "mesh", "file": file, "material": "red", "translate": [0, 0, -1]},
                    {"type": "sphere", "center": [0, 0, -3], "radius": 1}],
                "light": [{"type": "point", "position": [2, 2, 2]}],
            })
        };
        let meshes = HashMap::from([("quad".to_string(), quad())]);
        let a = from_value(&scene("quad"), dir.path(), &meshes, HashMap::new()).unwrap();
        let text = toml::to_string(&scene("quad.obj")).unwrap();
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, text).unwrap();
        let b = crate::format::load(&path).unwrap();
        let render = |f: SceneFile| {
            let s = crate::job::resolve(f, &crate::job::JobOptions::default()).unwrap();
            crate::render::Renderer::new(&s.scene, &s.camera, s.settings)
                .unwrap()
                .render(&())
                .unwrap()
                .0
                .pixels
        };
        let (pa, pb) = (render(a), render(b));
        assert!(pa.iter().any(|p| p[0] > 0.1));
        assert_eq!(
            pa.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>(),
            pb.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn bad_values_and_arrays_say_where() {
        let meshes = HashMap::from([("quad".to_string(), quad())]);
        let dir = Path::new("/nonexistent");
        let e = from_value(
            &json!({"object": [{"type": "sphere", "radius": -1}]}),
            dir,
            &meshes,
            HashMap::new(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("object[0]: `radius = -1`: expected radius > 0"),
            "{e}"
        );
        let e = from_value(
            &json!({"object": [{"type": "sphere", "radius": null}]}),
            dir,
            &meshes,
            HashMap::new(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("not a scene"), "{e}");
        let mut bad = quad();
        bad.faces[1] = [0, 2, 9];
        let bad = HashMap::from([("quad".to_string(), bad)]);
        let e = from_value(&json!({}), dir, &bad, HashMap::new())
            .unwrap_err()
            .to_string();
        assert_eq!(e, "mesh `quad`: face 1 names vertex 9, past the 4 vertices");
        let mut bad = quad();
        bad.colors = Some(vec![
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, -1.0],
            [1.0; 3],
        ]);
        let bad = HashMap::from([("quad".to_string(), bad)]);
        let e = from_value(&json!({}), dir, &bad, HashMap::new())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "mesh `quad`: colour 2 is not a finite, non-negative linear RGB"
        );
    }

    #[test]
    fn vertex_colours_are_interpolated_between_the_corners() {
        let mut quad = quad();
        quad.colors = Some(vec![
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ]);
        let meshes = HashMap::from([("quad".to_string(), quad)]);
        let f = from_value(
            &json!({"object": [{"type": "mesh", "file": "quad"}]}),
            Path::new("/nonexistent"),
            &meshes,
            HashMap::new(),
        )
        .unwrap();
        let s = &f.scene;
        let ray = crate::math::Ray::new(Vec3::new(0.75, 0.25, 1.0), -Vec3::Z);
        let accel = crate::accel::Accel::build(crate::accel::AccelKind::List, &s.shapes);
        let hit = accel.closest(&ray, f32::INFINITY).expect("the quad");
        let sp = s.surface_point(hit.id(), &ray, hit.t, true);
        // At (0.75, 0.25): a quarter of the way from the red bottom to the blue top.
        let c = sp.color;
        assert!(
            (c - Vec3::new(0.75, 0.0, 0.25)).abs().max_element() < 1e-6,
            "{c}"
        );
    }
}
