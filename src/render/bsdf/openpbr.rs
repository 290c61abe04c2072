//! The OpenPBR Surface BSDF at one hit: its lobes, layered as the specification
//! layers them, by albedo scaling (each layer passes on what it does not reflect,
//! `1 - E(wo)`), with single-scattering GGX lobes restored to the energy they lose.
//!
//! ```text
//! f = C f_coat + mix(1, T(ωo), C) mix(1, T(ωi), C) (1 - C E_coat) base
//! base = M metal + (1 - M) dielectric
//! dielectric = (S f_R + t T f_T) / E_RT + (1 - t) (1 - E_R / E_RT) w_b f_EON(rho)
//! metal = F82(wo.h) f_GGX (1 + F0 (1 - E_m) / E_m)
//! ```
//!
//! `E_R`, `E_T` are the interface's reflection and transmission albedos and `E_RT` their
//! sum (so the interface's lobes together keep all they receive); `E_m` a perfect
//! reflector's (Turquin's compensation). A lobe smoother than `microfacet::MIN_ALPHA` is a delta:
//! the mirror and the refraction are drawn, never evaluated. Directions are local to the
//! shading frame (normal +z), `wo.z > 0`.

mod params;

pub use params::{Params, dispersed_ior, weighted_ior};

use super::albedo::{self, refract_about};
use super::diffuse::eon;
use super::medium::Medium;
use super::microfacet::Ggx;
use super::{Sampled, cosine_hemisphere};
use crate::math::Vec3;
use crate::render::optics::fresnel_dielectric;
use std::f32::consts::FRAC_1_PI;

/// Schlick's Fresnel with the F82 tint: `specular_color` scales the curve at
/// `cos = 1/7`, where metals' reflectance dips (Kutz et al. 2021).
#[derive(Clone, Copy, Debug)]
struct F82 {
    f0: Vec3,
    /// The correction at `cos = 1/7`, divided by `mu (1 - mu)^6` there.
    b: Vec3,
}

impl F82 {
    fn new(f0: Vec3, tint: Vec3) -> F82 {
        const MU: f32 = 1.0 / 7.0;
        let at = schlick(f0, MU);
        let denom = MU * (1.0 - MU).powi(6);
        F82 {
            f0,
            b: at * (Vec3::ONE - tint) / denom,
        }
    }

    /// `2 ∫ F(mu) mu dmu`: the reflectance averaged over the hemisphere.
    fn average(&self) -> Vec3 {
        // Schlick's average is F0 + (1 - F0) / 21; the tint's, 2 B(3, 7) = 1 / 126.
        (self.f0 + (Vec3::ONE - self.f0) / 21.0 - self.b / 126.0).clamp(Vec3::ZERO, Vec3::ONE)
    }

    #[inline]
    fn at(&self, mu: f32) -> Vec3 {
        let mu = mu.clamp(0.0, 1.0);
        let m = 1.0 - mu;
        let m6 = (m * m * m) * (m * m * m);
        (schlick(self.f0, mu) - self.b * (mu * m6)).clamp(Vec3::ZERO, Vec3::ONE)
    }
}

#[inline]
fn schlick(f0: Vec3, mu: f32) -> Vec3 {
    let m = (1.0 - mu).clamp(0.0, 1.0);
    let m5 = (m * m) * (m * m) * m;
    f0 + (Vec3::ONE - f0) * m5
}

#[inline]
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// The coat's shading frame in the base's local frame: its tangent, bitangent and
/// normal, orthonormal.
#[derive(Clone, Copy, Debug)]
pub struct CoatFrame {
    t: Vec3,
    b: Vec3,
    n: Vec3,
}

impl CoatFrame {
    /// The frame about `n` (unit, local) whose tangent is the base's x axis made
    /// perpendicular to it (so the coat's anisotropy follows the base's tangent).
    pub fn about(n: Vec3) -> CoatFrame {
        let t = (Vec3::X - n * n.x).normalize_or_zero();
        let t = if t == Vec3::ZERO {
            n.any_orthonormal_pair().0
        } else {
            t
        };
        CoatFrame {
            t,
            b: crate::math::cross(n, t),
            n,
        }
    }

    #[inline]
    fn to_coat(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    #[inline]
    fn coat_to_local(self, v: Vec3) -> Vec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }
}

/// Which smooth lobe a sample came from.
const DIFFUSE: usize = 0;
const SPEC_R: usize = 1;
const SPEC_T: usize = 2;
const METAL: usize = 3;
const COAT: usize = 4;
const FUZZ: usize = 5;
const LOBES: usize = 6;

