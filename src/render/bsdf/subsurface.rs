//! The medium under an OpenPBR subsurface: a homogeneous volume of extinction
//! `1 / (subsurface_radius × subsurface_radius_scale)` per channel and a
//! Henyey–Greenstein phase function of anisotropy `subsurface_scatter_anisotropy`,
//! whose single-scattering albedo is chosen so that a semi-infinite slab of it reflects
//! `subsurface_color` (van de Hulst's relation, inverted, as the specification gives
//! it). The path model walks through it (`render::path::subsurface`).

use crate::math::{Vec3, sin_cos};
use std::f32::consts::TAU;

/// The anisotropy is held inside this bound: near ±1 the phase function is a delta
/// and the walk never turns.
const MAX_ANISOTROPY: f32 = 0.95;

/// A homogeneous scattering medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Extinction per unit length, per channel.
    pub sigma_t: Vec3,
    /// Single-scattering albedo: the share of extinction that scatters.
    pub albedo: Vec3,
    /// Henyey–Greenstein anisotropy.
    pub g: f32,
}

impl Medium {
    /// The medium OpenPBR's subsurface parameters describe: observed colour `color`,
    /// mean free paths `mfp` (world units, per channel), anisotropy `g`. `None` where
    /// no channel has a positive free path (an infinitely dense medium: the diffuse
    /// lobe it tends to stands in).
    pub fn subsurface(color: Vec3, mfp: Vec3, g: f32) -> Option<Medium> {
        let longest = mfp.max_element();
        if !(longest > 0.0 && longest.is_finite()) {
            return None;
        }
        let g = if g.is_finite() {
            g.clamp(-MAX_ANISOTROPY, MAX_ANISOTROPY)
        } else {
            0.0
        };
        // A channel far denser than the others (or of no free path) is held to a
        // thousandth of the longest: its extinction stays finite.
        let mfp = mfp.max(Vec3::splat(longest * 1e-3));
        Some(Medium {
            sigma_t: Vec3::ONE / mfp,
            albedo: Vec3::new(
                single_scattering_albedo(color.x, g),
                single_scattering_albedo(color.y, g),
                single_scattering_albedo(color.z, g),
            ),
            g,
        })
    }

    /// Scattering per unit length, per channel.
    #[inline]
    pub fn sigma_s(&self) -> Vec3 {
        self.sigma_t * self.albedo
    }

    /// A new direction for light travelling along `dir` that scatters, drawn from the
    /// phase function itself (so the path's weight is unchanged by it).
    #[inline]
    pub fn scatter(&self, dir: Vec3, (u, v): (f32, f32)) -> Vec3 {
        let g = self.g;
        let cos = if g.abs() < 1e-3 {
            1.0 - 2.0 * u
        } else {
            let k = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
            ((1.0 + g * g - k * k) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (s, c) = sin_cos(v * TAU);
        let (t, b) = dir.any_orthonormal_pair();
        t * (sin * c) + b * (sin * s) + dir * cos
    }
}

/// The single-scattering albedo whose semi-infinite slab (index-matched) reflects
/// `color` in all: van de Hulst's relation `C = (1 - s)(1 - 0.139 s) / (1 + 1.17 s)`,
/// `s = sqrt((1 - α) / (1 - α g))`, inverted as the specification writes it.
pub fn single_scattering_albedo(color: f32, g: f32) -> f32 {
    let c = if color.is_finite() {
        color.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = 4.09712 + 4.20863 * c - (9.59217 + 41.6808 * c + 17.7126 * c * c).sqrt();
    let s2 = s * s;
    ((1.0 - s2) / (1.0 - g * s2)).clamp(0.0, 1.0)
}

/// Van de Hulst's reflectance of a semi-infinite slab of albedo `alpha` and anisotropy
/// `g`: what [`single_scattering_albedo`] inverts.
#[cfg(test)]
fn slab_reflectance(alpha: f32, g: f32) -> f32 {
    let s = ((1.0 - alpha) / (1.0 - alpha * g)).sqrt();
    (1.0 - s) * (1.0 - 0.139 * s) / (1.0 + 1.17 * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_albedo_inverts_van_de_hulsts_relation() {
        for g in [-0.5, 0.0, 0.3, 0.8] {
            for c in [0.05, 0.2, 0.5, 0.8, 0.95] {
                let alpha = single_scattering_albedo(c, g);
                let back = slab_reflectance(alpha, g);
                assert!(
                    (back - c).abs() < 2e-3,
                    "g {g}, C {c}: α {alpha} reflects {back}"
                );
            }
        }
        assert!(single_scattering_albedo(0.0, 0.0) < 1e-5);
        assert!(single_scattering_albedo(1.0, 0.0) > 0.99999);
    }

    #[test]
    fn a_medium_of_no_free_path_is_none_and_a_dense_channel_stays_finite() {
        assert_eq!(Medium::subsurface(Vec3::ONE, Vec3::ZERO, 0.0), None);
        assert_eq!(
            Medium::subsurface(Vec3::ONE, Vec3::splat(f32::NAN), 0.0),
            None
        );
        let m = Medium::subsurface(Vec3::splat(0.5), Vec3::new(2.0, 0.5, 0.0), 1.0).unwrap();
        let want = Vec3::new(0.5, 2.0, 500.0);
        assert!(
            ((m.sigma_t - want) / want).abs().max_element() < 1e-6,
            "{}",
            m.sigma_t
        );
        assert_eq!(m.g, MAX_ANISOTROPY);
    }

    /// The phase function's samples have mean cosine `g` to the direction of travel.
    #[test]
    fn scattered_directions_have_the_mean_cosine_g() {
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(5, 0x9e37_79b9_7f4a_7c15);
        let mut u = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
        let dir = crate::math::normalize(Vec3::new(0.3, -0.5, 0.8));
        for g in [-0.6, 0.0, 0.5, 0.9] {
            let m = Medium::subsurface(Vec3::ONE, Vec3::ONE, g).unwrap();
            let n = 200_000;
            let mean: f64 = (0..n)
                .map(|_| {
                    let w = m.scatter(dir, (u(), u()));
                    assert!((w.length() - 1.0).abs() < 1e-4);
                    w.dot(dir) as f64
                })
                .sum::<f64>()
                / n as f64;
            assert!((mean - g as f64).abs() < 5e-3, "g {g}: mean cosine {mean}");
        }
    }
}
