//! A surface of Phong terms (MTL's and the scene file's older keys) as both physical
//! models scatter light at one hit: Lambert, an energy-normalised Phong or Blinn-Phong
//! highlight, a perfect mirror and smooth refraction, answering `eval`, `pdf` and
//! `sample` for the direction light leaves toward, `wo`.
//!
//! Directions are world-space unit vectors pointing away from the surface. The smooth
//! lobes (diffuse, highlight) are one mixture sampled in proportion to their
//! reflectance, so `pdf` is the mixture's; the mirror and the refraction are deltas,
//! chosen with their own probabilities and never found by `eval`.

use super::Sampled;
use crate::math::{Vec3, highlight_pow, normalize, sin_cos};
use crate::render::optics::{fresnel_dielectric, refract};
use std::f32::consts::{FRAC_1_PI, TAU};

/// Smallest microfacet `alpha`: smoother surfaces would need a delta lobe, and the
/// distribution's peak `1 / (pi alpha^2)` stays finite in f32 above it.
const MIN_ALPHA: f32 = 1e-3;

/// The highlight lobe of a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Highlight {
    /// None.
    None,
    /// `ks (e + 2) / 2pi max(0, R.wi)^e`, R the mirror direction of `wo`: its
    /// reflectance at normal incidence is `ks` when nothing of it is cut off.
    Phong {
        /// The lobe's colour.
        ks: Vec3,
        /// Its exponent.
        exponent: f32,
    },
    /// `ks k(e) max(0, N.H)^e`, `k` the normalisation that makes its reflectance at
    /// normal incidence `ks` (the common `(e + 8) / 8pi` overshoots it by a few percent).
    Blinn {
        /// The lobe's colour.
        ks: Vec3,
        /// Its exponent.
        exponent: f32,
    },
    /// GGX microfacets with Smith masking and Schlick's Fresnel of `f0`: glTF's
    /// specular, metals and dielectrics alike.
    Ggx {
        /// Reflectance at normal incidence.
        f0: Vec3,
        /// Microfacet roughness (glTF's roughness squared).
        alpha: f32,
    },
}

/// What a surface is made of at a hit, before it is seen from a direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Terms {
    /// Lambert reflectance.
    pub diffuse: Vec3,
    /// The highlight.
    pub highlight: Highlight,
    /// Mirror reflectance (with `fresnel`, the tint of the Fresnel reflection).
    pub reflection: Vec3,
    /// Transmittance of the smooth refraction (with `fresnel`, times `1 - F`).
    pub transmission: Vec3,
    /// Reflect `F` and transmit `1 - F` of a dielectric.
    pub fresnel: bool,
    /// Refractive index of the side `wo` is on, and of the other side.
    pub eta_i: f32,
    /// See `eta_i`.
    pub eta_t: f32,
}

impl Terms {
    /// A Lambertian surface of reflectance `diffuse`, nothing else.
    pub fn diffuse(diffuse: Vec3) -> Terms {
        Terms {
            diffuse,
            highlight: Highlight::None,
            reflection: Vec3::ZERO,
            transmission: Vec3::ZERO,
            fresnel: false,
            eta_i: 1.0,
            eta_t: 1.0,
        }
    }
}

/// A Phong surface's BSDF seen from `wo`.
#[derive(Clone, Copy, Debug)]
pub struct PhongBsdf {
    /// Shading normal and geometric normal, both on `wo`'s side.
    n: Vec3,
    ng: Vec3,
    wo: Vec3,
    cos_o: f32,
    diffuse: Vec3,
    highlight: Highlight,
    /// Weights of the mirror reflection and the refraction, as seen from `wo`.
    mirror: Vec3,
    transmit: Vec3,
    refracted: Option<Vec3>,
    /// Probabilities of drawing from the smooth lobes (and of the diffuse one among
    /// them), the mirror and the refraction; they sum to 1 unless the surface is black.
    p_smooth: f32,
    p_diffuse_in_smooth: f32,
    p_mirror: f32,
    p_transmit: f32,
}

/// A colour's mean over its channels: what sampling weighs lobes by.
#[inline]
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Schlick's Fresnel of reflectance `f0` at cosine `cos`.
#[inline]
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m5 = (m * m) * (m * m) * m;
    f0 + (Vec3::ONE - f0) * m5
}

