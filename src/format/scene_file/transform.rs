//! An object's placement: `scale`, then each `rotate` in order, then `translate`; or a
//! whole `matrix`. Computed in double precision and applied once to each vertex.

use super::raw::RawObject;
use super::source::Source;
use crate::error::Result;
use crate::math::Vec3;
use glam::{DMat3, DMat4, DVec3, DVec4};
use toml::Spanned;

/// Relative tolerance under which a transform counts as uniform (a similarity).
const UNIFORM_TOLERANCE: f64 = 1e-6;

#[derive(Clone, Copy, Debug)]
pub struct Transform {
    matrix: DMat4,
    /// The inverse transpose of the linear part: how normals transform.
    normal_matrix: DMat3,
}

impl Transform {
    pub fn new(source: &Source, raw: &RawObject) -> Result<Transform> {
        let mut m = DMat4::IDENTITY;
        if let Some(matrix) = &raw.matrix {
            if let Some((name, span)) = [
                ("translate", raw.translate.as_ref().map(Spanned::span)),
                ("rotate", raw.rotate.as_ref().map(Spanned::span)),
                ("scale", raw.scale.as_ref().map(Spanned::span)),
            ]
            .into_iter()
            .find_map(|(n, s)| s.map(|s| (n, s)))
            {
                return Err(source.error_at(
                    span,
                    format!(
                        "give `matrix` or `{name}`, not both: the matrix is the whole transform"
                    ),
                ));
            }
            let rows = matrix.get_ref().map(|row| row.map(|n| n.0));
            if rows[3] != [0.0, 0.0, 0.0, 1.0] {
                return Err(source.error(
                    matrix,
                    format!(
                        "expected the last row of the matrix to be [0, 0, 0, 1] (an affine \
                         transform), found {:?}",
                        rows[3]
                    ),
                ));
            }
            m = DMat4::from_cols_array_2d(&rows).transpose();
        } else {
            if let Some(s) = &raw.scale {
                m = DMat4::from_scale(s.get_ref().value);
            }
            if let Some(r) = &raw.rotate {
                for &[x, y, z, degrees] in &r.get_ref().0 {
                    let axis = DVec3::new(x, y, z);
                    if axis.length_squared() == 0.0 || !axis.normalize().is_finite() {
                        return Err(source.error(r, "expected a rotation axis that is not zero"));
                    }
                    m = DMat4::from_axis_angle(axis.normalize(), degrees.to_radians()) * m;
                }
            }
            if let Some(t) = &raw.translate {
                m = DMat4::from_translation(t.get_ref().0) * m;
            }
        }
        let linear = DMat3::from_mat4(m);
        let [c0, c1, c2] = [linear.x_axis, linear.y_axis, linear.z_axis];
        let det = linear.determinant();
        let volume = c0.length() * c1.length() * c2.length();
        if det.abs() <= 1e-12 * volume || !det.is_finite() {
            let at = raw
                .matrix
                .as_ref()
                .map(Spanned::span)
                .or(raw.scale.as_ref().map(Spanned::span))
                .unwrap_or(raw.kind.span());
            return Err(source.error_at(
                at,
                "the transform flattens the object (its determinant is 0): expected scales \
                 that are not zero",
            ));
        }
        Ok(Transform {
            matrix: m,
            normal_matrix: linear.inverse().transpose(),
        })
    }

    /// The transform `matrix` (affine, invertible).
    pub fn from_matrix(matrix: DMat4) -> Transform {
        Transform {
            matrix,
            normal_matrix: DMat3::from_mat4(matrix).inverse().transpose(),
        }
    }

    /// The whole transform.
    pub fn matrix(&self) -> DMat4 {
        self.matrix
    }

    pub fn point(&self, p: DVec3) -> Vec3 {
        let q = self.matrix * DVec4::new(p.x, p.y, p.z, 1.0);
        Vec3::new(q.x as f32, q.y as f32, q.z as f32)
    }

    pub fn point_f32(&self, p: Vec3) -> Vec3 {
        self.point(DVec3::new(p.x as f64, p.y as f64, p.z as f64))
    }

    /// A direction or edge: the linear part only.
    pub fn vector(&self, v: Vec3) -> Vec3 {
        let v = DMat3::from_mat4(self.matrix) * DVec3::new(v.x as f64, v.y as f64, v.z as f64);
        Vec3::new(v.x as f32, v.y as f32, v.z as f32)
    }

    /// A surface normal, by the inverse transpose, unit length.
    pub fn normal(&self, n: Vec3) -> Vec3 {
        let v = self.normal_matrix * DVec3::new(n.x as f64, n.y as f64, n.z as f64);
        Vec3::new(v.x as f32, v.y as f32, v.z as f32).normalize_or_zero()
    }

    /// The scale factor when the transform scales every direction alike (so a sphere
    /// stays a sphere), else `None`.
    pub fn uniform_scale(&self) -> Option<f64> {
        let l = DMat3::from_mat4(self.matrix);
        let g = l.transpose() * l;
        let s2 = (g.x_axis.x + g.y_axis.y + g.z_axis.z) / 3.0;
        let off = (g - DMat3::from_diagonal(DVec3::splat(s2))).to_cols_array();
        off.iter()
            .all(|v| v.abs() <= UNIFORM_TOLERANCE * s2)
            .then(|| s2.sqrt())
    }

    /// Whether the transform mirrors: triangles must then be rewound so their normals
    /// (and so inside and outside) stay as authored.
    pub fn mirrors(&self) -> bool {
        DMat3::from_mat4(self.matrix).determinant() < 0.0
    }
}

impl Transform {
    /// The scale of lengths on average: the cube root of the volume scale.
    pub fn volume_scale(&self) -> f64 {
        DMat3::from_mat4(self.matrix).determinant().abs().cbrt()
    }
}
