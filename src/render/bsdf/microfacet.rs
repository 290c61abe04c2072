//! GGX (Trowbridge-Reitz) microfacets, anisotropic, with height-correlated Smith
//! masking-shadowing and sampling of the normals a direction sees (Heitz 2018, in
//! Dupuy and Benyoub's spherical-cap form, 2023). Directions are in the shading frame,
//! the normal +z.

use crate::math::{Vec3, sin_cos};
use std::f32::consts::{FRAC_1_PI, TAU};

/// Smallest `alpha`: below it a lobe is treated as a perfect mirror (a delta), where
/// the distribution's peak `1 / (pi alpha^2)` would overflow what f32 sums keep.
pub const MIN_ALPHA: f32 = 1e-3;

/// A GGX distribution of microfacet normals with roughness `ax` along x, `ay` along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// Roughness along the tangent.
    pub ax: f32,
    /// Roughness along the bitangent.
    pub ay: f32,
}

impl Ggx {
    /// The distribution of perceptual roughness `r` and anisotropy `aniso` (OpenPBR's
    /// mapping: `alpha = r^2`, stretched along the tangent by `sqrt(2 / (1 + (1 -
    /// aniso)^2))` and shrunk across it by `1 - aniso` of that).
    pub fn from_roughness(r: f32, aniso: f32) -> Ggx {
        let a = r * r;
        if aniso <= 0.0 {
            return Ggx { ax: a, ay: a };
        }
        let k = 1.0 - aniso.min(1.0);
        let ax = a * (2.0 / (1.0 + k * k)).sqrt();
        Ggx { ax, ay: k * ax }
    }

    /// Whether the surface is smooth enough to be a perfect mirror.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.ax.max(self.ay) < MIN_ALPHA
    }

    /// The density of microfacet normal `m` (per projected area: ∫ D cos = 1).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.ax, m.y / self.ay);
        let k = x * x + y * y + m.z * m.z;
        FRAC_1_PI / (self.ax * self.ay * k * k)
    }

    /// Smith's Λ for direction `w`.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 <= 0.0 {
            return f32::INFINITY;
        }
        let a2 = (self.ax * w.x) * (self.ax * w.x) + (self.ay * w.y) * (self.ay * w.y);
        ((1.0 + a2 / z2).sqrt() - 1.0) * 0.5
    }

    /// The masking of one direction.
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking and shadowing of a pair.
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// A microfacet normal drawn with the density of the normals `wo` sees
    /// ([`Ggx::visible_pdf`]), from `u` uniform in the square. `wo.z > 0`.
    pub fn sample_visible(&self, wo: Vec3, (u, v): (f32, f32)) -> Vec3 {
        // Stretch to the unit hemisphere, sample a spherical cap, unstretch.
        let wh = Vec3::new(self.ax * wo.x, self.ay * wo.y, wo.z).normalize_or_zero();
        let (s, c) = sin_cos(u * TAU);
        let z = (1.0 - v) * (1.0 + wh.z) - wh.z;
        let r = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
        let h = Vec3::new(r * c, r * s, z) + wh;
        Vec3::new(self.ax * h.x, self.ay * h.y, h.z.max(0.0)).normalize_or_zero()
    }

    /// The density of visible normal `m` seen from `wo` (per solid angle of `m`).
    #[inline]
    pub fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        let om = wo.dot(m);
        if om <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * om * self.d(m) / wo.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// ∫ D(m) cos(m) dm = 1 and ∫ G1(wo) max(0, wo.m) D(m) dm = wo.z, by a Riemann sum.
    #[test]
    fn the_distribution_and_its_visible_normals_are_normalised() {
        for g in [
            Ggx { ax: 0.3, ay: 0.3 },
            Ggx { ax: 0.6, ay: 0.2 },
            Ggx::from_roughness(0.9, 0.5),
        ] {
            let wo = dir(1.0, 0.7);
            let (n_t, n_p) = (2000, 400);
            let (mut proj, mut vis) = (0.0f64, 0.0f64);
            for i in 0..n_t {
                let t = (i as f32 + 0.5) / n_t as f32 * std::f32::consts::FRAC_PI_2;
                for j in 0..n_p {
                    let p = (j as f32 + 0.5) / n_p as f32 * TAU;
                    let m = dir(t, p);
                    let dw = t.sin() as f64
                        * (std::f64::consts::FRAC_PI_2 / n_t as f64)
                        * (std::f64::consts::TAU / n_p as f64);
                    proj += (g.d(m) * m.z) as f64 * dw;
                    vis += g.visible_pdf(wo, m) as f64 * dw;
                }
            }
            assert!((proj - 1.0).abs() < 2e-3, "{g:?}: {proj}");
            assert!((vis - 1.0).abs() < 2e-3, "{g:?}: {vis}");
        }
    }

    #[test]
    fn anisotropy_keeps_the_mean_roughness_and_stretches_along_the_tangent() {
        let g = Ggx::from_roughness(0.5, 0.0);
        assert_eq!((g.ax, g.ay), (0.25, 0.25));
        let a = Ggx::from_roughness(0.5, 0.6);
        assert!(a.ax > 0.25 && a.ay < 0.25);
        assert!(((a.ax * a.ax + a.ay * a.ay) / 2.0 - 0.0625).abs() < 1e-6);
    }
}