/// An OpenPBR surface seen from `wo` (local frame, `wo.z > 0`).
#[derive(Clone, Copy, Debug)]
pub struct OpenPbrBsdf {
    wo: Vec3,
    /// EON albedo parameter and roughness, and the weight the layers above leave it.
    rho: Vec3,
    sigma: f32,
    diffuse: Vec3,
    /// The dielectric interface: its microfacets, relative index (side beyond over
    /// `wo`'s), and the weights of its reflection and transmission.
    spec: Ggx,
    eta: f32,
    spec_r: Vec3,
    spec_t: Vec3,
    thin: bool,
    /// The interface joins equal indices (`specular_weight` 0): light crosses it
    /// straight, unreflected, whatever its roughness.
    matched: bool,
    metal: Ggx,
    f82: F82,
    metal_w: Vec3,
    coat: Ggx,
    coat_eta: f32,
    coat_w: f32,
    /// The coat's own frame where its normal is not the base's (`geometry_coat_normal`,
    /// or the unperturbed normal over a normal-mapped base), with its mirror's weight
    /// and the rough coat's faded albedo, which then leave along the coat's mirror
    /// direction rather than the base's.
    coat_frame: Option<CoatFrame>,
    coat_mirror: Vec3,
    coat_glossy: Vec3,
    /// The coat's transmittance across its thickness (`sqrt(coat_color)`), its
    /// presence, and what it passes along `wo`.
    coat_tint: Vec3,
    coat_presence: f32,
    coat_passage_o: Vec3,
    /// What it passes along the base's mirror direction of `wo`.
    coat_passage_back: Vec3,
    /// The fuzz's colour times its presence, and its roughness.
    fuzz: Vec3,
    fuzz_roughness: f32,
    /// A thin film on the dielectric interface: presence, thickness (nm), index.
    film: Option<(f32, f32, f32)>,
    /// What enters the subsurface medium (a walk through it follows), the medium,
    /// and the probability of drawing the entry.
    enter: Vec3,
    medium: Option<Medium>,
    p_enter: f32,
    /// Probabilities of the smooth lobes, then of the two deltas.
    p: [f32; LOBES],
    p_mirror: f32,
    p_transmit: f32,
    p_coat_mirror: f32,
    /// Presence (`geometry_opacity`): the lobes and deltas are scaled by it, and the
    /// rest of the light passes straight through, with probability `p_pass`.
    opacity: f32,
    p_pass: f32,
    /// Weights of the deltas as seen from `wo` (times `cos / pdf`: what a path's
    /// throughput is multiplied by when it is chosen with probability 1).
    mirror: Vec3,
    transmit: Vec3,
    /// The rough lobes' albedos at `wo`, reflected and transmitted, each times
    /// `(1 - roughness)^2`: what a model that traces only the mirror and refraction
    /// directions sends along them for the scene the lobes would blur.
    glossy: Vec3,
    glossy_transmit: Vec3,
}

impl OpenPbrBsdf {
    /// `p` seen from `wo`; `outside` when `wo` is on the side the surface faces (the
    /// side the coat is on, and the index is `specular_ior` beyond), which a thin wall
    /// does not tell apart.
    pub fn new(p: &Params, wo: Vec3, outside: bool) -> OpenPbrBsdf {
        OpenPbrBsdf::with_coat_frame(p, wo, outside, None)
    }

