use super::*;
use crate::scene::OpenPbr;

/// A small deterministic generator for test draws (splitmix64).
struct Rng(u64);

impl Rng {
    fn f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn view(deg: f32) -> Vec3 {
    let t = deg.to_radians();
    Vec3::new(t.sin(), 0.0, t.cos())
}

fn params(set: impl FnOnce(&mut OpenPbr)) -> Params {
    let mut m = OpenPbr::default();
    set(&mut m);
    Params::of(&m, Vec3::ONE)
}

/// The directional albedo at `wo`: the mean of the sampled weights (deltas included),
/// as energy: light that crosses into a solid is counted without the radiance scale.
fn albedo(p: &Params, wo: Vec3, outside: bool, n: usize) -> Vec3 {
    let b = OpenPbrBsdf::new(p, wo, outside);
    let unscale = if b.thin { 1.0 } else { b.eta * b.eta };
    let mut rng = Rng(7);
    let mut sum = Vec3::ZERO;
    for _ in 0..n {
        let pick = rng.f32();
        let u = (rng.f32(), rng.f32());
        if let Some(s) = b.sample(pick, u) {
            sum += s.weight * if s.wi.z < 0.0 { unscale } else { 1.0 };
        }
    }
    sum / n as f32
}

#[test]
fn white_furnace_rough_metal_clear_glass_and_white_plastic_keep_all_light() {
    let cases: Vec<(&str, Params)> = vec![
        (
            "rough white metal",
            params(|m| {
                m.base_metalness.value = 1.0;
                m.specular_roughness.value = 0.7;
            }),
        ),
        (
            "rough clear glass",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.5;
            }),
        ),
        (
            "rough diamond",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.8;
                m.specular_ior.value = 2.42;
            }),
        ),
        (
            "smooth clear glass",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.0;
            }),
        ),
        (
            "thin-walled rough glass",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.4;
                m.geometry_thin_walled = true;
            }),
        ),
        (
            "white rough plastic, rough diffuse",
            params(|m| {
                m.specular_roughness.value = 0.6;
                m.base_diffuse_roughness.value = 1.0;
            }),
        ),
        (
            "white fuzz over white plastic",
            params(|m| {
                m.fuzz_weight.value = 1.0;
                m.fuzz_roughness.value = 0.6;
            }),
        ),
        (
            "rough glass under a thin film",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.3;
                m.thin_film_weight.value = 1.0;
                m.thin_film_thickness.value = 0.4;
            }),
        ),
        (
            "smooth glass under a thin film",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.0;
                m.thin_film_weight.value = 1.0;
                m.thin_film_thickness.value = 0.4;
            }),
        ),
        (
            "white plastic under a rough clear coat",
            params(|m| {
                m.coat_weight.value = 1.0;
                m.coat_roughness.value = 0.4;
            }),
        ),
    ];
    for (name, p) in &cases {
        for deg in [0.0, 45.0, 75.0] {
            let e = albedo(p, view(deg), true, 200_000);
            assert!(
                (e - Vec3::ONE).abs().max_element() < 0.03,
                "{name} at {deg} degrees: {e}"
            );
        }
    }
    // Glass seen from inside passes the furnace too.
    let glass = &cases[1].1;
    let e = albedo(glass, view(30.0), false, 200_000);
    assert!((e - Vec3::ONE).abs().max_element() < 0.03, "inside: {e}");
}

#[test]
fn an_opaque_surface_seen_from_behind_is_shaded_as_from_the_front() {
    // An open mesh or a plane: its back is not the inside of a solid.
    for p in [
        Params::of(&OpenPbr::default(), Vec3::new(0.8, 0.1, 0.1)),
        params(|m| {
            m.base_metalness.value = 1.0;
            m.specular_roughness.value = 0.5;
        }),
    ] {
        let (front, back) = (
            OpenPbrBsdf::new(&p, view(30.0), true),
            OpenPbrBsdf::new(&p, view(30.0), false),
        );
        for wi in [view(-20.0), view(60.0), Vec3::new(0.3, 0.4, -0.866)] {
            assert_eq!(front.eval_pdf(wi), back.eval_pdf(wi), "{wi}");
        }
        assert_eq!(back.deltas().1, Vec3::ZERO, "nothing crosses");
    }
}

