//! `[camera]`: a look-at camera with an optional thin lens, or a 2014 `.cmr` file.

use super::raw::RawCamera;
use super::source::{Source, regular_file};
use crate::error::Result;
use crate::math::Vec3;
use crate::options::RenderOptions;
use crate::scene::Camera;
use toml::Spanned;

/// Image size when `[render]` gives neither width nor height: 16:9.
pub const DEFAULT_SIZE: (u32, u32) = (640, 360);
/// Horizontal field of view when `fov` is not given, in degrees.
pub const DEFAULT_FOV: f32 = 60.0;

/// The camera's image size: `[render]`'s, the missing side following 16:9.
pub fn image_size(settings: &RenderOptions) -> (u32, u32) {
    let aspect = |v: u32, num: u64, den: u64| ((u64::from(v) * num).div_ceil(den)).max(1) as u32;
    match (settings.width, settings.height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, aspect(w, 9, 16)),
        (None, Some(h)) => (aspect(h, 16, 9), h),
        (None, None) => DEFAULT_SIZE,
    }
}

/// Where the keys of a perspective camera's field of view and lens are given.
fn lens_keys(raw: &RawCamera) -> impl Iterator<Item = std::ops::Range<usize>> {
    [
        raw.fov.as_ref().map(Spanned::span),
        raw.fov_axis.as_ref().map(Spanned::span),
        raw.aperture.as_ref().map(Spanned::span),
        raw.focus_distance.as_ref().map(Spanned::span),
        raw.focus_on.as_ref().map(Spanned::span),
        raw.spp.as_ref().map(Spanned::span),
        raw.shift.as_ref().map(Spanned::span),
    ]
    .into_iter()
    .flatten()
}

