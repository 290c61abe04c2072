//! Coherent rays traced together: up to sixteen rays (a tile's camera rays, one pixel's
//! lens rays, shadow rays toward one light) walk the tree as one packet. A node is
//! fetched once for all of them. When the rays' directions share their signs, its eight
//! child boxes are tested once against the packet's frustum; otherwise each child box is
//! tested against every ray at once (the rays are the lanes). A child is entered when
//! any ray may still need it.
//!
//! Each ray's answer is the one [`Bvh::closest`] / [`Bvh::occluded`] gives it, bit for
//! bit: a lane repeats the single-ray shape test operation for operation, and ties go to
//! the lower index, so the order shapes are met in does not matter.

use super::leaf4::{Flat, Prim};
use super::{BOX_SLACK, Bvh, Node8, STORED, Stack, WIDTH, inverse};
use crate::accel::Hit;
#[cfg(target_arch = "x86_64")]
use crate::accel::simd::SimdLevel;
use crate::math::Ray;
use crate::scene::Sphere;
use crate::scene::shape::EDGE_SLACK;

/// Runs `$body` with each shape of the leaf `$entry` as `$shape` (its index) and
/// `$prim`, whether the leaf lists indices or holds copies. A macro, not a closure:
/// the body must be compiled into the caller, with the caller's instruction set.
macro_rules! for_each_shape {
    ($bvh:ident, $entry:expr, |$shape:ident, $prim:ident| $body:block) => {{
        let first = $entry.child as usize;
        if $entry.count & STORED != 0 {
            let n = ($entry.count & !STORED) as usize;
            for leaf in &$bvh.stored[first..first + n] {
                for lane in 0..4 {
                    if let Some($prim) = leaf.prim(lane) {
                        let $shape = leaf.shape(lane);
                        $body
                    }
                }
            }
        } else {
            for &$shape in &$bvh.prims[first..first + $entry.count as usize] {
                let $prim = Prim::of($bvh.shapes, $shape);
                $body
            }
        }
    }};
}

/// A lane's answer as the sign of a 32-bit lane, for [`lane_bits`].
#[inline(always)]
pub(super) fn lane_flag(hit: bool) -> u32 {
    0u32.wrapping_sub(u32::from(hit))
}

/// Bit `i` set for each lane `i` flagged by [`lane_flag`]: one `movmskps` per four
/// lanes, where shifting and or-ing the lanes one by one compiled to a reduction of
/// shifted vectors.
#[inline(always)]
fn lane_bits<const N: usize>(flags: &[u32; N]) -> u32 {
    const { assert!(N.is_multiple_of(4) && N <= 32) };
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_castsi128_ps, _mm_loadu_si128, _mm_movemask_ps};
        let mut bits = 0;
        for (q, four) in flags.chunks_exact(4).enumerate() {
            // SAFETY: SSE2 is part of x86-64; `four` is four u32s, read unaligned.
            let m =
                unsafe { _mm_movemask_ps(_mm_castsi128_ps(_mm_loadu_si128(four.as_ptr().cast()))) };
            bits |= (m as u32) << (4 * q);
        }
        bits
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        flags
            .iter()
            .enumerate()
            .fold(0, |bits, (i, &f)| bits | (f >> 31) << i)
    }
}

/// Rays in a packet.
pub const PACKET_RAYS: usize = 16;

type Lanes = [f32; PACKET_RAYS];

/// The rays as structure of arrays, in `N` lanes (a packet's sixteen unless said).
/// Lanes past the rays copy the first ray and are never active.
pub(super) struct Rays<const N: usize = PACKET_RAYS> {
    origin: [[f32; N]; 3],
    dir: [[f32; N]; 3],
    inv_dir: [[f32; N]; 3],
}

