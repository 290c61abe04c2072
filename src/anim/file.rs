//! The animation file (TOML; `docs/animation.md`): parsed and checked, every error with
//! the file and line it comes from.

use super::curve::{Curve, Interpolation};
use super::motion::{Aim, Motion, Selection, Target, Track};
use super::{Animation, FNV_OFFSET, MAX_FPS, MAX_FRAMES, MIN_FPS, fnv1a};
use crate::error::{Error, Result};
use crate::options::{Filter, RenderOptions};
use crate::render::Renderer;
use crate::scene::{Camera, Scene};
use glam::DVec3;
use serde::Deserialize;
use std::path::Path;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    scene: Spanned<String>,
    /// A 2014 camera; optional for scenes with cameras of their own (glTF).
    camera: Option<Spanned<String>>,
    frames: Option<Spanned<i64>>,
    duration: Option<Spanned<f64>>,
    fps: Option<Spanned<f64>>,
    start: Option<Spanned<RawStart>>,
    render: Option<Spanned<RawRender>>,
    #[serde(default)]
    track: Vec<Spanned<RawTrack>>,
}

/// Where the camera starts, overriding the camera file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStart {
    eye: Option<[f64; 3]>,
    theta: Option<f64>,
    phi: Option<f64>,
    focal_length: Option<f64>,
    aperture: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRender {
    width: Option<u32>,
    height: Option<u32>,
    aa: Option<u32>,
    /// Samples per pixel; `dof_rays` is its older name.
    #[serde(alias = "dof_rays")]
    spp: Option<u32>,
    filter: Option<Spanned<String>>,
    seed: Option<u64>,
    denoise: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTrack {
    target: Spanned<String>,
    motion: Spanned<String>,
    interpolation: Option<Spanned<String>>,
    axis: Option<Spanned<[f64; 3]>>,
    center: Option<Spanned<[f64; 3]>>,
    keep_orientation: Option<Spanned<bool>>,
    at: Option<Spanned<RawAim>>,
    focus: Option<Spanned<bool>>,
    keys: Option<RawKeys>,
}

impl RawTrack {
    /// The optional fields given, each with where it starts in the file.
    fn given(&self) -> Vec<(&'static str, usize)> {
        let mut out = Vec::new();
        let mut add = |name, span: Option<std::ops::Range<usize>>| {
            if let Some(s) = span {
                out.push((name, s.start));
            }
        };
        add(
            "interpolation",
            self.interpolation.as_ref().map(|x| x.span()),
        );
        add("axis", self.axis.as_ref().map(|x| x.span()));
        add("center", self.center.as_ref().map(|x| x.span()));
        add(
            "keep_orientation",
            self.keep_orientation.as_ref().map(|x| x.span()),
        );
        add("at", self.at.as_ref().map(|x| x.span()));
        add("focus", self.focus.as_ref().map(|x| x.span()));
        add("keys", self.keys.as_ref().map(|x| x.span()));
        out
    }
}

/// The optional fields each motion takes.
fn fields_of(motion: &str) -> &'static [&'static str] {
    match motion {
        "translate" => &["keys", "interpolation"],
        "rotate" => &["keys", "interpolation", "axis", "center"],
        "orbit" => &[
            "keys",
            "interpolation",
            "axis",
            "center",
            "keep_orientation",
        ],
        "look_at" => &["at", "focus"],
        _ => &[],
    }
}

/// `keys = [[time, value], ...]`, each key with its place in the file.
type RawKeys = Spanned<Vec<Spanned<(f64, RawValue)>>>;

#[derive(Deserialize)]
#[serde(untagged)]
enum RawAim {
    Point([f64; 3]),
    Target(String),
}

#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum RawValue {
    Number(f64),
    Vector([f64; 3]),
}

/// Byte offsets to 1-based line numbers, by binary search over the line starts (a file
/// of 40 000 tracks asks once per track).
struct Lines<'a> {
    path: &'a Path,
    /// Byte offset of each line's first byte.
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(text: &str, path: &'a Path) -> Lines<'a> {
        let starts = std::iter::once(0)
            .chain(
                text.bytes()
                    .enumerate()
                    .filter(|&(_, b)| b == b'\n')
                    .map(|(i, _)| i + 1),
            )
            .collect();
        Lines { path, starts }
    }

    fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&s| s <= offset).max(1)
    }

    fn error<T>(&self, at: &Spanned<T>, message: impl Into<String>) -> Error {
        Error::parse(self.path, self.line(at.span().start), message)
    }
}

