//! `[[light]]`: point, directional, spot, and the quad, disk and sphere area lights.

use super::objects::unit;
use super::raw::RawLight;
use super::source::Source;
use super::values::{Num, Vector};
use crate::error::Result;
use crate::math::Vec3;
use crate::scene::{Falloff, Light, LightKind};
use glam::DVec3;
use toml::Spanned;

/// Shadow rays per shading point for an area light that does not say.
pub const DEFAULT_AREA_SAMPLES: u32 = 16;
/// Most shadow rays per shading point one area light may ask for.
pub const MAX_AREA_SAMPLES: u32 = 4096;
/// A spot light's cone half-angle when `angle` is not given, in degrees.
pub const DEFAULT_SPOT_ANGLE: f64 = 30.0;

fn keys_of(kind: &str) -> Option<&'static [&'static str]> {
    Some(match kind {
        "point" => &["position", "falloff"],
        "directional" => &["direction"],
        "spot" => &[
            "position",
            "direction",
            "at",
            "angle",
            "inner_angle",
            "falloff_angle",
            "edge",
            "falloff",
        ],
        "quad" => &[
            "corner",
            "center",
            "edge1",
            "edge2",
            "samples",
            "camera_visible",
        ],
        "disk" => &["center", "normal", "radius", "samples", "camera_visible"],
        "sphere" => &["center", "radius", "samples", "camera_visible"],
        _ => return None,
    })
}

