//! The background as a light: a constant colour sampled uniformly over the sphere,
//! an environment image sampled in proportion to its brightness (pbrt's piecewise
//! constant 2D distribution over the equirectangular image).

use crate::math::{Vec3, cross, sin_cos};
use crate::render::bsdf::uniform_sphere;
use crate::scene::{Background, Scene};
use std::f32::consts::{FRAC_1_PI, PI, TAU};

/// Cells of the brightness grid along the image's width at most (half as many rows):
/// finer than that costs memory and gains little.
const MAX_COLUMNS: u32 = 2048;
/// Every cell keeps this share of the mean brightness, so that a cell whose centre is
/// dark but whose filtered texels are not can still be drawn.
const FLOOR: f32 = 1e-3;

/// What rays leaving the scene meet, and how it is sampled.
pub enum Environment {
    /// The same radiance everywhere: directions uniform on the sphere.
    Uniform,
    /// An equirectangular image: directions drawn by its brightness.
    Image(ImageDistribution),
}

/// A piecewise constant density over the image's `(u, v)` square, `u` along the
/// horizon and `v` from the bottom (-up) to the top (+up), as
/// `ImageTexture::sample_direction` reads it.
pub struct ImageDistribution {
    columns: usize,
    rows: usize,
    /// Per row, the cumulative brightness of its cells, rising to the row's total.
    conditional: Vec<f32>,
    /// Cumulative row totals, rising to the grid's total.
    marginal: Vec<f32>,
    total: f32,
    up: Vec3,
    forward: Vec3,
    right: Vec3,
}

impl Environment {
    /// The scene's background as a light, or `None` where it is black.
    pub fn of(scene: &Scene) -> Option<Environment> {
        match &scene.background {
            Background::Black => None,
            Background::Color(c) => (c.max_element() > 0.0).then_some(Environment::Uniform),
            Background::Environment {
                image,
                up,
                forward,
                intensity,
            } => {
                if intensity.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return None;
                }
                let img = &scene.images[*image as usize];
                let columns = img.width.clamp(1, MAX_COLUMNS) as usize;
                let rows = img.height.clamp(1, MAX_COLUMNS / 2) as usize;
                Some(Environment::Image(ImageDistribution::new(
                    columns,
                    rows,
                    *up,
                    *forward,
                    |d| img.sample_direction(d, *up, *forward),
                )))
            }
        }
    }

    /// The radiance along `dir`.
    #[inline]
    pub fn radiance(&self, scene: &Scene, dir: Vec3) -> Vec3 {
        scene.background(dir)
    }

    /// The density per unit solid angle with which [`Environment::sample`] draws `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        match self {
            Environment::Uniform => 0.25 * FRAC_1_PI,
            Environment::Image(d) => d.pdf(dir),
        }
    }

    /// A direction drawn with `u`, the radiance along it and its density.
    pub fn sample(&self, scene: &Scene, u: (f32, f32)) -> Option<(Vec3, Vec3, f32)> {
        let (dir, pdf) = match self {
            Environment::Uniform => (uniform_sphere(u), 0.25 * FRAC_1_PI),
            Environment::Image(d) => d.sample(u)?,
        };
        let le = self.radiance(scene, dir);
        (pdf > 0.0 && le.max_element() > 0.0).then_some((dir, le, pdf))
    }
}