/// Reads an animation file and the scene and camera files it names.
pub fn load(path: &Path) -> Result<Animation> {
    parse(&read_bounded(path)?, path)
}

/// Largest animation file read: far beyond any real one, small enough to hold.
pub const MAX_FILE_BYTES: u64 = 64 << 20;

/// Reads a regular file of at most [`MAX_FILE_BYTES`] as UTF-8: a FIFO or a device
/// would block or never end, and a file that grows while read stops at the bound.
fn read_bounded(path: &Path) -> Result<String> {
    let cannot = |e: &dyn std::fmt::Display| Error::file(path, format!("cannot read: {e}"));
    let bytes = crate::util::file::read_regular(path, MAX_FILE_BYTES).map_err(|e| cannot(&e))?;
    String::from_utf8(bytes).map_err(|_| cannot(&"not UTF-8 text"))
}

/// Parses the text of the animation file at `path`; the scene and camera it names are
/// read from disk, relative to `path`'s folder.
pub fn parse(text: &str, path: &Path) -> Result<Animation> {
    // A file naming no `scene` is a Prism scene file that animates itself.
    if let Ok(table) = text.parse::<toml::Table>()
        && !table.contains_key("scene")
    {
        return parse_scene_file(text, path);
    }
    let lines = Lines::new(text, path);
    let raw: RawFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| lines.line(s.start));
        Error::parse(path, line, e.message().trim_end().replace('\n', "; "))
    })?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let scene_path = folder.join(raw.scene.get_ref());
    let camera_path = raw.camera.as_ref().map(|c| folder.join(c.get_ref()));
    let file = crate::format::load(&scene_path)?;
    if camera_path.is_none() && file.camera.is_none() {
        return Err(lines.error(
            &raw.scene,
            "the scene has no camera of its own: name a 2014 camera file with `camera`",
        ));
    }
    // The one resolution a still has: the animation's [render] over the scene file's.
    let options = crate::job::JobOptions {
        render: render_options(&lines, raw.render.as_ref())?,
        camera_file: camera_path.clone(),
        ..Default::default()
    };
    let job = crate::job::resolve(file, &options).map_err(|e| match (&raw.render, e) {
        (Some(r), Error::Settings(m)) => lines.error(r, m),
        (_, e) => e,
    })?;
    let crate::job::Job {
        scene,
        mut camera,
        settings,
        output,
        dialect,
        denoise,
        ..
    } = job;
    let mut fingerprint = fnv1a(FNV_OFFSET, text.as_bytes());
    for file in std::iter::once(&scene_path).chain(camera_path.as_ref()) {
        // The files were read once already; read again within the same bounds.
        let bytes = crate::util::file::read_regular(file, crate::util::limits::MAX_TEXT_BYTES)
            .map_err(|e| Error::file(file, format!("cannot read: {e}")))?;
        // The length first, so moving bytes from one file to the next changes the hash.
        fingerprint = fnv1a(fingerprint, &(bytes.len() as u64).to_le_bytes());
        fingerprint = fnv1a(fingerprint, &bytes);
    }
    if let Some(start) = &raw.start {
        apply_start(&lines, start, &mut camera)?;
    }
    let fps = fps_of(&lines, raw.fps.as_ref())?;
    let frames = frames_of(&lines, raw.frames.as_ref(), raw.duration.as_ref(), fps)?;
    // Check the settings against the camera now, not after the first frame.
    Renderer::new(&scene, &camera, settings.clone()).map_err(|e| match (&raw.render, e) {
        (Some(r), Error::Settings(m)) => lines.error(r, m),
        (_, e) => e,
    })?;
    let tracks = raw
        .track
        .iter()
        .map(|t| track(&lines, t, &scene))
        .collect::<Result<Vec<_>>>()?;
    Ok(Animation {
        path: path.to_path_buf(),
        scene,
        camera,
        frames,
        fps,
        settings,
        tracks,
        output,
        dialect,
        denoise,
        cancel: None,
        fingerprint,
    })
}