impl<const N: usize> Rays<N> {
    #[inline(always)]
    pub(super) fn new(rays: &[Ray]) -> Rays<N> {
        let mut r = Rays {
            origin: [[0.0; N]; 3],
            dir: [[0.0; N]; 3],
            inv_dir: [[0.0; N]; 3],
        };
        for i in 0..N {
            let ray = rays.get(i).unwrap_or(&rays[0]);
            for axis in 0..3 {
                r.origin[axis][i] = ray.origin[axis];
                r.dir[axis][i] = ray.dir[axis];
                r.inv_dir[axis][i] = inverse(ray.dir[axis]);
            }
        }
        r
    }

    /// The rays' origins and directions, axis by axis.
    pub(super) fn axes(&self) -> (&[[f32; N]; 3], &[[f32; N]; 3]) {
        (&self.origin, &self.dir)
    }

    /// Rays (bit `i` for ray `i`) that enter child `lane` of `node` before their bound,
    /// and the smallest entry distance among them. The slab test of [`super::Boxes4`],
    /// with the rays in the lanes instead of the boxes.
    #[inline(always)]
    pub(super) fn enter(&self, node: &Node8, lane: usize, bound: &[f32; N]) -> (u32, f32) {
        let (h, l) = (lane / 4, lane % 4);
        let lo = [node.min[0][h][l], node.min[1][h][l], node.min[2][h][l]];
        let hi = [node.max[0][h][l], node.max[1][h][l], node.max[2][h][l]];
        let (hits, t_near) = self.slab(lo, hi, bound);
        let mut first = f32::INFINITY;
        for i in 0..N {
            let hit = hits[i] != 0;
            first = if hit && t_near[i] < first {
                t_near[i]
            } else {
                first
            };
        }
        (lane_bits(&hits), first)
    }

    /// Whether any ray enters the box from `lo` to `hi` before its bound: [`Rays::enter`]
    /// for a box of its own.
    #[inline(always)]
    pub(super) fn enter_any(&self, lo: [f32; 3], hi: [f32; 3], bound: &[f32; N]) -> bool {
        let (hits, _) = self.slab(lo, hi, bound);
        hits.iter().fold(0, |any, &h| any | h) != 0
    }

    /// The slab test of every ray against one box: each ray's answer in its lane, as
    /// [`lane_flag`] gives it, and its entry distance.
    #[inline(always)]
    fn slab(&self, lo: [f32; 3], hi: [f32; 3], bound: &[f32; N]) -> ([u32; N], [f32; N]) {
        let mut t_near = [0.0f32; N];
        let mut t_far = *bound;
        for axis in 0..3 {
            for i in 0..N {
                let a = (lo[axis] - self.origin[axis][i]) * self.inv_dir[axis][i];
                let b = (hi[axis] - self.origin[axis][i]) * self.inv_dir[axis][i];
                // The near plane by the direction's sign, as the single-ray test reads
                // it, so an empty (inverted) box is missed.
                let (near, far) = if self.inv_dir[axis][i] < 0.0 {
                    (b, a)
                } else {
                    (a, b)
                };
                t_near[i] = if near > t_near[i] { near } else { t_near[i] };
                t_far[i] = if far < t_far[i] { far } else { t_far[i] };
            }
        }
        let mut hits = [0u32; N];
        for i in 0..N {
            hits[i] = lane_flag(t_near[i] <= t_far[i] * BOX_SLACK);
        }
        (hits, t_near)
    }

    /// Rays that meet the triangle or rectangle `f` before their bound, with the
    /// distances: [`super::leaf4::Leaf4::intersect_flat`] with rays for lanes.
    #[inline(always)]
    pub(super) fn meet(&self, f: &Flat, bound: &[f32; N]) -> (u32, [f32; N]) {
        let (met, t) = self.meet_each(f, bound);
        (lane_bits(&met), t)
    }

