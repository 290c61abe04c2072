//! The settings a user names, wherever they name them: a scene file's `[render]`, an
//! animation file, the command line, Python. [`RenderOptions`] holds them all as
//! optional values; the job resolves layers of them (caller over file over defaults)
//! once. The names here are the ones every front end accepts, and every stage may read
//! them: the readers check them where a file writes them, the renderer and the film act
//! on them.

use crate::util::text::shown;
use std::fmt;
use std::str::FromStr;

/// The one of `all` that `name` calls `s`, or a message naming the setting (`what`) and
/// listing every name: how each setting's name is read, in files and flags alike.
pub fn by_name<T: Copy>(
    s: &str,
    all: &[T],
    name: impl Fn(T) -> &'static str,
    what: &str,
) -> Result<T, String> {
    all.iter().copied().find(|&k| name(k) == s).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&k| name(k)).collect();
        let listed = match names.split_last() {
            Some((last, [])) => last.to_string(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        };
        format!("unknown {what} {}: expected {listed}", shown(s))
    })
}

/// What a user may state about a render and its development; `None` leaves it to the
/// layer below (the scene file, the camera, the defaults).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels; given alone, the height follows the camera's aspect.
    pub width: Option<u32>,
    /// Image height in pixels; given alone, the width follows the camera's aspect.
    pub height: Option<u32>,
    /// Anti-aliasing: `K × K` supersamples per pixel, resampled down with `filter`.
    pub aa: Option<u32>,
    /// The resampling filter of anti-aliasing.
    pub filter: Option<Filter>,
    /// Samples (camera rays) per supersampled pixel: more than 1 turns on depth of field
    /// for a camera with an aperture.
    pub spp: Option<u32>,
    /// Seed of every random sample (lens, lights): the same seed, the same image.
    pub seed: Option<u64>,
    /// The shading model.
    pub integrator: Option<IntegratorKind>,
    /// Deepest reflection and refraction recursion of the whitted model.
    pub max_depth: Option<u32>,
    /// Rays whose weight falls below this are not traced (whitted model), in 0..1.
    pub min_weight: Option<f32>,
    /// How many shadow rays a path vertex traces (path model).
    pub light_sampling: Option<LightSampling>,
    /// Exposure in stops for display formats (+1 doubles the light).
    pub exposure: Option<f32>,
    /// How display formats bring radiance above 1 into range.
    pub tonemap: Option<ToneMap>,
    /// Denoise the finished image (Intel Open Image Denoise, guided by the albedo and
    /// normal passes) before it is developed and written.
    pub denoise: Option<bool>,
}

impl RenderOptions {
    /// These options over `lower`: each value given here wins. The image size goes as
    /// one: a side given here replaces both of `lower`'s, so that a width alone keeps
    /// the camera's aspect rather than pairing with the file's height.
    pub fn over(&self, lower: &RenderOptions) -> RenderOptions {
        let (width, height) = match (self.width, self.height) {
            (None, None) => (lower.width, lower.height),
            given => given,
        };
        RenderOptions {
            width,
            height,
            aa: self.aa.or(lower.aa),
            filter: self.filter.or(lower.filter),
            spp: self.spp.or(lower.spp),
            seed: self.seed.or(lower.seed),
            integrator: self.integrator.or(lower.integrator),
            max_depth: self.max_depth.or(lower.max_depth),
            min_weight: self.min_weight.or(lower.min_weight),
            light_sampling: self.light_sampling.or(lower.light_sampling),
            exposure: self.exposure.or(lower.exposure),
            tonemap: self.tonemap.or(lower.tonemap),
            denoise: self.denoise.or(lower.denoise),
        }
    }
}

/// The shading models (SPEC 3.2 and 4.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// The 2014 program's weighted-mean colours: the 2014 files' model, frozen.
    #[default]
    Classic,
    /// Physically based Whitted: linear radiance, Fresnel, Beer, area lights.
    Whitted,
    /// Unidirectional path tracing: light that bounces, with next-event estimation
    /// and multiple importance sampling.
    Path,
}

impl IntegratorKind {
    /// Every shading model, in the order messages list them.
    pub const ALL: [IntegratorKind; 3] = [
        IntegratorKind::Classic,
        IntegratorKind::Whitted,
        IntegratorKind::Path,
    ];

    /// The curve a display format stores this model's values with: none for the classic
    /// model (the 2014 program wrote its 0..1 values as they are), sRGB for the linear
    /// radiance of the whitted and path models.
    pub fn transfer(self) -> Transfer {
        match self {
            IntegratorKind::Classic => Transfer::Classic,
            IntegratorKind::Whitted | IntegratorKind::Path => Transfer::Srgb,
        }
    }

    /// The depth a render of this model goes to when none is given: the whitted
    /// model's recursion limit, or no limit but [`MAX_PATH_DEPTH`] for paths (Russian
    /// roulette ends them long before).
    pub fn default_max_depth(self) -> u32 {
        match self {
            IntegratorKind::Path => MAX_PATH_DEPTH,
            _ => DEFAULT_MAX_DEPTH,
        }
    }