    /// [`OpenPbrBsdf::new`] with the coat in a frame of its own (its normal, in the
    /// base's local frame, facing `wo`).
    pub fn with_coat_frame(
        p: &Params,
        wo: Vec3,
        outside: bool,
        coat_frame: Option<CoatFrame>,
    ) -> OpenPbrBsdf {
        let mu_o = wo.z.clamp(1e-4, 1.0);
        let spec = Ggx::from_roughness(p.specular_roughness, p.specular_roughness_anisotropy);
        let coat = Ggx::from_roughness(p.coat_roughness, p.coat_roughness_anisotropy);
        let mut b = OpenPbrBsdf {
            wo,
            rho: Vec3::ZERO,
            sigma: p.base_diffuse_roughness,
            diffuse: Vec3::ZERO,
            spec,
            eta: 1.0,
            spec_r: Vec3::ZERO,
            spec_t: Vec3::ZERO,
            thin: p.thin_walled,
            matched: false,
            metal: spec,
            f82: F82::new(p.base_color * p.base_weight, p.specular_color),
            metal_w: Vec3::ZERO,
            coat,
            coat_eta: p.coat_ior,
            coat_w: 0.0,
            coat_frame,
            coat_mirror: Vec3::ZERO,
            coat_glossy: Vec3::ZERO,
            coat_tint: Vec3::ONE,
            coat_presence: 0.0,
            coat_passage_o: Vec3::ONE,
            coat_passage_back: Vec3::ONE,
            fuzz: Vec3::ZERO,
            fuzz_roughness: p.fuzz_roughness,
            film: None,
            p: [0.0; LOBES],
            p_mirror: 0.0,
            p_transmit: 0.0,
            p_coat_mirror: 0.0,
            enter: Vec3::ZERO,
            medium: None,
            p_enter: 0.0,
            opacity: p.opacity,
            p_pass: 0.0,
            mirror: Vec3::ZERO,
            transmit: Vec3::ZERO,
            glossy: Vec3::ZERO,
            glossy_transmit: Vec3::ZERO,
        };
        let mut weights = [0.0; LOBES];
        let r_spec = p.specular_roughness;
        // The back of a surface that lets no light through is shaded as its front:
        // it is an open mesh or a plane seen from behind, not the inside of a solid.
        if !outside && !p.thin_walled && p.transmission_weight > 0.0 {
            // Inside a transmissive solid only its boundary is met: light reflects or
            // leaves, untinted (the volume coloured it on the way).
            b.eta = 1.0 / weighted_ior(p.specular_ior, p.specular_weight);
            b.matched = (b.eta - 1.0).abs() < 1e-3;
            let (er, et) = if b.matched {
                (0.0, 1.0)
            } else {
                interface(spec, r_spec, b.eta, mu_o)
            };
            let (r, t) = compensate(er, et, b.eta);
            b.spec_r = Vec3::splat(ratio(r, er));
            b.spec_t = Vec3::splat(ratio(t, et));
            weights[SPEC_R] = r;
            weights[SPEC_T] = t;
            if !spec.is_delta() {
                let gloss = (1.0 - r_spec) * (1.0 - r_spec);
                b.glossy = Vec3::splat(r * gloss);
                b.glossy_transmit = Vec3::splat(t * gloss);
            }
            if spec.is_delta() || b.matched {
                b.mirror = Vec3::splat(er);
                b.transmit = Vec3::splat(et) * radiance_scale(b.eta);
            }
            b.finish(weights);
            return b;
        }
        // The fuzz on top, and what it passes on.
        let mut above = 1.0;
        if p.fuzz_weight > 0.0 {
            let e_f = albedo::fuzz(mu_o, p.fuzz_roughness);
            b.fuzz = p.fuzz_color * p.fuzz_weight;
            weights[FUZZ] = mean(b.fuzz) * e_f;
            above = 1.0 - p.fuzz_weight * e_f;
        }
        // The coat, and what it passes on to the base.
        let c = p.coat_weight;
        let mut below = Vec3::splat(above);
        if c > 0.0 {
            let mu_c = match &b.coat_frame {
                None => mu_o,
                Some(f) => f.to_coat(wo).z.clamp(1e-4, 1.0),
            };
            let (er, et) = interface(coat, p.coat_roughness, p.coat_ior, mu_c);
            let (e_c, _) = compensate(er, et, p.coat_ior);
            b.coat_w = above * c * ratio(e_c, er);
            weights[COAT] = above * c * e_c;
            let (glossy, mirror) = match b.coat_frame {
                None => (&mut b.glossy, &mut b.mirror),
                Some(_) => (&mut b.coat_glossy, &mut b.coat_mirror),
            };
            if !coat.is_delta() {
                let gloss = (1.0 - p.coat_roughness) * (1.0 - p.coat_roughness);
                *glossy += Vec3::splat(above * c * e_c * gloss);
            }
            if coat.is_delta() {
                *mirror += Vec3::splat(above * c * er);
            }
            // Light crosses the coat twice, tinted each way by the length of its path
            // in it: here on the way out toward `wo`, in `eval` on the way in.
            b.coat_tint = p.coat_color.max(Vec3::ZERO).powf(0.5);
            b.coat_presence = c;
            b.coat_passage_o = b.coat_passage(mu_c);
            // The base's mirror direction, at its own angle to a coat of its own normal.
            b.coat_passage_back = match &b.coat_frame {
                None => b.coat_passage_o,
                Some(f) => b.coat_passage(f.to_coat(Vec3::new(-wo.x, -wo.y, wo.z)).z),
            };
            below *= b.coat_passage_o
                * (1.0 - c * e_c)
                * Vec3::ONE.lerp(darkening(p, mu_o), c * p.coat_darkening);
        }
        // The metal.
        let m = p.base_metalness;
        if m > 0.0 {
            let e = albedo::metal(mu_o, r_spec).max(1e-4);
            // Turquin's compensation, by the Fresnel curve's hemispherical average.
            let ms = Vec3::ONE + b.f82.average() * ((1.0 - e) / e);
            b.metal_w = below * (m * p.specular_weight) * ms;
            let f_o = b.f82.at(mu_o);
            weights[METAL] = mean(b.metal_w * f_o * e);
            // What the base reflects toward its mirror direction crosses the coat
            // again at `wo`'s angle.
            let back = b.coat_passage_back;
            if !spec.is_delta() {
                b.glossy += b.metal_w * f_o * back * (e * (1.0 - r_spec) * (1.0 - r_spec));
            }
            if spec.is_delta() {
                b.mirror += b.metal_w * f_o * back;
            }
        }
        // The dielectric: its interface's reflection and transmission, and the diffuse
        // base under what the interface does not reflect.
        let d = 1.0 - m;
        if d > 0.0 {
            let eta_base = if c > 0.0 {
                // Under a coat the base's index contrast is with the coat.
                let under = p.specular_ior / p.coat_ior;
                p.specular_ior + (under - p.specular_ior) * c
            } else {
                p.specular_ior
            };
            b.eta = weighted_ior(eta_base, p.specular_weight);
            if p.thin_film_weight > 0.0 && p.thin_film_thickness > 0.0 {
                b.film = Some((
                    p.thin_film_weight,
                    p.thin_film_thickness * 1000.0,
                    p.thin_film_ior,
                ));
            }
            let t = p.transmission_weight;
            b.matched = !p.thin_walled && (b.eta - 1.0).abs() < 1e-3;
            // A thin wall reflects as the solid would (its reflection's compensation
            // the solid's); its transmission is the reflection lobe mirrored through.
            let (er, et_solid) = if b.matched {
                (0.0, 1.0)
            } else {
                interface(spec, r_spec, b.eta, mu_o)
            };
            let (r, t_all) = compensate(er, et_solid, b.eta);
            let et = if p.thin_walled && !spec.is_delta() {
                (albedo::metal(mu_o, r_spec) - er).max(0.0)
            } else {
                et_solid
            };
            let scale = if p.thin_walled {
                1.0
            } else {
                radiance_scale(b.eta)
            };
            b.spec_r = below * p.specular_color * (d * ratio(r, er));
            // The rough refraction's value carries the radiance scale itself.
            b.spec_t = below * p.transmission_tint * (d * t * ratio(t_all, et));
            weights[SPEC_R] = mean(b.spec_r) * er;
            weights[SPEC_T] = mean(b.spec_t) * et;
            if !spec.is_delta() && !b.matched {
                let gloss = (1.0 - r_spec) * (1.0 - r_spec);
                b.glossy += b.spec_r * b.coat_passage_back * (er * gloss);
                b.glossy_transmit += b.spec_t * (et * gloss * scale);
            }
            if spec.is_delta() || b.matched {
                // A film moves light between the reflection and the refraction.
                let f = b.fresnel(mu_o);
                let (r, t) = if b.film.is_some() {
                    (f, Vec3::ONE - f)
                } else {
                    (Vec3::splat(er), Vec3::splat(et))
                };
                b.mirror += b.spec_r * b.coat_passage_back * r;
                b.transmit += b.spec_t * t * scale;
            }
            // base_weight scales the albedo EON is given, as the reference does: its
            // multiple-scattering term then darkens a dim base as it does a dark one.
            let opaque = below * (d * (1.0 - t) * (1.0 - r));
            // Only from outside: the back of an opaque surface is an open mesh's (shaded
            // as its front), with no medium behind it to walk through.
            let walks = p.subsurface_walk && outside && !p.thin_walled;
            let medium = if walks && p.subsurface_weight > 0.0 {
                Medium::subsurface(
                    p.subsurface_color,
                    p.subsurface_radius,
                    p.subsurface_scatter_anisotropy,
                )
            } else {
                None
            };
            if medium.is_some() {
                // Light the interface passes into the medium leaves it elsewhere.
                let w = p.subsurface_weight;
                b.rho = p.base_color * p.base_weight;
                b.diffuse = opaque * (1.0 - w);
                // The walk's diffuse exit is taken to cross the coat at normal incidence.
                b.enter = opaque * b.coat_passage(1.0) * (w * p.base_weight);
                b.medium = medium;
            } else {
                b.rho = p.base_color.lerp(p.subsurface_color, p.subsurface_weight) * p.base_weight;
                b.diffuse = opaque;
            }
            weights[DIFFUSE] = mean(b.diffuse * b.rho);
        }
        b.finish(weights);
        b
    }

