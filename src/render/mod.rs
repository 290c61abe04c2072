//! From scene to samples: camera rays, the shading model, and the parallel loop that
//! fills the supersampled frame band by band and hands each band to the film.

pub mod aov;
pub mod bsdf;
pub mod camera;
pub mod classic;
mod cut_outs;
pub mod memory;
pub mod observer;
pub mod optics;
pub mod passes;
pub mod path;
pub mod sampler;
mod settings;
pub mod shadows;
mod spread;
pub mod whitted;
pub mod workers;

pub use crate::options::{IntegratorKind, Region};
pub use camera::CameraRays;
pub use classic::Classic;
pub use observer::{CancelOn, Observer, Progress, Rows};
use passes::SamplePass;
pub use passes::{Progressive, SampleSums, sample_totals};
pub use path::Path;
pub use sampler::{PixelSampler, PixelStreams, StreamLanes};
use settings::Plan;
pub use settings::{DEFAULT_MAX_DEPTH, DEFAULT_MIN_WEIGHT, RenderSettings, check_threads};
pub use whitted::{Casters, Whitted};

use crate::accel::{Accel, Hit, PACKET_RAYS};
use crate::error::Result;
use crate::film::Image;
use crate::film::resample::{AxisWeights, resample_window_into};
use crate::math::{Ray, Vec3};
use crate::options::Aov;
use crate::scene::{Camera, Scene};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Sum of weighted colours: the colour of a pixel is `sum / weight`. Both shading models
/// use it: the classic one with its own weights, an unweighted one with weight 1 per ray.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WeightedColor {
    /// Sum of each added colour times its weight.
    pub sum: Vec3,
    /// Sum of the weights added: what `sum` is divided by.
    pub weight: f32,
}

impl WeightedColor {
    /// Adds `color` with `weight`; a weight that is not positive and finite is dropped
    /// (one NaN or infinity would spoil the whole pixel).
    #[inline]
    pub fn add(&mut self, color: Vec3, weight: f32) {
        // Guard: a NaN or infinite weight would turn the whole pixel into NaN.
        if weight > 0.0 && weight.is_finite() {
            self.sum += color * weight;
            self.weight += weight;
        }
    }

    /// The weighted mean; black where nothing was seen.
    #[inline]
    pub fn mean(&self) -> Vec3 {
        if self.weight > 0.0 {
            let c = self.sum / self.weight;
            if c.is_finite() { c } else { Vec3::ZERO }
        } else {
            Vec3::ZERO
        }
    }
}

/// Rays traced, counted per thread and summed.
#[derive(Clone, Copy, Debug, Default)]
pub struct RayCount {
    /// Rays traced so far: camera, reflected, refracted and shadow rays alike.
    pub rays: u64,
}

/// A shading model: what one camera ray adds to its pixel. `sampler` is the pixel's
/// random stream (area lights draw from it), so the image does not depend on threads.
pub trait Integrator: Sync {
    /// Whether a pixel's camera rays may be traced as a packet ahead of their shading:
    /// true when shading draws nothing from the pixel's sampler, so generating all its
    /// rays first leaves every sample, and the image, as it was. (Pixels with one camera
    /// ray each are always traced a tile at a time: that ray is drawn before its
    /// shading either way.)
    fn lens_packets(&self) -> bool;

    /// Whether a pixel's samples spread over its area (each its own random stream,
    /// [`PixelSampler::for_sample`], a box filter over the supersampled pixel) rather
    /// than the pinhole ray through its centre and lens rays aimed at its focus.
    fn spreads_samples(&self) -> bool {
        false
    }

    /// Whether the model's work on a packet runs in sixteen-lane registers (AVX-512),
    /// so that the pixel streams it draws from may be made in them too: where the rest
    /// runs on eight, sixteen-lane work slows the processor's clock for all of it.
    fn sixteen_lanes(&self) -> bool {
        false
    }

    /// Traces camera ray `ray` and every ray it spawns, adding its colour to `acc` and
    /// the rays traced to `count`.
    fn trace_camera_ray(
        &self,
        ray: Ray,
        sampler: &mut PixelSampler,
        acc: &mut WeightedColor,
        count: &mut RayCount,
    );

    /// [`Integrator::trace_camera_ray`] for up to [`PACKET_RAYS`] camera rays whose
    /// closest hits were found together, shaded in order: ray `i` draws from
    /// `samplers[i]` and adds to `accs[i]`; where only one sampler or one accumulator
    /// is given, every ray shares it (the lens rays of a pixel share both, the spread
    /// samples of a pixel their accumulator). The model may
    /// trace the hits' own rays (shadow, reflected, refracted) together as well.
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        accs: &mut [WeightedColor],
        count: &mut RayCount,
    );
}