    /// [`Rays::meet`] with each ray's answer in its own lane, as [`lane_flag`] gives it.
    #[inline(always)]
    pub(super) fn meet_each(&self, f: &Flat, bound: &[f32; N]) -> ([u32; N], [f32; N]) {
        let [dx, dy, dz] = &self.dir;
        let [e1x, e1y, e1z] = f.e1;
        let [e2x, e2y, e2z] = f.e2;
        let mut t = [0.0f32; N];
        let mut hits = [0u32; N];
        let lo = -EDGE_SLACK;
        let hi = 1.0 + EDGE_SLACK;
        let max_sum = f.max_sum + EDGE_SLACK;
        for i in 0..N {
            let px = dy[i] * e2z - dz[i] * e2y;
            let py = dz[i] * e2x - dx[i] * e2z;
            let pz = dx[i] * e2y - dy[i] * e2x;
            let det = e1x * px + e1y * py + e1z * pz;
            let inv_det = 1.0 / det;
            let tx = self.origin[0][i] - f.p[0];
            let ty = self.origin[1][i] - f.p[1];
            let tz = self.origin[2][i] - f.p[2];
            let u = (tx * px + ty * py + tz * pz) * inv_det;
            let qx = ty * e1z - tz * e1y;
            let qy = tz * e1x - tx * e1z;
            let qz = tx * e1y - ty * e1x;
            let v = (dx[i] * qx + dy[i] * qy + dz[i] * qz) * inv_det;
            t[i] = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
            let finite = det.is_finite() & (det != 0.0);
            let inside = (u >= lo) & (u <= hi) & (v >= lo) & (v <= hi) & (u + v <= max_sum);
            let in_range = (t[i] > 0.0) & (t[i] < bound[i]);
            hits[i] = lane_flag(finite & inside & in_range);
        }
        (hits, t)
    }

    /// Rays that meet `sphere` before their bound, with the distances:
    /// [`Sphere::intersect`] with rays for lanes, operation for operation, its branches
    /// turned into selects so the loop runs on vector lanes.
    #[inline(always)]
    fn meet_sphere(&self, sphere: &Sphere, bound: &[f32; N]) -> (u32, [f32; N]) {
        let [dx, dy, dz] = &self.dir;
        let c = sphere.center;
        let r2 = sphere.radius * sphere.radius;
        let mut t = [0.0f32; N];
        let mut hits = [0u32; N];
        for i in 0..N {
            let ox = self.origin[0][i] - c.x;
            let oy = self.origin[1][i] - c.y;
            let oz = self.origin[2][i] - c.z;
            let b = ox * dx[i] + oy * dy[i] + oz * dz[i];
            let (px, py, pz) = (ox - b * dx[i], oy - b * dy[i], oz - b * dz[i]);
            let disc = r2 - (px * px + py * py + pz * pz);
            let c = (ox * ox + oy * oy + oz * oz) - r2;
            let sign = if b.is_sign_negative() { -1.0f32 } else { 1.0 };
            let q = -b - sign * disc.sqrt();
            let a = c / q;
            let (t0, t1) = if q == 0.0 {
                (0.0, 0.0)
            } else if a < q {
                (a, q)
            } else {
                (q, a)
            };
            let first = (t0 > 0.0) & (t0 < bound[i]);
            let second = (t1 > 0.0) & (t1 < bound[i]);
            t[i] = if first { t0 } else { t1 };
            // A NaN discriminant, which the scalar test lets through, gives NaN roots
            // and no hit there either.
            hits[i] = lane_flag((disc >= 0.0) & (first | second));
        }
        (lane_bits(&hits), t)
    }
}

/// Bounds over a packet's rays whose directions share their signs on every axis: the
/// range of their inverse directions, and per axis the origin bound each slab plane
/// needs. A node's eight boxes are tested once against these instead of once per ray.
///
/// The test is conservative: rounding is monotone, so with the direction positive on an
/// axis every ray's `(near - o) * inv` is at least `(near - o_max) * inv`, which lies
/// between that difference times the smallest and the largest inverse (and its far
/// plane's at most `(far - o_min) * inv`, likewise); with the direction negative the
/// origin bounds swap. A box some ray enters is never culled (it may be entered for
/// none, which only costs time). Leaves still test each ray exactly, so the answers are
/// the single-ray ones.
struct Frustum {
    /// The origin bound the near plane is measured from: the largest origin where the
    /// direction is positive, the smallest where it is negative.
    o_near: [f32; 3],
    /// The other bound, for the far plane.
    o_far: [f32; 3],
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
    negative: [bool; 3],
}