impl PhongBsdf {
    /// `terms` seen from `wo` at a point with shading normal `n` and geometric normal
    /// `ng`, both turned to `wo`'s side. A surface that would reflect and transmit more
    /// than it receives is scaled down to conserve energy.
    #[inline]
    pub fn new(terms: &Terms, wo: Vec3, n: Vec3, ng: Vec3) -> PhongBsdf {
        // A shading normal that faces away from the viewer says nothing useful about
        // reflection: the geometric one stands in.
        let n = if n.dot(wo) > 1e-4 { n } else { ng };
        let cos_o = n.dot(wo).max(1e-4);
        let d = -wo;
        let refracted = if terms.transmission.max_element() > 0.0 {
            refract(d, n, terms.eta_i, terms.eta_t)
        } else {
            None
        };
        let (mut mirror, mut transmit) = if terms.fresnel {
            let f = fresnel_dielectric(cos_o, terms.eta_i, terms.eta_t);
            (terms.reflection * f, terms.transmission * (1.0 - f))
        } else {
            (terms.reflection, terms.transmission)
        };
        if terms.transmission.max_element() > 0.0 && refracted.is_none() {
            // Total internal reflection: what would have crossed is reflected.
            mirror += transmit;
            transmit = Vec3::ZERO;
        }
        let mut diffuse = terms.diffuse.max(Vec3::ZERO);
        let mut highlight = terms.highlight;
        let highlight_reflectance = match highlight {
            Highlight::None => Vec3::ZERO,
            Highlight::Phong { ks, .. } | Highlight::Blinn { ks, .. } => ks,
            Highlight::Ggx { f0, .. } => {
                // Light the microfacets reflect does not reach the diffuse base.
                let f = schlick(f0, cos_o);
                diffuse *= Vec3::ONE - f;
                f
            }
        };
        let total = (diffuse + highlight_reflectance + mirror + transmit).max_element();
        if total > 1.0 {
            let k = 1.0 / total;
            diffuse *= k;
            mirror *= k;
            transmit *= k;
            highlight = match highlight {
                Highlight::Phong { ks, exponent } => Highlight::Phong {
                    ks: ks * k,
                    exponent,
                },
                Highlight::Blinn { ks, exponent } => Highlight::Blinn {
                    ks: ks * k,
                    exponent,
                },
                other => other,
            };
        }
        let w_diffuse = mean(diffuse);
        let w_highlight = mean(highlight_reflectance * total.max(1.0).recip());
        let w_mirror = mean(mirror);
        let w_transmit = mean(transmit);
        let sum = w_diffuse + w_highlight + w_mirror + w_transmit;
        let (p_smooth, p_diffuse_in_smooth, p_mirror, p_transmit) = if sum > 0.0 {
            let smooth = w_diffuse + w_highlight;
            (
                smooth / sum,
                if smooth > 0.0 {
                    w_diffuse / smooth
                } else {
                    0.0
                },
                w_mirror / sum,
                w_transmit / sum,
            )
        } else {
            (0.0, 0.0, 0.0, 0.0)
        };
        // Radiance crossing into a denser medium is compressed into a smaller solid
        // angle: (eta_i / eta_t)^2 of it goes on along the refracted ray.
        let eta = terms.eta_i / terms.eta_t;
        PhongBsdf {
            n,
            ng,
            wo,
            cos_o,
            diffuse,
            highlight,
            mirror,
            transmit: transmit * (eta * eta),
            refracted,
            p_smooth,
            p_diffuse_in_smooth,
            p_mirror,
            p_transmit,
        }
    }