/// `∫ f |cos| dwi` over the sphere by uniform directions equals the sampled albedo of
/// the smooth lobes: `eval` and `sample` describe the same lobes.
#[test]
fn eval_integrates_to_what_sample_returns() {
    let p = params(|m| {
        m.base_metalness.value = 0.3;
        m.specular_roughness.value = 0.5;
        m.transmission_weight.value = 0.4;
        m.coat_weight.value = 0.5;
        m.coat_roughness.value = 0.3;
        m.base_diffuse_roughness.value = 0.5;
    });
    let wo = view(40.0);
    let b = OpenPbrBsdf::new(&p, wo, true);
    let mut rng = Rng(3);
    let n = 400_000;
    let mut by_eval = Vec3::ZERO;
    for _ in 0..n {
        let wi = super::super::uniform_sphere((rng.f32(), rng.f32()));
        let (f, _) = b.eval_pdf(wi);
        let energy = if wi.z < 0.0 { b.eta * b.eta } else { 1.0 };
        by_eval += f * (wi.z.abs() * 4.0 * std::f32::consts::PI * energy);
    }
    let by_eval = by_eval / n as f32;
    let by_sample = albedo(&p, wo, true, n);
    assert!(
        (by_eval - by_sample).abs().max_element() < 0.02,
        "{by_eval} vs {by_sample}"
    );
}

/// Chi-square of the sampled directions against `pdf`, on a grid over the sphere.
#[test]
fn sampling_follows_the_pdf() {
    let lobes: Vec<(&str, Params)> = vec![
        ("diffuse", params(|m| m.specular_weight.value = 0.0)),
        (
            "rough diffuse",
            params(|m| {
                m.specular_weight.value = 0.0;
                m.base_diffuse_roughness.value = 1.0;
            }),
        ),
        (
            "anisotropic metal",
            params(|m| {
                m.base_metalness.value = 1.0;
                m.specular_roughness.value = 0.5;
                m.specular_roughness_anisotropy.value = 0.7;
            }),
        ),
        (
            "rough glass",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.4;
            }),
        ),
        (
            "thin rough glass",
            params(|m| {
                m.transmission_weight.value = 1.0;
                m.specular_roughness.value = 0.4;
                m.geometry_thin_walled = true;
            }),
        ),
        (
            "fuzz over a dark base",
            params(|m| {
                m.fuzz_weight.value = 1.0;
                m.fuzz_roughness.value = 0.4;
                m.specular_weight.value = 0.0;
            }),
        ),
        (
            "coated plastic",
            params(|m| {
                m.coat_weight.value = 1.0;
                m.coat_roughness.value = 0.2;
                m.specular_roughness.value = 0.6;
            }),
        ),
    ];
    for (name, p) in &lobes {
        for (deg, outside) in [(30.0, true), (70.0, true), (30.0, false)] {
            let b = OpenPbrBsdf::new(p, view(deg), outside);
            assert_follows_pdf(&b, &format!("{name} at {deg} (outside {outside})"));
        }
    }
}