    /// Sets the sampling probabilities from the lobes' albedos at `wo`: deltas take
    /// their share from the smooth ones.
    fn finish(&mut self, mut weights: [f32; LOBES]) {
        let present = self.opacity;
        self.mirror *= present;
        self.transmit *= present;
        self.coat_mirror *= present;
        self.enter *= present;
        self.glossy *= present;
        self.glossy_transmit *= present;
        self.coat_glossy *= present;
        weights = weights.map(|w| w * present);
        let pass = 1.0 - present;
        let delta_mirror = mean(self.mirror);
        let delta_transmit = mean(self.transmit);
        if self.spec.is_delta() || self.matched {
            weights[SPEC_R] = 0.0;
            weights[SPEC_T] = 0.0;
        }
        if self.spec.is_delta() {
            weights[METAL] = 0.0;
        }
        if self.coat.is_delta() {
            weights[COAT] = 0.0;
        }
        let delta_coat = mean(self.coat_mirror);
        let enter = mean(self.enter);
        let total: f32 =
            weights.iter().sum::<f32>() + delta_mirror + delta_transmit + delta_coat + enter + pass;
        if total > 0.0 && total.is_finite() {
            self.p_enter = enter / total;
            self.p = weights.map(|w| w / total);
            self.p_mirror = delta_mirror / total;
            self.p_transmit = delta_transmit / total;
            self.p_coat_mirror = delta_coat / total;
            self.p_pass = pass / total;
        }
    }

