//! The samples of one pixel traced side by side: sixteen paths step together, vertex
//! by vertex, and the arithmetic of each step — the surface at a hit on a plain flat
//! shape, the BSDF's frame, the light samples' densities and weights, the next
//! direction, Russian roulette — runs over all sixteen at once in vector registers,
//! while the steps that follow pointers (the intersector, any other surface at a hit,
//! the sample streams) go one path at a time.
//!
//! Each lane does what [`Path::radiance`] does for its path, operation for operation
//! in the same order, so a pixel's value is the same bit for bit either way (and
//! whichever vector instructions the processor has). That holds for the scenes whose
//! every surface is Lambertian and whose every light is an emissive mesh, without an
//! environment: the ones [`Path::lanes_apply`] accepts; the others step their paths
//! together through the path at a time's own step (`wave.rs`).

// Each lane's work is a loop over the lanes that reads and writes several arrays at
// the lane's index: the shape the compiler turns into vector instructions.
#![allow(clippy::needless_range_loop)]

use super::{MAX_CONTINUE, Path, ROULETTE_DEPTH, Weighing, power_heuristic};
use crate::accel::Hit;
use crate::accel::PACKET_RAYS;
#[cfg(target_arch = "x86_64")]
use crate::accel::simd::SimdLevel;
use crate::math::{Ray, Vec3};
use crate::render::{PixelSampler, RayCount};
use crate::scene::light::sampling::{MeshTriangle, pick_triangle, triangle_point};
use crate::scene::{LightKind, Scene, Surface};
use std::f32::consts::FRAC_1_PI;

mod hits;
use hits::{FlatHit, LaneHits, flat_hits};
#[cfg(test)]
mod tests;

/// Paths traced side by side: a packet of camera rays.
pub const LANES: usize = PACKET_RAYS;

/// One number a lane.
type Lanes = [f32; LANES];

/// One vector a lane, structure of arrays.
#[derive(Clone, Copy)]
struct V3 {
    x: Lanes,
    y: Lanes,
    z: Lanes,
}

impl V3 {
    const ZERO: V3 = V3::splat(0.0);

    const fn splat(v: f32) -> V3 {
        V3 {
            x: [v; LANES],
            y: [v; LANES],
            z: [v; LANES],
        }
    }

    #[inline(always)]
    fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: Vec3) {
        self.x[i] = v.x;
        self.y[i] = v.y;
        self.z[i] = v.z;
    }

    #[inline(always)]
    fn at(&self, i: usize) -> [f32; 3] {
        [self.x[i], self.y[i], self.z[i]]
    }

    #[inline(always)]
    fn put(&mut self, i: usize, [x, y, z]: [f32; 3]) {
        self.x[i] = x;
        self.y[i] = y;
        self.z[i] = z;
    }

    /// `self + a * b` in the lanes of `bits`, channel by channel as [`Vec3`]'s
    /// operators take it: chosen in every lane rather than gathered into vectors one
    /// lane at a time.
    #[inline(always)]
    fn add_product_where(&mut self, bits: u32, a: &V3, b: &V3) {
        for i in 0..LANES {
            let on = bits >> i & 1 == 1;
            let sum = |s: f32, a: f32, b: f32| if on { s + a * b } else { s };
            self.x[i] = sum(self.x[i], a.x[i], b.x[i]);
            self.y[i] = sum(self.y[i], a.y[i], b.y[i]);
            self.z[i] = sum(self.z[i], a.z[i], b.z[i]);
        }
    }

    /// `self + a` in the lanes of `bits` (see [`V3::add_product_where`]).
    #[inline(always)]
    fn add_where(&mut self, bits: u32, a: &V3) {
        for i in 0..LANES {
            let on = bits >> i & 1 == 1;
            self.x[i] = if on { self.x[i] + a.x[i] } else { self.x[i] };
            self.y[i] = if on { self.y[i] + a.y[i] } else { self.y[i] };
            self.z[i] = if on { self.z[i] + a.z[i] } else { self.z[i] };
        }
    }
}