    /// The shading normal the BSDF's cosines are taken to.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.n
    }

    /// Whether any lobe is smooth (not a delta): only then can light sampled from a
    /// light be scattered toward `wo`.
    pub fn has_smooth(&self) -> bool {
        self.p_smooth > 0.0
    }

    /// The BSDF's value for light arriving from `wi` (without the cosine): the smooth
    /// lobes only, which reflect and do not transmit.
    pub fn eval(&self, wi: Vec3) -> Vec3 {
        self.eval_pdf(wi).0
    }

    /// The density with which [`PhongBsdf::sample`] draws `wi`, per unit solid angle (the
    /// smooth lobes' share of it).
    pub fn pdf(&self, wi: Vec3) -> f32 {
        self.eval_pdf(wi).1
    }

    /// [`PhongBsdf::eval`], [`PhongBsdf::pdf`] and the cosine of `wi` to the shading normal
    /// together: what a light sample needs, with the cosines found once. Zero where
    /// `wi` is below either normal.
    #[inline]
    pub fn eval_pdf(&self, wi: Vec3) -> (Vec3, f32, f32) {
        let cos_i = self.n.dot(wi);
        if cos_i <= 0.0 || wi.dot(self.ng) <= 0.0 {
            return (Vec3::ZERO, 0.0, 0.0);
        }
        let pd = self.p_diffuse_in_smooth;
        let diffuse_pdf = pd * cos_i * FRAC_1_PI;
        let (f, pdf) = match self.highlight {
            // Lambert alone: no lobe to look up.
            Highlight::None => (self.diffuse * FRAC_1_PI, self.p_smooth * diffuse_pdf),
            _ => (
                self.diffuse * FRAC_1_PI + self.highlight_value(wi, cos_i),
                self.p_smooth * (diffuse_pdf + (1.0 - pd) * self.highlight_pdf(wi)),
            ),
        };
        (f, if self.p_smooth > 0.0 { pdf } else { 0.0 }, cos_i)
    }

    /// [`PhongBsdf::eval`] and the cosine, without the density: what a model that only
    /// gathers light from lights needs (the value is [`PhongBsdf::eval_pdf`]'s, bit for
    /// bit).
    #[inline]
    pub fn eval_cos(&self, wi: Vec3) -> (Vec3, f32) {
        let cos_i = self.n.dot(wi);
        if cos_i <= 0.0 || wi.dot(self.ng) <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let f = match self.highlight {
            Highlight::None => self.diffuse * FRAC_1_PI,
            _ => self.diffuse * FRAC_1_PI + self.highlight_value(wi, cos_i),
        };
        (f, cos_i)
    }

    /// A direction drawn for `wo`: `pick` chooses the lobe, `u` the direction in it.
    /// `None` where the surface absorbs (black, or a draw below the surface).
    pub fn sample(&self, pick: f32, u: (f32, f32)) -> Option<Sampled> {
        if pick < self.p_mirror {
            let wi = self.n * (2.0 * self.cos_o) - self.wo;
            return (wi.dot(self.ng) > 0.0).then_some(Sampled {
                wi,
                weight: self.mirror / self.p_mirror,
                pdf: 0.0,
                subsurface: false,
            });
        }
        if pick < self.p_mirror + self.p_transmit {
            let wi = self.refracted?;
            return (wi.dot(self.ng) < 0.0).then_some(Sampled {
                wi,
                weight: self.transmit / self.p_transmit,
                pdf: 0.0,
                subsurface: false,
            });
        }
        if self.p_smooth <= 0.0 {
            return None;
        }
        // The pick's place within the smooth share chooses diffuse or highlight.
        let within = (pick - self.p_mirror - self.p_transmit) / self.p_smooth;
        let wi = if within < self.p_diffuse_in_smooth {
            self.local(cosine_hemisphere(u))
        } else {
            self.sample_highlight(u)?
        };
        let (f, pdf, cos_i) = self.eval_pdf(wi);
        if pdf <= 0.0 {
            return None;
        }
        let weight = f * (cos_i / pdf);
        weight.is_finite().then_some(Sampled {
            wi,
            weight,
            pdf,
            subsurface: false,
        })
    }

    /// A direction given in a frame about the normal: made when a direction is drawn,
    /// not for every hit (the whitted model draws none).
    #[inline]
    fn local(&self, v: Vec3) -> Vec3 {
        let (t, b) = self.n.any_orthonormal_pair();
        t * v.x + b * v.y + self.n * v.z
    }

    fn highlight_value(&self, wi: Vec3, cos_i: f32) -> Vec3 {
        match self.highlight {
            Highlight::None => Vec3::ZERO,
            Highlight::Phong { ks, exponent } => {
                let c = self.mirror_of_wo().dot(wi);
                if c <= 0.0 {
                    return Vec3::ZERO;
                }
                ks * ((exponent + 2.0) * 0.5 * FRAC_1_PI * highlight_pow(c, exponent))
            }
            Highlight::Blinn { ks, exponent } => {
                let c = self.n.dot(normalize(self.wo + wi));
                if c <= 0.0 {
                    return Vec3::ZERO;
                }
                ks * (blinn_normalization(exponent) * highlight_pow(c, exponent))
            }
            Highlight::Ggx { f0, alpha } => {
                let h = (self.wo + wi).normalize_or_zero();
                let cos_h = self.n.dot(h);
                if cos_h <= 0.0 {
                    return Vec3::ZERO;
                }
                let a = alpha.max(MIN_ALPHA);
                let g = smith_g1(self.cos_o, a) * smith_g1(cos_i, a);
                schlick(f0, self.wo.dot(h)) * (ggx_d(cos_h, a) * g / (4.0 * self.cos_o * cos_i))
            }
        }
    }

    fn highlight_pdf(&self, wi: Vec3) -> f32 {
        match self.highlight {
            Highlight::None => 0.0,
            Highlight::Phong { exponent, .. } => {
                let c = self.mirror_of_wo().dot(wi);
                if c <= 0.0 {
                    return 0.0;
                }
                (exponent + 1.0) * 0.5 * FRAC_1_PI * highlight_pow(c, exponent)
            }
            Highlight::Blinn { exponent, .. } => {
                let h = normalize(self.wo + wi);
                let (c, o) = (self.n.dot(h), self.wo.dot(h));
                if c <= 0.0 || o <= 0.0 {
                    return 0.0;
                }
                (exponent + 1.0) * 0.5 * FRAC_1_PI * highlight_pow(c, exponent) / (4.0 * o)
            }
            Highlight::Ggx { alpha, .. } => {
                let h = (self.wo + wi).normalize_or_zero();
                let (c, o) = (self.n.dot(h), self.wo.dot(h));
                if c <= 0.0 || o <= 0.0 {
                    return 0.0;
                }
                ggx_d(c, alpha.max(MIN_ALPHA)) * c / (4.0 * o)
            }
        }
    }

    fn sample_highlight(&self, (u, v): (f32, f32)) -> Option<Vec3> {
        let (sin_p, cos_p) = sin_cos(v * TAU);
        let around = |axis: Vec3, cos: f32| {
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            let (t, b) = axis.any_orthonormal_pair();
            normalize(t * (sin * cos_p) + b * (sin * sin_p) + axis * cos)
        };
        let reflect_about = |h: Vec3| {
            let o = self.wo.dot(h);
            (o > 0.0).then(|| h * (2.0 * o) - self.wo)
        };
        match self.highlight {
            Highlight::None => None,
            Highlight::Phong { exponent, .. } => {
                Some(around(self.mirror_of_wo(), u.powf(1.0 / (exponent + 1.0))))
            }
            Highlight::Blinn { exponent, .. } => {
                reflect_about(around(self.n, u.powf(1.0 / (exponent + 1.0))))
            }
            Highlight::Ggx { alpha, .. } => {
                let a = alpha.max(MIN_ALPHA);
                let tan2 = a * a * u / (1.0 - u).max(f32::MIN_POSITIVE);
                reflect_about(around(self.n, 1.0 / (1.0 + tan2).sqrt()))
            }
        }
    }

    /// `wo` mirrored about the shading normal.
    #[inline]
    fn mirror_of_wo(&self) -> Vec3 {
        self.n * (2.0 * self.cos_o) - self.wo
    }
}

