//! The diffuse base: energy-preserving Oren-Nayar (EON, Portsmouth et al. 2024, as
//! OpenPBR 1.1 specifies): Fujii's Oren-Nayar with a reciprocal term that returns what
//! single scattering between the V-cavities loses, so a white base of any roughness
//! reflects all it receives. Roughness 0 is Lambert exactly.

use crate::math::Vec3;
use std::f32::consts::{FRAC_1_PI, PI};

/// `1/2 - 2 / (3 pi)`: Fujii's A at roughness 1 is `1 / (1 + this)`.
const C1: f32 = 0.5 - 2.0 / (3.0 * PI);
/// `2/3 - 28 / (15 pi)`: the average albedo's slope.
const C2: f32 = 2.0 / 3.0 - 28.0 / (15.0 * PI);

/// The EON lobe of albedo parameter `rho` and roughness `sigma` for cosines `mu_o`,
/// `mu_i` (both > 0) and `cos_oi = wo.wi`, without the cosine factor.
#[inline]
pub fn eon(rho: Vec3, sigma: f32, mu_o: f32, mu_i: f32, cos_oi: f32) -> Vec3 {
    if sigma <= 0.0 {
        return rho * FRAC_1_PI;
    }
    let a = 1.0 / (1.0 + C1 * sigma);
    let s = cos_oi - mu_i * mu_o;
    let s_over_t = if s > 0.0 { s / mu_i.max(mu_o) } else { s };
    let single = rho * (FRAC_1_PI * a * (1.0 + sigma * s_over_t));
    let e_avg = a * (1.0 + C2 * sigma);
    let rho_ms = rho * rho * e_avg / (Vec3::ONE - rho * (1.0 - e_avg));
    let eps = 1e-7;
    let multiple = rho_ms
        * (FRAC_1_PI
            * (1.0 - fon_albedo(mu_o, sigma)).max(eps)
            * (1.0 - fon_albedo(mu_i, sigma)).max(eps)
            / (1.0 - e_avg).max(eps));
    single + multiple
}

/// The directional albedo of Fujii's Oren-Nayar lobe of unit `rho` at cosine `mu`
/// (exact, from the EON paper).
pub fn fon_albedo(mu: f32, sigma: f32) -> f32 {
    let mu = mu.clamp(1e-4, 1.0);
    let a = 1.0 / (1.0 + C1 * sigma);
    let b = sigma * a;
    let si = (1.0 - mu * mu).max(0.0).sqrt();
    let g = si * (mu.acos() - si * mu) + (2.0 / 3.0) * ((si / mu) * (1.0 - si * si * si) - si);
    a + b * FRAC_1_PI * g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::bsdf::cosine_hemisphere;

    /// ∫ f cos over the hemisphere, by cosine-weighted samples on a grid.
    fn albedo(rho: Vec3, sigma: f32, mu_o: f32) -> Vec3 {
        let wo = Vec3::new((1.0 - mu_o * mu_o).sqrt(), 0.0, mu_o);
        let n = 256;
        let mut sum = Vec3::ZERO;
        for a in 0..n {
            for b in 0..n {
                let u = ((a as f32 + 0.5) / n as f32, (b as f32 + 0.5) / n as f32);
                let wi = cosine_hemisphere(u);
                // f cos / (cos / pi)
                sum += eon(rho, sigma, mu_o, wi.z, wo.dot(wi)) * PI;
            }
        }
        sum / (n * n) as f32
    }

    #[test]
    fn a_white_base_of_any_roughness_reflects_everything() {
        for sigma in [0.0, 0.3, 1.0] {
            for mu in [1.0, 0.5, 0.1] {
                let e = albedo(Vec3::ONE, sigma, mu);
                assert!((e.x - 1.0).abs() < 5e-3, "sigma {sigma} mu {mu}: {e}");
            }
        }
    }

    #[test]
    fn roughness_zero_is_lambert_and_roughness_darkens_colours_slightly() {
        let rho = Vec3::new(0.8, 0.5, 0.2);
        assert_eq!(eon(rho, 0.0, 0.3, 0.9, 0.1), rho * FRAC_1_PI);
        let e = albedo(rho, 1.0, 0.8);
        assert!(e.x < 0.8 && e.x > 0.7 && e.z < 0.2, "{e}");
    }

    #[test]
    fn the_lobe_is_reciprocal() {
        let rho = Vec3::new(0.8, 0.5, 0.2);
        let (a, b) = (eon(rho, 0.7, 0.3, 0.9, 0.2), eon(rho, 0.7, 0.9, 0.3, 0.2));
        assert!((a - b).abs().max_element() < 1e-6);
    }
}
