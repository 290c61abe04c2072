//! The fuzz (sheen) layer: the "Charlie" distribution of fibres (Estevez and Kulla
//! 2017) with Neubelt and Pettineo's visibility term, as glTF's KHR_materials_sheen
//! defines it. OpenPBR 1.1 specifies Zeltner et al.'s fitted LTC lobe instead; this
//! lobe has the same role and layering (docs/materials.md tables the difference).

use crate::math::Vec3;
use std::f32::consts::TAU;

/// The lobe of a white fuzz of roughness `r` (0 to 1) for `wo`, `wi` above the
/// surface (local frame), without the cosine.
#[inline]
pub fn sheen(r: f32, wo: Vec3, wi: Vec3) -> f32 {
    let (mu_o, mu_i) = (wo.z, wi.z);
    if mu_o <= 0.0 || mu_i <= 0.0 {
        return 0.0;
    }
    let h = (wo + wi).normalize_or_zero();
    let alpha = (r * r).max(1e-3);
    let inv = 1.0 / alpha;
    let sin2 = (1.0 - h.z * h.z).max(0.0);
    let d = (2.0 + inv) * sin2.powf(0.5 * inv) / TAU;
    let v = 1.0 / (4.0 * (mu_i + mu_o - mu_i * mu_o));
    d * v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fuzz_reflects_less_than_it_receives_and_most_at_grazing_views() {
        let albedo = |mu: f32, r: f32| crate::render::bsdf::albedo::fuzz(mu, r);
        for r in [0.2, 0.5, 1.0] {
            for mu in [0.1, 0.5, 1.0] {
                let e = albedo(mu, r);
                assert!(e > 0.0 && e < 1.0, "{r} {mu}: {e}");
            }
            assert!(albedo(0.1, r) > albedo(1.0, r), "{r}");
        }
        let (wo, wi) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.3, 0.2, 0.93));
        let wi = crate::math::normalize(wi);
        assert!((sheen(0.5, wo, wi) - sheen(0.5, wi, wo)).abs() < 1e-6);
    }
}
