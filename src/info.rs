//! What Prism read in a scene file, for `prism info`: dialect, counts, bounds and
//! warnings, as text or as one JSON object.

use crate::format::SceneFile;
use crate::scene::Shape;
use serde::Serialize;
use std::collections::HashSet;

/// The figures of a loaded scene file. Counts are of what Prism renders (triangles after
/// triangulation; a 2014 rectangle is two) unless they say otherwise.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SceneInfo {
    /// The format the file was read as, by the name `--dialect` takes.
    pub dialect: &'static str,
    /// The file's vertex records (`v` lines, PLY vertices); for formats that do not
    /// count them, the distinct corner positions of the shapes.
    pub vertices: usize,
    /// The file's normal records (`vn` lines and the like), else the meshes' vertex
    /// normals.
    pub normals: usize,
    /// The file's texture-coordinate records (`vt` lines and the like), else the meshes'.
    pub texcoords: usize,
    /// Triangles rendered, each rectangle counted as two, and each instance's placed
    /// triangles counted once an instance.
    pub triangles: usize,
    /// Triangles held in memory: `triangles` counting each instanced object's once.
    pub unique_triangles: usize,
    /// Instances: placements of an object held once.
    pub instances: usize,
    /// Objects the instances place.
    pub instanced_objects: usize,
    /// Spheres rendered.
    pub spheres: usize,
    /// 2014 rectangles (already counted twice in `triangles`).
    pub rectangles: usize,
    /// Named objects and groups that hold at least one shape.
    pub objects: usize,
    /// Names of the objects counted in `objects`, in file order.
    pub object_names: Vec<String>,
    /// Materials in the loaded scene, a default one the reader added included.
    pub materials: usize,
    /// Images: the 2014 textures and those read at texture coordinates.
    pub textures: usize,
    /// Point, directional, spot and area lights, emissive meshes included.
    pub lights: usize,
    /// The kind of each light, in order.
    pub light_kinds: Vec<&'static str>,
    /// `[[min x, y, z], [max x, y, z]]` of every shape (zeros for an empty scene).
    pub bounds: [[f32; 3]; 2],
    /// The file's cameras (glTF camera nodes), which `--camera-name` and
    /// `--camera-index` choose from.
    pub cameras: Vec<CameraInfo>,
    /// What was read but not used, or read with a guess, one message each.
    pub warnings: Vec<String>,
}

/// One camera of a scene file.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CameraInfo {
    /// The camera's name in the file; `None` when it has none.
    pub name: Option<String>,
    /// `perspective` or `orthographic`.
    pub projection: &'static str,
    /// Eye position in world space.
    pub position: [f32; 3],
}

impl SceneInfo {
    /// The figures of the loaded `file`.
    pub fn of(file: &SceneFile) -> SceneInfo {
        let scene = &file.scene;
        let mut triangles = 0;
        let mut spheres = 0;
        let mut rectangles = 0;
        for s in scene.shapes.iter() {
            match s {
                Shape::Triangle(_) => triangles += 1,
                Shape::Rectangle(_) => rectangles += 1,
                Shape::Sphere(_) => spheres += 1,
            }
        }
        let counts = file.counts;
        let vertices = if counts.vertices > 0 {
            counts.vertices
        } else {
            distinct_corners(&scene.shapes)
        };
        let normals = if counts.normals > 0 {
            counts.normals
        } else {
            scene.meshes.iter().map(|m| m.normals.len()).sum()
        };
        let texcoords = if counts.texcoords > 0 {
            counts.texcoords
        } else {
            scene.meshes.iter().map(|m| m.texcoords.len()).sum()
        };
        let object_names: Vec<String> = scene
            .groups
            .iter()
            .filter(|g| !g.shapes.is_empty())
            .map(|g| g.name.clone())
            .collect();
        let bounds = scene.bounds();
        let bounds = if bounds.is_empty() {
            [[0.0; 3]; 2]
        } else {
            [bounds.min.to_array(), bounds.max.to_array()]
        };
        SceneInfo {
            dialect: file.dialect.name(),
            vertices,
            normals,
            texcoords,
            triangles: triangles + 2 * rectangles + scene.placed_triangles() as usize,
            unique_triangles: triangles
                + 2 * rectangles
                + scene.objects.iter().map(|o| o.shapes.len()).sum::<usize>(),
            instances: scene.instances.len(),
            instanced_objects: scene.objects.len(),
            spheres,
            rectangles,
            objects: object_names.len(),
            object_names,
            materials: scene.materials.len(),
            textures: scene.textures.len() + scene.images.len(),
            lights: scene.lights.len(),
            light_kinds: scene.lights.iter().map(|l| l.kind_name()).collect(),
            bounds,
            cameras: file
                .cameras
                .iter()
                .map(|c| CameraInfo {
                    name: c.name.clone(),
                    projection: match c.camera.projection {
                        crate::scene::Projection::Perspective => "perspective",
                        crate::scene::Projection::Orthographic => "orthographic",
                    },
                    position: c.camera.eye.to_array(),
                })
                .collect(),
            warnings: file.warnings.clone(),
        }
    }

