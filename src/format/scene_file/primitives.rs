//! The shapes of `[[object]]` types in their own coordinates: spheres, rectangles, and
//! triangles with smooth normals for the round shapes Prism has no exact primitive for.

use glam::DVec3;
use std::f64::consts::TAU;

/// Triangles around a disk or a cylinder. 64 keeps the silhouette within 0.12 % of the
/// radius (1 - cos(pi / 64)) while a capped cylinder stays at 256 triangles.
pub const SEGMENTS: u32 = 64;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    Sphere {
        center: DVec3,
        radius: f64,
    },
    Triangle([DVec3; 3]),
    /// A parallelogram `v0 v1 v2 v3`, facing `(v1 - v0) x (v3 - v0)`.
    Rectangle([DVec3; 4]),
}

/// Pieces in object space, with per-vertex normals and texture coordinates when every
/// piece is a triangle of a smooth surface.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Local {
    pub pieces: Vec<Piece>,
    pub normals: Vec<DVec3>,
    pub normal_indices: Vec<[u32; 3]>,
    pub texcoords: Vec<[f32; 2]>,
    pub texcoord_indices: Vec<[u32; 3]>,
}

/// `t1`, `t2` with `t1 x t2 = n` (unit `n`): the frame a disk or ring is drawn in.
fn frame(n: DVec3) -> (DVec3, DVec3) {
    let t1 = n.any_orthonormal_vector();
    (t1, n.cross(t1))
}

fn ring(i: u32) -> (f64, f64) {
    let a = TAU * f64::from(i % SEGMENTS) / f64::from(SEGMENTS);
    (a.cos(), a.sin())
}

pub fn sphere(center: DVec3, radius: f64) -> Local {
    Local {
        pieces: vec![Piece::Sphere { center, radius }],
        ..Local::default()
    }
}

pub fn triangle(v: [DVec3; 3]) -> Local {
    Local {
        pieces: vec![Piece::Triangle(v)],
        ..Local::default()
    }
}

/// The parallelogram `corner + s edge1 + t edge2`, `s, t` in `[0, 1]`, facing
/// `edge1 x edge2`.
pub fn quad(corner: DVec3, edge1: DVec3, edge2: DVec3) -> Local {
    Local {
        pieces: vec![Piece::Rectangle([
            corner,
            corner + edge1,
            corner + edge1 + edge2,
            corner + edge2,
        ])],
        ..Local::default()
    }
}

/// Six rectangles, each facing out of the box.
pub fn cuboid(min: DVec3, max: DVec3) -> Local {
    let d = max - min;
    let (x, y, z) = (DVec3::X * d.x, DVec3::Y * d.y, DVec3::Z * d.z);
    let face = |corner: DVec3, e1: DVec3, e2: DVec3| {
        Piece::Rectangle([corner, corner + e1, corner + e1 + e2, corner + e2])
    };
    Local {
        pieces: vec![
            face(min, y, x),     // -z
            face(min + z, x, y), // +z
            face(min, z, y),     // -x
            face(min + x, y, z), // +x
            face(min, x, z),     // -y
            face(min + y, z, x), // +y
        ],
        ..Local::default()
    }
}

/// A fan of [`SEGMENTS`] triangles around `center`, all sharing the normal `n`;
/// texture coordinates map the disk into the unit square.
pub fn disk(center: DVec3, n: DVec3, radius: f64) -> Local {
    let mut out = Local {
        normals: vec![n],
        texcoords: vec![[0.5, 0.5]],
        ..Local::default()
    };
    append_disk(&mut out, center, n, radius, 0);
    out
}

/// Appends a fan of [`SEGMENTS`] triangles around `center`, wound counter-clockwise
/// seen from the side `n` points to; `normal` indexes `out.normals`, and the last
/// texture coordinate is the centre's.
fn append_disk(out: &mut Local, center: DVec3, n: DVec3, radius: f64, normal: u32) {
    let (t1, t2) = frame(n);
    let centre_uv = out.texcoords.len() as u32 - 1;
    let first_uv = out.texcoords.len() as u32;
    for i in 0..SEGMENTS {
        let (c, s) = ring(i);
        out.texcoords
            .push([(0.5 + 0.5 * c) as f32, (0.5 + 0.5 * s) as f32]);
    }
    let at = |k: u32| {
        let (c, s) = ring(k);
        center + radius * (c * t1 + s * t2)
    };
    for i in 0..SEGMENTS {
        let j = (i + 1) % SEGMENTS;
        out.pieces.push(Piece::Triangle([center, at(i), at(j)]));
        out.normal_indices.push([normal; 3]);
        out.texcoord_indices
            .push([centre_uv, first_uv + i, first_uv + j]);
    }
}

/// The side of a cylinder from `base` to `top` as [`SEGMENTS`] quads of two triangles
/// with radial normals, and with `capped` a disk at each end.
pub fn cylinder(base: DVec3, top: DVec3, radius: f64, capped: bool) -> Local {
    let axis = (top - base).normalize();
    let (t1, t2) = frame(axis);
    let dir = |i: u32| {
        let (c, s) = ring(i);
        c * t1 + s * t2
    };
    let mut out = Local {
        normals: (0..SEGMENTS).map(dir).collect(),
        ..Local::default()
    };
    // Side texture coordinates: u around (a seam column at u = 1), v along the axis.
    for row in 0..2 {
        for i in 0..=SEGMENTS {
            out.texcoords.push([i as f32 / SEGMENTS as f32, row as f32]);
        }
    }
    let up = SEGMENTS + 1;
    for i in 0..SEGMENTS {
        let j = (i + 1) % SEGMENTS;
        let (b0, b1) = (base + radius * dir(i), base + radius * dir(j));
        let (t0, t1) = (top + radius * dir(i), top + radius * dir(j));
        out.pieces.push(Piece::Triangle([b0, b1, t1]));
        out.normal_indices.push([i, j, j]);
        out.texcoord_indices.push([i, i + 1, up + i + 1]);
        out.pieces.push(Piece::Triangle([b0, t1, t0]));
        out.normal_indices.push([i, j, i]);
        out.texcoord_indices.push([i, up + i + 1, up + i]);
    }
    if capped {
        for (center, n) in [(base, -axis), (top, axis)] {
            out.normals.push(n);
            out.texcoords.push([0.5, 0.5]);
            let normal = out.normals.len() as u32 - 1;
            append_disk(&mut out, center, n, radius, normal);
        }
    }
    out
}