impl ImageDistribution {
    /// The density of a `columns` x `rows` grid over the image `radiance` reads,
    /// each cell weighed by its brightness at its centre and by the solid angle it
    /// spans (the cosine of its latitude).
    pub(super) fn new(
        columns: usize,
        rows: usize,
        up: Vec3,
        forward: Vec3,
        radiance: impl Fn(Vec3) -> Vec3,
    ) -> ImageDistribution {
        let right = cross(forward, up);
        let mut d = ImageDistribution {
            columns,
            rows,
            conditional: Vec::with_capacity(columns * rows),
            marginal: Vec::with_capacity(rows),
            total: 0.0,
            up,
            forward,
            right,
        };
        let mut weights = Vec::with_capacity(columns * rows);
        for j in 0..rows {
            let v = (j as f32 + 0.5) / rows as f32;
            let cos_lat = ((v - 0.5) * PI).cos();
            for i in 0..columns {
                let u = (i as f32 + 0.5) / columns as f32;
                let c = radiance(d.direction(u, v));
                let y = (c.x + c.y + c.z) / 3.0;
                weights.push(if y.is_finite() {
                    y.max(0.0) * cos_lat
                } else {
                    0.0
                });
            }
        }
        let mean = weights.iter().map(|&w| f64::from(w)).sum::<f64>() / weights.len() as f64;
        let floor = (mean as f32 * FLOOR).max(f32::MIN_POSITIVE);
        let mut total = 0.0f64;
        for row in weights.chunks(columns) {
            let mut sum = 0.0f64;
            for &w in row {
                sum += f64::from(w.max(floor));
                d.conditional.push(sum as f32);
            }
            total += sum;
            d.marginal.push(total as f32);
        }
        d.total = total as f32;
        d
    }

    /// The direction at image coordinates `(u, v)`.
    #[inline]
    fn direction(&self, u: f32, v: f32) -> Vec3 {
        let (sin_lat, cos_lat) = sin_cos((v - 0.5) * PI);
        let (sin_phi, cos_phi) = sin_cos((u - 0.5) * TAU);
        self.up * sin_lat + (self.forward * cos_phi + self.right * sin_phi) * cos_lat
    }

    /// A cell's weight over the mean cell weight: the density over the unit square.
    #[inline]
    fn cell_density(&self, i: usize, j: usize) -> f32 {
        let row = &self.conditional[j * self.columns..(j + 1) * self.columns];
        let w = row[i] - if i == 0 { 0.0 } else { row[i - 1] };
        w * (self.columns * self.rows) as f32 / self.total
    }

    pub(super) fn sample(&self, (a, b): (f32, f32)) -> Option<(Vec3, f32)> {
        let (j, fv) = pick(&self.marginal, a * self.total);
        let row = &self.conditional[j * self.columns..(j + 1) * self.columns];
        let (i, fu) = pick(row, b * row[self.columns - 1]);
        let u = (i as f32 + fu) / self.columns as f32;
        let v = (j as f32 + fv) / self.rows as f32;
        let pdf = self.solid_angle_density(self.cell_density(i, j), v);
        (pdf > 0.0).then(|| (self.direction(u, v), pdf))
    }

    pub(super) fn pdf(&self, dir: Vec3) -> f32 {
        let y = dir.dot(self.up).clamp(-1.0, 1.0);
        let phi = dir.dot(self.right).atan2(dir.dot(self.forward));
        let u = 0.5 + phi / TAU;
        let v = 0.5 + y.asin() / PI;
        let i = ((u * self.columns as f32) as usize).min(self.columns - 1);
        let j = ((v * self.rows as f32) as usize).min(self.rows - 1);
        self.solid_angle_density(self.cell_density(i, j), v)
    }

    /// A density over the `(u, v)` square as a density per unit solid angle at `v`:
    /// the square maps onto the sphere with `dw = 2 pi^2 cos(latitude) du dv`.
    #[inline]
    fn solid_angle_density(&self, density: f32, v: f32) -> f32 {
        let cos_lat = ((v - 0.5) * PI).cos();
        let pdf = density / (2.0 * PI * PI * cos_lat);
        if pdf.is_finite() { pdf } else { 0.0 }
    }
}

/// The cell of cumulative weights `cdf` that `x` (in `[0, total)`) falls in, and its
/// place within it in [0, 1).
#[inline]
fn pick(cdf: &[f32], x: f32) -> (usize, f32) {
    let k = cdf.partition_point(|&c| c <= x).min(cdf.len() - 1);
    let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
    let within = (x - lo) / (cdf[k] - lo).max(f32::MIN_POSITIVE);
    (k, within.clamp(0.0, crate::math::ONE_BELOW))
}
