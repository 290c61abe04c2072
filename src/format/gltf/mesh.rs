//! A glTF mesh's primitives as triangles with their per-vertex attributes, in the
//! mesh's own frame (placed by each node that names the mesh).

use super::accessor::{read_floats, read_indices};
use crate::math::Vec3;
use gltf::Document;
use gltf::mesh::Mode;

/// One primitive of a mesh, triangulated.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    /// POSITION, in the mesh's frame; only the vertices some triangle uses.
    pub positions: Vec<Vec3>,
    /// NORMAL, in the mesh's frame, one per position as stored; empty when absent.
    pub normals: Vec<Vec3>,
    /// TEXCOORD_0 and TEXCOORD_1 with v turned upward (`1 - v`), as Prism's images are
    /// read (glTF's v runs down the image).
    pub texcoords: [Vec<[f32; 2]>; 2],
    /// COLOR_0, linear RGB (its alpha is not used).
    pub colors: Vec<Vec3>,
    /// Indices into `positions`, strips and fans unrolled, wound as glTF winds them
    /// (counter-clockwise front faces).
    pub triangles: Vec<[u32; 3]>,
    /// Index into the file's `materials`; `None` for glTF's default material.
    pub material: Option<usize>,
}

impl Primitive {
    /// Drops the vertices no triangle uses (renumbering the triangles), so what is kept
    /// and placed is in proportion to the triangles: an accessor may hold far more
    /// vertices than its primitive's indices name. Most files use every vertex, and
    /// then nothing is copied.
    fn keep_used_vertices(&mut self) {
        let n = self.positions.len();
        let mut new_index = vec![u32::MAX; n];
        let mut used = 0u32;
        for t in &self.triangles {
            for &i in t {
                if new_index[i as usize] == u32::MAX {
                    new_index[i as usize] = used;
                    used += 1;
                }
            }
        }
        if used as usize == n && new_index.iter().enumerate().all(|(i, &k)| k as usize == i) {
            return;
        }
        fn keep<T: Copy>(v: &mut Vec<T>, new_index: &[u32], used: u32) {
            if v.is_empty() {
                return;
            }
            let mut out = vec![v[0]; used as usize];
            for (i, &k) in new_index.iter().enumerate() {
                if k != u32::MAX {
                    out[k as usize] = v[i];
                }
            }
            *v = out;
        }
        keep(&mut self.positions, &new_index, used);
        keep(&mut self.normals, &new_index, used);
        keep(&mut self.texcoords[0], &new_index, used);
        keep(&mut self.texcoords[1], &new_index, used);
        keep(&mut self.colors, &new_index, used);
        for t in &mut self.triangles {
            *t = t.map(|i| new_index[i as usize]);
        }
    }
}

/// Most bytes one file's meshes may decode in all (4 GiB, the most a file's buffers
/// hold): a small file can name one large accessor from many primitives, or fill a
/// sparse accessor with no bytes behind it.
pub const MAX_DECODED_BYTES: usize = 1 << 32;

/// What reading a file's meshes skipped and how much it has read.
#[derive(Clone, Copy, Debug, Default)]
pub struct Skipped {
    /// Primitives of points or lines.
    pub points_and_lines: usize,
    /// Bytes decoded so far, against [`MAX_DECODED_BYTES`].
    pub decoded: usize,
}

