//! What a triangle mesh carries beyond its positions: per-vertex normals, texture
//! coordinates and colours, shared between triangles by index.
//!
//! The positions stay in `Scene::shapes` (one `Shape::Triangle` each) so the
//! intersectors read geometry only; a mesh names the run of shapes it owns.

use crate::math::Vec3;

/// Per-vertex attributes of the triangles `Scene::shapes[first_shape..][..len]`.
/// Each attribute array is empty when the file gave none; its index triples then are
/// empty too.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    pub first_shape: u32,
    /// Number of triangles (shapes) the mesh owns.
    pub len: u32,
    pub normals: Vec<Vec3>,
    /// One index triple into `normals` per triangle (or none at all).
    pub normal_indices: Vec<[u32; 3]>,
    pub texcoords: Vec<[f32; 2]>,
    pub texcoord_indices: Vec<[u32; 3]>,
    /// Linear RGB, multiplied into the albedo.
    pub colors: Vec<Vec3>,
    pub color_indices: Vec<[u32; 3]>,
}

impl MeshAttributes {
    /// Whether shape `shape` is one of this mesh's triangles.
    #[inline]
    pub fn owns(&self, shape: u32) -> bool {
        shape >= self.first_shape && shape - self.first_shape < self.len
    }

    /// Interpolated normal of triangle `tri` at barycentrics `(b0, b1, b2)`, if the mesh
    /// has normals.
    pub fn normal(&self, tri: usize, b: [f32; 3]) -> Option<Vec3> {
        let [i, j, k] = *self.normal_indices.get(tri)?;
        let n = self.normals[i as usize] * b[0]
            + self.normals[j as usize] * b[1]
            + self.normals[k as usize] * b[2];
        let n = n.normalize_or_zero();
        (n != Vec3::ZERO).then_some(n)
    }

    /// The vertex normals of triangle `tri`, for the shadow-terminator offset.
    pub fn vertex_normals(&self, tri: usize) -> Option<[Vec3; 3]> {
        let idx = *self.normal_indices.get(tri)?;
        Some(idx.map(|i| self.normals[i as usize]))
    }

    pub fn texcoord(&self, tri: usize, b: [f32; 3]) -> Option<[f32; 2]> {
        let [i, j, k] = *self.texcoord_indices.get(tri)?;
        let (a, c, d) = (
            self.texcoords[i as usize],
            self.texcoords[j as usize],
            self.texcoords[k as usize],
        );
        Some([
            a[0] * b[0] + c[0] * b[1] + d[0] * b[2],
            a[1] * b[0] + c[1] * b[1] + d[1] * b[2],
        ])
    }

    pub fn color(&self, tri: usize, b: [f32; 3]) -> Option<Vec3> {
        let [i, j, k] = *self.color_indices.get(tri)?;
        Some(
            self.colors[i as usize] * b[0]
                + self.colors[j as usize] * b[1]
                + self.colors[k as usize] * b[2],
        )
    }

    /// Checks that every index triple names an existing attribute and that the index
    /// arrays are empty or one per triangle: readers build meshes, renderers trust them.
    pub fn check(&self) -> Result<(), String> {
        fn check<T>(what: &str, values: &[T], idx: &[[u32; 3]], len: u32) -> Result<(), String> {
            if !idx.is_empty() && idx.len() != len as usize {
                return Err(format!(
                    "{} {what} index triples for {len} triangles",
                    idx.len()
                ));
            }
            if idx.iter().flatten().any(|&i| i as usize >= values.len()) {
                return Err(format!("a {what} index beyond the {} {what}", values.len()));
            }
            Ok(())
        }
        check("normal", &self.normals, &self.normal_indices, self.len)?;
        check(
            "texture coordinate",
            &self.texcoords,
            &self.texcoord_indices,
            self.len,
        )?;
        check("colour", &self.colors, &self.color_indices, self.len)
    }
}