    /// The dielectric interface's Fresnel reflectance at cosine `cos` to a microfacet,
    /// with its thin film where it has one.
    #[inline]
    fn fresnel(&self, cos: f32) -> Vec3 {
        let f = fresnel_dielectric(cos, 1.0, self.eta);
        match self.film {
            None => Vec3::splat(f),
            Some((weight, nm, ior)) => Vec3::splat(f).lerp(
                super::thin_film::reflectance(cos, ior, self.eta, nm),
                weight,
            ),
        }
    }

    /// What the coat passes of light crossing it at cosine `mu` to its normal: its
    /// tint raised to the length of the path refracted into it (the specification's
    /// view-dependent absorption), where it is present.
    fn coat_passage(&self, mu: f32) -> Vec3 {
        // Below the coat's plane (a base lobe's direction under a coat of its own
        // normal) nothing crosses it, as the reference has it.
        if self.coat_tint == Vec3::ONE || mu <= 0.0 {
            return Vec3::ONE;
        }
        let eta = self.coat_eta;
        let mu_t = (1.0 - (1.0 - mu * mu) / (eta * eta)).max(0.0).sqrt();
        let through = if mu_t > 0.0 {
            self.coat_tint.powf(1.0 / mu_t)
        } else {
            Vec3::ZERO
        };
        Vec3::ONE.lerp(through, self.coat_presence)
    }

    /// Whether any lobe is smooth: only then does light from a light scatter toward `wo`.
    pub fn has_smooth(&self) -> bool {
        self.p.iter().any(|&p| p > 0.0)
    }

    /// What the rough lobes reflect and transmit, faded by roughness, for a model that
    /// follows only the mirror and refraction directions (the whitted model's stand-in
    /// for the blurred scene they show).
    pub fn glossy(&self) -> (Vec3, Vec3) {
        (self.glossy, self.glossy_transmit)
    }

    /// Where the coat has a normal of its own: its mirror's weight plus its rough
    /// lobe's faded albedo, and their direction (the coat's mirror direction, local).
    pub fn coat_reflection(&self) -> Option<(Vec3, Vec3)> {
        let f = self.coat_frame?;
        let o = f.to_coat(self.wo);
        Some((
            self.coat_mirror + self.coat_glossy,
            f.coat_to_local(Vec3::new(-o.x, -o.y, o.z)),
        ))
    }

    /// The medium under the surface that [`OpenPbrBsdf::sample`] may send light into.
    pub fn medium(&self) -> Option<Medium> {
        self.medium
    }

