//! Directional albedos of single-scattering GGX lobes, tabulated by Prism:
//! what the OpenPBR BSDF layers by (a layer beneath receives what the one above does
//! not reflect) and what restores the energy single scattering loses on rough
//! microfacets (a white rough metal and a clear rough glass then reflect and transmit
//! all they receive).
//!
//! Each entry integrates the lobe over the normals `wo` sees (VNDF sampling on a fixed
//! stratified grid of 4096 points, summed in f64). The integrals take seconds, so they
//! are computed once by [`computed`] and stored in `albedo.tables` (16-bit fractions),
//! which the binary carries: renders start at once, and read the same numbers on every
//! machine. `cargo test --release --lib -- --ignored write_albedo_tables` writes the
//! file anew; a test holds stored entries to fresh integrals. Lookups interpolate
//! linearly.

use super::microfacet::{Ggx, MIN_ALPHA};
use crate::math::Vec3;
use crate::render::optics::fresnel_dielectric;
use rayon::prelude::*;
use std::sync::OnceLock;

/// Points along the cosine of the view angle, the perceptual roughness and the
/// reflectance axis.
const N_MU: usize = 32;
const N_R: usize = 32;
const N_X: usize = 65;
/// Stratified samples per entry (a `SAMPLES_U` x `SAMPLES_V` grid).
const SAMPLES_U: usize = 64;
const SAMPLES_V: usize = 64;

/// Smallest cosine tabulated: grazing views read the first row.
const MIN_MU: f32 = 1e-3;

/// What the albedo tables hold.
struct Tables {
    /// Reflection and transmission albedos of a dielectric interface, by
    /// (mu, roughness, x), `x = (eta - 1) / (eta + 1)` in [-1/2, 1/2] (relative index
    /// eta from 1/3 to 3): light from outside (x > 0) and from inside (x < 0) alike.
    dielectric: Vec<[f32; 2]>,
    /// Albedo of a perfect reflector (Fresnel 1), by (mu, roughness).
    metal: Vec<f32>,
    /// Albedo of a white fuzz (sheen) lobe, by (mu, roughness).
    fuzz: Vec<f32>,
}

/// The tables as `albedo.tables` stores them.
static STORED: &[u8] = include_bytes!("albedo.tables");

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| decode(STORED))
}

/// Entries in the file, in its order: the dielectric's (R, T) pairs, the metal's, the
/// fuzz's.
const ENTRIES: usize = N_MU * N_R * N_X * 2 + 2 * N_MU * N_R;

/// The tables integrated afresh: what `albedo.tables` holds.
pub fn computed() -> Vec<u8> {
    let dielectric: Vec<[f32; 2]> = (0..N_MU * N_R * N_X)
        .into_par_iter()
        .map(dielectric_entry)
        .collect();
    let metal: Vec<f32> = (0..N_MU * N_R).into_par_iter().map(metal_entry).collect();
    let fuzz: Vec<f32> = (0..N_MU * N_R).into_par_iter().map(fuzz_entry).collect();
    dielectric
        .iter()
        .flatten()
        .chain(&metal)
        .chain(&fuzz)
        .flat_map(|&v| (((v.clamp(0.0, 1.0) * 65535.0).round()) as u16).to_le_bytes())
        .collect()
}

fn decode(bytes: &[u8]) -> Tables {
    assert_eq!(
        bytes.len(),
        ENTRIES * 2,
        "albedo.tables does not match its grid"
    );
    let mut values = bytes
        .chunks_exact(2)
        .map(|b| f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0);
    let dielectric = (0..N_MU * N_R * N_X)
        .map(|_| [values.next().unwrap(), values.next().unwrap()])
        .collect();
    let metal = values.by_ref().take(N_MU * N_R).collect();
    let fuzz = values.collect();
    Tables {
        dielectric,
        metal,
        fuzz,
    }
}

fn dielectric_entry(k: usize) -> [f32; 2] {
    let (i, j, l) = (k / (N_R * N_X), (k / N_X) % N_R, k % N_X);
    let x = l as f32 / (N_X - 1) as f32 - 0.5;
    integrate_dielectric(mu_at(i), r_at(j), eta_of_x(x))
}

fn metal_entry(k: usize) -> f32 {
    integrate_metal(mu_at(k / N_R), r_at(k % N_R))
}

fn fuzz_entry(k: usize) -> f32 {
    integrate_fuzz(mu_at(k / N_R), r_at(k % N_R))
}

fn mu_at(i: usize) -> f32 {
    (i as f32 / (N_MU - 1) as f32).max(MIN_MU)
}

fn r_at(j: usize) -> f32 {
    j as f32 / (N_R - 1) as f32
}

fn eta_of_x(x: f32) -> f32 {
    (1.0 + x) / (1.0 - x)
}

