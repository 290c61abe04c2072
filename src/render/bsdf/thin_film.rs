//! Thin-film interference (iridescence) on a dielectric: the reflectance of a film of
//! index `n2` and thickness `d` over a substrate, summed over the film's internal
//! reflections (Airy's formula), for the s and p polarisations, at one wavelength per
//! channel (620, 540 and 450 nm, as the reference implementation takes them).

use crate::math::Vec3;
use std::f32::consts::PI;

/// The wavelengths, in nanometres, the red, green and blue channels stand for.
pub const WAVELENGTHS: [f32; 3] = [620.0, 540.0, 450.0];

/// Reflectance at incidence cosine `cos` (from index 1) of a film of index `film`
/// and thickness `nm` over a substrate of index `base`. Where light cannot enter the
/// film or leave it into the substrate, the plain interface's reflectance stands.
pub fn reflectance(cos: f32, film: f32, base: f32, nm: f32) -> Vec3 {
    let cos1 = cos.clamp(0.0, 1.0);
    let sin2_1 = 1.0 - cos1 * cos1;
    let sin2_2 = sin2_1 / (film * film);
    let sin2_3 = sin2_1 / (base * base);
    if sin2_2 >= 1.0 || sin2_3 >= 1.0 {
        return Vec3::splat(crate::render::optics::fresnel_dielectric(cos1, 1.0, base));
    }
    let cos2 = (1.0 - sin2_2).sqrt();
    let cos3 = (1.0 - sin2_3).sqrt();
    let r12s = (cos1 - film * cos2) / (cos1 + film * cos2);
    let r12p = (film * cos1 - cos2) / (film * cos1 + cos2);
    let r23s = (film * cos2 - base * cos3) / (film * cos2 + base * cos3);
    let r23p = (base * cos2 - film * cos3) / (base * cos2 + film * cos3);
    let airy = |r12: f32, r23: f32, c: f32| {
        let x = 2.0 * r12 * r23 * c;
        ((r12 * r12 + r23 * r23 + x) / (1.0 + r12 * r12 * r23 * r23 + x)).clamp(0.0, 1.0)
    };
    Vec3::from_array(WAVELENGTHS.map(|lambda| {
        let phase = 4.0 * PI * film * nm * cos2 / lambda;
        let c = phase.cos();
        0.5 * (airy(r12s, r23s, c) + airy(r12p, r23p, c))
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::optics::fresnel_dielectric;

    #[test]
    fn a_film_of_no_thickness_is_the_bare_interface() {
        for cos in [1.0, 0.7, 0.3] {
            let r = reflectance(cos, 1.33, 1.5, 0.0);
            let f = fresnel_dielectric(cos, 1.0, 1.5);
            assert!(
                (r - Vec3::splat(f)).abs().max_element() < 1e-6,
                "{cos}: {r} {f}"
            );
        }
    }

    #[test]
    fn a_quarter_wave_film_of_the_mean_index_reflects_nothing_at_its_wavelength() {
        // n2 = sqrt(n3), d = lambda / (4 n2): the two reflections cancel at normal
        // incidence for green (540 nm) and not for red or blue.
        let base = 1.69f32;
        let film = base.sqrt();
        let r = reflectance(1.0, film, base, 540.0 / (4.0 * film));
        assert!(r.y < 1e-6, "{r}");
        assert!(r.x > 1e-3 && r.z > 1e-3, "{r}");
    }
}
