//! How a surface scatters light at a hit, for both physical models: the whitted model
//! gathers light from lights through [`Bsdf::eval_pdf`] (and traces the mirror and
//! refraction deltas), the path model also draws its next direction from
//! [`Bsdf::sample`]. So on the same surface under the same light the two agree.
//!
//! A surface is either an OpenPBR material (`openpbr`: its lobes in the shading frame)
//! or one of Phong terms (`phong`: MTL's and the scene file's older keys).

pub mod albedo;
mod diffuse;
mod fuzz;
pub mod medium;
pub mod microfacet;
pub mod openpbr;
mod phong;
mod thin_film;

pub use openpbr::{OpenPbrBsdf, Params};
pub use phong::{Highlight, PhongBsdf, Terms, cosine_hemisphere, schlick, uniform_sphere};

use crate::math::Vec3;
use crate::scene::{Scene, ShapeId, Surface, SurfacePoint};

/// A direction drawn from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampled {
    /// Unit direction light arrives from.
    pub wi: Vec3,
    /// `f cos / pdf`: what the path's throughput is multiplied by.
    pub weight: Vec3,
    /// The density the direction was drawn with per unit solid angle; zero for a
    /// mirror or refraction (a delta).
    pub pdf: f32,
    /// The direction enters the surface's subsurface medium ([`Bsdf::medium`]): light
    /// leaves it elsewhere, where a walk through the medium ends.
    pub subsurface: bool,
}

/// An OpenPBR BSDF in world space: its shading frame and geometric normal.
#[derive(Clone, Copy, Debug)]
pub struct Framed {
    t: Vec3,
    b: Vec3,
    n: Vec3,
    ng: Vec3,
    local: OpenPbrBsdf,
}

impl Framed {
    /// The mirror's and the refraction's weights, for a model that traces both.
    pub fn deltas(&self) -> (Vec3, Vec3) {
        self.local.deltas()
    }

    /// The rough lobes' reflection and transmission faded by roughness
    /// ([`OpenPbrBsdf::glossy`]).
    pub fn glossy(&self) -> (Vec3, Vec3) {
        self.local.glossy()
    }

    /// Where the coat has a normal of its own, what it reflects (its mirror's weight
    /// plus its rough lobe faded by roughness) and the world direction it reflects
    /// along, for a model that traces both.
    pub fn coat_reflection(&self) -> Option<(Vec3, Vec3)> {
        self.local
            .coat_reflection()
            .map(|(k, wi)| (k, self.to_world(wi)))
    }

    /// The share of light that passes straight through (`1 - geometry_opacity`).
    pub fn pass_through(&self) -> f32 {
        self.local.pass_through()
    }

    /// The refraction delta's direction in world space.
    pub fn refracted(&self) -> Option<Vec3> {
        self.local.refracted().map(|w| self.to_world(w))
    }

    #[inline]
    fn to_local(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    #[inline]
    fn to_world(self, v: Vec3) -> Vec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }
}

/// A surface's BSDF seen from `wo`.
// Made on the stack at every hit: boxing the larger variant would allocate per ray.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    /// Phong terms.
    Phong(PhongBsdf),
    /// An OpenPBR material.
    OpenPbr(Framed),
}

