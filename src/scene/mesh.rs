//! What a triangle mesh carries beyond its positions: per-vertex normals, texture
//! coordinates and colours, shared between triangles by index.
//!
//! The positions stay in `Scene::shapes` (one `Shape::Triangle` each) so the
//! intersectors read geometry only; a mesh names the run of shapes it owns.

use crate::math::{Vec3, cross};

/// Per-vertex attributes of the triangles `Scene::shapes[first_shape..][..len]`.
/// Each attribute array is empty when the file gave none; its index triples then are
/// empty too.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    /// Index in `Scene::shapes` of the mesh's first triangle.
    pub first_shape: u32,
    /// Number of triangles (shapes) the mesh owns.
    pub len: u32,
    /// Vertex normals in world space (unit length not required; interpolation
    /// normalises).
    pub normals: Vec<Vec3>,
    /// One index triple into `normals` per triangle (or none at all).
    pub normal_indices: Vec<[u32; 3]>,
    /// Texture coordinates `(u, v)`, v running bottom to top as in OBJ and PLY.
    pub texcoords: Vec<[f32; 2]>,
    /// One index triple into `texcoords` per triangle (or none at all).
    pub texcoord_indices: Vec<[u32; 3]>,
    /// Linear RGB, multiplied into the albedo.
    pub colors: Vec<Vec3>,
    /// One index triple into `colors` per triangle (or none at all).
    pub color_indices: Vec<[u32; 3]>,
}

impl MeshAttributes {
    /// Attributes given one per vertex (glTF, PLY, arrays): each one present is indexed
    /// by the triangles' own corners; an empty one stays empty.
    pub fn per_vertex(
        triangles: &[[u32; 3]],
        normals: Vec<Vec3>,
        texcoords: Vec<[f32; 2]>,
        colors: Vec<Vec3>,
    ) -> MeshAttributes {
        let indices = |present: bool| {
            if present {
                triangles.to_vec()
            } else {
                Vec::new()
            }
        };
        MeshAttributes {
            first_shape: 0,
            len: triangles.len() as u32,
            normal_indices: indices(!normals.is_empty()),
            texcoord_indices: indices(!texcoords.is_empty()),
            color_indices: indices(!colors.is_empty()),
            normals,
            texcoords,
            colors,
        }
    }

    /// Whether shape `shape` is one of this mesh's triangles.
    #[inline]
    pub fn owns(&self, shape: u32) -> bool {
        shape >= self.first_shape && shape - self.first_shape < self.len
    }

    /// Interpolated normal of triangle `tri` at barycentrics `(b0, b1, b2)`, if the mesh
    /// has normals.
    pub fn normal(&self, tri: usize, b: [f32; 3]) -> Option<Vec3> {
        interpolate_normal(self.vertex_normals(tri)?, b)
    }

    /// The vertex normals of triangle `tri`, for the shadow-terminator offset.
    pub fn vertex_normals(&self, tri: usize) -> Option<[Vec3; 3]> {
        let idx = *self.normal_indices.get(tri)?;
        Some(idx.map(|i| self.normals[i as usize]))
    }

    /// Interpolated texture coordinates of triangle `tri` at barycentrics `(b0, b1, b2)`,
    /// if the mesh has them.
    pub fn texcoord(&self, tri: usize, b: [f32; 3]) -> Option<[f32; 2]> {
        let t = *self.texcoord_indices.get(tri)?;
        Some(interpolate_texcoord(
            t.map(|k| self.texcoords[k as usize]),
            b,
        ))
    }