    /// The deepest `max_depth` a user may ask of this model.
    pub fn max_depth_limit(self) -> u32 {
        match self {
            IntegratorKind::Path => MAX_PATH_DEPTH,
            _ => crate::util::limits::MAX_DEPTH,
        }
    }

    /// The name front ends accept and print (`classic`, `whitted`); parsed back by
    /// `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Classic => "classic",
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
        }
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        by_name(s, &IntegratorKind::ALL, IntegratorKind::name, "integrator")
    }
}

/// Recursion depth of the whitted model: POV-Ray's `max_trace_level` default is 5;
/// ten lets light cross a few glass surfaces.
pub const DEFAULT_MAX_DEPTH: u32 = 10;

/// The most bounces a path takes: "unlimited" for a user. Russian roulette continues
/// a path with probability at most 0.95, so one reaches this with odds below 1e-22; the
/// bound keeps a path between two white mirrors finite all the same.
pub const MAX_PATH_DEPTH: u32 = 1024;

/// A pass for compositing and denoising, written beside the image as a layer of its
/// OpenEXR file: what the camera's rays first meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// The surface's albedo (linear RGB, textures and vertex colours included).
    Albedo,
    /// The shading normal, world space, on the side the ray came from.
    Normal,
    /// The distance along the ray to the surface (0 where it escapes).
    Depth,
    /// Coverage: 1 where the ray meets a surface, 0 where it escapes; resampled like
    /// the image, so edges are fractions (film transparency).
    Alpha,
    /// The background where the ray escapes, black where it meets a surface: the
    /// image less this pass is the image on a transparent film.
    Background,
}

impl Aov {
    /// Every pass, in the order messages list them.
    pub const ALL: [Aov; 5] = [
        Aov::Albedo,
        Aov::Normal,
        Aov::Depth,
        Aov::Alpha,
        Aov::Background,
    ];

    /// Its name: what `--aov` takes and the layer is called.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Alpha => "alpha",
            Aov::Background => "background",
        }
    }

    /// The channels of its layer.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Albedo => &["R", "G", "B"],
            Aov::Normal => &["X", "Y", "Z"],
            Aov::Depth => &["Z"],
            Aov::Alpha => &["A"],
            Aov::Background => &["R", "G", "B"],
        }
    }
}

impl std::str::FromStr for Aov {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        by_name(s, &Aov::ALL, Aov::name, "pass")
    }
}

/// A window `x, y, width, height` of the final frame, in output pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    /// Column of the window's left edge, counted from the frame's left.
    pub x: u32,
    /// Row of the window's top edge, counted from the frame's top.
    pub y: u32,
    /// Window width in pixels, at least 1; `x + width` stays within the frame.
    pub width: u32,
    /// Window height in pixels, at least 1; `y + height` stays within the frame.
    pub height: u32,
}

impl std::str::FromStr for Region {
    type Err = String;
    fn from_str(s: &str) -> Result<Region, String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let nums: Option<Vec<u32>> = parts.iter().map(|p| p.parse().ok()).collect();
        match nums.as_deref() {
            Some(&[x, y, width, height]) => Ok(Region {
                x,
                y,
                width,
                height,
            }),
            _ => Err(format!(
                "expected X,Y,W,H (four non-negative integers), found {}",
                shown(s)
            )),
        }
    }
}

/// How the path model gathers light from lights at a vertex. Under `all` and `one`
/// every light (and the environment) is sampled and weighed against the BSDF's own
/// samples, and they differ in the shadow rays traced; `tree` samples one light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSampling {
    /// `all` up to [`LightSampling::AUTO_ALL_UP_TO`] lights, `tree` above.
    #[default]
    Auto,
    /// A shadow ray toward every light's sample: the least noise a sample, and work
    /// that grows with the number of lights.
    All,
    /// One shadow ray a vertex, toward one of the lights' samples chosen in proportion
    /// to its unshadowed contribution and weighed by the odds of the choice (resampled
    /// importance sampling over the lights): unbiased, and as many shadow rays with a
    /// thousand lights as with one.
    One,
    /// One light a vertex, drawn from a tree over the lights by how much each part of
    /// the tree may light the point (pbrt-v4's BVH light sampler), and one shadow ray
    /// toward its sample (besides one toward each of a few suns and the sky): work
    /// that grows with the depth of the tree, not the number of lights; noisier a
    /// sample than `one`, where nearby lights differ little.
    Tree,
}

impl LightSampling {
    /// Every choice, in the order messages list them.
    pub const ALL: [LightSampling; 4] = [
        LightSampling::Auto,
        LightSampling::All,
        LightSampling::One,
        LightSampling::Tree,
    ];

    /// Scenes of at most this many lights trace a shadow ray toward each under `auto`;
    /// above, `auto` draws one light from the tree (a scene of 20 glowing lamps takes a
    /// third of `one`'s time and a fifth of `all`'s to the same noise, 400 lamps a
    /// fourteenth of `one`'s: `benches/many_lights.py`).
    pub const AUTO_ALL_UP_TO: usize = 16;