/// Which entry of a packet's samplers and accumulators ray `i` uses: its own, or the
/// one shared by every ray.
#[inline]
fn slot(shared: &[impl Sized], i: usize) -> usize {
    if shared.len() == 1 { 0 } else { i }
}

/// A ray to fill unused packet slots.
pub(crate) const NO_RAY: Ray = Ray {
    origin: Vec3::ZERO,
    dir: Vec3::Z,
};

/// Figures of one render.
#[derive(Clone, Copy, Debug)]
pub struct RenderStats {
    /// Rays traced: camera, reflected, refracted and shadow rays alike.
    pub rays: u64,
    /// Wall-clock time of the render, the intersector's build included when the
    /// render built it.
    pub elapsed: Duration,
}

impl RenderStats {
    /// Throughput in millions of rays per second of `elapsed`.
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// Output rows resampled per band. Large enough that the rows a wide filter needs on
/// both sides of a band are a small share of it, small enough to bound memory.
const BAND_ROWS: u32 = 32;

/// Pixels across a tile of camera rays traced as one packet.
pub const TILE_COLUMNS: usize = 4;
/// Rows of a tile of camera rays: a packet in all.
pub const TILE_ROWS: usize = PACKET_RAYS / TILE_COLUMNS;

/// Renders a scene seen by a camera with given settings.
pub struct Renderer<'a> {
    scene: &'a Scene,
    plan: Plan,
}