/// The factor that makes a Blinn-Phong lobe of exponent `e` reflect all it receives
/// at normal incidence: `(e + 2)(e + 4) / (8 pi (2^(-e/2) + e))`.
#[inline]
fn blinn_normalization(e: f32) -> f32 {
    (e + 2.0) * (e + 4.0) / (8.0 * std::f32::consts::PI * ((-e / 2.0).exp2() + e))
}

/// GGX's distribution of normals at cosine `c` to the surface normal.
#[inline]
fn ggx_d(c: f32, a: f32) -> f32 {
    let a2 = a * a;
    let k = c * c * (a2 - 1.0) + 1.0;
    a2 * FRAC_1_PI / (k * k)
}

/// Smith's masking of one direction at cosine `c` for GGX.
#[inline]
fn smith_g1(c: f32, a: f32) -> f32 {
    let a2 = a * a;
    2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt())
}

/// A direction about +z with density `cos / pi`, from `u` uniform in the square.
#[inline]
pub fn cosine_hemisphere(u: (f32, f32)) -> Vec3 {
    let (x, y) = crate::math::concentric_disk(u);
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

/// A direction uniform on the unit sphere, from `u` uniform in the square.
#[inline]
pub fn uniform_sphere((u, v): (f32, f32)) -> Vec3 {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos(v * TAU);
    Vec3::new(r * c, r * s, z)
}