pub fn build(source: &Source, raw: &RawLight) -> Result<Light> {
    let kind = raw.kind.get_ref().as_str();
    let allowed = keys_of(kind).ok_or_else(|| {
        source.error(
            &raw.kind,
            format!(
                "unknown light type \"{kind}\": expected point, directional, spot, quad, disk \
                 or sphere"
            ),
        )
    })?;
    super::source::refuse_foreign_keys(
        source,
        raw.shape_keys(),
        allowed,
        &format!("{kind} light"),
    )?;
    let missing = |key: &str| source.error(&raw.kind, format!("a {kind} light needs `{key}`"));
    let need = |v: &Option<Spanned<Vector>>, key: &str| -> Result<DVec3> {
        v.as_ref()
            .map(|v| v.get_ref().0)
            .ok_or_else(|| missing(key))
    };
    let f = |v: DVec3| Vec3::new(v.x as f32, v.y as f32, v.z as f32);
    let non_negative = |v: &Option<Spanned<Num>>, key: &str, default: f64| -> Result<f64> {
        match v {
            None => Ok(default),
            Some(n) if n.get_ref().0 >= 0.0 => Ok(n.get_ref().0),
            Some(n) => {
                Err(source.error(n, format!("expected {key} >= 0, found {}", n.get_ref().0)))
            }
        }
    };
    let radius = || -> Result<f32> {
        let r = raw.radius.as_ref().ok_or_else(|| missing("radius"))?;
        match r.get_ref().0 {
            x if x > 0.0 => Ok(x as f32),
            x => Err(source.error(r, format!("expected radius > 0, found {x}"))),
        }
    };
    let (position, light_kind) = match kind {
        "point" => (need(&raw.position, "position")?, LightKind::Point),
        "directional" => {
            let d = raw.direction.as_ref().ok_or_else(|| missing("direction"))?;
            (
                DVec3::ZERO,
                LightKind::Directional {
                    direction: f(unit(source, d, "direction")?),
                },
            )
        }
        "spot" => {
            let position = need(&raw.position, "position")?;
            let direction = match (&raw.direction, &raw.at) {
                (Some(d), None) => unit(source, d, "direction")?,
                (None, Some(at)) => {
                    let d = at.get_ref().0 - position;
                    if d.length_squared() == 0.0 {
                        return Err(
                            source.error(at, "expected `at` away from the light's position")
                        );
                    }
                    d.normalize()
                }
                (Some(_), Some(at)) => {
                    return Err(source.error(at, "give `direction` or `at`, not both"));
                }
                (None, None) => return Err(missing("`direction` or `at`")),
            };
            let angle = match &raw.angle {
                None => DEFAULT_SPOT_ANGLE,
                Some(a) if a.get_ref().0 > 0.0 && a.get_ref().0 < 180.0 => a.get_ref().0,
                Some(a) => {
                    return Err(source.error(
                        a,
                        format!(
                            "expected an angle between 0 and 180 degrees, found {}",
                            a.get_ref().0
                        ),
                    ));
                }
            };
            let inner = match (&raw.inner_angle, &raw.falloff_angle) {
                (None, None) => angle,
                (Some(i), None) => within(source, i, angle, "inner_angle")?,
                (None, Some(w)) => angle - within(source, w, angle, "falloff_angle")?,
                (Some(_), Some(w)) => {
                    return Err(source.error(w, "give `inner_angle` or `falloff_angle`, not both"));
                }
            };
            let edge = match raw.edge.as_ref().map(|e| (e, e.get_ref().as_str())) {
                None | Some((_, "smooth")) => crate::scene::ConeEdge::Smooth,
                Some((_, "smooth_cosine")) => crate::scene::ConeEdge::SmoothCosine,
                Some((e, other)) => {
                    return Err(source.error(
                        e,
                        format!("expected edge \"smooth\" or \"smooth_cosine\", found \"{other}\""),
                    ));
                }
            };
            (
                position,
                LightKind::Spot {
                    direction: f(direction),
                    cos_inner: inner.to_radians().cos() as f32,
                    cos_outer: angle.to_radians().cos() as f32,
                    edge,
                },
            )
        }
        "quad" => {
            let (e1, e2) = (need(&raw.edge1, "edge1")?, need(&raw.edge2, "edge2")?);
            if e1.cross(e2).length_squared() == 0.0 {
                return Err(source.error(
                    raw.edge2.as_ref().expect("needed above"),
                    "expected edges that span an area, found parallel or zero edges",
                ));
            }
            let center = match (&raw.corner, &raw.center) {
                (Some(c), None) => c.get_ref().0 + 0.5 * (e1 + e2),
                (None, Some(c)) => c.get_ref().0,
                (Some(_), Some(c)) => {
                    return Err(source.error(c, "give `corner` or `center`, not both"));
                }
                (None, None) => return Err(missing("`corner` or `center`")),
            };
            (center, LightKind::Quad { u: f(e1), v: f(e2) })
        }
        "disk" => {
            let normal = match &raw.normal {
                None => DVec3::NEG_Y,
                Some(n) => unit(source, n, "normal")?,
            };
            let center = need(&raw.center, "center")?;
            (
                center,
                LightKind::Disk {
                    normal: f(normal),
                    radius: radius()?,
                },
            )
        }
        "sphere" => (
            need(&raw.center, "center")?,
            LightKind::Sphere { radius: radius()? },
        ),
        _ => unreachable!("keys_of knows every type"),
    };
    let falloff = match &raw.falloff {
        None => Falloff::None,
        Some(s) => match s.get_ref().as_str() {
            "none" => Falloff::None,
            "inverse_square" => Falloff::InverseSquare,
            other => {
                return Err(source.error(
                    s,
                    format!("expected falloff \"none\" or \"inverse_square\", found \"{other}\""),
                ));
            }
        },
    };
    let samples = match &raw.samples {
        None => DEFAULT_AREA_SAMPLES,
        Some(n) if (1..=MAX_AREA_SAMPLES).contains(n.get_ref()) => *n.get_ref(),
        Some(n) => {
            return Err(source.error(
                n,
                format!(
                    "expected samples between 1 and {MAX_AREA_SAMPLES}, found {}",
                    n.get_ref()
                ),
            ));
        }
    };
    let mut light = Light {
        position: f(position),
        color: raw.color.as_ref().map_or(Vec3::ONE, |c| c.get_ref().rgb),
        intensity: non_negative(&raw.intensity, "intensity", 1.0)? as f32,
        kind: light_kind,
        falloff,
        samples: 1,
        camera_visible: raw.camera_visible.as_ref().is_none_or(|v| *v.get_ref()),
    };
    if light.is_area() {
        light.samples = samples;
    }
    Ok(light)
}

/// An angle in `[0, limit]` degrees.
fn within(source: &Source, v: &Spanned<Num>, limit: f64, key: &str) -> Result<f64> {
    let a = v.get_ref().0;
    if (0.0..=limit).contains(&a) {
        Ok(a)
    } else {
        Err(source.error(
            v,
            format!("expected {key} between 0 and `angle` ({limit} degrees), found {a}"),
        ))
    }
}