/// The smaller of two numbers, as one `minps`: `f32::min` spends two more instructions
/// on NaN. The frustum's origins and inverses are finite and its inverses nonzero; a
/// NaN product would only leave a box entered, and a NaN bound (a closest-hit packet's
/// NaN `t_max`, in every lane) meets nothing, as a single ray's does.
#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// The larger of two numbers, as one `maxps` (see [`min`]).
#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// The largest of a packet's bounds, halving the lanes each step rather than folding
/// them one after another.
#[inline(always)]
fn widest_of(bound: &Lanes) -> f32 {
    let mut m = *bound;
    let mut half = PACKET_RAYS / 2;
    while half > 0 {
        for i in 0..half {
            m[i] = max(m[i], m[i + half]);
        }
        half /= 2;
    }
    m[0]
}

/// The lanes' bounds for shadow rays limited by `t_max`: a NaN limit is met by
/// nothing, as for a single ray, and lanes without a ray meet nothing either; as -inf
/// neither can lower or poison a packet's widest bound.
#[inline(always)]
pub(super) fn shadow_bounds(t_max: &[f32]) -> Lanes {
    let mut bound = [f32::NEG_INFINITY; PACKET_RAYS];
    for (b, &t) in bound.iter_mut().zip(t_max) {
        *b = if t.is_nan() { f32::NEG_INFINITY } else { t };
    }
    bound
}

impl Frustum {
    /// The frustum of the first `n` rays, or `None` when a direction changes sign
    /// across them on some axis (the range of inverses would span infinity), a value
    /// is not finite or an inverse is zero (an infinite direction, where a product with
    /// an infinite plane would be NaN).
    #[inline(always)]
    fn of(rays: &Rays, n: usize) -> Option<Frustum> {
        let mut f = Frustum {
            o_near: [0.0; 3],
            o_far: [0.0; 3],
            inv_lo: [f32::INFINITY; 3],
            inv_hi: [f32::NEG_INFINITY; 3],
            negative: [false; 3],
        };
        for axis in 0..3 {
            let negative = rays.dir[axis][0].is_sign_negative();
            let (mut o_lo, mut o_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for i in 0..n {
                let (o, inv) = (rays.origin[axis][i], rays.inv_dir[axis][i]);
                if rays.dir[axis][i].is_sign_negative() != negative
                    || !o.is_finite()
                    || !inv.is_finite()
                    || inv == 0.0
                {
                    return None;
                }
                o_lo = min(o_lo, o);
                o_hi = max(o_hi, o);
                f.inv_lo[axis] = min(f.inv_lo[axis], inv);
                f.inv_hi[axis] = max(f.inv_hi[axis], inv);
            }
            (f.o_near[axis], f.o_far[axis]) = if negative { (o_lo, o_hi) } else { (o_hi, o_lo) };
            f.negative[axis] = negative;
        }
        Some(f)
    }

    /// Children of `node` (bit `i` for child `i`) some ray may enter before `bound`,
    /// and a lower bound of every ray's entry distance into each.
    #[inline(always)]
    fn enter(&self, node: &Node8, bound: f32) -> (u32, [f32; WIDTH]) {
        let row = |v: &[glam::Vec4; 2]| {
            let (a, b) = (v[0].to_array(), v[1].to_array());
            [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
        };
        // Each axis's entry and exit, then reduced as trees rather than chains: two
        // steps from the planes to the test.
        let mut lo = [[0.0f32; WIDTH]; 3];
        let mut hi = [[0.0f32; WIDTH]; 3];
        for axis in 0..3 {
            let (near, far) = if self.negative[axis] {
                (row(&node.max[axis]), row(&node.min[axis]))
            } else {
                (row(&node.min[axis]), row(&node.max[axis]))
            };
            let (o_near, o_far) = (self.o_near[axis], self.o_far[axis]);
            let (i_lo, i_hi) = (self.inv_lo[axis], self.inv_hi[axis]);
            for lane in 0..WIDTH {
                let a = near[lane] - o_near;
                lo[axis][lane] = min(a * i_lo, a * i_hi);
                let c = far[lane] - o_far;
                hi[axis][lane] = max(c * i_lo, c * i_hi);
            }
        }
        let mut t_near = [0.0f32; WIDTH];
        let mut hits = [0u32; WIDTH];
        for lane in 0..WIDTH {
            t_near[lane] = max(max(lo[0][lane], lo[1][lane]), max(lo[2][lane], 0.0));
            let t_far = min(min(hi[0][lane], hi[1][lane]), min(hi[2][lane], bound));
            hits[lane] = lane_flag(t_near[lane] <= t_far * BOX_SLACK);
        }
        (lane_bits(&hits), t_near)
    }
}

impl Bvh<'_> {
    /// The closest hit of each of up to [`PACKET_RAYS`] rays with `0 < t < t_max`, into
    /// `hits[i]`: what [`Bvh::closest`] gives each ray, found faster when the rays run
    /// close together.
    pub fn closest_packet(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        assert!(rays.len() <= PACKET_RAYS && hits.len() == rays.len());
        if rays.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.closest_packet_avx2(rays, t_max, hits) };
        }
        self.closest_packet_in(rays, t_max, hits);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn closest_packet_avx2(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        self.closest_packet_in(rays, t_max, hits);
    }

