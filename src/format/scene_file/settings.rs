//! `[render]`, `[ambient]` and `[background]`.

use super::images::ImageCache;
use super::objects::unit;
use super::raw::{RawAmbient, RawBackground, RawRender};
use super::source::Source;
use crate::error::Result;
use crate::math::Vec3;
use crate::options::MAX_PATH_DEPTH;
use crate::options::RenderOptions;
use crate::scene::Background;
use crate::util::limits::{MAX_AA, MAX_SIDE, MAX_SPP};
use glam::DVec3;
use toml::Spanned;

pub fn render(source: &Source, raw: &RawRender) -> Result<RenderOptions> {
    let range = |v: &Option<Spanned<u32>>, key: &str, lo: u32, hi: u32| -> Result<Option<u32>> {
        match v {
            Some(n) if !(lo..=hi).contains(n.get_ref()) => Err(source.error(
                n,
                format!(
                    "expected {key} between {lo} and {hi}, found {}",
                    n.get_ref()
                ),
            )),
            v => Ok(v.as_ref().map(|n| *n.get_ref())),
        }
    };
    let min_weight = match &raw.min_weight {
        Some(w) if !(0.0..=1.0).contains(&w.get_ref().0) => {
            return Err(source.error(
                w,
                format!(
                    "expected min_weight between 0 and 1, found {}",
                    w.get_ref().0
                ),
            ));
        }
        w => w.as_ref().map(|w| w.get_ref().f32()),
    };
    let integrator: Option<crate::options::IntegratorKind> = parsed(source, &raw.integrator)?;
    // The file's own model bounds its depth; without one, the deepest any model takes
    // (the render checks the model it is given).
    let depth_limit = integrator.map_or(MAX_PATH_DEPTH, |i| i.max_depth_limit());
    Ok(RenderOptions {
        width: range(&raw.width, "width", 1, MAX_SIDE)?,
        height: range(&raw.height, "height", 1, MAX_SIDE)?,
        aa: range(&raw.aa, "aa", 1, MAX_AA)?,
        filter: parsed(source, &raw.filter)?,
        spp: range(&raw.spp, "spp", 1, MAX_SPP)?,
        max_depth: range(&raw.max_depth, "max_depth", 0, depth_limit)?,
        min_weight,
        light_sampling: parsed(source, &raw.light_sampling)?,
        seed: raw.seed.as_ref().map(|s| *s.get_ref()),
        integrator,
        exposure: raw.exposure.as_ref().map(|e| e.get_ref().f32()),
        tonemap: parsed(source, &raw.tonemap)?,
        denoise: raw.denoise.as_ref().map(|d| *d.get_ref()),
    })
}

/// A name the program parses (`filter`, `integrator`), its message at the key.
fn parsed<T: std::str::FromStr<Err = String>>(
    source: &Source,
    v: &Option<Spanned<String>>,
) -> Result<Option<T>> {
    v.as_ref()
        .map(|s| s.get_ref().parse().map_err(|m: String| source.error(s, m)))
        .transpose()
}

fn intensity(source: &Source, v: &Option<Spanned<super::values::Num>>) -> Result<f32> {
    match v {
        None => Ok(1.0),
        Some(n) if n.get_ref().0 >= 0.0 => Ok(n.get_ref().f32()),
        Some(n) => Err(source.error(
            n,
            format!("expected intensity >= 0, found {}", n.get_ref().0),
        )),
    }
}

/// La, the light every surface's Ka multiplies.
pub fn ambient(source: &Source, raw: &RawAmbient) -> Result<Vec3> {
    Ok(raw.color.get_ref().rgb * intensity(source, &raw.intensity)?)
}

pub fn background(
    source: &Source,
    at: &Spanned<RawBackground>,
    images: &mut crate::scene::SceneBuilder,
    cache: &mut ImageCache,
) -> Result<Background> {
    let raw = at.get_ref();
    let intensity = intensity(source, &raw.intensity)?;
    match (&raw.color, &raw.image) {
        (Some(_), Some(i)) => Err(source.error(i, "give `color` or `image`, not both")),
        (None, None) => Err(source.error(at, "[background] needs `color` or `image`")),
        (Some(c), None) => {
            if let Some((key, span)) = [("up", &raw.up), ("forward", &raw.forward)]
                .into_iter()
                .find_map(|(k, v)| v.as_ref().map(|v| (k, v.span())))
            {
                return Err(
                    source.error_at(span, format!("`{key}` goes with `image`, not `color`"))
                );
            }
            Ok(Background::Color(c.get_ref().rgb * intensity))
        }
        (None, Some(file)) => {
            let up = raw
                .up
                .as_ref()
                .map_or(Ok(DVec3::Y), |u| unit(source, u, "up"))?;
            let forward = match &raw.forward {
                None => {
                    // -z made perpendicular to `up` (or +x when up is along z).
                    let f = DVec3::NEG_Z - up * up.dot(DVec3::NEG_Z);
                    f.try_normalize()
                        .unwrap_or(DVec3::X - up * up.x)
                        .normalize()
                }
                Some(f) => {
                    let d = unit(source, f, "forward")?;
                    (d - up * up.dot(d))
                        .try_normalize()
                        .ok_or_else(|| source.error(f, "expected `forward` not parallel to `up`"))?
                }
            };
            let image = cache.get(source, file, true, images)?;
            let v = |d: DVec3| Vec3::new(d.x as f32, d.y as f32, d.z as f32);
            Ok(Background::Environment {
                image,
                up: v(up),
                forward: v(forward),
                intensity,
            })
        }
    }
}