/// The timing and tracks of a Prism scene file that animates (its `[animation]` and
/// `[[track]]`s; the scene file's reader checks the rest).
#[derive(Deserialize)]
struct RawSceneAnimation {
    animation: Option<Spanned<RawTiming>>,
    #[serde(default)]
    track: Vec<Spanned<RawTrack>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTiming {
    frames: Option<Spanned<i64>>,
    duration: Option<Spanned<f64>>,
    fps: Option<Spanned<f64>>,
}

/// A Prism scene file as an animation: its scene, camera (or the default view) and
/// render settings, `[animation]` timing and `[[track]]`s, whose `object:NAME` and
/// `light:NAME` targets are the scene file's named objects and lights.
fn parse_scene_file(text: &str, path: &Path) -> Result<Animation> {
    let lines = Lines::new(text, path);
    let file = crate::format::scene_file::parse(text, path)?;
    let job = crate::job::resolve(file, &crate::job::JobOptions::default())?;
    let raw: RawSceneAnimation = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| lines.line(s.start));
        Error::parse(path, line, e.message().trim_end().replace('\n', "; "))
    })?;
    let Some(timing) = &raw.animation else {
        return Err(Error::parse(
            path,
            1,
            "expected an [animation] table (frames or duration, and fps) to animate this scene",
        ));
    };
    let t = timing.get_ref();
    let fps = fps_of(&lines, t.fps.as_ref())?;
    let frames = frames_of(&lines, t.frames.as_ref(), t.duration.as_ref(), fps)?;
    job.renderer()?;
    let tracks = raw
        .track
        .iter()
        .map(|tr| track(&lines, tr, &job.scene))
        .collect::<Result<Vec<_>>>()?;
    Ok(Animation {
        path: path.to_path_buf(),
        scene: job.scene,
        camera: job.camera,
        frames,
        fps,
        settings: job.settings,
        tracks,
        output: job.output,
        dialect: job.dialect,
        denoise: job.denoise,
        cancel: None,
        fingerprint: fnv1a(FNV_OFFSET, text.as_bytes()),
    })
}

fn fps_of(lines: &Lines, fps: Option<&Spanned<f64>>) -> Result<f64> {
    match fps {
        None => Ok(24.0),
        Some(f) => {
            let v = *f.get_ref();
            if !(MIN_FPS..=MAX_FPS).contains(&v) {
                return Err(lines.error(
                    f,
                    format!("expected fps between {MIN_FPS} and {MAX_FPS}, found {v}"),
                ));
            }
            Ok(v)
        }
    }
}

fn apply_start(lines: &Lines, start: &Spanned<RawStart>, camera: &mut Camera) -> Result<()> {
    let s = start.get_ref();
    let finite = |v: f64, what: &str| {
        if in_range(v) {
            Ok(v as f32)
        } else {
            Err(lines.error(
                start,
                format!(
                    "expected a finite number of magnitude at most {MAX_VALUE:e} for {what}, \
                     found {v}"
                ),
            ))
        }
    };
    if let Some([x, y, z]) = s.eye {
        camera.eye = crate::math::Vec3::new(
            finite(x, "start.eye")?,
            finite(y, "start.eye")?,
            finite(z, "start.eye")?,
        );
    }
    if let Some(v) = s.theta {
        camera.theta_deg = finite(v, "start.theta")?;
    }
    if let Some(v) = s.phi {
        camera.phi_deg = finite(v, "start.phi")?;
    }
    if let Some(v) = s.focal_length {
        if v < 0.0 {
            return Err(lines.error(
                start,
                format!("expected start.focal_length >= 0, found {v}"),
            ));
        }
        camera.focal_length = finite(v, "start.focal_length")?;
    }
    if let Some(v) = s.aperture {
        if v < 0.0 {
            return Err(lines.error(start, format!("expected start.aperture >= 0, found {v}")));
        }
        camera.aperture = finite(v, "start.aperture")?;
    }
    Ok(())
}

fn frames_of(
    lines: &Lines,
    frames: Option<&Spanned<i64>>,
    duration: Option<&Spanned<f64>>,
    fps: f64,
) -> Result<u32> {
    let (n, span): (f64, _) = match (frames, duration) {
        (Some(f), Some(_)) => {
            return Err(lines.error(f, "give frames or duration, not both"));
        }
        (None, None) => {
            return Err(Error::parse(
                lines.path,
                1,
                "expected `frames = N` or `duration = SECONDS` (with `fps`, default 24)",
            ));
        }
        (Some(f), None) => (*f.get_ref() as f64, f.span()),
        (None, Some(d)) => {
            let secs = *d.get_ref();
            if !(secs.is_finite() && secs > 0.0) {
                return Err(lines.error(d, format!("expected a duration > 0, found {secs}")));
            }
            ((secs * fps).round(), d.span())
        }
    };
    if !(1.0..=MAX_FRAMES as f64).contains(&n) {
        return Err(Error::parse(
            lines.path,
            lines.line(span.start),
            format!(
                "expected between 1 and {MAX_FRAMES} frames, found {}",
                if n < 1e15 {
                    n.to_string()
                } else {
                    format!("{n:e}")
                }
            ),
        ));
    }
    Ok(n as u32)
}