    #[inline(always)]
    fn closest_packet_in(&self, rays: &[Ray], t_max: f32, hits: &mut [Option<Hit>]) {
        hits.fill(None);
        if self.shape_count == 0 {
            return;
        }
        let lanes = Rays::new(rays);
        let frustum = Frustum::of(&lanes, rays.len());
        let mut best: [Option<Hit>; PACKET_RAYS] = [None; PACKET_RAYS];
        // Each ray's bound: t_max, then just past its best hit so a tie is still seen.
        // Lanes without a ray get -inf, so no box or shape is ever entered for them.
        let mut bound = [f32::NEG_INFINITY; PACKET_RAYS];
        bound[..rays.len()].fill(t_max);
        // The largest bound, kept as the bounds fall: a box beyond it helps no ray.
        let mut widest = t_max;
        let mut stack = Stack::new(self.root);
        while let Some(entry) = stack.pop() {
            if entry.t > widest * BOX_SLACK {
                continue;
            }
            if entry.count > 0 {
                // The entry after this leaf is asked for now: the leaf's tests against
                // every ray take long enough to hide most of its wait.
                if let Some(next) = stack.peek() {
                    self.prefetch(next);
                }
                // Each arm updates the hits itself: one loop after a `match` that
                // returns the distances measured 7 % slower (they went through memory).
                for_each_shape!(self, entry, |shape, prim| {
                    match prim {
                        Prim::Flat(flat) => {
                            let (mut mask, t) = lanes.meet(&flat, &bound);
                            while mask != 0 {
                                let i = mask.trailing_zeros() as usize;
                                mask &= mask - 1;
                                if Hit::beats(t[i], shape, &best[i]) {
                                    best[i] = Some(Hit::world(t[i], shape));
                                    bound[i] = Hit::bound(&best[i], t_max);
                                }
                            }
                        }
                        Prim::Sphere(sphere) => {
                            let (mut mask, t) = lanes.meet_sphere(&sphere, &bound);
                            while mask != 0 {
                                let i = mask.trailing_zeros() as usize;
                                mask &= mask - 1;
                                if Hit::beats(t[i], shape, &best[i]) {
                                    best[i] = Some(Hit::world(t[i], shape));
                                    bound[i] = Hit::bound(&best[i], t_max);
                                }
                            }
                        }
                    }
                });
                widest = widest_of(&bound);
                continue;
            }
            let node = self.node(entry);
            if let Some(frustum) = &frustum {
                let (mask, t) = frustum.enter(node, widest);
                stack.push_children(node, mask, &t);
                continue;
            }
            let base = stack.len;
            for lane in 0..WIDTH {
                let (mask, t) = lanes.enter(node, lane, &bound);
                if mask != 0 {
                    stack.push_sorted(node.entry(lane, t), base);
                }
            }
        }
        hits.copy_from_slice(&best[..rays.len()]);
    }