/// `a . b` in the order of [`Vec3::dot`]: `(x + y) + z`.
#[inline(always)]
fn dot([ax, ay, az]: [f32; 3], [bx, by, bz]: [f32; 3]) -> f32 {
    ax * bx + ay * by + az * bz
}

/// SSE's `max`: `a` where `a > b`, else `b` (so a NaN gives `b`), as [`Vec3`] takes
/// maxima.
#[inline(always)]
fn max_ps(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// [`Vec3::max_element`] as glam 0.34.2 takes it, `max(max(x, z), max(y, z))`: where a
/// channel is NaN the order decides what comes out (a test holds the two together).
#[inline(always)]
fn max_element([x, y, z]: [f32; 3]) -> f32 {
    max_ps(max_ps(x, z), max_ps(y, z))
}

/// [`Vec3::is_finite`].
#[inline(always)]
fn is_finite([x, y, z]: [f32; 3]) -> bool {
    x.abs() < f32::INFINITY && y.abs() < f32::INFINITY && z.abs() < f32::INFINITY
}

/// [`crate::math::surface_epsilon`].
#[inline(always)]
fn surface_epsilon([x, y, z]: [f32; 3]) -> f32 {
    crate::math::SURFACE_EPSILON * (1.0 + max_element([x.abs(), y.abs(), z.abs()]))
}

/// [`crate::math::offset_origin`].
#[inline(always)]
fn offset_origin(p: [f32; 3], n: [f32; 3], toward: [f32; 3]) -> [f32; 3] {
    let n = if dot(n, toward) >= 0.0 {
        n
    } else {
        [-n[0], -n[1], -n[2]]
    };
    let e = surface_epsilon(p);
    [p[0] + n[0] * e, p[1] + n[1] * e, p[2] + n[2] * e]
}

/// [`power_heuristic`] worked out whole and then chosen: the same bits, without a
/// branch.
#[inline(always)]
fn power_heuristic_selected(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    let w = a2 / (a2 + b2);
    let w = if w.is_finite() { w } else { 0.0 };
    if a2.is_infinite() { 1.0 } else { w }
}

/// The bits of the lanes for which `f(lane)` holds.
#[inline(always)]
fn lanes_where(f: impl Fn(usize) -> bool) -> u32 {
    let mut bits = 0;
    for i in 0..LANES {
        bits |= u32::from(f(i)) << i;
    }
    bits
}

/// The lanes set in `bits`, lowest first.
#[inline(always)]
fn each(mut bits: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (bits != 0).then(|| {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            i
        })
    })
}

/// What the lanes work out once about a scene they trace.
pub(super) struct LaneScene {
    /// Every light: emissive meshes, each triangle's corners, normal and radiance.
    lights: Vec<MeshLight>,
    /// No mesh has vertex normals or colours: a hit on a surface that reads no
    /// texture is its point and flat normal alone ([`Scene::flat_point`]).
    flat: bool,
    /// No surface reads texture coordinates: hits need not ask each one.
    untextured: bool,
    /// Where hits are flat: what a hit on each of the scene's own shapes needs, worked
    /// out once as a hit works it out, when all are flat and few (empty otherwise). A
    /// hit then reads one row instead of its corners, an edge product and a root, and
    /// its surface.
    flat_hits: Vec<FlatHit>,
}

struct MeshLight {
    area: f32,
    cdf: Vec<f32>,
    triangles: Vec<MeshTriangle>,
    /// Few triangles, their cdf ordered and finite: every lane picks its triangle at
    /// once, by counting and selecting, instead of a search one lane at a time.
    few: bool,
}

/// Triangles a light may have for its lanes to pick among them all at once.
const FEW_TRIANGLES: usize = 8;

impl MeshLight {
    fn new(area: f32, cdf: Vec<f32>, triangles: Vec<MeshTriangle>) -> MeshLight {
        let few = triangles.len() <= FEW_TRIANGLES
            && cdf.len() == triangles.len()
            && cdf.iter().all(|c| c.is_finite())
            && cdf.is_sorted();
        MeshLight {
            area,
            cdf,
            triangles,
            few,
        }
    }

