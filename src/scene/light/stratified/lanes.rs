//! A light's samples from one shading point worked out sixteen at a time in lanes: each
//! field an array with a lane a sample, and every step a plain loop over the lanes,
//! which the compiler turns into SIMD. One sample at a time, a sample's square roots and
//! divisions wait on each other; in lanes they go side by side.
//!
//! Every lane does the arithmetic [`Light::for_each_sample`] does for its sample, in
//! the same order, so the samples are the same bit for bit (but the sign of a NaN made
//! from NaN inputs, which is not specified); the random numbers are drawn first, in
//! the order that function draws them.

// Loops over lane indices read like the formulas they vectorise.
#![allow(clippy::needless_range_loop)]

use super::{LightSample, Strata};
use crate::math::{Vec3, sin_cos};
use crate::scene::light::sampling::{MeshTriangle, SphereCone, pick_triangle, triangle_point};
use crate::scene::{Light, LightKind, Scene, Surface};

/// Samples worked out together.
pub const LANES: usize = 16;

/// Up to [`LANES`] samples of one light with an extent from one point.
pub struct SampleLanes {
    dir: [[f32; LANES]; 3],
    dist: [f32; LANES],
    e: [[f32; LANES]; 3],
    /// Whether the sample lights the point (`for_each_sample` skips it otherwise).
    lit: [bool; LANES],
    len: usize,
}

impl Default for SampleLanes {
    fn default() -> SampleLanes {
        SampleLanes {
            dir: [[0.0; LANES]; 3],
            dist: [0.0; LANES],
            e: [[0.0; LANES]; 3],
            lit: [false; LANES],
            len: 0,
        }
    }
}

impl SampleLanes {
    /// The samples that light the point, in order.
    pub fn lit(&self) -> impl Iterator<Item = LightSample> + '_ {
        (0..self.len).filter(|&k| self.lit[k]).map(|k| LightSample {
            dir: Vec3::new(self.dir[0][k], self.dir[1][k], self.dir[2][k]),
            dist: self.dist[k],
            e: Vec3::new(self.e[0][k], self.e[1][k], self.e[2][k]),
        })
    }
}

/// The point of an emitter each lane drew, and what [`share_lanes`] needs of the
/// emitter there.
struct EmitterLanes {
    y: [[f32; LANES]; 3],
    /// The emitter's unit normal at each lane's point.
    normal: [[f32; LANES]; 3],
    /// Emitted radiance at each lane's point.
    le: [[f32; LANES]; 3],
    /// Whether the lane drew a point (a mesh light's lane may not).
    drawn: [bool; LANES],
}

impl EmitterLanes {
    fn new() -> EmitterLanes {
        EmitterLanes {
            y: [[0.0; LANES]; 3],
            normal: [[0.0; LANES]; 3],
            le: [[0.0; LANES]; 3],
            drawn: [false; LANES],
        }
    }

    fn set(&mut self, k: usize, y: Vec3, normal: Vec3, le: Vec3) {
        for c in 0..3 {
            self.y[c][k] = y[c];
            self.normal[c][k] = normal[c];
            self.le[c][k] = le[c];
        }
        self.drawn[k] = true;
    }
}

/// `(a.x * b.x + a.y * b.y) + a.z * b.z` in each lane: the order of `Vec3::dot`.
#[inline(always)]
fn dot_lanes(a: &[[f32; LANES]; 3], b: &[[f32; LANES]; 3], out: &mut [f32; LANES]) {
    for k in 0..LANES {
        out[k] = a[0][k] * b[0][k] + a[1][k] * b[1][k] + a[2][k] * b[2][k];
    }
}

/// `share_sample` in lanes: each lane's sample of an emitter standing for `share` of
/// its area.
#[inline(always)]
fn share_lanes(p: Vec3, em: &EmitterLanes, share: f32, len: usize, out: &mut SampleLanes) {
    let mut to = [[0.0; LANES]; 3];
    for (c, to) in to.iter_mut().enumerate() {
        for k in 0..LANES {
            to[k] = em.y[c][k] - p[c];
        }
    }
    let mut d2 = [0.0; LANES];
    dot_lanes(&to, &to, &mut d2);
    for k in 0..LANES {
        out.dist[k] = d2[k].sqrt();
    }
    for (c, dir) in out.dir.iter_mut().enumerate() {
        for k in 0..LANES {
            dir[k] = to[c][k] / out.dist[k];
        }
    }
    let mut cos_l = [0.0; LANES];
    dot_lanes(&em.normal, &out.dir, &mut cos_l);
    let mut scale = [0.0; LANES];
    for k in 0..LANES {
        cos_l[k] = -cos_l[k];
        scale[k] = cos_l[k] * share / d2[k];
    }
    for (c, e) in out.e.iter_mut().enumerate() {
        for k in 0..LANES {
            e[k] = em.le[c][k] * scale[k];
        }
    }
    for k in 0..len {
        // `share_sample`'s two refusals; a NaN cosine (an emitter without area) is not
        // one of them.
        let faces = cos_l[k] > 0.0 || cos_l[k].is_nan();
        out.lit[k] = em.drawn[k] && d2[k] > 0.0 && d2[k].is_finite() && faces;
    }
    out.len = len;
}

