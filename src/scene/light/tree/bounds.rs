//! Bounds of lights for the tree: where they lie, the cone their light leaves in, and
//! their power; how much they may light a point (`LightBounds::importance`), and what
//! a group of them costs a split (`LightBounds::cost`).

use crate::math::{Aabb, Vec3, cross, normalize};
use crate::scene::light::{Falloff, Light, LightKind};
use crate::scene::{Scene, Shape, Surface};
use std::f32::consts::{FRAC_PI_2, PI};

/// Importance is kept below this, so that two children's sum stays finite.
const MAX_IMPORTANCE: f32 = f32::MAX / 4.0;
/// The angle beyond a spot light's outer cone where its bounds stop: a margin far above
/// the rounding of the angles the importance compares, so no lit point reads zero.
const SPOT_MARGIN: f32 = 0.02;

/// A cone of directions: its axis and the cosine of its half-angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    /// Unit axis.
    pub w: Vec3,
    /// Cosine of the half-angle: 1 for the axis alone, -1 for every direction.
    pub cos_theta: f32,
}

impl DirectionCone {
    /// Every direction.
    pub const SPHERE: DirectionCone = DirectionCone {
        w: Vec3::Z,
        cos_theta: -1.0,
    };

    /// The axis alone.
    pub fn of(w: Vec3) -> DirectionCone {
        DirectionCone { w, cos_theta: 1.0 }
    }

    /// Whether `dir` (unit) lies inside the cone.
    pub fn holds(&self, dir: Vec3) -> bool {
        self.w.dot(dir) >= self.cos_theta
    }

    /// The narrowest cone (up to rounding, which widens it) holding both.
    pub fn union(self, b: DirectionCone) -> DirectionCone {
        let a = self;
        let theta_a = safe_acos(a.cos_theta);
        let theta_b = safe_acos(b.cos_theta);
        let theta_d = angle_between(a.w, b.w);
        if (theta_d + theta_b).min(PI) <= theta_a {
            return a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return b;
        }
        let theta_o = (theta_a + theta_d + theta_b) / 2.0;
        if theta_o >= PI {
            return DirectionCone::SPHERE;
        }
        let theta_r = theta_o - theta_a;
        let axis = cross(a.w, b.w);
        if axis.length_squared() == 0.0 {
            return DirectionCone::SPHERE;
        }
        // `a.w` turned by `theta_r` toward `b.w`, about their common normal (to which
        // `a.w` is square, so Rodrigues' formula loses its third term).
        let k = normalize(axis);
        let (sin_r, cos_r) = theta_r.sin_cos();
        let w = a.w * cos_r + cross(k, a.w) * sin_r;
        // Rounding in the rotation and the cosine could leave an edge direction a hair
        // outside: widen by a few parts in a million of a radian.
        DirectionCone {
            w: normalize(w),
            cos_theta: (theta_o + 1e-5).min(PI).cos(),
        }
    }
}

/// Bounds of some lights: where they are, the directions they emit in, and their power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Where the lights lie.
    pub bounds: Aabb,
    /// Their power (watts, the brightest channel): what a node is chosen in proportion
    /// to, at equal distance and angle.
    pub phi: f32,
    /// The axis of their normals (or emitting directions).
    pub w: Vec3,
    /// Cosine of the half-angle of the cone of normals about `w`.
    pub cos_theta_o: f32,
    /// Cosine of how far beyond a normal their light spreads (a flat emitter: 90°).
    pub cos_theta_e: f32,
    /// Whether they emit on both sides of their normals.
    pub two_sided: bool,
}

impl LightBounds {
    /// Bounds of lights at `bounds` whose normals lie in `cone`, emitting `phi` to at
    /// most `theta_e` beyond them.
    fn new(bounds: Aabb, phi: f32, cone: DirectionCone, cos_theta_e: f32) -> LightBounds {
        LightBounds {
            bounds,
            phi: phi.min(MAX_IMPORTANCE),
            w: cone.w,
            cos_theta_o: cone.cos_theta,
            cos_theta_e,
            two_sided: false,
        }
    }