    /// [`pick_triangle`] and [`triangle_point`] in every lane, for a light of
    /// [`MeshLight::few`] triangles: the point of each lane's `(a, b)` with its
    /// triangle's normal and radiance, bit for bit as one lane at a time finds them.
    /// On an ordered cdf, counting the entries at most `a` is what the search finds.
    #[inline(always)]
    fn points(&self, a: &Lanes, b: &Lanes, y: &mut V3, normal: &mut V3, le: &mut V3) {
        debug_assert!(self.few);
        // Each lane's triangle, counted in 32 bits (a few triangles): twice the lanes
        // a vector register holds in 64.
        let mut below = [0u32; LANES];
        for &c in &self.cdf {
            for i in 0..LANES {
                below[i] += u32::from(c <= a[i]);
            }
        }
        let last = self.triangles.len() as u32 - 1;
        let mut pick = [0u32; LANES];
        for i in 0..LANES {
            pick[i] = below[i].min(last);
        }
        let mut lo = [0.0f32; LANES];
        let mut hi = [0.0f32; LANES];
        for (j, &c) in (0u32..).zip(&self.cdf) {
            for i in 0..LANES {
                lo[i] = if pick[i] == j + 1 { c } else { lo[i] };
                hi[i] = if pick[i] == j { c } else { hi[i] };
            }
        }
        let mut su = [0.0f32; LANES];
        for i in 0..LANES {
            // As pick_triangle: NaN included.
            let d = (hi[i] - lo[i]).max(f32::MIN_POSITIVE);
            let within = ((a[i] - lo[i]) / d).clamp(0.0, 1.0);
            su[i] = within.sqrt();
        }
        // Every lane's point on every triangle, each lane keeping its own triangle's:
        // chosen, not branched to, so the loop stays in vector registers.
        for (j, tri) in (0u32..).zip(&self.triangles) {
            let [v0, v1, v2] = tri.v.map(|v| v.to_array());
            let (n, l) = (tri.normal.to_array(), tri.le.to_array());
            for i in 0..LANES {
                let here = pick[i] == j;
                let (s, t) = (su[i], b[i]);
                let (w0, w1, w2) = (1.0 - s, s * (1.0 - t), s * t);
                let point = [0, 1, 2].map(|k| v0[k] * w0 + v1[k] * w1 + v2[k] * w2);
                let keep = |v: [f32; 3], mine: [f32; 3]| if here { mine } else { v };
                y.put(i, keep(y.at(i), point));
                normal.put(i, keep(normal.at(i), n));
                le.put(i, keep(le.at(i), l));
            }
        }
    }
}

/// A Lambertian surface at each lane's hit, as [`super::Bsdf`] sees it from `wo`: the
/// normal its cosines are taken to, a frame about it, and the reflectance after
/// energy conservation. A surface that reflects nothing has no smooth lobe.
struct Lambert {
    n: V3,
    t: V3,
    b: V3,
    diffuse: V3,
    smooth: u32,
}

impl Lambert {
    #[inline(always)]
    fn new(wo: &V3, n: &V3, ng: &V3, diffuse: &V3) -> Lambert {
        let mut out = Lambert {
            n: V3::ZERO,
            t: V3::ZERO,
            b: V3::ZERO,
            diffuse: V3::ZERO,
            smooth: 0,
        };
        let mut smooth = [false; LANES];
        for i in 0..LANES {
            let n = if dot(n.at(i), wo.at(i)) > 1e-4 {
                n.at(i)
            } else {
                ng.at(i)
            };
            out.n.put(i, n);
            // Vec3::any_orthonormal_pair.
            let [x, y, z] = n;
            let sign = z.signum();
            let a = -1.0 / (sign + z);
            let b = x * y * a;
            out.t.put(i, [1.0 + sign * x * x * a, sign * b, -sign * x]);
            out.b.put(i, [b, sign + y * y * a, -y]);
            let mut d = diffuse.at(i).map(|c| max_ps(c, 0.0));
            let total = max_element(d);
            if total > 1.0 {
                let k = 1.0 / total;
                d = d.map(|c| c * k);
            }
            out.diffuse.put(i, d);
            // The mixture's weights: 1 for the diffuse lobe, or none at all.
            smooth[i] = (d[0] + d[1] + d[2]) / 3.0 > 0.0;
        }
        out.smooth = lanes_where(|i| smooth[i]);
        out
    }