impl Bsdf {
    /// Surface `s` at hit `sp` of shape `shape`, seen from `wo`; `albedo` its base colour
    /// there, `n` and `ng` the shading and geometric normals turned to `wo`'s side,
    /// `entering` whether `wo` is on the side the surface faces; `channel` the one
    /// colour channel a path carries once a dispersive surface has split it; `walks`
    /// whether the model follows light through a subsurface medium (else the medium's
    /// colour is a diffuse lobe's, the look it tends to as it grows dense).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn at(
        scene: &Scene,
        s: &Surface,
        sp: &SurfacePoint,
        shape: ShapeId,
        albedo: Vec3,
        wo: Vec3,
        n: Vec3,
        ng: Vec3,
        entering: bool,
        channel: Option<usize>,
        walks: bool,
    ) -> Bsdf {
        match &s.openpbr {
            Some(m) => {
                let mut params = Params::at(scene, m, albedo, sp);
                params.subsurface_walk = walks;
                let params = match channel {
                    Some(c) if m.disperses() => params.for_channel(m, c),
                    _ => params,
                };
                let tangent = if params.specular_roughness_anisotropy > 0.0
                    || params.coat_roughness_anisotropy > 0.0
                {
                    scene.dpdu(shape)
                } else {
                    None
                };
                // The coat's normal: its own map on the unperturbed normal, or that
                // normal itself (a base's normal map bumps what lies under the coat).
                let coat_normal = (params.coat_weight > 0.0).then(|| {
                    let c = match &m.geometry_coat_normal {
                        Some((slot, scale)) => scene.normal_mapped(sp, shape, slot, *scale),
                        None => sp.n,
                    };
                    if entering { c } else { -c }
                });
                Bsdf::openpbr(
                    &params,
                    wo,
                    [n, ng],
                    tangent,
                    m.tangent_rotation,
                    entering,
                    coat_normal,
                )
            }
            None => Bsdf::Phong(PhongBsdf::new(
                &phong_terms(scene, s, sp, albedo, entering),
                wo,
                n,
                ng,
            )),
        }
    }

    /// OpenPBR parameters `p` seen from `wo` at a point of shading normal `n` and
    /// geometric normal `ng` (both on `wo`'s side); the anisotropy's tangent follows
    /// `tangent` (where given) turned by `rotation` turns; the coat lies along
    /// `coat_normal` (on `wo`'s side) where it is given and differs from `n`.
    pub fn openpbr(
        p: &Params,
        wo: Vec3,
        [n, ng]: [Vec3; 2],
        tangent: Option<Vec3>,
        rotation: f32,
        outside: bool,
        coat_normal: Option<Vec3>,
    ) -> Bsdf {
        // A shading normal that faces away from the viewer says nothing useful about
        // reflection: the geometric one stands in.
        let n = if n.dot(wo) > 1e-4 { n } else { ng };
        let (mut t, mut b) = match tangent {
            Some(t) => {
                let t = (t - n * n.dot(t)).normalize_or_zero();
                if t == Vec3::ZERO {
                    n.any_orthonormal_pair()
                } else {
                    (t, crate::math::cross(n, t))
                }
            }
            None => n.any_orthonormal_pair(),
        };
        if rotation != 0.0 {
            let (s, c) = crate::math::sin_cos(rotation * std::f32::consts::TAU);
            (t, b) = (t * c + b * s, b * c - t * s);
        }
        let local = crate::math::normalize(Vec3::new(wo.dot(t), wo.dot(b), wo.dot(n).max(1e-4)));
        // A coat normal facing away from the viewer, or the base's own, leaves the
        // coat in the base's frame.
        let coat_frame = coat_normal
            .filter(|c| c.dot(wo) > 1e-4 && (*c - n).length_squared() > 1e-10)
            .map(|c| {
                openpbr::CoatFrame::about(crate::math::normalize(Vec3::new(
                    c.dot(t),
                    c.dot(b),
                    c.dot(n),
                )))
            });
        Bsdf::OpenPbr(Framed {
            t,
            b,
            n,
            ng,
            local: OpenPbrBsdf::with_coat_frame(p, local, outside, coat_frame),
        })
    }

    /// The medium under the surface that [`Bsdf::sample`] may send light into.
    #[inline]
    pub fn medium(&self) -> Option<medium::Medium> {
        match self {
            Bsdf::Phong(_) => None,
            Bsdf::OpenPbr(f) => f.local.medium(),
        }
    }

    /// The shading normal the BSDF's cosines are taken to.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        match self {
            Bsdf::Phong(b) => b.normal(),
            Bsdf::OpenPbr(f) => f.n,
        }
    }

    /// Whether any lobe is smooth (not a delta): only then can light sampled from a
    /// light be scattered toward `wo`.
    #[inline]
    pub fn has_smooth(&self) -> bool {
        match self {
            Bsdf::Phong(b) => b.has_smooth(),
            Bsdf::OpenPbr(f) => f.local.has_smooth(),
        }
    }

    /// The smooth lobes' value for light from `wi` (no cosine), the density with which
    /// [`Bsdf::sample`] draws `wi`, and `|cos|` of `wi` to the shading normal. Zero
    /// where `wi` is on the wrong side of the geometric surface for the lobe that
    /// would carry it.
    #[inline]
    pub fn eval_pdf(&self, wi: Vec3) -> (Vec3, f32, f32) {
        match self {
            Bsdf::Phong(b) => b.eval_pdf(wi),
            Bsdf::OpenPbr(f) => {
                let l = f.to_local(wi);
                let g = wi.dot(f.ng);
                if l.z == 0.0 || (l.z > 0.0) != (g > 0.0) {
                    return (Vec3::ZERO, 0.0, 0.0);
                }
                let (v, pdf) = f.local.eval_pdf(l);
                (v, pdf, l.z.abs())
            }
        }
    }

    /// [`Bsdf::eval_pdf`]'s value and cosine without the density, for the whitted model.
    #[inline]
    pub fn eval_cos(&self, wi: Vec3) -> (Vec3, f32) {
        match self {
            Bsdf::Phong(b) => b.eval_cos(wi),
            Bsdf::OpenPbr(_) => {
                let (f, _, cos) = self.eval_pdf(wi);
                (f, cos)
            }
        }
    }

    /// A direction drawn for `wo`: `pick` chooses the lobe, `u` the direction in it.
    /// `None` where the surface absorbs.
    #[inline]
    pub fn sample(&self, pick: f32, u: (f32, f32)) -> Option<Sampled> {
        match self {
            Bsdf::Phong(b) => b.sample(pick, u),
            Bsdf::OpenPbr(f) => {
                let s = f.local.sample(pick, u)?;
                let wi = f.to_world(s.wi);
                // Reflections stay on the geometric side of `wo`, refractions cross it.
                ((wi.dot(f.ng) > 0.0) == (s.wi.z > 0.0)).then_some(Sampled { wi, ..s })
            }
        }
    }
}

/// A Phong surface's terms at a hit: its albedo and maps read there.
#[inline]
pub fn phong_terms(
    scene: &Scene,
    s: &Surface,
    sp: &SurfacePoint,
    albedo: Vec3,
    entering: bool,
) -> Terms {
    let (eta_i, eta_t) = if entering { (1.0, s.ior) } else { (s.ior, 1.0) };
    let ks = s.specular * scene.map(&s.specular_map, sp);
    let highlight = if ks == Vec3::ZERO {
        Highlight::None
    } else {
        match s.highlight {
            crate::scene::Highlight::Phong => Highlight::Phong {
                ks,
                exponent: s.shininess,
            },
            crate::scene::Highlight::BlinnPhong => Highlight::Blinn {
                ks,
                exponent: s.shininess,
            },
        }
    };
    let (diffuse, reflection) = (albedo * s.diffuse, s.reflection);
    Terms {
        diffuse,
        highlight,
        reflection,
        transmission: s.transmission,
        fresnel: s.fresnel,
        eta_i,
        eta_t,
    }
}