    /// The share of light that passes straight through where the surface is absent
    /// (`1 - geometry_opacity`).
    pub fn pass_through(&self) -> f32 {
        1.0 - self.opacity
    }

    /// The mirror and refraction deltas' weights (what a path multiplies by when it
    /// follows them).
    pub fn deltas(&self) -> (Vec3, Vec3) {
        (self.mirror, self.transmit)
    }

    /// The direction of the refraction delta: `wo` refracted through the normal, or
    /// straight through a thin wall; `None` past the critical angle.
    pub fn refracted(&self) -> Option<Vec3> {
        if self.thin || self.matched {
            return Some(-self.wo);
        }
        refract_about(self.wo, Vec3::Z, self.eta)
    }

    /// The smooth lobes' value for light from `wi` (no cosine) and the density with
    /// which [`OpenPbrBsdf::sample`] draws `wi`.
    pub fn eval_pdf(&self, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = self.eval_present(wi);
        (f * self.opacity, pdf)
    }

    /// [`OpenPbrBsdf::eval_pdf`] of the surface where it is present.
    fn eval_present(&self, wi: Vec3) -> (Vec3, f32) {
        let wo = self.wo;
        let mu_o = wo.z.max(1e-4);
        let mut f = Vec3::ZERO;
        let mut pdf = 0.0;
        if wi.z > 0.0 {
            let mu_i = wi.z;
            // Light reaching the base crosses the coat on its way in.
            let coat_in = if self.coat_presence > 0.0 {
                self.coat_passage(match self.coat_frame {
                    None => mu_i,
                    Some(frame) => frame.to_coat(wi).z,
                })
            } else {
                Vec3::ONE
            };
            if self.p[DIFFUSE] > 0.0 {
                f += self.diffuse * coat_in * eon(self.rho, self.sigma, mu_o, mu_i, wo.dot(wi));
                pdf += self.p[DIFFUSE] * mu_i * FRAC_1_PI;
            }
            let h = (wo + wi).normalize_or_zero();
            let oh = wo.dot(h);
            if oh <= 0.0 || h.z <= 0.0 {
                if let Some(frame) = self.coat_frame {
                    let (fc, pc) = self.coat_in(frame, wi);
                    return (f + fc, pdf + pc);
                }
                return (f, pdf);
            }
            let k = 1.0 / (4.0 * mu_o * mu_i);
            if self.p[FUZZ] > 0.0 {
                f += self.fuzz * super::fuzz::sheen(self.fuzz_roughness, wo, wi);
                pdf += self.p[FUZZ] * mu_i * FRAC_1_PI;
            }
            if self.p[SPEC_R] > 0.0 {
                let g = self.spec;
                let fr = self.fresnel(oh);
                f += self.spec_r * coat_in * fr * (g.d(h) * g.g2(wo, wi) * k);
                pdf += self.p[SPEC_R] * g.visible_pdf(wo, h) / (4.0 * oh);
            }
            if self.p[METAL] > 0.0 {
                let g = self.metal;
                f += self.metal_w * coat_in * self.f82.at(oh) * (g.d(h) * g.g2(wo, wi) * k);
                pdf += self.p[METAL] * g.visible_pdf(wo, h) / (4.0 * oh);
            }
            if let Some(frame) = self.coat_frame {
                let (fc, pc) = self.coat_in(frame, wi);
                f += fc;
                pdf += pc;
            } else if self.p[COAT] > 0.0 {
                let g = self.coat;
                let fr = fresnel_dielectric(oh, 1.0, self.coat_eta);
                f += Vec3::splat(self.coat_w * fr * g.d(h) * g.g2(wo, wi) * k);
                pdf += self.p[COAT] * g.visible_pdf(wo, h) / (4.0 * oh);
            }
        } else if wi.z < 0.0 && self.p[SPEC_T] > 0.0 {
            let g = self.spec;
            let mu_i = -wi.z;
            if self.thin {
                // Through a thin wall: the reflection lobe, mirrored to the far side.
                let wr = Vec3::new(wi.x, wi.y, -wi.z);
                let h = (wo + wr).normalize_or_zero();
                let oh = wo.dot(h);
                if oh > 0.0 && h.z > 0.0 {
                    let ft = Vec3::ONE - self.fresnel(oh);
                    f += self.spec_t * ft * (g.d(h) * g.g2(wo, wr) / (4.0 * mu_o * mu_i));
                    pdf += self.p[SPEC_T] * g.visible_pdf(wo, h) / (4.0 * oh);
                }
            } else {
                let eta = self.eta;
                let mut h = -(wo + wi * eta);
                if h.z < 0.0 {
                    h = -h;
                }
                let h = h.normalize_or_zero();
                let (oh, ih) = (wo.dot(h), wi.dot(h));
                if oh > 0.0 && ih < 0.0 && h.z > 0.0 {
                    let denom = oh + eta * ih;
                    let denom2 = denom * denom;
                    let ft = Vec3::ONE - self.fresnel(oh);
                    let v = g.d(h) * g.g2(wo, wi) * (ih.abs() * oh) / (mu_i * mu_o * denom2);
                    f += self.spec_t * ft * v;
                    pdf += self.p[SPEC_T] * g.visible_pdf(wo, h) * (eta * eta * ih.abs()) / denom2;
                }
            }
        }
        (f, pdf)
    }