/// `object_center(name)` is the centre of the bounds of the object called `name`.
pub fn build(
    source: &Source,
    at: &Spanned<RawCamera>,
    settings: &RenderOptions,
    object_center: impl Fn(&str) -> Option<Vec3>,
) -> Result<Camera> {
    let raw = at.get_ref();
    if let Some(cmr) = &raw.cmr {
        let other = [
            raw.from.as_ref().map(Spanned::span),
            raw.at.as_ref().map(Spanned::span),
            raw.up.as_ref().map(Spanned::span),
            raw.projection.as_ref().map(Spanned::span),
            raw.view_width.as_ref().map(Spanned::span),
        ];
        if let Some(span) = other.into_iter().flatten().chain(lens_keys(raw)).next() {
            return Err(source.error_at(
                span,
                "a camera given by `cmr` takes no other key: the .cmr file says everything",
            ));
        }
        let path = source.resolve(cmr.get_ref());
        regular_file(source, cmr, &path)?;
        return crate::format::load_camera(&path);
    }
    let from = raw
        .from
        .as_ref()
        .ok_or_else(|| source.error(at, "[camera] needs `from` (or `cmr`)"))?;
    let look = raw
        .at
        .as_ref()
        .ok_or_else(|| source.error(at, "[camera] needs `at` (or `cmr`)"))?;
    let (eye, target) = (from.get_ref().vec3(), look.get_ref().vec3());
    if eye == target {
        return Err(source.error(
            look,
            "expected `at` away from `from`: the camera needs a direction",
        ));
    }
    let up = match &raw.up {
        None => Vec3::Y,
        Some(u) => super::objects::unit(source, u, "up")
            .map(|d| Vec3::new(d.x as f32, d.y as f32, d.z as f32))?,
    };
    let (width, height) = image_size(settings);
    let fov = match &raw.fov {
        None => DEFAULT_FOV,
        Some(f) if f.get_ref().0 > 0.0 && f.get_ref().0 < 180.0 => f.get_ref().f32(),
        Some(f) => {
            return Err(source.error(
                f,
                format!(
                    "expected fov between 0 and 180 degrees, found {}",
                    f.get_ref().0
                ),
            ));
        }
    };
    let horizontal_fov = match raw.fov_axis.as_ref().map(|a| (a, a.get_ref().as_str())) {
        None | Some((_, "horizontal")) => fov,
        Some((_, "vertical")) => {
            let half = (fov * 0.5).to_radians().tan() * width as f32 / height as f32;
            2.0 * half.atan().to_degrees()
        }
        Some((a, other)) => {
            return Err(source.error(
                a,
                format!("expected fov_axis \"horizontal\" or \"vertical\", found \"{other}\""),
            ));
        }
    };
    let mut camera = Camera::look_at(eye, target, up, horizontal_fov, width, height);
    if let Some(shift) = &raw.shift {
        let [x, y] = *shift.get_ref();
        if !(x.0.abs() <= 10.0 && y.0.abs() <= 10.0) {
            return Err(source.error(
                shift,
                format!(
                    "expected a shift within [-10, 10], found [{}, {}]",
                    x.0, y.0
                ),
            ));
        }
        // Given in units of the fitted side; kept in units of the screen's width.
        let side = match raw.fov_axis.as_ref().map(|a| a.get_ref().as_str()) {
            Some("vertical") => height as f64 / width as f64,
            _ => 1.0,
        };
        camera.shift = [(x.0 * side) as f32, (y.0 * side) as f32];
    }
    match raw.projection.as_ref().map(|p| (p, p.get_ref().as_str())) {
        None | Some((_, "perspective")) => {
            if let Some(w) = &raw.view_width {
                return Err(source.error(w, "`view_width` is for projection = \"orthographic\""));
            }
        }
        Some((p, "orthographic")) => {
            let w = raw
                .view_width
                .as_ref()
                .ok_or_else(|| source.error(p, "an orthographic camera needs `view_width`"))?;
            if !(w.get_ref().0 > 0.0 && w.get_ref().0.is_finite()) {
                return Err(source.error(
                    w,
                    format!("expected view_width > 0, found {}", w.get_ref().0),
                ));
            }
            if let Some(span) = lens_keys(raw).next() {
                return Err(source.error_at(
                    span,
                    "an orthographic camera has no field of view or lens: `view_width` sets \
                     what it sees",
                ));
            }
            camera.retina_scale = (0.5 * w.get_ref().0 / f64::from(width)) as f32;
            camera.projection = crate::scene::Projection::Orthographic;
            camera.aa = settings.aa.unwrap_or(1);
            return Ok(camera);
        }
        Some((p, other)) => {
            return Err(source.error(
                p,
                format!(
                    "expected projection \"perspective\" or \"orthographic\", found \"{other}\""
                ),
            ));
        }
    }
    let aperture = match &raw.aperture {
        None => 0.0,
        Some(a) if a.get_ref().0 >= 0.0 => a.get_ref().f32(),
        Some(a) => {
            return Err(source.error(
                a,
                format!("expected aperture >= 0, found {}", a.get_ref().0),
            ));
        }
    };
    let focus = match (&raw.focus_distance, &raw.focus_on) {
        (Some(_), Some(on)) => {
            return Err(source.error(on, "give `focus_distance` or `focus_on`, not both"));
        }
        (Some(d), None) => Spanned::new(d.span(), d.get_ref().f32()),
        (None, Some(on)) => {
            let centre = object_center(on.get_ref()).ok_or_else(|| {
                source.error(on, format!("no object is called \"{}\"", on.get_ref()))
            })?;
            Spanned::new(on.span(), (centre - eye).length())
        }
        (None, None) => Spanned::new(look.span(), (target - eye).length()),
    };
    // The screen sits at distance 1 from the eye and the focal plane `focal_length`
    // beyond it. A pinhole has no focus, so only a lens needs a reachable one.
    if aperture > 0.0 && *focus.get_ref() < 1.0 {
        return Err(source.error(
            &focus,
            format!(
                "expected a focus distance of at least 1 (the screen's distance from the \
                 eye), found {}",
                focus.get_ref()
            ),
        ));
    }
    camera.focal_length = (focus.get_ref() - 1.0).max(0.0);
    camera.aperture = aperture;
    camera.spp = raw
        .spp
        .as_ref()
        .map(|n| *n.get_ref())
        .or(settings.spp)
        .unwrap_or(1)
        .max(1);
    camera.aa = settings.aa.unwrap_or(1);
    Ok(camera)
}