/// The lobes are reciprocal; only the layering's scale by what the layer above
/// passes on (`1 - E(wo)`, the specification's one-sided albedo scaling) and the
/// metal's energy compensation depend on which side the viewer is.
#[test]
fn the_lobes_are_reciprocal() {
    let (a, b) = (
        view(20.0),
        crate::math::normalize(Vec3::new(-0.3, 0.4, 0.866)),
    );
    let diffuse = params(|m| {
        m.specular_weight.value = 0.0;
        m.base_diffuse_roughness.value = 0.6;
    });
    let fab = OpenPbrBsdf::new(&diffuse, a, true).eval_pdf(b).0;
    let fba = OpenPbrBsdf::new(&diffuse, b, true).eval_pdf(a).0;
    assert!((fab - fba).abs().max_element() < 1e-6, "{fab} {fba}");
    let metal = params(|m| {
        m.base_metalness.value = 1.0;
        m.specular_roughness.value = 0.4;
        m.specular_color.value = Vec3::new(1.0, 0.7, 0.4);
    });
    let (oa, ob) = (
        OpenPbrBsdf::new(&metal, a, true),
        OpenPbrBsdf::new(&metal, b, true),
    );
    let fab = oa.eval_pdf(b).0 / oa.metal_w;
    let fba = ob.eval_pdf(a).0 / ob.metal_w;
    assert!(
        (fab - fba).abs().max_element() < 1e-5 * fab.max_element(),
        "{fab} {fba}"
    );
}

#[test]
fn specular_weight_scales_the_reflectance_at_normal_incidence() {
    let f0 = |eta: f32| ((eta - 1.0) / (eta + 1.0)).powi(2);
    assert_eq!(weighted_ior(1.5, 1.0), 1.5);
    assert!((f0(weighted_ior(1.5, 0.5)) - 0.02).abs() < 1e-6);
    assert!((f0(weighted_ior(1.5, 2.0)) - 0.08).abs() < 1e-6);
    assert_eq!(weighted_ior(1.5, 0.0), 1.0);
    assert!((f0(1.0 / weighted_ior(1.0 / 1.5, 0.5)) - 0.02).abs() < 1e-6);
}

#[test]
fn f82_meets_the_tinted_curve_at_its_angle_and_schlick_at_the_ends() {
    let f0 = Vec3::new(0.9, 0.6, 0.3);
    let tint = Vec3::new(1.0, 0.8, 0.5);
    let f = F82::new(f0, tint);
    assert!((f.at(1.0) - f0).abs().max_element() < 1e-6);
    assert!((f.at(0.0) - Vec3::ONE).abs().max_element() < 1e-6);
    let at = f.at(1.0 / 7.0);
    assert!((at - tint * schlick(f0, 1.0 / 7.0)).abs().max_element() < 1e-5);
}

/// A Lambertian white base with no specular: the value is exactly 1/pi.
#[test]
fn a_plain_white_base_is_lambert() {
    let p = params(|m| m.specular_weight.value = 0.0);
    let b = OpenPbrBsdf::new(&p, view(30.0), true);
    let (f, pdf) = b.eval_pdf(crate::math::normalize(Vec3::new(0.2, 0.3, 0.9)));
    assert!(
        (f - Vec3::splat(FRAC_1_PI)).abs().max_element() < 1e-7,
        "{f}"
    );
    assert!(pdf > 0.0);
}

#[test]
fn coat_darkening_darkens_a_grey_base_and_spares_a_white_one() {
    let coated = |c: f32, darkening: f32| {
        let mut m = OpenPbr::default();
        m.coat_weight.value = 1.0;
        m.coat_darkening.value = darkening;
        m.specular_roughness.value = 0.8;
        Params::of(&m, Vec3::splat(c))
    };
    let wo = view(0.0);
    let grey = albedo(&coated(0.5, 1.0), wo, true, 100_000);
    let bright = albedo(&coated(0.5, 0.0), wo, true, 100_000);
    assert!(grey.x < bright.x - 0.02, "{grey} {bright}");
    let white = albedo(&coated(1.0, 1.0), wo, true, 100_000);
    assert!((white.x - 1.0).abs() < 0.02, "{white}");
}

