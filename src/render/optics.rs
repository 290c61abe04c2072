//! Optics both shading models rely on, in their physical form: Snell's law and the
//! exact dielectric Fresnel reflectance.

use crate::math::{Vec3, normalize};

/// Direction of `d` refracted through a surface with unit normal `n` facing the side `d`
/// comes from (`d.n < 0`), from index `eta_i` into `eta_t`; `None` past the critical
/// angle (total internal reflection).
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
    let eta = eta_i / eta_t;
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(normalize(eta * d + (eta * cos_i - cos_t) * n))
}

/// Fresnel reflectance of an unpolarised wave meeting a dielectric boundary at
/// incidence cosine `cos_i` (0..1), from index `eta_i` into `eta_t`: the mean of the s
/// and p reflectances, 1 past the critical angle.
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (eta_i / eta_t).powi(2) * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    let f = 0.5 * (rs * rs + rp * rp);
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_at_normal_incidence_is_the_closed_form() {
        // ((n1 - n2) / (n1 + n2))^2: 0.04 for air to glass of index 1.5.
        assert!((fresnel_dielectric(1.0, 1.0, 1.5) - 0.04).abs() < 1e-7);
        assert!((fresnel_dielectric(1.0, 1.5, 1.0) - 0.04).abs() < 1e-7);
        assert!((fresnel_dielectric(1.0, 1.0, 1.33) - (0.33f32 / 2.33).powi(2)).abs() < 1e-7);
    }

    #[test]
    fn fresnel_at_45_degrees_matches_the_s_and_p_formulas() {
        // Air to glass 1.5 at 45 degrees: sin t = sin 45 / 1.5.
        let ci = std::f64::consts::FRAC_1_SQRT_2;
        let st = ci / 1.5;
        let ct = (1.0 - st * st).sqrt();
        let rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
        let rp = (1.5 * ci - ct) / (1.5 * ci + ct);
        let expected = 0.5 * (rs * rs + rp * rp); // 0.0502...
        let f = fresnel_dielectric(ci as f32, 1.0, 1.5);
        assert!((f64::from(f) - expected).abs() < 1e-6, "{f} vs {expected}");
        assert!((expected - 0.050_23).abs() < 1e-4);
    }

    #[test]
    fn past_the_critical_angle_everything_reflects() {
        // Glass to air: critical angle asin(1/1.5) = 41.8 degrees.
        let critical = (1.0f32 / 1.5).asin();
        let beyond = (critical + 0.01).cos();
        let before = (critical - 0.01).cos();
        assert_eq!(fresnel_dielectric(beyond, 1.5, 1.0), 1.0);
        assert!(fresnel_dielectric(before, 1.5, 1.0) < 1.0);
        let d = Vec3::new((critical + 0.01).sin(), -(critical + 0.01).cos(), 0.0);
        assert_eq!(refract(d, Vec3::Y, 1.5, 1.0), None);
    }

    #[test]
    fn snell_holds_and_normal_incidence_goes_straight() {
        let d = Vec3::new(0.6, -0.8, 0.0);
        let t = refract(d, Vec3::Y, 1.0, 1.5).unwrap();
        assert!((t.x * 1.5 - d.x).abs() < 1e-6, "{t}");
        assert!(t.y < 0.0 && (t.length() - 1.0).abs() < 1e-6);
        assert_eq!(refract(-Vec3::Y, Vec3::Y, 1.0, 1.5).unwrap(), -Vec3::Y);
    }
}
