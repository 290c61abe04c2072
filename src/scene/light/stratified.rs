//! A light's stratified samples as the irradiance each delivers: what the whitted model
//! sums at a shading point (one sample for a point, spot or directional light,
//! `light.samples` for a light with an extent, each standing for its share of the
//! light), one at a time here and in lanes in [`lanes`].
//!
//! Where a sample's point lies is the light's own ([`Light::flat`],
//! [`SphereCone::direction`]), shared with the path model's samples of
//! [`Light::sample_incident`]; only how a sample is weighed differs (irradiance over a
//! share of the area here, radiance over a density there).

pub mod lanes;

use super::sampling::{Seen, SphereCone};
use super::{Light, LightKind};
use crate::math::Vec3;
use crate::scene::{Scene, Surface};

/// One sample of a light as seen from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point toward the light.
    pub dir: Vec3,
    /// Distance to the sample (infinite for a directional light).
    pub dist: f32,
    /// Irradiance the sample delivers to a surface facing it.
    pub e: Vec3,
}

/// Stratified points, sample `i` of `n`: what a light's samples are drawn from. The
/// renderer's per-pixel sampler is one; the strata are its business.
pub trait Strata {
    /// A point of the unit square.
    fn square(&mut self, i: u32, n: u32) -> (f32, f32);
    /// A point of the unit disk.
    fn disk(&mut self, i: u32, n: u32) -> (f32, f32);
}

impl Light {
    /// Calls `f` with each sample of the light seen from `p`: one for a point, spot or
    /// directional light, `samples` stratified ones from `strata` for a light with an
    /// extent. `surfaces` gives a mesh light's emission.
    pub fn for_each_sample(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        p: Vec3,
        strata: &mut impl Strata,
        mut f: impl FnMut(LightSample),
    ) {
        let n = self.samples.max(1);
        match &self.kind {
            LightKind::Point | LightKind::Spot { .. } | LightKind::Directional { .. } => {
                if let Some((dir, dist, e)) = self.delta_irradiance(p) {
                    f(LightSample { dir, dist, e });
                }
            }
            LightKind::Mesh { shapes, .. } if shapes.is_empty() => {}
            LightKind::Quad { .. } | LightKind::Disk { .. } | LightKind::Mesh { .. } => {
                let Some(flat) = self.flat() else {
                    return;
                };
                let share = flat.area / n as f32;
                let disk = matches!(self.kind, LightKind::Disk { .. });
                for i in 0..n {
                    let at = if disk {
                        strata.disk(i, n)
                    } else {
                        strata.square(i, n)
                    };
                    if let Some(y) = flat.point(scene, surfaces, at)
                        && let Some(ls) = share_sample(p, y.y, y.normal, share, y.le)
                    {
                        f(ls);
                    }
                }
            }
            LightKind::Sphere { radius } => {
                let Some(cone) = SphereCone::new(self.position, *radius, p) else {
                    return;
                };
                let e = self.color * self.intensity * (cone.solid_angle / n as f32);
                for i in 0..n {
                    let (dir, cos) = cone.direction(strata.square(i, n));
                    f(LightSample {
                        dir,
                        dist: cone.near_side(cos),
                        e,
                    });
                }
            }
        }
    }
}

/// A sample at `y` on a flat emitter of radiance `le` with unit normal `normal`,
/// standing for `share` of its area: irradiance `le cos_l share / r^2` toward `p`.
/// One-sided: nothing from behind.
#[inline]
fn share_sample(p: Vec3, y: Vec3, normal: Vec3, share: f32, le: Vec3) -> Option<LightSample> {
    let seen = Seen::from(p, y, normal)?;
    // Refused when facing away, not when NaN: the lanes keep the same rule.
    if seen.cos_l <= 0.0 {
        return None;
    }
    Some(LightSample {
        dir: seen.dir,
        dist: seen.dist,
        e: le * (seen.cos_l * share / seen.d2),
    })
}