    /// The bounds of `light`, or `None` where it is drawn beside the tree (directional,
    /// no inverse-square falloff) or emits nothing. `surfaces` give a mesh light's
    /// emission.
    pub fn of(light: &Light, scene: &Scene, surfaces: &[Surface]) -> Option<LightBounds> {
        let radiance = (light.color * light.intensity).max_element().max(0.0);
        let at = Aabb::EMPTY.grow(light.position);
        let bounds = match &light.kind {
            LightKind::Directional { .. } => return None,
            LightKind::Point | LightKind::Spot { .. }
                if light.falloff != Falloff::InverseSquare =>
            {
                return None;
            }
            LightKind::Point => {
                LightBounds::new(at, 4.0 * PI * radiance, DirectionCone::SPHERE, 0.0)
            }
            LightKind::Spot {
                direction,
                cos_inner,
                cos_outer,
                ..
            } => {
                // The wider cone, whichever is called outer: the edge's fade may light
                // either way between them.
                let widest = cos_inner.min(*cos_outer).clamp(-1.0, 1.0);
                let axis = direction.normalize_or_zero();
                let cone = if axis == Vec3::ZERO {
                    DirectionCone::SPHERE
                } else {
                    DirectionCone {
                        w: axis,
                        cos_theta: widest,
                    }
                };
                LightBounds::new(at, 4.0 * PI * radiance, cone, SPOT_MARGIN.cos())
            }
            LightKind::Quad { u, v } => {
                let p = light.position;
                let corners = [
                    p - 0.5 * (*u + *v),
                    p + 0.5 * (*u - *v),
                    p + 0.5 * (*u + *v),
                ];
                let bounds = Aabb::from_points(&corners).grow(p - 0.5 * (*u - *v));
                let normal = cross(*u, *v).normalize_or_zero();
                flat(bounds, PI * radiance * light.flat_area(), normal)?
            }
            LightKind::Disk { normal, radius } => {
                let r = Vec3::splat(radius.abs());
                let bounds = Aabb {
                    min: light.position - r,
                    max: light.position + r,
                };
                let area = light.flat_area();
                flat(bounds, PI * radiance * area, normal.normalize_or(Vec3::Y))?
            }
            LightKind::Sphere { radius } => {
                let r = Vec3::splat(radius.abs());
                let bounds = Aabb {
                    min: light.position - r,
                    max: light.position + r,
                };
                let area = 4.0 * PI * radius * radius;
                LightBounds::new(bounds, PI * radiance * area, DirectionCone::SPHERE, 0.0)
            }
            LightKind::Mesh { shapes, .. } => {
                let mut bounds = Aabb::EMPTY;
                let mut cone: Option<DirectionCone> = None;
                let mut phi = 0.0f32;
                for &shape in shapes {
                    let Shape::Triangle(tri) = scene.shape_at(shape) else {
                        continue;
                    };
                    let le =
                        surfaces[scene.material_index(shape) as usize].emission * light.intensity;
                    let area = 0.5 * cross(tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]).length();
                    bounds = bounds.union(tri.bounds());
                    phi += PI * area * le.max_element().max(0.0);
                    let normal = DirectionCone::of(tri.normal());
                    cone = Some(cone.map_or(normal, |c| c.union(normal)));
                }
                let cone = cone?;
                LightBounds::new(bounds, phi, cone, 0.0)
            }
        };
        (bounds.phi > 0.0 && !bounds.bounds.is_empty()).then_some(bounds)
    }

    /// Both bounds together.
    pub fn union(self, b: LightBounds) -> LightBounds {
        let a = self;
        if a.phi == 0.0 {
            return b;
        }
        if b.phi == 0.0 {
            return a;
        }
        let cone = DirectionCone {
            w: a.w,
            cos_theta: a.cos_theta_o,
        }
        .union(DirectionCone {
            w: b.w,
            cos_theta: b.cos_theta_o,
        });
        LightBounds {
            bounds: a.bounds.union(b.bounds),
            phi: (a.phi + b.phi).min(MAX_IMPORTANCE),
            w: cone.w,
            cos_theta_o: cone.cos_theta,
            cos_theta_e: a.cos_theta_e.min(b.cos_theta_e),
            two_sided: a.two_sided || b.two_sided,
        }
    }

    /// How much light the bounded lights may send to point `p` of a surface with normal
    /// `n` (either side; zero: `n` unknown), up to a common factor: zero only where none
    /// can reach it.
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let pc = self.bounds.center();
        let d2 = p
            .distance_squared(pc)
            .max(self.bounds.extent().length() / 2.0);
        // The cone of directions from `p` that the box subtends (its bounding sphere's).
        let radius = if self.bounds.extent() == Vec3::ZERO {
            0.0
        } else {
            pc.distance(self.bounds.max)
        };
        let center_d2 = p.distance_squared(pc);
        let cos_theta_b = if center_d2 < radius * radius {
            -1.0
        } else {
            safe_sqrt(1.0 - radius * radius / center_d2)
        };
        let sin_theta_b = safe_sqrt(1.0 - cos_theta_b * cos_theta_b);
        // The angle at the lights between their cone's axis and the way to `p`, less the
        // cone's half-angle and the box's: how far outside every light's cone `p` lies.
        let wi = (p - pc).normalize_or_zero();
        let mut cos_theta_w = self.w.dot(wi);
        if self.two_sided {
            cos_theta_w = cos_theta_w.abs();
        }
        let sin_theta_w = safe_sqrt(1.0 - cos_theta_w * cos_theta_w);
        let sin_theta_o = safe_sqrt(1.0 - self.cos_theta_o * self.cos_theta_o);
        let cos_theta_x = cos_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, self.cos_theta_o);
        let sin_theta_x = sin_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, self.cos_theta_o);
        let cos_theta_p = cos_sub_clamped(sin_theta_x, cos_theta_x, sin_theta_b, cos_theta_b);
        if cos_theta_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_theta_p / d2;
        if n != Vec3::ZERO {
            let cos_theta_i = wi.dot(n).abs();
            let sin_theta_i = safe_sqrt(1.0 - cos_theta_i * cos_theta_i);
            importance *= cos_sub_clamped(sin_theta_i, cos_theta_i, sin_theta_b, cos_theta_b);
        }
        if importance > 0.0 {
            importance.min(MAX_IMPORTANCE)
        } else {
            0.0
        }
    }

    /// The split cost of one side (pbrt's): its power times the solid angle its directions
    /// may cover times its box's surface area, stretched by `kr` for thin splits.
    pub(super) fn cost(&self, kr: f32) -> f32 {
        let b = self;
        let theta_o = safe_acos(b.cos_theta_o);
        let theta_e = safe_acos(b.cos_theta_e);
        let theta_w = (theta_o + theta_e).min(PI);
        let sin_theta_o = safe_sqrt(1.0 - b.cos_theta_o * b.cos_theta_o);
        let m_omega = 2.0 * PI * (1.0 - b.cos_theta_o)
            + FRAC_PI_2
                * (2.0 * theta_w * sin_theta_o
                    - (theta_o - 2.0 * theta_w).cos()
                    - 2.0 * theta_o * sin_theta_o
                    + b.cos_theta_o);
        let e = b.bounds.extent();
        let area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
        b.phi * m_omega * kr * area
    }

    /// The box's centre: where the build sorts the lights by.
    pub(super) fn centroid(&self) -> Vec3 {
        self.bounds.center()
    }
}

/// The bounds of a one-sided flat emitter facing `normal`; `None` for a degenerate one.
fn flat(bounds: Aabb, phi: f32, normal: Vec3) -> Option<LightBounds> {
    (normal != Vec3::ZERO).then(|| LightBounds::new(bounds, phi, DirectionCone::of(normal), 0.0))
}

/// `cos(a - b)` from the sines and cosines of `a` and `b`, or 1 where `a < b`.
#[inline]
fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 1.0;
    }
    cos_a * cos_b + sin_a * sin_b
}

/// `sin(a - b)` from the sines and cosines of `a` and `b`, or 0 where `a < b`.
#[inline]
fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 0.0;
    }
    sin_a * cos_b - cos_a * sin_b
}

#[inline]
fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

#[inline]
fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// The angle between unit vectors, accurate near 0 and π too.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * safe_asin((a + b).length() / 2.0)
    } else {
        2.0 * safe_asin((b - a).length() / 2.0)
    }
}

#[inline]
fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}
