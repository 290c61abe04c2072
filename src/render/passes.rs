//! Rendering in sample passes (a progressive render): each pass adds samples to every
//! pixel's running sum, and its image is the means of the sums so far. The preview and
//! the Python API refine a path-traced image this way; passes that end on the job's
//! samples give a whole render's image bit for bit.

use super::spread::PixelSum;
use super::{
    CameraRays, Integrator, RayCount, RenderStats, Renderer, TILE_ROWS, WeightedColor,
    memory_estimate,
};
use crate::accel::Accel;
use crate::error::Result;
use crate::film::Image;
use crate::math::Vec3;
use crate::render::observer::Observer;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// A render in sample passes as a front end drives it (the preview, Python): the
/// samples a pixel after each pass, and the sums between them. A model that does not
/// spread its samples, or sums that would not fit the memory budget, give one pass: the
/// whole render.
pub struct Progressive {
    sums: Option<SampleSums>,
    totals: Vec<u32>,
    next: usize,
}

impl Progressive {
    /// Samples a pixel after each pass, the last the render's own.
    pub fn totals(&self) -> &[u32] {
        &self.totals
    }

    /// The next pass's samples a pixel and image (the means of all samples so far,
    /// [`Renderer::render_samples`]); `None` after the last. `renderer` and `accel` are
    /// those [`Renderer::progressive`] was asked of.
    pub fn next_pass(
        &mut self,
        renderer: &Renderer,
        accel: &Accel,
        observer: &dyn Observer,
    ) -> Option<(u32, Result<(Image, RenderStats)>)> {
        let &to = self.totals.get(self.next)?;
        self.next += 1;
        let rendered = match &mut self.sums {
            Some(sums) => renderer.render_samples(accel, sums, to, observer),
            None => renderer.render_with(accel, observer),
        };
        Some((to, rendered))
    }
}

/// Samples a pixel after each sample pass of an image of `spp`: one, then doubling,
/// then `spp`. Each pass adds as many samples as all before it, so each cuts the noise
/// by about √2 for a wait as long as the picture so far, and the passes cost what one
/// render of `spp` does.
pub fn sample_totals(spp: u32) -> Vec<u32> {
    let mut totals: Vec<u32> = std::iter::successors(Some(1u32), |&n| n.checked_mul(2))
        .take_while(|&n| n < spp)
        .collect();
    totals.push(spp);
    totals
}

impl Renderer<'_> {
    /// This render in sample passes ([`sample_totals`]) where its model spreads its
    /// samples and the sums fit the memory budget; else in one pass.
    pub fn progressive(&self) -> Progressive {
        // Sums are refused to a model that does not spread its samples, and over the
        // memory budget: the two cases of one pass.
        let sums = self.sample_sums().ok();
        let totals = match sums {
            Some(_) => sample_totals(self.spp()),
            None => vec![self.spp()],
        };
        Progressive {
            sums,
            totals,
            next: 0,
        }
    }

    /// Empty sums for rendering in sample passes ([`Renderer::render_samples`]): one
    /// per supersampled pixel the film reads. Refused for a model that does not spread
    /// its samples, and when the sums would not fit the memory budget.
    pub fn sample_sums(&self) -> Result<SampleSums> {
        if !self.spreads_samples() {
            return Err(crate::error::Error::Settings(format!(
                "the {} model does not render in sample passes",
                self.plan.integrator.name()
            )));
        }
        self.check_sums_fit()?;
        let ((x_lo, x_hi), (y_lo, y_hi)) = self.traced_span();
        let (columns, rows) = ((x_hi - x_lo) as usize, (y_hi - y_lo) as usize);
        Ok(SampleSums {
            pixels: vec![[0.0; 4]; columns * rows],
            origin: (x_lo, y_lo),
            columns,
            samples: 0,
            torn: false,
        })
    }

    /// Whether sample sums for this render fit its memory budget beside the rest of
    /// the render: the error [`Renderer::sample_sums`] would give, without making them.
    fn check_sums_fit(&self) -> Result<()> {
        let ((x_lo, x_hi), (y_lo, y_hi)) = self.traced_span();
        let pixels = u64::from(x_hi - x_lo) * u64::from(y_hi - y_lo);
        let bytes = pixels.saturating_mul(size_of::<[f32; 4]>() as u64);
        let mut estimate = memory_estimate(self.scene, &self.plan);
        estimate.film = estimate.film.saturating_add(bytes);
        estimate.check(self.plan.max_memory, self.plan.accel)
    }

    /// Samples a pixel after each pass of [`Renderer::progressive`], worked out
    /// without making its sums: what a front end shows before the first pass.
    pub fn pass_totals(&self) -> Vec<u32> {
        if self.spreads_samples() && self.check_sums_fit().is_ok() {
            sample_totals(self.spp())
        } else {
            vec![self.spp()]
        }
    }

    /// One sample pass: adds samples `sums.samples()..to` of every pixel to `sums`
    /// and returns the image of all the samples summed (their means, resampled as
    /// [`Renderer::render`] resamples), through the same driver, observer and
    /// cancellation. Passes that end at [`Renderer::spp`] give `render`'s image bit for
    /// bit however the samples were split: each pixel's sum takes its samples in the
    /// same order. `accel` is [`Renderer::build_accel`]'s; `sums` are this renderer's
    /// ([`Renderer::sample_sums`]). A cancelled pass leaves some pixels with more
    /// samples than others: its sums are refused from then on.
    pub fn render_samples(
        &self,
        accel: &Accel,
        sums: &mut SampleSums,
        to: u32,
        observer: &dyn Observer,
    ) -> Result<(Image, RenderStats)> {
        let refuse = |why: String| Err(crate::error::Error::Settings(why));
        let ((x_lo, x_hi), (y_lo, y_hi)) = self.traced_span();
        let size = (x_hi - x_lo) as usize * (y_hi - y_lo) as usize;
        if sums.torn {
            return refuse("these sample sums were left part-way by a cancelled pass".into());
        }
        if !self.spreads_samples() || sums.origin != (x_lo, y_lo) || sums.pixels.len() != size {
            return refuse("these sample sums are not this render's".into());
        }
        if to < sums.samples || to > self.plan.spp {
            return refuse(format!(
                "a sample pass must end between the {} samples summed and the {} of the \
                 image, found {to}",
                sums.samples, self.plan.spp
            ));
        }
        let out = self.drive(Some(accel), Some(SamplePass { sums, to }), observer);
        match out {
            Ok(_) => sums.samples = to,
            Err(crate::error::Error::Interrupted) => sums.torn = true,
            Err(_) => {}
        }
        out
    }

    /// Adds samples `sums.samples..to` of every pixel to `sums`, a strip of
    /// [`TILE_ROWS`] rows at a time, reporting each strip as progress.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sum_samples<I: Integrator>(
        &self,
        integrator: &I,
        accel: &Accel,
        rays: &CameraRays,
        sums: &mut SampleSums,
        to: u32,
        total_rays: &AtomicU64,
        observer: &dyn Observer,
    ) {
        let (from, (x_lo, y_lo), columns) = (sums.samples, sums.origin, sums.columns);
        sums.pixels
            .par_chunks_mut(columns * TILE_ROWS)
            .enumerate()
            .with_max_len(1)
            .for_each(|(i, strip)| {
                let mut count = RayCount::default();
                let origin = (x_lo, y_lo + (i * TILE_ROWS) as u32);
                self.add_strip_samples(
                    integrator,
                    accel,
                    rays,
                    origin,
                    columns,
                    from..to,
                    strip,
                    &mut count,
                    observer,
                );
                total_rays.fetch_add(count.rays, Ordering::Relaxed);
                if !observer.cancelled() {
                    observer.progress((strip.len() / columns) as u64);
                }
            });
    }
}