    /// [`super::Bsdf::eval_pdf`] of lane `i` toward `wi`: `f`, its density and the
    /// cosine, zero below either normal.
    /// Worked out whole and then chosen, without a branch, so a loop over the lanes
    /// stays in vector registers.
    #[inline(always)]
    fn eval_pdf(&self, i: usize, ng: [f32; 3], wi: [f32; 3]) -> ([f32; 3], f32, f32) {
        let cos_i = dot(self.n.at(i), wi);
        let below = (cos_i <= 0.0) | (dot(wi, ng) <= 0.0);
        let f = self.diffuse.at(i).map(|c| c * FRAC_1_PI);
        let pick = |v: f32| if below { 0.0 } else { v };
        (f.map(pick), pick(cos_i * FRAC_1_PI), pick(cos_i))
    }
}

impl Path<'_> {
    /// What the lanes need to know of `scene` if every path of it can be traced in
    /// lanes: every surface lit and Lambertian (textures and vertex colours allowed)
    /// with nothing that cuts out, bends normals or absorbs, every light an emissive
    /// mesh of triangles, and no environment.
    pub(super) fn lanes_apply(scene: &Scene, surfaces: &[Surface]) -> Option<LaneScene> {
        let lambertian = |s: &Surface| {
            s.lit
                && s.openpbr.is_none()
                && s.specular == Vec3::ZERO
                && s.reflection == Vec3::ZERO
                && s.transmission == Vec3::ZERO
                && !s.fresnel
                && s.absorption == Vec3::ZERO
                && s.alpha_map.is_none()
                && s.normal_map.is_none()
        };
        if !surfaces.iter().all(lambertian) || super::Environment::of(scene).is_some() {
            return None;
        }
        let meshes = scene.lights.iter().map(|light| {
            let LightKind::Mesh { shapes, cdf, area } = &light.kind else {
                return None;
            };
            let triangles = shapes
                .iter()
                .map(|&shape| light.mesh_triangle(scene, surfaces, shape))
                .collect::<Option<Vec<_>>>()?;
            (!triangles.is_empty()).then(|| MeshLight::new(*area, cdf.clone(), triangles))
        });
        let flat = scene
            .meshes
            .iter()
            .chain(scene.objects.iter().flat_map(|o| &o.meshes))
            .all(|m| m.normal_indices.is_empty() && m.color_indices.is_empty());
        Some(LaneScene {
            lights: meshes.collect::<Option<_>>()?,
            flat,
            untextured: !surfaces.iter().any(Surface::reads_texture_coords),
            flat_hits: if flat {
                flat_hits(scene, surfaces)
            } else {
                Vec::new()
            },
        })
    }

    /// Radiance along each of `rays` (at most [`LANES`]), whose closest hits are
    /// `hits`, each drawing from its own sampler: [`Path::radiance`] of each.
    pub(super) fn radiance_lanes(
        &self,
        prepared: &LaneScene,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
        out: &mut [Vec3],
    ) {
        #[cfg(target_arch = "x86_64")]
        if SimdLevel::current() == SimdLevel::Avx2 {
            if crate::accel::simd::avx512_wanted() {
                // SAFETY: the processor runs AVX-512 F, VL, DQ and BW (and AVX2 and FMA).
                return unsafe {
                    self.radiance_lanes_avx512(prepared, rays, hits, samplers, count, out)
                };
            }
            // SAFETY: `current` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.radiance_lanes_avx2(prepared, rays, hits, samplers, count, out) };
        }
        self.radiance_lanes_in(prepared, rays, hits, samplers, count, out)
    }

    /// [`Path::radiance_lanes`] in sixteen-lane registers: the same operations.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
    unsafe fn radiance_lanes_avx512(
        &self,
        prepared: &LaneScene,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
        out: &mut [Vec3],
    ) {
        self.radiance_lanes_in(prepared, rays, hits, samplers, count, out)
    }

    /// [`Path::radiance_lanes`] in eight-lane registers: the same operations.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn radiance_lanes_avx2(
        &self,
        prepared: &LaneScene,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
        out: &mut [Vec3],
    ) {
        self.radiance_lanes_in(prepared, rays, hits, samplers, count, out)
    }

    #[inline(always)]
    fn radiance_lanes_in(
        &self,
        prepared: &LaneScene,
        rays: &[Ray],
        hits: &[Option<Hit>],
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
        out: &mut [Vec3],
    ) {
        debug_assert!(self.weighing == Weighing::PowerHeuristic);
        let n = rays.len();
        debug_assert!(n <= LANES && hits.len() == n && samplers.len() == n);
        let mut origin = V3::ZERO;
        let mut dir = V3::ZERO;
        for (i, ray) in rays.iter().enumerate() {
            origin.set(i, ray.origin);
            dir.set(i, ray.dir);
        }
        let mut beta = V3::splat(1.0);
        let mut l = V3::ZERO;
        // Where each path last scattered and the density of its direction (every
        // scattering here is diffuse: it has one from the first bounce on).
        let mut last_p = V3::ZERO;
        let mut last_pdf = [0.0f32; LANES];
        let mut alive: u32 = if n == LANES {
            u32::MAX >> (32 - LANES)
        } else {
            (1 << n) - 1
        };
        let mut depth = 0;
        // Each vertex's point, normals (on the side the path arrives from), the
        // direction back and the surface's reflectance.
        let mut p = V3::ZERO;
        let mut ng = V3::ZERO;
        let mut ns = V3::ZERO;
        let mut wo = V3::ZERO;
        let mut diffuse = V3::ZERO;
        let mut from = V3::ZERO;
        let mut lane_hits = LaneHits::NONE;
        for (i, hit) in hits.iter().enumerate() {
            lane_hits.set(i, *hit);
        }
        while alive != 0 {
            if depth > 0 {
                // The hits of the paths still going, together.
                let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); LANES];
                let mut at = [0; LANES];
                let mut m = 0;
                for i in each(alive) {
                    rays[m] = Ray {
                        origin: origin.get(i),
                        dir: dir.get(i),
                    };
                    at[m] = i;
                    m += 1;
                }
                let mut found = [None; LANES];
                self.accel
                    .closest_many(&rays[..m], f32::INFINITY, &mut found[..m]);
                for k in 0..m {
                    lane_hits.set(at[k], found[k]);
                }
            }
            count.rays += u64::from(alive.count_ones());
            // A path that meets nothing ends.
            alive &= lane_hits.met();
            // The surfaces at the hits on plain flat shapes, all at once...
            let plain = lane_hits.plain(alive, &prepared.flat_hits);
            if plain != 0 {
                // The rows one lane at a time, then the arithmetic in vector lanes.
                let mut row_ng = V3::ZERO;
                let mut row_diffuse = V3::ZERO;
                for i in each(plain) {
                    let row = &prepared.flat_hits[lane_hits.shape[i] as usize];
                    row_ng.put(i, row.ng);
                    row_diffuse.put(i, row.diffuse);
                }
                for i in 0..LANES {
                    let on = plain >> i & 1 == 1;
                    let (o, d, t) = (origin.at(i), dir.at(i), lane_hits.t[i]);
                    let ng_in = row_ng.at(i);
                    let g = if dot(d, ng_in) < 0.0 {
                        ng_in
                    } else {
                        ng_in.map(|c| -c)
                    };
                    let at = [o[0] + d[0] * t, o[1] + d[1] * t, o[2] + d[2] * t];
                    let keep = |v: [f32; 3], mine: [f32; 3]| if on { mine } else { v };
                    diffuse.put(i, keep(diffuse.at(i), row_diffuse.at(i)));
                    p.put(i, keep(p.at(i), at));
                    ng.put(i, keep(ng.at(i), g));
                    ns.put(i, keep(ns.at(i), g));
                    wo.put(i, keep(wo.at(i), d.map(|c| -c)));
                    from.put(i, keep(from.at(i), at));
                }
            }
            // ...and the others one path at a time.
            for i in each(alive & !plain) {
                let ray = Ray {
                    origin: origin.get(i),
                    dir: dir.get(i),
                };
                let at = self.surface_lane(prepared, &ray, lane_hits.get(i), depth, last_p.get(i));
                if let Some((le, pdf)) = at.emitted {
                    let w = pdf.map_or(1.0, |pdf| power_heuristic(last_pdf[i], pdf));
                    l.set(i, l.get(i) + beta.get(i) * le * w);
                }
                diffuse.set(i, at.diffuse);
                p.set(i, at.p);
                ng.set(i, at.ng);
                ns.set(i, at.ns);
                wo.set(i, -ray.dir);
                from.set(i, at.from);
            }
            if alive == 0 {
                break;
            }
            let bsdf = Lambert::new(&wo, &ns, &ng, &diffuse);
            let lit = alive & bsdf.smooth;
            if lit != 0 {
                let direct = self.direct_lanes(
                    prepared,
                    &bsdf,
                    lit,
                    &p,
                    &ng,
                    &from,
                    depth >= self.max_depth,
                    samplers,
                    count,
                );
                l.add_product_where(lit, &beta, &direct);
            }
            if depth >= self.max_depth {
                break;
            }
            // The next direction: one path's numbers at a time, then all together.
            let mut pick_u = [(0.0f32, 0.0f32); LANES];
            for i in each(alive) {
                let _pick = samplers[i].next_f32();
                pick_u[i] = samplers[i].next_2d();
            }
            let mut go_on = [false; LANES];
            for i in 0..LANES {
                let (x, y) = crate::math::concentric_disk(pick_u[i]);
                let z = (1.0 - x * x - y * y).max(0.0).sqrt();
                let (t, b, nn) = (bsdf.t.at(i), bsdf.b.at(i), bsdf.n.at(i));
                let wi = [0, 1, 2].map(|k| t[k] * x + b[k] * y + nn[k] * z);
                let (f, pdf, cos_i) = bsdf.eval_pdf(i, ng.at(i), wi);
                let k = cos_i / pdf;
                let weight = f.map(|c| c * k);
                go_on[i] = pdf > 0.0 && is_finite(weight);
                let bt = beta.at(i);
                beta.put(i, [bt[0] * weight[0], bt[1] * weight[1], bt[2] * weight[2]]);
                last_pdf[i] = pdf;
                let o = offset_origin(p.at(i), ng.at(i), wi);
                origin.put(i, o);
                let len = dot(wi, wi).sqrt();
                dir.put(i, wi.map(|c| c / len));
            }
            alive &= bsdf.smooth & lanes_where(|i| go_on[i]);
            last_p = p;
            depth += 1;
            let mut roulette = [0.0f32; LANES];
            if depth >= ROULETTE_DEPTH {
                for i in each(alive) {
                    roulette[i] = samplers[i].next_f32();
                }
            }
            for i in 0..LANES {
                let mut bt = beta.at(i);
                let mut kept = true;
                if depth >= ROULETTE_DEPTH {
                    let q = max_element(bt).min(MAX_CONTINUE);
                    // As the path at a time ends a path: when the number is at least `q`.
                    kept = roulette[i] < q || q.is_nan();
                    bt = bt.map(|c| c / q);
                    beta.put(i, bt);
                }
                go_on[i] = kept && is_finite(bt) && max_element(bt) > 0.0;
            }
            alive &= lanes_where(|i| go_on[i]);
        }
        for (i, o) in out.iter_mut().enumerate().take(n) {
            let v = l.get(i);
            *o = if v.is_finite() { v } else { Vec3::ZERO };
        }
    }

    /// [`Path::direct`] for the lanes in `lit`: light from every light, one sample
    /// each, weighed against the BSDF's own samples unless the vertex is the `last`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn direct_lanes(
        &self,
        prepared: &LaneScene,
        bsdf: &Lambert,
        lit: u32,
        p: &V3,
        ng: &V3,
        from: &V3,
        last: bool,
        samplers: &mut [PixelSampler],
        count: &mut RayCount,
    ) -> V3 {
        let mut sum = V3::ZERO;
        for light in &prepared.lights {
            let area = light.area;
            // The light's points, one path at a time.
            let mut y = V3::ZERO;
            let mut normal = V3::ZERO;
            let mut le = V3::ZERO;
            if light.few {
                let (mut a, mut b) = ([0.0f32; LANES], [0.0f32; LANES]);
                for i in each(lit) {
                    (a[i], b[i]) = samplers[i].next_2d();
                }
                light.points(&a, &b, &mut y, &mut normal, &mut le);
            } else {
                for i in each(lit) {
                    let (a, b) = samplers[i].next_2d();
                    let (k, su) = pick_triangle(&light.cdf, light.triangles.len(), a);
                    let tri = &light.triangles[k];
                    y.set(i, triangle_point(tri.v, su, b));
                    normal.set(i, tri.normal);
                    le.set(i, tri.le);
                }
            }
            // Their densities, values and weights, all at once.
            let mut contribution = V3::ZERO;
            let mut ray_origin = V3::ZERO;
            let mut ray_dir = V3::ZERO;
            let mut t_max = [0.0f32; LANES];
            let mut traced = [false; LANES];
            for i in 0..LANES {
                let (pi, yi) = (p.at(i), y.at(i));
                let to = [yi[0] - pi[0], yi[1] - pi[1], yi[2] - pi[2]];
                let d2 = dot(to, to);
                let dist = d2.sqrt();
                let dir = to.map(|c| c / dist);
                let cos_l = -dot(normal.at(i), dir);
                let pdf = d2 / (cos_l * area);
                // Bitwise `&`, not `&&`: no branch, so the loop stays in vector registers.
                let sampled = (d2 > 0.0) & d2.is_finite() & (cos_l > 0.0) & pdf.is_finite();
                let (f, bsdf_pdf, cos) = bsdf.eval_pdf(i, ng.at(i), dir);
                let li = le.at(i);
                let fl = [f[0] * li[0], f[1] * li[1], f[2] * li[2]];
                let w = if last {
                    1.0
                } else {
                    power_heuristic_selected(pdf, bsdf_pdf)
                };
                let k = if pdf > 0.0 { cos * w / pdf } else { cos };
                let c = fl.map(|v| v * k);
                let some = |v: [f32; 3]| (v[0] != 0.0) | (v[1] != 0.0) | (v[2] != 0.0);
                let nonzero = some(f) & some(li);
                // A NaN is traced, as the path at a time traces it.
                let brightest = max_element(c);
                traced[i] = sampled & nonzero & ((brightest > 0.0) | brightest.is_nan());
                contribution.put(i, c);
                let o = offset_origin(from.at(i), ng.at(i), dir);
                ray_origin.put(i, o);
                ray_dir.put(i, dir);
                // Stop short of the light itself: an emissive mesh is geometry too.
                t_max[i] = dist * (1.0 - 1e-4) - surface_epsilon(o);
            }
            // The shadow rays, each walking the tree on its own past a root tested
            // against them all at once: in a scene of a few shapes too, where most
            // reach the light, meeting every shape cost more than walking the tree.
            let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); LANES];
            let mut limits = [0.0f32; LANES];
            let mut at = [0; LANES];
            let mut m = 0;
            for i in each(lit & lanes_where(|i| traced[i])) {
                count.rays += 1;
                rays[m] = Ray {
                    origin: ray_origin.get(i),
                    dir: ray_dir.get(i),
                };
                limits[m] = t_max[i];
                at[m] = i;
                m += 1;
            }
            // A limit that is NaN or not positive is met by nothing: the light is seen.
            let blocked = self.accel.occluded_many(&rays[..m], &limits[..m]);
            let mut seen = 0;
            for (k, &i) in at.iter().enumerate().take(m) {
                seen |= u32::from(blocked >> k & 1 == 0) << i;
            }
            sum.add_where(seen, &contribution);
        }
        sum
    }
}