/// The triangle primitives of mesh `mesh`; `at` is its JSON path for messages.
pub fn read(
    document: &Document,
    buffers: &[Vec<u8>],
    mesh: &gltf::Mesh,
    skipped: &mut Skipped,
) -> std::result::Result<Vec<Primitive>, String> {
    let mut out = Vec::new();
    for p in mesh.primitives() {
        let at = format!("meshes[{}].primitives[{}]", mesh.index(), p.index());
        let mode = p.mode();
        if matches!(
            mode,
            Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
        ) {
            skipped.points_and_lines += 1;
            continue;
        }
        let attribute = |name: &str| p.get(&semantic(name));
        let Some(position) = attribute("POSITION") else {
            return Err(format!("{at}: no POSITION attribute"));
        };
        // What the reads below will hold, from the accessors' counts, before any read.
        let sizes = [
            ("POSITION", 12),
            ("NORMAL", 12),
            ("TEXCOORD_0", 8),
            ("TEXCOORD_1", 8),
            ("COLOR_0", 16),
        ]
        .into_iter()
        .filter_map(|(name, size)| attribute(name).map(|a| a.count().saturating_mul(size)))
        .chain(p.indices().map(|a| a.count().saturating_mul(4)));
        for bytes in sizes {
            skipped.decoded = skipped.decoded.saturating_add(bytes);
        }
        if skipped.decoded > MAX_DECODED_BYTES {
            return Err(format!(
                "{at}: the file's meshes would decode to more than {MAX_DECODED_BYTES} bytes"
            ));
        }
        let with = |what: &str, e: String| format!("{at}.attributes.{what}: {e}");
        let positions: Vec<Vec3> = read_floats::<3>(document, buffers, &position, &[3])
            .map_err(|e| with("POSITION", e))?
            .into_iter()
            .map(Vec3::from_array)
            .collect();
        if let Some(i) = positions.iter().position(|v| !v.is_finite()) {
            return Err(with("POSITION", format!("vertex {i} is not finite")));
        }
        let n = positions.len();
        let same_count = |what: &str, len: usize| {
            if len == n {
                Ok(())
            } else {
                Err(with(what, format!("{len} values for {n} positions")))
            }
        };
        let normals = match attribute("NORMAL") {
            Some(a) => {
                let v: Vec<Vec3> = read_floats::<3>(document, buffers, &a, &[3])
                    .map_err(|e| with("NORMAL", e))?
                    .into_iter()
                    .map(Vec3::from_array)
                    .collect();
                same_count("NORMAL", v.len())?;
                v
            }
            None => Vec::new(),
        };
        let mut texcoords: [Vec<[f32; 2]>; 2] = Default::default();
        for (k, name) in ["TEXCOORD_0", "TEXCOORD_1"].into_iter().enumerate() {
            if let Some(a) = attribute(name) {
                let v: Vec<[f32; 2]> = read_floats::<2>(document, buffers, &a, &[2])
                    .map_err(|e| with(name, e))?
                    .into_iter()
                    .map(|[u, v]| [u, 1.0 - v])
                    .collect();
                same_count(name, v.len())?;
                texcoords[k] = v;
            }
        }
        let colors = match attribute("COLOR_0") {
            Some(a) => {
                let v: Vec<Vec3> = read_floats::<4>(document, buffers, &a, &[3, 4])
                    .map_err(|e| with("COLOR_0", e))?
                    .into_iter()
                    .map(|[r, g, b, _]| Vec3::new(r, g, b))
                    .collect();
                same_count("COLOR_0", v.len())?;
                v
            }
            None => Vec::new(),
        };
        let indices = match p.indices() {
            Some(a) => {
                let v = read_indices(document, buffers, &a)
                    .map_err(|e| format!("{at}.indices: {e}"))?;
                if let Some(&bad) = v.iter().find(|&&i| i as usize >= n) {
                    return Err(format!(
                        "{at}.indices: index {bad} is past the primitive's {n} vertices"
                    ));
                }
                v
            }
            None => (0..n as u32).collect(),
        };
        let triangles = triangulate(mode, &indices);
        let mut primitive = Primitive {
            positions,
            normals,
            texcoords,
            colors,
            triangles,
            material: p.material().index(),
        };
        primitive.keep_used_vertices();
        out.push(primitive);
    }
    Ok(out)
}

fn semantic(name: &str) -> gltf::Semantic {
    match name {
        "POSITION" => gltf::Semantic::Positions,
        "NORMAL" => gltf::Semantic::Normals,
        "TEXCOORD_0" => gltf::Semantic::TexCoords(0),
        "TEXCOORD_1" => gltf::Semantic::TexCoords(1),
        _ => gltf::Semantic::Colors(0),
    }
}

/// The triangles of a list, strip or fan of vertex indices, wound as the spec says.
pub fn triangulate(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [idx[i], idx[i + 1], idx[i + 2]]
                } else {
                    [idx[i + 1], idx[i], idx[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..idx.len().saturating_sub(1))
            .map(|i| [idx[i], idx[i + 1], idx[0]])
            .collect(),
        _ => idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_wind_as_the_spec_says() {
        let i = [0, 1, 2, 3, 4];
        assert_eq!(
            triangulate(Mode::TriangleStrip, &i),
            [[0, 1, 2], [2, 1, 3], [2, 3, 4]]
        );
        assert_eq!(
            triangulate(Mode::TriangleFan, &i),
            [[1, 2, 0], [2, 3, 0], [3, 4, 0]]
        );
        assert_eq!(triangulate(Mode::Triangles, &[0, 1, 2, 3, 4]), [[0, 1, 2]]);
        assert!(triangulate(Mode::TriangleStrip, &[0, 1]).is_empty());
    }
}