    /// Whether each of up to [`PACKET_RAYS`] rays meets, with `0 < t < t_max[i]`, a
    /// shape for which `blocks(shape)` holds: [`Bvh::occluded`] for each ray.
    pub fn occluded_packet(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(u32) -> bool,
    ) -> u32 {
        assert!(rays.len() <= PACKET_RAYS && t_max.len() == rays.len());
        if rays.is_empty() {
            return 0;
        }
        #[cfg(target_arch = "x86_64")]
        if self.simd == SimdLevel::Avx2 {
            // SAFETY: `simd` is AVX2 only where the processor runs AVX2 and FMA.
            return unsafe { self.occluded_packet_avx2(rays, t_max, blocks) };
        }
        self.occluded_packet_in(rays, t_max, blocks)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn occluded_packet_avx2(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(u32) -> bool,
    ) -> u32 {
        self.occluded_packet_in(rays, t_max, blocks)
    }

    /// The mask of blocked rays (bit `i` for ray `i`).
    #[inline(always)]
    fn occluded_packet_in(&self, rays: &[Ray], t_max: &[f32], blocks: impl Fn(u32) -> bool) -> u32 {
        let lanes = Rays::new(rays);
        let all = (1u32 << rays.len()) - 1;
        // A packet whose rays all keep off the walls walks the tree without them.
        let tree = match &self.indoors {
            Some(indoors)
                if indoors.clear_lanes(&lanes.origin, &lanes.dir, &shadow_bounds(t_max)) & all
                    == all =>
            {
                indoors.tree()
            }
            _ => self,
        };
        tree.occluded_packet_walk(&lanes, rays, t_max, blocks)
    }

    /// [`Bvh::occluded_packet_in`] down this tree, the rays already in `lanes`.
    #[inline(always)]
    fn occluded_packet_walk(
        &self,
        lanes: &Rays,
        rays: &[Ray],
        t_max: &[f32],
        blocks: impl Fn(u32) -> bool,
    ) -> u32 {
        if self.shape_count == 0 {
            return 0;
        }
        let all = (1u32 << rays.len()) - 1;
        let frustum = Frustum::of(lanes, rays.len());
        let mut blocked = 0u32;
        // A blocked ray's bound drops to -inf: it needs nothing more.
        let mut bound = shadow_bounds(t_max);
        let mut widest = widest_of(&bound);
        let mut stack = Stack::new(self.root);
        while let Some(entry) = stack.pop() {
            if entry.count > 0 {
                if let Some(next) = stack.peek() {
                    self.prefetch(next);
                }
                for_each_shape!(self, entry, |shape, prim| {
                    let (mask, _) = match prim {
                        Prim::Flat(flat) => lanes.meet(&flat, &bound),
                        Prim::Sphere(sphere) => lanes.meet_sphere(&sphere, &bound),
                    };
                    let newly = if mask != 0 && blocks(shape) { mask } else { 0 };
                    if newly != 0 {
                        blocked |= newly;
                        if blocked == all {
                            return blocked;
                        }
                        for (i, b) in bound.iter_mut().enumerate() {
                            if newly >> i & 1 == 1 {
                                *b = f32::NEG_INFINITY;
                            }
                        }
                        widest = widest_of(&bound);
                    }
                });
                continue;
            }
            let node = self.node(entry);
            if let Some(frustum) = &frustum {
                let (mask, t) = frustum.enter(node, widest);
                stack.push_children(node, mask, &t);
                continue;
            }
            let base = stack.len;
            for lane in 0..WIDTH {
                let (mask, t) = lanes.enter(node, lane, &bound);
                if mask != 0 {
                    stack.push_sorted(node.entry(lane, t), base);
                }
            }
        }
        blocked
    }
}

#[cfg(test)]
mod tests;