    /// The name front ends accept and print; parsed back by `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Auto => "auto",
            LightSampling::All => "all",
            LightSampling::One => "one",
            LightSampling::Tree => "tree",
        }
    }

    /// Whether a scene of `lights` lights traces one shadow ray a vertex.
    pub fn traces_one(self, lights: usize) -> bool {
        match self {
            LightSampling::Auto => lights > LightSampling::AUTO_ALL_UP_TO,
            LightSampling::All => false,
            LightSampling::One | LightSampling::Tree => true,
        }
    }

    /// Whether a scene of `lights` lights draws its one light a vertex from a tree.
    pub fn draws_from_tree(self, lights: usize) -> bool {
        match self {
            LightSampling::Auto => lights > LightSampling::AUTO_ALL_UP_TO,
            LightSampling::All | LightSampling::One => false,
            LightSampling::Tree => true,
        }
    }
}

impl fmt::Display for LightSampling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LightSampling {
    type Err = String;

    fn from_str(s: &str) -> Result<LightSampling, String> {
        by_name(
            s,
            &LightSampling::ALL,
            LightSampling::name,
            "light sampling",
        )
    }
}

/// Reconstruction filter used to shrink the supersampled frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// One supersample per pixel, the one at (or just past) its centre: no averaging,
    /// so edges stay aliased.
    Nearest,
    /// Triangle (tent) kernel, radius 1 output pixel.
    Bilinear,
    /// Box filter: mean of each `k x k` block.
    #[default]
    Area,
    /// Catmull-Rom cubic (`a = -0.5`), radius 2 output pixels; its negative lobes
    /// sharpen and may ring.
    Bicubic,
    /// Lanczos-3 windowed sinc, radius 3 output pixels: sharpest, rings most.
    Lanczos,
}

impl Filter {
    /// Every filter, in the order messages list them.
    pub const ALL: [Filter; 5] = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::Area,
        Filter::Bicubic,
        Filter::Lanczos,
    ];

    /// The name front ends accept and print (`nearest`, `area`, ...); parsed back by
    /// `FromStr`.
    pub fn name(&self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::Area => "area",
            Filter::Bicubic => "bicubic",
            Filter::Lanczos => "lanczos",
        }
    }
}

impl fmt::Display for Filter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Filter {
    type Err = String;
    fn from_str(s: &str) -> Result<Filter, String> {
        by_name(s, &Filter::ALL, |f| f.name(), "filter")
    }
}

/// How radiance above 1 (after exposure) is brought into 0..1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// `min(x, 1)`: what the classic model has always done.
    #[default]
    Clamp,
    /// `x / (1 + x)` on each channel: never reaches 1, so highlights keep some detail and
    /// saturated colours fade towards white as they brighten (luminance-based Reinhard
    /// keeps the hue but pushes channels past 1, to be clipped again).
    Reinhard,
    /// Narkowicz's fit of the ACES filmic curve, on each channel:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to 0..1. Applied to
    /// radiance as is (no 0.6 pre-scale; `--exposure -0.737` gives it).
    Aces,
}

impl ToneMap {
    /// Every tone map, in the order messages list them.
    pub const ALL: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Aces];

    /// The name front ends accept and print (`clamp`, `reinhard`, `aces`); parsed back
    /// by `FromStr`.
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Reinhard => "reinhard",
            ToneMap::Aces => "aces",
        }
    }
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ToneMap {
    type Err = String;

    fn from_str(s: &str) -> Result<ToneMap, String> {
        by_name(s, &ToneMap::ALL, ToneMap::name, "tone map")
    }
}

/// The curve from tone-mapped values (0..1, linear) to the values stored in the file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Transfer {
    /// IEC 61966-2-1: `12.92 v` up to `v = 0.0031308`, `1.055 v^(1/2.4) - 0.055` above.
    /// What every viewer assumes of an untagged 8-bit image.
    #[default]
    Srgb,
    /// No curve: values are stored as they are, as the 2014 program stored them.
    Classic,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_unknown_ones_list_every_name() {
        for t in ToneMap::ALL {
            assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
        }
        assert_eq!("lanczos".parse::<Filter>(), Ok(Filter::Lanczos));
        assert_eq!(
            "Whitted".parse::<IntegratorKind>(),
            Err("unknown integrator `Whitted`: expected classic, whitted or path".into())
        );
        assert_eq!(
            "gauss".parse::<Filter>(),
            Err(
                "unknown filter `gauss`: expected nearest, bilinear, area, bicubic or \
                 lanczos"
                    .into()
            )
        );
        assert_eq!(
            by_name("x", &[1u8], |_| "one", "thing"),
            Err("unknown thing `x`: expected one".into())
        );
    }

    #[test]
    fn a_side_given_replaces_both_sides_below() {
        let file = RenderOptions {
            width: Some(640),
            height: Some(360),
            spp: Some(4),
            ..Default::default()
        };
        let width = RenderOptions {
            width: Some(320),
            ..Default::default()
        };
        let o = width.over(&file);
        assert_eq!((o.width, o.height, o.spp), (Some(320), None, Some(4)));
        assert_eq!(RenderOptions::default().over(&file), file);
    }
}