impl Light {
    /// Samples `first..first + len` of the `samples` (at least one) of this light with
    /// an extent seen from `p` into `out`: those [`Light::for_each_sample`] would hand
    /// its callback, with the same values. `len` is at most [`LANES`].
    // Not inlined: in its caller's frame its buffers measured slower.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub fn sample_lanes(
        &self,
        scene: &Scene,
        surfaces: &[Surface],
        p: Vec3,
        strata: &mut impl Strata,
        first: u32,
        len: usize,
        out: &mut SampleLanes,
    ) {
        debug_assert!(len <= LANES && self.is_area());
        let n = self.samples.max(1);
        let share = self.flat_area() / n as f32;
        let mut em = EmitterLanes::new();
        match &self.kind {
            LightKind::Quad { .. } | LightKind::Disk { .. } => {
                let Some(flat) = self.flat() else {
                    out.len = 0;
                    return;
                };
                let disk = matches!(self.kind, LightKind::Disk { .. });
                for k in 0..len {
                    let i = first + k as u32;
                    let at = if disk {
                        strata.disk(i, n)
                    } else {
                        strata.square(i, n)
                    };
                    if let Some(y) = flat.point(scene, surfaces, at) {
                        em.set(k, y.y, y.normal, y.le);
                    }
                }
                share_lanes(p, &em, share, len, out);
            }
            LightKind::Mesh { shapes, cdf, .. } => {
                if !shapes.is_empty() {
                    // Stratified samples pick the triangles in order, so neighbouring
                    // lanes mostly share one: it is looked up once.
                    let mut last: Option<(usize, Option<MeshTriangle>)> = None;
                    for k in 0..len {
                        let (a, b) = strata.square(first + k as u32, n);
                        let (j, su) = pick_triangle(cdf, shapes.len(), a);
                        let triangle = match last {
                            Some((i, triangle)) if i == j => triangle,
                            _ => {
                                let triangle = self.mesh_triangle(scene, surfaces, shapes[j]);
                                last = Some((j, triangle));
                                triangle
                            }
                        };
                        if let Some(tri) = triangle {
                            em.set(k, triangle_point(tri.v, su, b), tri.normal, tri.le);
                        }
                    }
                }
                share_lanes(p, &em, share, len, out);
            }
            LightKind::Sphere { radius } => {
                let Some(cone) = SphereCone::new(self.position, *radius, p) else {
                    out.len = 0;
                    return;
                };
                let (axis, t1, t2) = (cone.axis, cone.t1, cone.t2);
                let e = self.color * self.intensity * (cone.solid_angle / n as f32);
                // Drawn in order, then worked out in lanes.
                let (mut a, mut b) = ([0.0; LANES], [0.0; LANES]);
                for k in 0..len {
                    (a[k], b[k]) = strata.square(first + k as u32, n);
                }
                let mut d = [[0.0; LANES]; 3];
                let mut cos = [0.0; LANES];
                for k in 0..LANES {
                    cos[k] = cone.cos_of(a[k]);
                    let sin = (1.0 - cos[k] * cos[k]).max(0.0).sqrt();
                    let (sp, cp) = sin_cos(b[k] * std::f32::consts::TAU);
                    let (s_cp, s_sp) = (sin * cp, sin * sp);
                    for (c, d) in d.iter_mut().enumerate() {
                        d[k] = axis[c] * cos[k] + t1[c] * s_cp + t2[c] * s_sp;
                    }
                }
                let mut length = [0.0; LANES];
                dot_lanes(&d, &d, &mut length);
                for k in 0..LANES {
                    length[k] = length[k].sqrt();
                    out.dist[k] = cone.near_side(cos[k]);
                }
                for (c, dir) in out.dir.iter_mut().enumerate() {
                    for k in 0..LANES {
                        dir[k] = d[c][k] / length[k];
                    }
                }
                for (c, lanes) in out.e.iter_mut().enumerate() {
                    lanes.fill(e[c]);
                }
                out.lit[..len].fill(true);
                out.len = len;
            }
            LightKind::Point | LightKind::Spot { .. } | LightKind::Directional { .. } => {
                unreachable!("a point, spot or directional light is not sampled in lanes")
            }
        }
    }
}