    /// Interpolated vertex colour (linear RGB) of triangle `tri` at barycentrics
    /// `(b0, b1, b2)`, if the mesh has colours.
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

/// The mesh of `meshes` (in ascending order of `first_shape`) that owns shape
/// `shape`, with the shape's triangle number in it.
#[inline]
pub fn owning(meshes: &[MeshAttributes], shape: u32) -> Option<(&MeshAttributes, usize)> {
    let i = meshes.partition_point(|m| m.first_shape <= shape);
    let mesh = meshes.get(i.checked_sub(1)?)?;
    mesh.owns(shape)
        .then(|| (mesh, (shape - mesh.first_shape) as usize))
}

/// The unit normal at barycentrics `b` of a triangle with vertex normals `n`; `None`
/// where they cancel.
#[inline]
pub fn interpolate_normal(n: [Vec3; 3], b: [f32; 3]) -> Option<Vec3> {
    let n = (n[0] * b[0] + n[1] * b[1] + n[2] * b[2]).normalize_or_zero();
    (n != Vec3::ZERO).then_some(n)
}

/// The texture coordinates at barycentrics `b` of a triangle with corner coordinates
/// `uv`.
#[inline]
pub fn interpolate_texcoord(uv: [[f32; 2]; 3], b: [f32; 3]) -> [f32; 2] {
    let [a, c, d] = uv;
    [
        a[0] * b[0] + c[0] * b[1] + d[0] * b[2],
        a[1] * b[0] + c[1] * b[1] + d[1] * b[2],
    ]
}

/// Gives the triangles `shapes` of `scene` smooth vertex normals where their mesh has
/// none: corners at the same position (bit for bit) share a vertex whose normal is the
/// area-weighted mean of the faces around it. For scanned models (the Stanford bunny,
/// spot) that carry no normals; creases are smoothed too.
pub fn smooth_normals(scene: &mut super::Scene, shapes: std::ops::Range<u32>) {
    use std::collections::HashMap;
    let (first, len) = (shapes.start, shapes.end.saturating_sub(shapes.start));
    if len == 0 || shapes.end as usize > scene.shapes.len() {
        return;
    }
    let mut vertex_of: HashMap<[u32; 3], u32> = HashMap::new();
    let mut sums: Vec<Vec3> = Vec::new();
    let mut indices: Vec<[u32; 3]> = Vec::with_capacity(len as usize);
    for shape in (shapes.start as usize..shapes.end as usize).map(|i| scene.shapes.get(i)) {
        let super::Shape::Triangle(t) = shape else {
            // Not a triangle: a flat normal of its own.
            let n = sums.len() as u32;
            sums.push(shape.normal(Vec3::ZERO));
            indices.push([n; 3]);
            continue;
        };
        // Twice the area times the unit normal.
        let face = cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
        let face = if face.is_finite() { face } else { Vec3::ZERO };
        let idx = t.v.map(|p| {
            let key = p.to_array().map(f32::to_bits);
            *vertex_of.entry(key).or_insert_with(|| {
                sums.push(Vec3::ZERO);
                sums.len() as u32 - 1
            })
        });
        for &i in &idx {
            sums[i as usize] += face;
        }
        indices.push(idx);
    }
    let normals: Vec<Vec3> = sums.iter().map(|n| n.normalize_or_zero()).collect();
    match scene
        .meshes
        .iter_mut()
        .find(|m| m.first_shape == first && m.len == len)
    {
        Some(mesh) if !mesh.normal_indices.is_empty() => {}
        Some(mesh) => {
            mesh.normals = normals;
            mesh.normal_indices = indices;
        }
        None => {
            let at = scene.meshes.partition_point(|m| m.first_shape < first);
            scene.meshes.insert(
                at,
                MeshAttributes {
                    first_shape: first,
                    len,
                    normals,
                    normal_indices: indices,
                    ..MeshAttributes::default()
                },
            );
        }
    }
}

/// [`smooth_normals`] for every triangle of `scene` without vertex normals: each mesh
/// that has none, and each run of triangles outside every mesh (`--smooth`).
pub fn smooth_all(scene: &mut super::Scene) {
    let n = scene.shapes.len() as u32;
    let mut ranges = Vec::new();
    let outside = |scene: &super::Scene, from: u32, to: u32, out: &mut Vec<_>| {
        // Runs of triangles only: spheres and rectangles keep their own normals.
        let mut start = None;
        for i in from..to {
            match (scene.shapes.is_triangle(i as usize), start) {
                (true, None) => start = Some(i),
                (false, Some(s)) => {
                    out.push(s..i);
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(s) = start {
            out.push(s..to);
        }
    };
    let mut at = 0;
    for m in &scene.meshes {
        outside(scene, at, m.first_shape, &mut ranges);
        if m.normal_indices.is_empty() {
            ranges.push(m.first_shape..m.first_shape + m.len);
        }
        at = m.first_shape + m.len;
    }
    outside(scene, at, n, &mut ranges);
    for r in ranges {
        smooth_normals(scene, r);
    }
}

/// Turns a scene modelled with +z up (Blender's frame, which its PLY and OBJ exports
/// keep) into Prism's +y up: `(x, y, z)` becomes `(x, z, -y)`, a rotation, so
/// nothing mirrors and every light keeps its power.
pub fn turn_z_up_to_y_up(scene: &mut super::Scene) {
    let turn = |v: Vec3| Vec3::new(v.x, v.z, -v.y);
    let mut shapes = super::Shapes::new();
    shapes
        .append_placed(&scene.shapes, turn, false, Ok::<_, ()>)
        .expect("a rotation places every shape");
    scene.shapes = shapes;
    for m in &mut scene.meshes {
        for n in &mut m.normals {
            *n = turn(*n);
        }
    }
    for l in &mut scene.lights {
        l.position = turn(l.position);
        match &mut l.kind {
            super::LightKind::Point | super::LightKind::Sphere { .. } => {}
            super::LightKind::Directional { direction }
            | super::LightKind::Spot { direction, .. } => *direction = turn(*direction),
            super::LightKind::Quad { u, v } => (*u, *v) = (turn(*u), turn(*v)),
            super::LightKind::Disk { normal, .. } => *normal = turn(*normal),
            super::LightKind::Mesh { .. } => {}
        }
    }
    if let super::Background::Environment { up, forward, .. } = &mut scene.background {
        (*up, *forward) = (turn(*up), turn(*forward));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;
    use crate::scene::{Material, Scene, Shape, Triangle};

    #[test]
    fn shared_corners_get_the_area_weighted_mean_normal() {
        // Two triangles folded along the x axis: one in the plane z = 0 (normal +z,
        // area 1/2), one rising at 90 degrees (normal +y, area 1).
        let mut scene = Scene {
            materials: vec![Material::default_white()],
            ..Scene::default()
        };
        let o = Vec3::ZERO;
        let x = Vec3::X;
        scene.push_shape(Shape::Triangle(Triangle { v: [o, x, Vec3::Y] }), 0);
        scene.push_shape(
            Shape::Triangle(Triangle {
                v: [x, o, Vec3::new(0.0, 0.0, 2.0)],
            }),
            0,
        );
        smooth_normals(&mut scene, 0..2);
        let (mesh, _) = scene.mesh_of(0).unwrap();
        assert_eq!(
            mesh.normals.len(),
            4,
            "two shared corners, two of their own"
        );
        let shared = mesh.normal(0, [1.0, 0.0, 0.0]).unwrap();
        let expected = normalize(Vec3::Z + Vec3::Y * 2.0);
        assert!((shared - expected).length() < 1e-6, "{shared}");
        // A corner of one face only keeps that face's normal.
        assert_eq!(mesh.normal(0, [0.0, 0.0, 1.0]), Some(Vec3::Z));
        assert!(mesh.check().is_ok());
    }
}