/// The animation file's `[render]` table, over the scene file's.
fn render_options(lines: &Lines, render: Option<&Spanned<RawRender>>) -> Result<RenderOptions> {
    let Some(r) = render else {
        return Ok(RenderOptions::default());
    };
    let raw = r.get_ref();
    let filter = raw
        .filter
        .as_ref()
        .map(|f| f.get_ref().parse::<Filter>().map_err(|m| lines.error(f, m)))
        .transpose()?;
    Ok(RenderOptions {
        width: raw.width,
        height: raw.height,
        aa: raw.aa,
        filter,
        spp: raw.spp,
        seed: raw.seed,
        denoise: raw.denoise,
        ..RenderOptions::default()
    })
}

/// The shapes and lights a target names: `shape:N`, `material:NAME`, `group:NAME`.
fn selection(lines: &Lines, at: &Spanned<String>, scene: &Scene) -> Result<Selection> {
    let name = at.get_ref();
    let unknown = |why: String| {
        let name = crate::util::text::shown(name);
        lines.error(at, format!("unknown target {name}: {why}"))
    };
    let (kind, what) = name.split_once(':').ok_or_else(|| {
        unknown(
            "expected camera, shape:N, material:NAME, group:NAME, object:NAME or light:NAME".into(),
        )
    })?;
    let (shapes, lights, instances) = match kind {
        "shape" => {
            let i: u32 = what.parse().map_err(|_| {
                unknown(format!(
                    "expected a shape index, found {}",
                    crate::util::text::shown(what)
                ))
            })?;
            if i as usize >= scene.shapes.len() {
                return Err(unknown(format!(
                    "the scene has {} shapes (numbered from 0)",
                    scene.shapes.len()
                )));
            }
            (vec![i], vec![], vec![])
        }
        "material" => {
            let shapes: Vec<u32> = (0..scene.shapes.len() as u32)
                .filter(|&i| scene.material(i).name == what)
                .collect();
            if shapes.is_empty() {
                return Err(unknown(format!(
                    "no shape wears material {}",
                    crate::util::text::shown(what)
                )));
            }
            (shapes, vec![], vec![])
        }
        // A scene file's named objects and lights are groups of that name.
        "group" | "object" | "light" => {
            let g = scene
                .group(what)
                .ok_or_else(|| unknown(format!("the scene has no `g {what}` or `o {what}`")))?;
            if g.shapes.is_empty() && g.lights.is_empty() && g.instances.is_empty() {
                return Err(unknown(format!(
                    "group {} is empty",
                    crate::util::text::shown(what)
                )));
            }
            (g.shapes.clone(), g.lights.clone(), g.instances.clone())
        }
        _ => {
            return Err(unknown(
                "expected camera, shape:N, material:NAME, group:NAME, object:NAME or light:NAME"
                    .into(),
            ));
        }
    };
    Ok(Selection {
        shapes,
        lights,
        instances,
    })
}

/// Largest coordinate, offset or angle accepted: beyond it, f32 scene coordinates
/// would overflow.
const MAX_VALUE: f64 = 1e30;

fn in_range(x: f64) -> bool {
    x.is_finite() && x.abs() <= MAX_VALUE
}

fn vector(lines: &Lines, v: &Spanned<[f64; 3]>, what: &str) -> Result<DVec3> {
    let d = DVec3::from_array(*v.get_ref());
    if !d.to_array().into_iter().all(in_range) {
        return Err(lines.error(
            v,
            format!("expected finite numbers of magnitude at most {MAX_VALUE:e} for {what}"),
        ));
    }
    Ok(d)
}