impl<'a> Renderer<'a> {
    /// Checks the settings against the camera (resolution overrides, region, caps).
    pub fn new(
        scene: &'a Scene,
        camera: &Camera,
        settings: RenderSettings,
    ) -> Result<Renderer<'a>> {
        let plan = settings.resolve(camera)?;
        if scene.shapes.len() > crate::scene::MAX_SHAPES {
            return Err(crate::error::Error::Settings(format!(
                "the scene has {} shapes, more than the {} Prism renders",
                scene.shapes.len(),
                crate::scene::MAX_SHAPES
            )));
        }
        memory_estimate(scene, &plan).check(plan.max_memory, plan.accel)?;
        Ok(Renderer { scene, plan })
    }

    /// Whether the shading model spreads each pixel's samples over its area, each
    /// sample its own random stream ([`Integrator::spreads_samples`]): the path model.
    /// Only such a render can be made in sample passes ([`Renderer::render_samples`]).
    pub fn spreads_samples(&self) -> bool {
        matches!(self.plan.integrator, IntegratorKind::Path)
    }

    /// Samples per pixel of the finished image: the settings' `spp`.
    pub fn spp(&self) -> u32 {
        self.plan.spp
    }

    /// The camera after the settings' overrides.
    pub fn camera(&self) -> &Camera {
        &self.plan.camera
    }

    /// The window of the frame being rendered (the whole frame without `--region`).
    pub fn region(&self) -> Region {
        self.plan.region
    }

    /// Supersampled rows that will be traced: the unit of progress.
    pub fn rows_to_trace(&self) -> u64 {
        let (_, wy) = self.weights();
        self.bands(&wy, self.plan.region)
            .map(|(_, _, lo, hi)| u64::from(hi - lo))
            .sum()
    }

    fn weights(&self) -> (AxisWeights, AxisWeights) {
        let (k, f) = (self.plan.aa, self.plan.filter);
        (
            AxisWeights::new(f, k, self.plan.camera.width),
            AxisWeights::new(f, k, self.plan.camera.height),
        )
    }

    /// Bands of output rows with the supersampled rows each needs.
    fn bands<'w>(
        &self,
        wy: &'w AxisWeights,
        region: Region,
    ) -> impl Iterator<Item = (u32, u32, u32, u32)> + 'w {
        let end = region.y + region.height;
        (region.y..end).step_by(BAND_ROWS as usize).map(move |y0| {
            let y1 = (y0 + BAND_ROWS).min(end);
            let (lo, hi) = wy.input_span(y0, y1);
            (y0, y1, lo, hi)
        })
    }

    /// The supersampled pixels the film reads for the window: `(x_lo, x_hi)` and
    /// `(y_lo, y_hi)`, ends excluded.
    fn traced_span(&self) -> ((u32, u32), (u32, u32)) {
        let (wx, wy) = self.weights();
        let r = self.plan.region;
        (
            wx.input_span(r.x, r.x + r.width),
            wy.input_span(r.y, r.y + r.height),
        )
    }

    /// Renders the image (the region, if one is set), reporting to `observer` as it
    /// goes: the one render driver. Returns [`crate::error::Error::Interrupted`] if the
    /// observer cancelled it.
    pub fn render(&self, observer: &dyn Observer) -> Result<(Image, RenderStats)> {
        self.drive(None, None, observer)
    }

    /// Passes `aovs` of the image [`Renderer::render`] makes, through its camera
    /// samples and resampling, one image each (depth's value in every channel).
    pub fn render_aovs(&self, aovs: &[Aov]) -> Result<Vec<Image>> {
        if aovs.is_empty() {
            return Ok(Vec::new());
        }
        let accel = self.build_accel()?;
        self.render_aovs_with(&accel, aovs, &())
    }

    /// [`Renderer::render_aovs`] with an intersector built earlier
    /// ([`Renderer::build_accel`]) and an observer that may cancel it
    /// ([`crate::error::Error::Interrupted`]): a front end rendering passes while its
    /// user waits (the preview's denoiser guides).
    pub fn render_aovs_with(
        &self,
        accel: &Accel,
        aovs: &[Aov],
        observer: &dyn Observer,
    ) -> Result<Vec<Image>> {
        let pool = self.pool()?;
        let images: Vec<Image> = pool.install(|| {
            let surfaces = self.scene.resolved_surfaces();
            let spread = self.spreads_samples();
            aovs.iter()
                .map_while(|&aov| {
                    if observer.cancelled() {
                        return None;
                    }
                    let tracer = aov::AovTracer::new(self.scene, accel, &surfaces, aov, spread);
                    Some(
                        self.render_frame(&tracer, accel, Instant::now(), observer, None)
                            .0,
                    )
                })
                .collect()
        });
        if observer.cancelled() {
            return Err(crate::error::Error::Interrupted);
        }
        Ok(images)
    }

    /// `image`, which [`Renderer::render`] made, denoised ([`crate::film::denoise()`])
    /// with its albedo and normal passes: those among `passes` (rendered already, for
    /// `--aov`) as they are, the others rendered now.
    pub fn denoise(&self, image: &Image, passes: &[(Aov, Image)]) -> Result<Image> {
        // Before the passes are rendered for nothing.
        crate::film::denoise::check_available()?;
        let given = |aov| passes.iter().find(|(a, _)| *a == aov).map(|(_, p)| p);
        let missing: Vec<Aov> = [Aov::Albedo, Aov::Normal]
            .into_iter()
            .filter(|&aov| given(aov).is_none())
            .collect();
        let rendered = self.render_aovs(&missing)?;
        let pass = |aov| {
            given(aov).or_else(|| {
                let i = missing.iter().position(|&m| m == aov)?;
                rendered.get(i)
            })
        };
        crate::film::denoise(
            image,
            pass(Aov::Albedo),
            pass(Aov::Normal),
            self.plan.threads,
        )
    }

    /// Builds the intersector [`Renderer::render`] would, on the renderer's threads.
    pub fn build_accel(&self) -> Result<Accel<'a>> {
        Ok(self
            .pool()?
            .install(|| Accel::build_scene(self.plan.accel, self.scene)))
    }

    /// [`Renderer::render`] with an intersector built earlier over shapes equal to this
    /// scene's (an animation whose geometry stays still builds it once for every
    /// frame). An intersector over a different number of shapes is refused.
    pub fn render_with(
        &self,
        accel: &Accel,
        observer: &dyn Observer,
    ) -> Result<(Image, RenderStats)> {
        self.drive(Some(accel), None, observer)
    }

    /// The whole image, or with `pass` one sample pass of it.
    fn drive(
        &self,
        accel: Option<&Accel>,
        pass: Option<SamplePass>,
        observer: &dyn Observer,
    ) -> Result<(Image, RenderStats)> {
        if let Some(accel) = accel
            && accel.shape_count() != self.scene.shapes.len()
        {
            return Err(crate::error::Error::Settings(format!(
                "the intersector was built over {} shapes, the scene has {}",
                accel.shape_count(),
                self.scene.shapes.len()
            )));
        }
        let start = Instant::now();
        // A sample pass traces each supersampled row once, where bands under a wide
        // filter share some.
        let units = match &pass {
            Some(pass) => pass.sums.rows() as u64,
            None => self.rows_to_trace(),
        };
        observer.begin(self.plan.region, units);
        let out = self.pool()?.install(|| match accel {
            Some(accel) => self.render_in_pool(accel, start, observer, pass),
            None => {
                let accel = Accel::build_scene(self.plan.accel, self.scene);
                self.render_in_pool(&accel, start, observer, pass)
            }
        });
        if observer.cancelled() {
            return Err(crate::error::Error::Interrupted);
        }
        observer.finished(&out.1);
        Ok(out)
    }

    fn pool(&self) -> Result<rayon::ThreadPool> {
        workers::pool(self.plan.threads)
    }

    fn render_in_pool(
        &self,
        accel: &Accel,
        start: Instant,
        observer: &dyn Observer,
        pass: Option<SamplePass>,
    ) -> (Image, RenderStats) {
        let plan = &self.plan;
        match plan.integrator {
            IntegratorKind::Classic if !self.scene.instances.is_empty() => {
                // The 2014 model, frozen, knows shapes of the scene only: it renders
                // the scene's flattened twin.
                let flat = self.scene.flattened();
                let accel = Accel::build(plan.accel, &flat.shapes);
                let classic = Classic::new(&flat, &accel, plan.camera.medium_ior);
                self.render_frame(&classic, &accel, start, observer, pass)
            }
            IntegratorKind::Classic => {
                let classic = Classic::new(self.scene, accel, plan.camera.medium_ior);
                self.render_frame(&classic, accel, start, observer, pass)
            }
            IntegratorKind::Whitted => {
                let surfaces = self.scene.resolved_surfaces();
                let whitted = Whitted::new(
                    self.scene,
                    accel,
                    &surfaces,
                    plan.max_depth,
                    plan.min_weight,
                );
                // Casters gather the scene's own shapes; with instances every shadow
                // ray meets the whole scene.
                let casters = if self.scene.instances.is_empty() {
                    Casters::of(self.scene, &surfaces)
                } else {
                    None
                };
                let caster_accel = casters
                    .as_ref()
                    .map(|c| Accel::build(plan.accel, c.shapes()));
                let whitted = match (&casters, &caster_accel) {
                    (Some(casters), Some(accel)) => whitted.with_casters(accel, casters),
                    _ => whitted,
                };
                self.render_frame(&whitted, accel, start, observer, pass)
            }
            IntegratorKind::Path => {
                let surfaces = self.scene.resolved_surfaces();
                let path = Path::new(self.scene, accel, &surfaces, plan.max_depth)
                    .light_sampling(plan.light_sampling);
                self.render_frame(&path, accel, start, observer, pass)
            }
        }
    }

    /// The band loop, for one shading model (static dispatch: one copy per model). A
    /// sample pass first adds its samples to every pixel's sums; its bands are then
    /// made of the sums' means, where a whole render traces them.
    fn render_frame<I: Integrator>(
        &self,
        integrator: &I,
        accel: &Accel,
        start: Instant,
        observer: &dyn Observer,
        pass: Option<SamplePass>,
    ) -> (Image, RenderStats) {
        let plan = &self.plan;
        let rays = CameraRays::new(&plan.camera, plan.aa, plan.spp);
        let region = plan.region;
        let (wx, wy) = self.weights();
        let (x_lo, x_hi) = wx.input_span(region.x, region.x + region.width);
        let row_len = (x_hi - x_lo) as usize;
        let total_rays = AtomicU64::new(0);
        // Rows go a strip of `TILE_ROWS` at a time, so that camera rays make packets
        // of square tiles (a row of sixteen pixels traced 1.25x slower on the bunny).
        let row_len = row_len.max(1);
        let trace_strip = |y0: u32, strip: &mut [[f32; 3]]| {
            if observer.cancelled() {
                return;
            }
            let mut count = RayCount::default();
            if integrator.spreads_samples() {
                let mut sums = vec![WeightedColor::default(); strip.len()];
                let (origin, samples) = ((x_lo, y0), 0..plan.spp);
                self.add_strip_samples(
                    integrator, accel, &rays, origin, row_len, samples, &mut sums, &mut count,
                    observer,
                );
                if observer.cancelled() {
                    return;
                }
                for (out, sum) in strip.iter_mut().zip(&sums) {
                    *out = sum.mean().to_array();
                }
            } else if rays.spp() == 1 {
                self.strip_in_packets(
                    integrator,
                    accel,
                    &rays,
                    (x_lo, y0),
                    row_len,
                    strip,
                    &mut count,
                    observer,
                );
            } else {
                for (k, out) in strip.iter_mut().enumerate() {
                    // A pixel of many rays is a long wait: Ctrl-C should not last a strip.
                    if observer.cancelled() {
                        return;
                    }
                    let x = x_lo + (k % row_len) as u32;
                    let y = y0 + (k / row_len) as u32;
                    *out = self
                        .pixel(integrator, accel, &rays, x, y, &mut count)
                        .to_array();
                }
            }
            total_rays.fetch_add(count.rays, Ordering::Relaxed);
            if !observer.cancelled() {
                observer.progress((strip.len() / row_len) as u64);
            }
        };
        let sums = pass.map(|pass| {
            self.sum_samples(
                integrator,
                accel,
                &rays,
                pass.sums,
                pass.to,
                &total_rays,
                observer,
            );
            &*pass.sums
        });
        let fill_strip = |y0: u32, strip: &mut [[f32; 3]]| match sums {
            Some(sums) => sums.means_into(y0, strip),
            None => trace_strip(y0, strip),
        };
        if plan.aa == 1 {
            // One traced pixel to each output pixel: no band buffers to fill and copy.
            let mut pixels = vec![[0.0f32; 3]; region.width as usize * region.height as usize];
            pixels
                .par_chunks_mut(row_len * TILE_ROWS)
                .enumerate()
                .with_max_len(1)
                .for_each(|(i, strip)| {
                    let y = (i * TILE_ROWS) as u32;
                    fill_strip(region.y + y, strip);
                    if !observer.cancelled() {
                        // `+ 0` is what a one-tap resample adds (`0 + 1 p`, turning -0
                        // into +0), so filling the image straight gives the same bits.
                        for out in strip.iter_mut() {
                            *out = (Vec3::from_array(*out) + Vec3::ZERO).to_array();
                        }
                        observer.rows(y, strip);
                    }
                });
            let stats = RenderStats {
                rays: total_rays.into_inner(),
                elapsed: start.elapsed(),
            };
            return (Image::new(region.width, region.height, pixels), stats);
        }
        // Bands run in parallel as well as the rows inside them, so no core waits for
        // a band's last row or for its resampling; each band's pixels stay its own, so
        // the image does not depend on which thread did what. Every band and every row
        // is a task of its own (`with_max_len(1)`): rayon would otherwise hand a thread
        // a run of rows to trace in turn, which no other thread can take from, and the
        // frame's last run kept one core busy for some 15 ms while the other waited.
        // Each band resamples straight into its rows of the frame: no copy at the end,
        // which took one thread some 5 ms at the end of a 0.41 s render of scene1.
        let mut pixels = vec![[0.0f32; 3]; region.width as usize * region.height as usize];
        let out_rows = region.width as usize * BAND_ROWS as usize;
        pixels
            .par_chunks_mut(out_rows.max(1))
            .zip(self.bands(&wy, region).collect::<Vec<_>>())
            .with_max_len(1)
            .for_each(|(out, (y0, y1, lo, hi))| {
                // A cancelled render's bands are neither traced nor resampled: at 4K
                // with anti-aliasing, resampling the rest of the frame took half a second
                // after Ctrl-C.
                if observer.cancelled() {
                    return;
                }
                let mut band = vec![[0.0f32; 3]; row_len * (hi - lo) as usize];
                band.par_chunks_mut(row_len * TILE_ROWS)
                    .enumerate()
                    .with_max_len(1)
                    .for_each(|(i, strip)| fill_strip(lo + (i * TILE_ROWS) as u32, strip));
                if observer.cancelled() {
                    return;
                }
                resample_window_into(
                    &band,
                    x_lo,
                    lo,
                    x_hi - x_lo,
                    hi - lo,
                    &wx,
                    &wy,
                    region.x,
                    y0,
                    region.width,
                    y1 - y0,
                    out,
                );
                observer.rows(y0 - region.y, out);
            });
        let stats = RenderStats {
            rays: total_rays.into_inner(),
            elapsed: start.elapsed(),
        };
        (Image::new(region.width, region.height, pixels), stats)
    }

    /// Colour of supersampled pixel `(x, y)`: all its camera rays into one weighted mean.
    /// Where the model allows, the lens rays go as packets, shaded in their order.
    #[inline]
    fn pixel<I: Integrator>(
        &self,
        integrator: &I,
        accel: &Accel,
        rays: &CameraRays,
        x: u32,
        y: u32,
        count: &mut RayCount,
    ) -> Vec3 {
        let mut sampler = PixelSampler::new(self.plan.seed, x, y);
        let mut acc = WeightedColor::default();
        if !integrator.lens_packets() || rays.spp() == 1 {
            rays.for_each_ray(x, y, &mut sampler, |ray, sampler| {
                integrator.trace_camera_ray(ray, sampler, &mut acc, count)
            });
            return acc.mean();
        }
        let mut batch = [NO_RAY; PACKET_RAYS];
        let mut n = 0;
        rays.for_each_ray(x, y, &mut sampler, |ray, sampler| {
            batch[n] = ray;
            n += 1;
            if n == PACKET_RAYS {
                trace_packet(integrator, accel, &batch, sampler, &mut acc, count);
                n = 0;
            }
        });
        trace_packet(
            integrator,
            accel,
            &batch[..n],
            &mut sampler,
            &mut acc,
            count,
        );
        acc.mean()
    }

    /// A strip of supersampled rows (starting at pixel `origin`, `row_len` pixels
    /// each) with one camera ray per pixel, traced in packets of [`TILE_COLUMNS`] x
    /// [`TILE_ROWS`] pixels; each pixel keeps its own sampler, as in
    /// [`Renderer::pixel`].
    #[allow(clippy::too_many_arguments)]
    fn strip_in_packets<I: Integrator>(
        &self,
        integrator: &I,
        accel: &Accel,
        rays: &CameraRays,
        origin: (u32, u32),
        row_len: usize,
        strip: &mut [[f32; 3]],
        count: &mut RayCount,
        observer: &dyn Observer,
    ) {
        let rows = strip.len() / row_len;
        let mut batch = [NO_RAY; PACKET_RAYS];
        let mut hits = [None; PACKET_RAYS];
        let mut at = [0usize; PACKET_RAYS];
        let pixel = |k: usize| {
            (
                origin.0 + (k % row_len) as u32,
                origin.1 + (k / row_len) as u32,
            )
        };
        for x0 in (0..row_len).step_by(TILE_COLUMNS) {
            // Checked tile by tile: a strip of a wide frame takes a while.
            if observer.cancelled() {
                return;
            }
            let mut n = 0;
            for r in 0..rows {
                for c in x0..(x0 + TILE_COLUMNS).min(row_len) {
                    at[n] = r * row_len + c;
                    let (x, y) = pixel(at[n]);
                    batch[n] = rays.pinhole(x, y);
                    n += 1;
                }
            }
            accel.closest_packet(&batch[..n], f32::INFINITY, &mut hits[..n]);
            let mut samplers: [PixelSampler; PACKET_RAYS] = std::array::from_fn(|i| {
                let (x, y) = pixel(at[i]);
                PixelSampler::new(self.plan.seed, x, y)
            });
            let mut accs = [WeightedColor::default(); PACKET_RAYS];
            integrator.trace_camera_packet(
                &batch[..n],
                &hits[..n],
                &mut samplers[..n],
                &mut accs[..n],
                count,
            );
            for (&k, acc) in at[..n].iter().zip(&accs) {
                strip[k] = acc.mean().to_array();
            }
        }
    }
}

/// The big allocations of rendering `scene` as `plan` says.
fn memory_estimate(scene: &Scene, plan: &Plan) -> memory::MemoryEstimate {
    let region = plan.region;
    let estimate =
        memory::MemoryEstimate::of(scene, plan.accel, region.width, region.height, plan.aa);
    if matches!(plan.integrator, IntegratorKind::Whitted)
        && let Some(casters) = Casters::count(scene, &scene.resolved_surfaces())
    {
        return estimate.with_casters(scene, plan.accel, casters);
    }
    estimate
}

/// Traces `batch` as one packet, then shades each ray in order.
#[inline]
fn trace_packet<I: Integrator>(
    integrator: &I,
    accel: &Accel,
    batch: &[Ray],
    sampler: &mut PixelSampler,
    acc: &mut WeightedColor,
    count: &mut RayCount,
) {
    let mut hits = [None; PACKET_RAYS];
    let hits = &mut hits[..batch.len()];
    accel.closest_packet(batch, f32::INFINITY, hits);
    integrator.trace_camera_packet(
        batch,
        hits,
        std::slice::from_mut(sampler),
        std::slice::from_mut(acc),
        count,
    );
}

#[cfg(test)]
mod tests;
