//! A PLY mesh as a scene: its triangles in a matte white (PLY files carry no
//! materials), with their vertex normals, colours and texture coordinates.

use super::ply::{self, PlyMesh};
use super::{SceneDialect, SceneFile, SourceCounts};
use crate::error::Result;
use crate::scene::{Material, MeshAttributes, MeshMaterials, SceneBuilder, Surface};
use std::path::Path;

pub fn load(path: &Path) -> Result<SceneFile> {
    Ok(from_ply(ply::load(path)?, path))
}

/// The scene of a parsed PLY mesh; `path` names it in warnings.
pub fn from_ply(mesh: PlyMesh, path: &Path) -> SceneFile {
    let counts = SourceCounts {
        vertices: mesh.positions.len(),
        normals: mesh.normals.len(),
        texcoords: mesh.texcoords.len(),
    };
    let mut scene = SceneBuilder::new();
    let white = scene.add_material(Material::default_white(), Surface::default());
    // PLY attributes are per vertex: every attribute shares the position indices.
    let attributes =
        MeshAttributes::per_vertex(&mesh.triangles, mesh.normals, mesh.texcoords, mesh.colors);
    scene.add_mesh(
        &mesh.positions,
        &mesh.triangles,
        MeshMaterials::All(white),
        Some(attributes),
    );
    let scene = scene.finish();
    let warnings = mesh
        .warnings
        .into_iter()
        .map(|w| format!("{}: {w}", path.display()))
        .collect();
    SceneFile {
        dialect: SceneDialect::Ply,
        scene,
        camera: None,
        cameras: Vec::new(),
        settings: Default::default(),
        warnings,
        counts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn a_coloured_quad_with_normals_becomes_a_mesh() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                    property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
                    property uchar red\nproperty uchar green\nproperty uchar blue\n\
                    element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                    0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n1 1 0 0 0 1 0 0 255\n\
                    0 1 0 0 0 1 255 255 255\n4 0 1 2 3\n";
        let path = Path::new("/nonexistent/q.ply");
        let file = from_ply(ply::parse(text.as_bytes(), path).unwrap(), path);
        let s = &file.scene;
        assert_eq!(file.dialect, SceneDialect::Ply);
        assert_eq!(s.shapes.len(), 2);
        assert_eq!(file.counts.vertices, 4);
        let (mesh, i) = s.mesh_of(1).unwrap();
        assert_eq!(mesh.normal(i, [0.2, 0.3, 0.5]), Some(Vec3::Z));
        // Triangle (0, 2, 3): its second corner is vertex 2, blue.
        assert_eq!(mesh.color(i, [0.0, 1.0, 0.0]), Some(Vec3::Z));
        assert!(mesh.check().is_ok());
    }
}