/// Chi-square of `b`'s sampled directions against its `pdf`, on a grid over the sphere.
fn assert_follows_pdf(b: &OpenPbrBsdf, name: &str) {
    let (nt, np) = (16, 32);
    let cell = |w: Vec3| {
        let t = ((w.z.clamp(-1.0, 1.0) + 1.0) * 0.5 * nt as f32) as usize;
        let ph = (w.y.atan2(w.x) + std::f32::consts::PI) / std::f32::consts::TAU;
        t.min(nt - 1) * np + ((ph * np as f32) as usize).min(np - 1)
    };
    let n = 200_000;
    let mut observed = vec![0.0f64; nt * np];
    let mut rng = Rng(11);
    let mut drawn = 0;
    for _ in 0..n {
        let pick = rng.f32();
        let u = (rng.f32(), rng.f32());
        if let Some(s) = b.sample(pick, u)
            && s.pdf > 0.0
        {
            observed[cell(s.wi)] += 1.0;
            drawn += 1;
        }
    }
    if !b.has_smooth() {
        assert_eq!(drawn, 0, "{name}: a delta-only surface drew from a pdf");
        return;
    }
    // Expected counts: the pdf integrated over each cell (the pdf of the
    // smooth lobes, scaled to the draws that came from them).
    let mut expected = vec![0.0f64; nt * np];
    let sub = 24;
    let mut total = 0.0;
    for (k, cell) in expected.iter_mut().enumerate() {
        let (ti, pi) = (k / np, k % np);
        for a in 0..sub {
            for c in 0..sub {
                let z = -1.0 + 2.0 * (ti as f32 + (a as f32 + 0.5) / sub as f32) / nt as f32;
                let ph = -std::f32::consts::PI
                    + std::f32::consts::TAU * (pi as f32 + (c as f32 + 0.5) / sub as f32)
                        / np as f32;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let w = Vec3::new(r * ph.cos(), r * ph.sin(), z);
                let area = 4.0 * std::f64::consts::PI / (nt * np * sub * sub) as f64;
                let pdf = b.eval_pdf(w).1 as f64 * area;
                *cell += pdf;
                total += pdf;
            }
        }
    }
    let mut chi2 = 0.0;
    let mut dof = 0;
    let mut pooled = (0.0, 0.0);
    for (k, &expected) in expected.iter().enumerate() {
        let e = expected / total * drawn as f64;
        if e < 5.0 {
            pooled.0 += observed[k];
            pooled.1 += e;
            continue;
        }
        chi2 += (observed[k] - e).powi(2) / e;
        dof += 1;
    }
    if pooled.1 > 5.0 {
        chi2 += (pooled.0 - pooled.1).powi(2) / pooled.1;
        dof += 1;
    }
    // A chi-square of `dof` degrees has mean dof and sd sqrt(2 dof): far beyond
    // 5 sd means the draws do not follow the pdf.
    let limit = dof as f64 + 5.0 * (2.0 * dof as f64).sqrt();
    assert!(chi2 < limit, "{name}: chi2 {chi2:.1} over {dof} cells");
}