    /// The rough coat's value and density for light from `wi` (above the base), worked
    /// in the coat's own frame. The value is scaled by the ratio of the cosines to the
    /// two normals, as the caller multiplies by the base's.
    fn coat_in(&self, frame: CoatFrame, wi: Vec3) -> (Vec3, f32) {
        let (o, i) = (frame.to_coat(self.wo), frame.to_coat(wi));
        if self.p[COAT] <= 0.0 || o.z <= 0.0 || i.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let h = (o + i).normalize_or_zero();
        let oh = o.dot(h);
        if oh <= 0.0 || h.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let g = self.coat;
        let fr = fresnel_dielectric(oh, 1.0, self.coat_eta);
        let k = 1.0 / (4.0 * o.z.max(1e-4) * wi.z);
        let f = Vec3::splat(self.coat_w * fr * g.d(h) * g.g2(o, i) * k);
        (f, self.p[COAT] * g.visible_pdf(o, h) / (4.0 * oh))
    }

    /// A direction drawn for `wo`: `pick` chooses the lobe, `u` the direction in it.
    pub fn sample(&self, pick: f32, u: (f32, f32)) -> Option<Sampled> {
        let wo = self.wo;
        if pick < self.p_pass {
            return Some(Sampled {
                wi: -wo,
                weight: Vec3::splat((1.0 - self.opacity) / self.p_pass),
                pdf: 0.0,
                subsurface: false,
            });
        }
        let pick = pick - self.p_pass;
        if pick < self.p_mirror {
            return Some(Sampled {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: self.mirror / self.p_mirror,
                pdf: 0.0,
                subsurface: false,
            });
        }
        let mut rest = pick - self.p_mirror;
        if rest < self.p_transmit {
            return Some(Sampled {
                wi: self.refracted()?,
                weight: self.transmit / self.p_transmit,
                pdf: 0.0,
                subsurface: false,
            });
        }
        rest -= self.p_transmit;
        if rest < self.p_coat_mirror {
            let (_, wi) = self.coat_reflection()?;
            return (wi.z > 0.0).then(|| Sampled {
                wi,
                weight: self.coat_mirror / self.p_coat_mirror,
                pdf: 0.0,
                subsurface: false,
            });
        }
        rest -= self.p_coat_mirror;
        if rest < self.p_enter {
            let d = cosine_hemisphere(u);
            return Some(Sampled {
                wi: Vec3::new(d.x, d.y, -d.z),
                weight: self.enter / self.p_enter,
                pdf: 0.0,
                subsurface: true,
            });
        }
        rest -= self.p_enter;
        let mut lobe = LOBES;
        for (k, &p) in self.p.iter().enumerate() {
            if p > 0.0 && rest < p {
                lobe = k;
                break;
            }
            rest -= p;
        }
        // A reflection drawn below the surface is lost (masked), as is a refraction
        // drawn above it: read by `eval_pdf`, it would be another lobe's direction.
        let reflect = |g: Ggx| {
            let m = g.sample_visible(wo, u);
            let c = wo.dot(m);
            let wi = m * (2.0 * c) - wo;
            (c > 0.0 && wi.z > 0.0).then_some(wi)
        };
        let wi = match lobe {
            DIFFUSE | FUZZ => cosine_hemisphere(u),
            SPEC_R => reflect(self.spec)?,
            METAL => reflect(self.metal)?,
            COAT => match self.coat_frame {
                None => reflect(self.coat)?,
                Some(frame) => {
                    let o = frame.to_coat(wo);
                    let m = self.coat.sample_visible(o, u);
                    let c = o.dot(m);
                    let wi = frame.coat_to_local(m * (2.0 * c) - o);
                    (c > 0.0 && wi.z > 0.0).then_some(wi)?
                }
            },
            SPEC_T if self.thin => {
                let w = reflect(self.spec)?;
                Vec3::new(w.x, w.y, -w.z)
            }
            SPEC_T => {
                let m = self.spec.sample_visible(wo, u);
                if wo.dot(m) <= 0.0 {
                    return None;
                }
                refract_about(wo, m, self.eta).filter(|wi| wi.z < 0.0)?
            }
            _ => return None,
        };
        let (f, pdf) = self.eval_pdf(wi);
        if pdf <= 0.0 {
            return None;
        }
        let weight = f * (wi.z.abs() / pdf);
        weight.is_finite().then_some(Sampled {
            wi,
            weight,
            pdf,
            subsurface: false,
        })
    }
}