fn track(lines: &Lines, t: &Spanned<RawTrack>, scene: &Scene) -> Result<Track> {
    let raw = t.get_ref();
    // The span of an array-of-tables entry starts at its own `[[track]]` header.
    let line = lines.line(t.span().start);
    let target = match raw.target.get_ref().as_str() {
        "camera" => Target::Camera,
        _ => Target::Objects(selection(lines, &raw.target, scene)?),
    };
    let interpolation = match &raw.interpolation {
        None => Interpolation::Linear,
        Some(i) => i.get_ref().parse().map_err(|m: String| lines.error(i, m))?,
    };
    let allowed = fields_of(raw.motion.get_ref());
    if !allowed.is_empty()
        && let Some(&(name, at)) = raw.given().iter().find(|(n, _)| !allowed.contains(n))
    {
        return Err(Error::parse(
            lines.path,
            lines.line(at),
            format!(
                "{} does not apply to motion `{}`, which takes {}",
                crate::util::text::shown(name),
                raw.motion.get_ref(),
                allowed
                    .iter()
                    .map(|f| format!("`{f}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    let missing = |what: &str| {
        lines.error(
            &raw.motion,
            format!("motion `{}` needs `{what}`", raw.motion.get_ref()),
        )
    };
    let axis = || -> Result<DVec3> {
        let a = raw.axis.as_ref().ok_or_else(|| missing("axis"))?;
        let v = vector(lines, a, "the axis")?;
        if v.length() == 0.0 || !v.normalize().is_finite() {
            return Err(lines.error(a, "the axis must not be zero"));
        }
        Ok(v.normalize())
    };
    let center = || -> Result<DVec3> {
        raw.center
            .as_ref()
            .map_or(Ok(DVec3::ZERO), |c| vector(lines, c, "the center"))
    };
    let keys = || raw.keys.as_ref().ok_or_else(|| missing("keys"));
    let motion = match raw.motion.get_ref().as_str() {
        "translate" => {
            Motion::Translate(curve(lines, keys()?, interpolation, true, |v| match v {
                RawValue::Vector(v) => Some(DVec3::from_array(v)),
                RawValue::Number(_) => None,
            })?)
        }
        m @ ("rotate" | "orbit") => {
            let angle = curve(lines, keys()?, interpolation, false, |v| match v {
                RawValue::Number(n) => Some(n),
                RawValue::Vector(_) => None,
            })?;
            let (axis, center) = (axis()?, center()?);
            let keep_orientation = raw.keep_orientation.as_ref().is_none_or(|k| *k.get_ref());
            if m == "orbit" && keep_orientation {
                Motion::Orbit {
                    axis,
                    center,
                    angle,
                }
            } else {
                // An orbit that does not keep its orientation turns the target: a rotation.
                Motion::Rotate {
                    axis,
                    center,
                    angle,
                }
            }
        }
        "look_at" => {
            if target != Target::Camera {
                return Err(lines.error(&raw.motion, "only the camera can look_at"));
            }
            let at = raw.at.as_ref().ok_or_else(|| missing("at"))?;
            let aim = match at.get_ref() {
                RawAim::Point(p) => {
                    let p = Spanned::new(at.span(), *p);
                    Aim::Point(vector(lines, &p, "`at`")?)
                }
                RawAim::Target(name) => {
                    let named = Spanned::new(at.span(), name.clone());
                    Aim::Objects(selection(lines, &named, scene)?)
                }
            };
            Motion::LookAt {
                aim,
                focus: raw.focus.as_ref().is_some_and(|f| *f.get_ref()),
            }
        }
        other => {
            return Err(lines.error(
                &raw.motion,
                format!(
                    "unknown motion {}: expected translate, rotate, orbit or look_at",
                    crate::util::text::shown(other)
                ),
            ));
        }
    };
    Ok(Track {
        target,
        motion,
        line,
    })
}

/// Keys `[time, value]` in increasing time order, each value of the motion's kind.
fn curve<T: super::curve::Blend>(
    lines: &Lines,
    keys: &RawKeys,
    interpolation: Interpolation,
    vector_values: bool,
    value: impl Fn(RawValue) -> Option<T>,
) -> Result<Curve<T>> {
    if keys.get_ref().is_empty() {
        return Err(lines.error(keys, "expected at least one key [time, value]"));
    }
    let mut out: Vec<(f64, T)> = Vec::with_capacity(keys.get_ref().len());
    for key in keys.get_ref() {
        let (time, raw) = *key.get_ref();
        let finite = match raw {
            RawValue::Number(n) => in_range(n),
            RawValue::Vector(v) => v.into_iter().all(in_range),
        };
        if !in_range(time) || !finite {
            return Err(lines.error(
                key,
                format!("expected finite numbers of magnitude at most {MAX_VALUE:e} in the key"),
            ));
        }
        let v = value(raw).ok_or_else(|| {
            lines.error(
                key,
                if vector_values {
                    "expected [time, [x, y, z]]: this motion's keys hold offsets"
                } else {
                    "expected [time, degrees]: this motion's keys hold angles"
                },
            )
        })?;
        if let Some(&(previous, _)) = out.last()
            && time <= previous
        {
            return Err(lines.error(
                key,
                format!("key times must increase: {time} s comes after {previous} s"),
            ));
        }
        out.push((time, v));
    }
    Ok(Curve::new(out, interpolation))
}