#[test]
fn a_coat_of_its_own_normal_reflects_about_it() {
    // A smooth coat tilted 20 degrees from the base: its mirror leaves along the
    // reflection about its own normal, with the coat's Fresnel at its own cosine.
    let smooth = params(|m| {
        m.coat_weight.value = 1.0;
        m.coat_roughness.value = 0.0;
        m.specular_roughness.value = 0.5;
    });
    let (nc, wo) = (view(20.0), view(-10.0));
    let b = OpenPbrBsdf::with_coat_frame(&smooth, wo, true, Some(CoatFrame::about(nc)));
    let (k, wi) = b.coat_reflection().expect("a coat of its own");
    let mirror = nc * (2.0 * wo.dot(nc)) - wo;
    assert!((wi - mirror).length() < 1e-5, "{wi} vs {mirror}");
    let f = fresnel_dielectric(wo.dot(nc), 1.0, 1.6);
    assert!(
        (k - Vec3::splat(f)).abs().max_element() < 1e-4,
        "{k} vs {f}"
    );
    assert_eq!(
        b.deltas().0,
        Vec3::ZERO,
        "the base's mirror holds none of it"
    );
    let drawn: Vec<_> = (0..1000)
        .filter_map(|i| b.sample(i as f32 / 1000.0, (0.3, 0.6)))
        .filter(|s| s.pdf == 0.0)
        .collect();
    assert!(!drawn.is_empty());
    assert!(drawn.iter().all(|s| (s.wi - mirror).length() < 1e-5));
    // A rough tilted coat: sampling follows its density.
    let rough = params(|m| {
        m.coat_weight.value = 1.0;
        m.coat_roughness.value = 0.3;
        m.specular_roughness.value = 0.6;
    });
    let tilted = CoatFrame::about(crate::math::normalize(Vec3::new(-0.2, 0.1, 1.0)));
    for deg in [30.0, 70.0] {
        let b = OpenPbrBsdf::with_coat_frame(&rough, view(deg), true, Some(tilted));
        assert_follows_pdf(&b, &format!("a tilted rough coat at {deg}"));
    }
    // The base's own frame given as the coat's changes nothing.
    let same =
        OpenPbrBsdf::with_coat_frame(&rough, view(40.0), true, Some(CoatFrame::about(Vec3::Z)));
    let none = OpenPbrBsdf::new(&rough, view(40.0), true);
    for wi in [view(-30.0), view(10.0), Vec3::new(0.3, -0.5, 0.812)] {
        let (a, b) = (same.eval_pdf(wi), none.eval_pdf(wi));
        assert!(
            (a.0 - b.0).abs().max_element() <= 1e-5 * b.0.max_element(),
            "{a:?} {b:?}"
        );
        assert!((a.1 - b.1).abs() <= 1e-5 * b.1, "{a:?} {b:?}");
    }
}

#[test]
fn dispersion_meets_its_abbe_number_through_the_d_line() {
    let n = |nm| dispersed_ior(1.5, 20.0, 1.0, nm);
    assert!((n(587.6) - 1.5).abs() < 1e-6);
    // V_d = (n_d - 1) / (n_F - n_C).
    let v = (n(587.6) - 1.0) / (n(486.1) - n(656.3));
    assert!((v - 20.0).abs() < 1e-2, "{v}");
    // Half the scale, twice the Abbe number; none, the index as given.
    let half = (n(587.6) - 1.0)
        / (dispersed_ior(1.5, 20.0, 0.5, 486.1) - dispersed_ior(1.5, 20.0, 0.5, 656.3));
    assert!((half - 40.0).abs() < 2e-2, "{half}");
    assert_eq!(dispersed_ior(1.5, 20.0, 0.0, 450.0), 1.5);
}

#[test]
fn a_partly_present_surface_scales_its_lobes_and_passes_the_rest() {
    let solid = params(|m| m.specular_roughness.value = 0.4);
    let veil = params(|m| {
        m.specular_roughness.value = 0.4;
        m.geometry_opacity.value = 0.25;
    });
    let (a, b) = (
        OpenPbrBsdf::new(&solid, view(30.0), true),
        OpenPbrBsdf::new(&veil, view(30.0), true),
    );
    for wi in [view(-20.0), view(50.0)] {
        let (fa, fb) = (a.eval_pdf(wi).0, b.eval_pdf(wi).0);
        assert!((fb - fa * 0.25).abs().max_element() < 1e-6, "{fa} {fb}");
    }
    assert_eq!(b.pass_through(), 0.75);
    // The furnace: what is reflected plus what passes is all the light (nothing is
    // refracted, so no radiance scale is undone).
    let mut rng = Rng(5);
    let n = 200_000;
    let mut e = Vec3::ZERO;
    for _ in 0..n {
        let pick = rng.f32();
        if let Some(s) = b.sample(pick, (rng.f32(), rng.f32())) {
            e += s.weight;
        }
    }
    let e = e / n as f32;
    assert!((e - Vec3::ONE).abs().max_element() < 0.03, "{e}");
    // Passing draws go straight on.
    let straight = (0..100)
        .filter_map(|i| b.sample(i as f32 / 100.0, (0.5, 0.5)))
        .filter(|s| s.wi == -view(30.0))
        .count();
    assert!((70..=80).contains(&straight), "{straight}");
}