/// How much the coat's internal reflections darken the base beneath it, per channel
/// (the specification's Δ = (1 - K) / (1 - E_b K)): K, the share of light leaving the
/// base that the coat returns, blends a smooth base's (the coat's Fresnel) and a rough
/// one's by an estimate of the base's roughness; E_b is the base's albedo at normal
/// incidence.
fn darkening(p: &Params, mu_o: f32) -> Vec3 {
    let eta = p.coat_ior;
    let e_f = if eta >= 1.0 {
        fresnel_average(eta)
    } else {
        0.0
    };
    let k_rough = 1.0 - (1.0 - e_f) / (eta * eta);
    let k_smooth = fresnel_dielectric(mu_o, 1.0, eta);
    let f0 = |e: f32| ((e - 1.0) / (e + 1.0)).powi(2);
    let xi = (p.specular_weight * f0(p.specular_ior)).clamp(0.0, 1.0);
    let r_dielectric = 1.0 + (p.specular_roughness - 1.0) * xi;
    let r_base = r_dielectric + (p.specular_roughness - r_dielectric) * p.base_metalness;
    let k = k_smooth + (k_rough - k_smooth) * r_base;
    let rho = p.base_color * p.base_weight;
    let dielectric = Vec3::splat(xi) + (1.0 - xi) * (1.0 - p.transmission_weight) * rho;
    let e_b = dielectric.lerp(rho, p.base_metalness);
    (Vec3::splat(1.0 - k) / (Vec3::ONE - e_b * k).max(Vec3::splat(1e-4))).min(Vec3::ONE)
}

/// `(1 / eta)^2`: radiance crossing into a denser medium is compressed into a smaller
/// solid angle.
#[inline]
fn radiance_scale(eta: f32) -> f32 {
    1.0 / (eta * eta)
}

/// An interface's reflection and transmission albedos `er`, `et` with the energy
/// single scattering loses on rough microfacets given back, the share of it the
/// Fresnel average reflects reflected and the rest transmitted (as light scattered
/// among the microfacets meets them again): totals that sum to 1.
fn compensate(er: f32, et: f32, eta: f32) -> (f32, f32) {
    let lost = (1.0 - er - et).max(0.0);
    let f = fresnel_average(eta);
    (er + lost * f, et + lost * (1.0 - f))
}

/// The hemispherical average of a dielectric's Fresnel reflectance for relative
/// index `eta` (Kulla and Conty's fit above 1; below, what reciprocity leaves:
/// `1 - (1 - F(1/eta)) eta^2`).
fn fresnel_average(eta: f32) -> f32 {
    let outside = |e: f32| (e - 1.0) / (4.08567 + 1.00071 * e);
    if eta >= 1.0 {
        outside(eta)
    } else {
        1.0 - (1.0 - outside(1.0 / eta)) * eta * eta
    }
}

/// `total / single`, the factor a lobe is scaled by; 0 for a lobe that is not there.
#[inline]
fn ratio(total: f32, single: f32) -> f32 {
    if single > 1e-6 { total / single } else { 0.0 }
}

/// The reflection and transmission albedos of an interface at `mu_o`: Fresnel's for a
/// smooth one, the tables' for a rough one.
fn interface(g: Ggx, roughness: f32, eta: f32, mu_o: f32) -> (f32, f32) {
    if g.is_delta() {
        let f = fresnel_dielectric(mu_o, 1.0, eta);
        return (f, 1.0 - f);
    }
    let [r, t] = albedo::dielectric(mu_o, roughness, eta);
    (r, t)
}

#[cfg(test)]
mod tests;
