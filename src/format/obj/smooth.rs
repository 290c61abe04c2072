//! Vertex normals for smoothing groups (`s N`): faces without `vn` in one non-zero group
//! share, at each position, the area-weighted mean of their face normals. Area weights
//! come free from the unnormalised cross product, and a sliver between two large faces
//! then barely bends the shared normal.

use super::ObjTriangle;
use crate::math::{Vec3, cross};

/// Gives every triangle without normals and with a smoothing group `vn` indices into
/// new normals appended to `normals`: one per (position, group) pair.
pub fn smooth_normals(positions: &[Vec3], triangles: &mut [ObjTriangle], normals: &mut Vec<Vec3>) {
    // (group << 32 | position, corner = 3 * triangle + k), sorted so each run is one
    // shared vertex: no hash map, and memory linear in the corners.
    let mut corners: Vec<(u64, usize)> = Vec::new();
    for (t, triangle) in triangles.iter().enumerate() {
        if triangle.vn.is_none() && triangle.smoothing != 0 {
            for (k, &v) in triangle.v.iter().enumerate() {
                corners.push(((triangle.smoothing as u64) << 32 | v as u64, 3 * t + k));
            }
        }
    }
    if corners.is_empty() {
        return;
    }
    corners.sort_unstable();
    let face_normal = |t: usize| {
        let [a, b, c] = triangles[t].v.map(|i| positions[i as usize]);
        cross(b - a, c - a)
    };
    let mut assigned: Vec<(usize, u32)> = Vec::with_capacity(corners.len());
    for run in corners.chunk_by(|a, b| a.0 == b.0) {
        let sum: Vec3 = run.iter().map(|&(_, corner)| face_normal(corner / 3)).sum();
        let normal = sum.try_normalize().unwrap_or_else(|| {
            // Faces that cancel out or have no area: the first usable face normal.
            run.iter()
                .find_map(|&(_, corner)| face_normal(corner / 3).try_normalize())
                .unwrap_or(Vec3::Z)
        });
        let index = normals.len() as u32;
        normals.push(normal);
        assigned.extend(run.iter().map(|&(_, corner)| (corner, index)));
    }
    for (corner, index) in assigned {
        let triangle = &mut triangles[corner / 3];
        let vn = triangle.vn.get_or_insert([u32::MAX; 3]);
        vn[corner % 3] = index;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;

    fn triangle(v: [u32; 3], smoothing: u32) -> ObjTriangle {
        ObjTriangle {
            v,
            vt: None,
            vn: None,
            material: None,
            smoothing,
        }
    }

    #[test]
    fn shared_positions_average_the_faces_of_their_group_by_area() {
        // A roof: a 2x1 slope facing +x+z and a 1x1 slope facing -x+z, sharing the ridge
        // (positions 1 and 2); a flat triangle (group 0) and one of group 2 also touch it.
        let positions = [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 2.0, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ];
        let mut triangles = vec![
            triangle([0, 1, 2], 1),
            triangle([1, 3, 4], 1),
            triangle([1, 4, 2], 1),
            triangle([0, 1, 2], 0),
            triangle([0, 1, 2], 2),
        ];
        let mut normals = vec![Vec3::X];
        smooth_normals(&positions, &mut triangles, &mut normals);
        // Left face: normal (-1, 0, 1)·1 per unit area, area sqrt(2); the right pair:
        // (1, 0, 1), area 2 sqrt(2). The ridge at 1 sees both right triangles.
        let left = cross(positions[1] - positions[0], positions[2] - positions[0]);
        assert_eq!(left, Vec3::new(-2.0, 0.0, 2.0));
        let ridge = normalize(Vec3::new(-2.0, 0.0, 2.0) + Vec3::new(2.0, 0.0, 2.0) * 2.0);
        let n = |t: usize, k: usize| normals[triangles[t].vn.unwrap()[k] as usize];
        assert_eq!(n(0, 1), ridge);
        assert_eq!(n(1, 0), ridge);
        assert_eq!(n(2, 0), ridge);
        assert_eq!(n(0, 0), normalize(Vec3::new(-2.0, 0.0, 2.0)));
        assert_eq!(n(1, 1), normalize(Vec3::new(2.0, 0.0, 2.0)));
        assert_eq!(n(0, 2), Vec3::Z);
        // Group 0 stays flat; group 2 does not share with group 1.
        assert_eq!(triangles[3].vn, None);
        assert_eq!(n(4, 1), normalize(Vec3::new(-2.0, 0.0, 2.0)));
        // One normal per (position, group): 5 in group 1, 3 in group 2, after the file's.
        assert_eq!(normals.len(), 1 + 5 + 3);
        assert_eq!(normals[0], Vec3::X);
    }

    #[test]
    fn faces_with_their_own_normals_and_degenerate_faces_are_handled() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::X];
        let mut triangles = vec![triangle([0, 1, 2], 1)];
        let mut with_vn = triangle([0, 1, 2], 1);
        with_vn.vn = Some([0, 0, 0]);
        triangles.push(with_vn);
        let mut normals = vec![Vec3::Y];
        smooth_normals(&positions, &mut triangles, &mut normals);
        assert_eq!(triangles[1].vn, Some([0, 0, 0]));
        assert_eq!(triangles[0].vn, Some([1, 2, 3]));
        assert_eq!(&normals[1..], [Vec3::Z, Vec3::Z, Vec3::Z]);
    }
}