/// The view direction at cosine `mu`.
fn view(mu: f32) -> Vec3 {
    Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

fn ggx_of(r: f32) -> Ggx {
    let a = (r * r).max(MIN_ALPHA);
    Ggx { ax: a, ay: a }
}

/// The grid of `(u, v)` cell centres every entry sums over.
fn grid() -> impl Iterator<Item = (f32, f32)> {
    (0..SAMPLES_U).flat_map(|a| {
        (0..SAMPLES_V).map(move |b| {
            (
                (a as f32 + 0.5) / SAMPLES_U as f32,
                (b as f32 + 0.5) / SAMPLES_V as f32,
            )
        })
    })
}

/// `(E_R, E_T)` of an interface of relative index `eta` seen at cosine `mu`: a
/// visible normal drawn, reflected with weight `F G2 / G1` and refracted with weight
/// `(1 - F) G2 / G1` (energy, not radiance: no `1 / eta^2`).
fn integrate_dielectric(mu: f32, r: f32, eta: f32) -> [f32; 2] {
    let g = ggx_of(r);
    let wo = view(mu);
    let g1o = g.g1(wo);
    let (mut er, mut et) = (0.0f64, 0.0f64);
    for u in grid() {
        let m = g.sample_visible(wo, u);
        let c = wo.dot(m);
        if c <= 0.0 {
            continue;
        }
        let f = fresnel_dielectric(c, 1.0, eta);
        let wr = m * (2.0 * c) - wo;
        if wr.z > 0.0 {
            er += (f * g.g2(wo, wr) / g1o) as f64;
        }
        if let Some(wt) = refract_about(wo, m, eta)
            && wt.z < 0.0
        {
            et += ((1.0 - f) * g.g2(wo, -wt) / g1o) as f64;
        }
    }
    let n = (SAMPLES_U * SAMPLES_V) as f64;
    [(er / n) as f32, (et / n) as f32]
}

fn integrate_metal(mu: f32, r: f32) -> f32 {
    let g = ggx_of(r);
    let wo = view(mu);
    let g1o = g.g1(wo);
    let mut e = 0.0f64;
    for u in grid() {
        let m = g.sample_visible(wo, u);
        let c = wo.dot(m);
        let wr = m * (2.0 * c) - wo;
        if c > 0.0 && wr.z > 0.0 {
            e += (g.g2(wo, wr) / g1o) as f64;
        }
    }
    (e / (SAMPLES_U * SAMPLES_V) as f64) as f32
}

/// The fuzz lobe's albedo: cosine-weighted directions on the grid, weight `f pi`.
/// The fuzz lobe's albedo: cosine-weighted directions on the grid, weight `f pi`.
fn integrate_fuzz(mu: f32, r: f32) -> f32 {
    let wo = view(mu);
    let mut e = 0.0f64;
    for u in grid() {
        let wi = super::cosine_hemisphere(u);
        if wi.z > 0.0 {
            e += (super::fuzz::sheen(r, wo, wi) * std::f32::consts::PI) as f64;
        }
    }
    (e / (SAMPLES_U * SAMPLES_V) as f64) as f32
}

/// `wo` refracted through a microfacet of normal `m` (`wo.m > 0`) into relative index
/// `eta`; `None` past the critical angle.
#[inline]
pub fn refract_about(wo: Vec3, m: Vec3, eta: f32) -> Option<Vec3> {
    let c = wo.dot(m);
    let k = 1.0 / eta;
    let sin2_t = k * k * (1.0 - c * c).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((m * (k * c - cos_t) - wo * k).normalize_or_zero())
}

/// Where `v` falls between the `n` points spread over [0, 1]: an index and a weight.
#[inline]
fn place(v: f32, n: usize) -> (usize, f32) {
    let s = v.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (s as usize).min(n - 2);
    (i, s - i as f32)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// `(E_R, E_T)` of a GGX dielectric interface of perceptual roughness `r` and relative
/// index `eta` (that of the side light crosses into over the side `wo` is on), seen at
/// cosine `mu`, before any compensation.
pub fn dielectric(mu: f32, r: f32, eta: f32) -> [f32; 2] {
    let t = tables();
    let x = ((eta - 1.0) / (eta + 1.0)).clamp(-0.5, 0.5) + 0.5;
    let (i, fi) = place((mu - MIN_MU) / (1.0 - MIN_MU), N_MU);
    let (j, fj) = place(r, N_R);
    let (l, fl) = place(x, N_X);
    let at = |i: usize, j: usize, l: usize| t.dielectric[(i * N_R + j) * N_X + l];
    let mut out = [0.0; 2];
    for (c, o) in out.iter_mut().enumerate() {
        let v = |i, j| lerp(at(i, j, l)[c], at(i, j, l + 1)[c], fl);
        let a = lerp(v(i, j), v(i, j + 1), fj);
        let b = lerp(v(i + 1, j), v(i + 1, j + 1), fj);
        *o = lerp(a, b, fi);
    }
    out
}

/// The albedo of a perfect GGX reflector of perceptual roughness `r` at cosine `mu`.
pub fn metal(mu: f32, r: f32) -> f32 {
    bilinear(&tables().metal, mu, r)
}

/// The albedo of a white fuzz lobe of roughness `r` at cosine `mu`.
pub fn fuzz(mu: f32, r: f32) -> f32 {
    bilinear(&tables().fuzz, mu, r)
}

/// A table by (mu, roughness) read between its points.
fn bilinear(table: &[f32], mu: f32, r: f32) -> f32 {
    let (i, fi) = place((mu - MIN_MU) / (1.0 - MIN_MU), N_MU);
    let (j, fj) = place(r, N_R);
    let at = |i: usize, j: usize| table[i * N_R + j];
    lerp(
        lerp(at(i, j), at(i, j + 1), fj),
        lerp(at(i + 1, j), at(i + 1, j + 1), fj),
        fi,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes `albedo.tables` from fresh integrals (seconds in a release build).
    #[test]
    #[ignore = "writes src/render/bsdf/albedo.tables; run after changing a lobe or the grid"]
    fn write_albedo_tables() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/render/bsdf/albedo.tables");
        std::fs::write(path, computed()).unwrap();
    }

    #[test]
    fn the_stored_tables_are_the_integrals_prism_computes() {
        let t = tables();
        let near = |a: f32, b: f32| (a - b).abs() <= 1.0 / 65535.0;
        // A spread of entries, the grid's corners among them.
        for k in (0..N_MU * N_R * N_X)
            .step_by(4099)
            .chain([0, N_MU * N_R * N_X - 1])
        {
            let [r, tr] = dielectric_entry(k);
            assert!(
                near(t.dielectric[k][0], r) && near(t.dielectric[k][1], tr),
                "{k}"
            );
        }
        for k in (0..N_MU * N_R).step_by(97) {
            assert!(near(t.metal[k], metal_entry(k)), "metal {k}");
            assert!(near(t.fuzz[k], fuzz_entry(k)), "fuzz {k}");
        }
    }

    #[test]
    fn a_smooth_interface_reflects_fresnel_and_transmits_the_rest() {
        for (mu, eta) in [(1.0, 1.5), (0.5, 1.5), (0.95, 1.0 / 1.33)] {
            let [r, t] = dielectric(mu, 0.0, eta);
            let f = fresnel_dielectric(mu, 1.0, eta);
            assert!((r - f).abs() < 2e-3, "{mu} {eta}: {r} vs {f}");
            assert!(
                (t - (1.0 - f)).abs() < 2e-3,
                "{mu} {eta}: {t} vs {}",
                1.0 - f
            );
        }
    }

    /// The tables hold the integral of the lobes' own values: a Riemann sum of
    /// `f cos` over the hemisphere agrees with them.
    #[test]
    fn the_tables_integrate_the_lobes() {
        let n = 400;
        for (mu, r) in [(0.2, 0.7), (0.8, 0.6), (0.5, 1.0)] {
            let g = ggx_of(r);
            let wo = view(mu);
            let (mut metal_sum, mut refl_sum) = (0.0f64, 0.0f64);
            for i in 0..n {
                let t = (i as f32 + 0.5) / n as f32 * std::f32::consts::FRAC_PI_2;
                for j in 0..n {
                    let p = (j as f32 + 0.5) / n as f32 * std::f32::consts::TAU;
                    let wi = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                    let h = crate::math::normalize(wo + wi);
                    let f = g.d(h) * g.g2(wo, wi) / (4.0 * wo.z * wi.z);
                    let dw = (t.sin() * wi.z) as f64
                        * (std::f64::consts::FRAC_PI_2 / n as f64)
                        * (std::f64::consts::TAU / n as f64);
                    metal_sum += f as f64 * dw;
                    refl_sum += (f * fresnel_dielectric(wo.dot(h), 1.0, 1.5)) as f64 * dw;
                }
            }
            let m = metal(mu, r);
            assert!(
                (m as f64 - metal_sum).abs() < 5e-3,
                "{mu} {r}: {m} vs {metal_sum}"
            );
            let [er, _] = dielectric(mu, r, 1.5);
            assert!(
                (er as f64 - refl_sum).abs() < 2e-3,
                "{mu} {r}: {er} vs {refl_sum}"
            );
        }
        // Rough lobes lose energy to single scattering; smooth ones keep it.
        assert!((metal(0.8, 0.0) - 1.0).abs() < 1e-3);
        assert!(metal(0.8, 0.7) < 0.9);
    }
}