    /// The human-readable form.
    pub fn to_text(&self) -> String {
        use std::fmt::Write as _;
        let mut out = String::new();
        let _ = writeln!(out, "dialect    {}", self.dialect);
        let _ = writeln!(
            out,
            "vertices   {}   normals {}   texcoords {}",
            self.vertices, self.normals, self.texcoords
        );
        let _ = writeln!(
            out,
            "shapes     {} triangles, {} spheres ({} rectangles counted as 2 triangles each)",
            self.triangles, self.spheres, self.rectangles
        );
        if self.instances > 0 {
            let _ = writeln!(
                out,
                "instances  {} placing {} meshes: {} unique triangles in memory",
                self.instances, self.instanced_objects, self.unique_triangles
            );
        }
        let _ = write!(out, "objects    {}", self.objects);
        if !self.object_names.is_empty() {
            let shown: Vec<&str> = self
                .object_names
                .iter()
                .take(12)
                .map(String::as_str)
                .collect();
            let more = self.objects.saturating_sub(shown.len());
            let _ = write!(out, ": {}", shown.join(", "));
            if more > 0 {
                let _ = write!(out, " and {more} more");
            }
        }
        out.push('\n');
        let _ = writeln!(
            out,
            "materials  {}   textures {}",
            self.materials, self.textures
        );
        let _ = write!(out, "lights     {}", self.lights);
        if !self.light_kinds.is_empty() {
            let _ = write!(out, ": {}", summarize(&self.light_kinds));
        }
        out.push('\n');
        if !self.cameras.is_empty() {
            let names: Vec<String> = self
                .cameras
                .iter()
                .enumerate()
                .map(|(i, c)| match &c.name {
                    Some(n) => format!("{i}: {n} ({})", c.projection),
                    None => format!("{i}: unnamed ({})", c.projection),
                })
                .collect();
            let _ = writeln!(
                out,
                "cameras    {}: {}",
                self.cameras.len(),
                names.join(", ")
            );
        }
        let [lo, hi] = self.bounds;
        let _ = writeln!(
            out,
            "bounds     [{}, {}, {}] .. [{}, {}, {}]",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        );
        let _ = writeln!(out, "warnings   {}", self.warnings.len());
        for w in &self.warnings {
            let _ = writeln!(out, "  {w}");
        }
        out
    }

    /// The figures as one pretty-printed JSON object, keyed by these fields' names.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serialises")
    }
}

/// `3 point, 1 mesh`: kinds with their counts, in order of first appearance.
fn summarize(kinds: &[&'static str]) -> String {
    let mut seen: Vec<(&str, usize)> = Vec::new();
    for k in kinds {
        match seen.iter_mut().find(|(name, _)| name == k) {
            Some((_, n)) => *n += 1,
            None => seen.push((k, 1)),
        }
    }
    seen.iter()
        .map(|(k, n)| format!("{n} {k}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Distinct corner positions of the triangles and rectangles, and sphere centres.
fn distinct_corners(shapes: &crate::scene::Shapes) -> usize {
    let mut seen = HashSet::new();
    let key = |v: crate::math::Vec3| v.to_array().map(f32::to_bits);
    for s in shapes.iter() {
        match s {
            Shape::Triangle(t) => seen.extend(t.v.iter().map(|&v| key(v))),
            Shape::Rectangle(r) => seen.extend(r.v.iter().map(|&v| key(v))),
            Shape::Sphere(s) => {
                seen.insert(key(s.center));
            }
        }
    }
    seen.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn the_example_scene_in_figures() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/example/example.objx");
        let file = crate::format::load(&path).unwrap();
        let info = SceneInfo::of(&file);
        assert_eq!(info.dialect, "objx");
        let spheres = file
            .scene
            .shapes
            .iter()
            .filter(|s| matches!(s, Shape::Sphere(_)))
            .count();
        assert_eq!(info.spheres, spheres);
        assert_eq!(info.lights, file.scene.lights.len());
        assert_eq!(info.light_kinds, vec!["point"; info.lights]);
        let json: serde_json::Value = serde_json::from_str(&info.to_json()).unwrap();
        for key in [
            "dialect",
            "vertices",
            "normals",
            "texcoords",
            "triangles",
            "objects",
            "materials",
            "textures",
            "lights",
            "bounds",
            "cameras",
            "warnings",
        ] {
            assert!(json.get(key).is_some(), "{key} missing in {json}");
        }
        assert_eq!(json["bounds"].as_array().unwrap().len(), 2);
        assert!(info.to_text().starts_with("dialect    objx\n"));
    }

    #[test]
    fn summaries_count_kinds_in_order() {
        assert_eq!(
            summarize(&["point", "mesh", "point"]),
            "2 point, 1 mesh".to_string()
        );
    }
}