/// The running sums of a render in sample passes (a progressive render's
/// accumulation buffer): for every supersampled pixel the film reads, the weighted sum
/// of the samples traced so far, kept as sums rather than means so that the last pass
/// ends on the very floats a whole render adds up. Made by [`Renderer::sample_sums`],
/// filled by [`Renderer::render_samples`].
pub struct SampleSums {
    /// Per pixel, row after row: the sum's colour and its weight, 16 bytes where a
    /// [`WeightedColor`] takes 32 (a 1080p frame at aa 2 keeps 130 MB rather than 260).
    pixels: Vec<[f32; 4]>,
    /// The first pixel's place in the supersampled frame.
    origin: (u32, u32),
    /// Pixels a row.
    columns: usize,
    /// Samples of every pixel summed so far.
    samples: u32,
    /// A pass was cancelled part-way: pixels hold different numbers of samples.
    torn: bool,
}

impl SampleSums {
    /// Samples of every pixel summed so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    pub(super) fn rows(&self) -> usize {
        self.pixels.len() / self.columns.max(1)
    }

    /// The means of the strip of rows from supersampled row `y0` (whole rows of the
    /// sums), the means of the samples summed.
    pub(super) fn means_into(&self, y0: u32, strip: &mut [[f32; 3]]) {
        let first = (y0 - self.origin.1) as usize * self.columns;
        for (out, &sum) in strip.iter_mut().zip(&self.pixels[first..]) {
            *out = sum_of(sum).mean().to_array();
        }
    }
}

/// A stored sum as the [`WeightedColor`] it was (every float as it was).
#[inline]
fn sum_of([r, g, b, weight]: [f32; 4]) -> WeightedColor {
    WeightedColor {
        sum: Vec3::new(r, g, b),
        weight,
    }
}

impl PixelSum for [f32; 4] {
    #[inline]
    fn add_sample(&mut self, sample: &WeightedColor) {
        let mut acc = sum_of(*self);
        acc.add_sample(sample);
        *self = stored(acc);
    }
}

/// A [`WeightedColor`] as it is stored.
#[inline]
fn stored(acc: WeightedColor) -> [f32; 4] {
    [acc.sum.x, acc.sum.y, acc.sum.z, acc.weight]
}

/// Samples `sums.samples..to` of every pixel, added to `sums`.
pub(super) struct SamplePass<'s> {
    pub(super) sums: &'s mut SampleSums,
    pub(super) to: u32,
}

#[cfg(test)]
mod tests {
    use super::sample_totals;

    #[test]
    fn sample_passes_double_and_end_on_the_job_s_samples() {
        assert_eq!(sample_totals(1), [1]);
        assert_eq!(sample_totals(2), [1, 2]);
        assert_eq!(sample_totals(12), [1, 2, 4, 8, 12]);
        assert_eq!(sample_totals(256), [1, 2, 4, 8, 16, 32, 64, 128, 256]);
        assert_eq!(sample_totals(u32::MAX).last(), Some(&u32::MAX));
    }
}
