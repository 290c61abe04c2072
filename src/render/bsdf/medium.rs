//! The homogeneous media an OpenPBR surface may hold, each of an extinction per
//! channel, a single-scattering albedo and a Henyey–Greenstein phase function:
//!
//! - under a subsurface ([`Medium::subsurface`]): extinction
//!   `1 / (subsurface_radius × subsurface_radius_scale)`, and the albedo whose
//!   semi-infinite slab reflects `subsurface_color` (van de Hulst's relation, inverted,
//!   as the specification gives it). The path model walks through it from where the
//!   BSDF sends light in to where it leaves (`render::path::subsurface`);
//! - inside a transmissive solid ([`Medium::transmission`]): `transmission_color` after
//!   `transmission_depth` sets the extinction, `transmission_scatter` the scattering.
//!   The path model flies through it between the solid's surfaces
//!   (`render::path::interior`).
//!
//! Both are crossed by the same free flights ([`Medium::flight`], [`Medium::weigh`]).

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
        let g = anisotropy(g);
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

    /// The medium inside a transmissive solid, as the specification builds it:
    /// extinction `-ln(color) / depth`, scattering `scatter / depth`, and where the
    /// absorption left over would be negative in a channel, grey added to all three so
    /// it is not. `None` where nothing scatters (Beer's absorption alone is the
    /// surface's `absorption`) or without a depth (the colour is then a tint).
    pub fn transmission(color: Vec3, depth: f32, scatter: Vec3, g: f32) -> Option<Medium> {
        if !(depth > 0.0 && depth.is_finite() && scatter.is_finite()) {
            return None;
        }
        let sigma_s = scatter.max(Vec3::ZERO) / depth;
        if sigma_s.max_element() <= 0.0 {
            return None;
        }
        let c = if color.is_finite() {
            color.clamp(Vec3::splat(1e-6), Vec3::ONE)
        } else {
            Vec3::ONE
        };
        let mu_t = -Vec3::new(c.x.ln(), c.y.ln(), c.z.ln()) / depth;
        let mut mu_a = mu_t - sigma_s;
        let lowest = mu_a.min_element();
        if lowest < 0.0 {
            mu_a -= Vec3::splat(lowest);
        }
        let sigma_t = mu_a + sigma_s;
        if !sigma_t.is_finite() {
            return None;
        }
        let albedo = Vec3::new(
            ratio(sigma_s.x, sigma_t.x),
            ratio(sigma_s.y, sigma_t.y),
            ratio(sigma_s.z, sigma_t.z),
        );
        Some(Medium {
            sigma_t,
            albedo,
            g: anisotropy(g),
        })
    }

    /// A free flight for light of throughput `beta`: one colour channel chosen by the
    /// share of `beta` it carries (`u`), the distance drawn by that channel's
    /// extinction (`v`). The flight's density is then the throughput-weighed mean of
    /// the channels', and the sum of the channels' weights cannot grow from one flight
    /// to the next. `None` where `beta` carries nothing.
    #[inline]
    pub fn flight(&self, beta: Vec3, u: f32, v: f32) -> Option<f32> {
        let total = beta.x + beta.y + beta.z;
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let u = u * total;
        let c = if u < beta.x {
            0
        } else if u < beta.x + beta.y || beta.z <= 0.0 {
            1
        } else {
            2
        };
        Some(-(1.0 - v).ln() / self.sigma_t[c])
    }

    /// The throughput `beta` after a [`Medium::flight`] of `t`: ended by scattering
    /// there (`scattered`: the density of stopping at `t` times what scatters), or
    /// carried through to a surface at `t` (the chance of flying that far). `None`
    /// where nothing is left.
    #[inline]
    pub fn weigh(&self, beta: Vec3, t: f32, scattered: bool) -> Option<Vec3> {
        let total = beta.x + beta.y + beta.z;
        let tr = (-self.sigma_t * t).exp();
        let (chance, kept) = if scattered {
            (beta.dot(self.sigma_t * tr), self.sigma_s() * tr)
        } else {
            (beta.dot(tr), tr)
        };
        if chance.is_nan() || chance <= 0.0 {
            return None;
        }
        let beta = beta * kept * (total / chance);
        (beta.is_finite() && beta.max_element() > 0.0).then_some(beta)
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

/// A phase function's anisotropy held inside [`MAX_ANISOTROPY`].
fn anisotropy(g: f32) -> f32 {
    if g.is_finite() {
        g.clamp(-MAX_ANISOTROPY, MAX_ANISOTROPY)
    } else {
        0.0
    }
}

/// `a / b`, zero where `b` is.
fn ratio(a: f32, b: f32) -> f32 {
    if b > 0.0 { (a / b).min(1.0) } else { 0.0 }
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

    /// The specification's construction: extinction from the colour after the depth,
    /// scattering from `transmission_scatter` over it, and grey added to an absorption
    /// that would fall below zero.
    #[test]
    fn a_transmission_medium_is_built_as_the_specification_builds_it() {
        let color = Vec3::new(0.5, 0.7, 0.9);
        let m = Medium::transmission(color, 2.0, Vec3::new(0.2, 0.1, 0.0), 0.3).unwrap();
        let mu_t = -Vec3::new(color.x.ln(), color.y.ln(), color.z.ln()) / 2.0;
        assert!(
            (m.sigma_t - mu_t).abs().max_element() < 1e-6,
            "{}",
            m.sigma_t
        );
        let sigma_s = Vec3::new(0.1, 0.05, 0.0);
        assert!((m.sigma_s() - sigma_s).abs().max_element() < 1e-6);
        assert_eq!(m.g, 0.3);
        // Scatter above the extinction: blue's absorption is lifted to zero, the
        // others by as much.
        let m = Medium::transmission(color, 1.0, Vec3::splat(0.5), 0.0).unwrap();
        let lift = 0.5 - mu_t.z * 2.0;
        let want = mu_t * 2.0 + Vec3::splat(lift);
        assert!(
            (m.sigma_t - want).abs().max_element() < 1e-6,
            "{}",
            m.sigma_t
        );
        assert!((m.albedo.z - 1.0).abs() < 1e-6 && m.albedo.x < 1.0);
        // Nothing scatters, or no depth: no medium (Beer's absorption, or a tint).
        assert_eq!(Medium::transmission(color, 1.0, Vec3::ZERO, 0.0), None);
        assert_eq!(Medium::transmission(color, 0.0, Vec3::ONE, 0.0), None);
        assert_eq!(Medium::transmission(color, f32::NAN, Vec3::ONE, 0.0), None);
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
