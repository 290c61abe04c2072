//! The slab test of one ray against a node's eight child boxes, on eight AVX2 lanes or
//! two halves of four on SSE2: which children the ray enters before its bound, and where.

use super::{BOX_SLACK, Node8, WIDTH};
use crate::math::Ray;
#[cfg(target_arch = "x86_64")]
use crate::math::Vec3;
use glam::Vec4;

/// The slab test of one ray against a node's eight boxes: lanes whose box the ray
/// enters before `t_max` (bit `i` for lane `i`), and the entry distances.
pub(super) trait BoxTest {
    fn hit(&self, node: &Node8, t_max: f32) -> (u32, [f32; WIDTH]);
}

/// Where the slab test measures each axis's near and far planes from: the origin, or
/// for boxes grown by `pad`, the origin moved by `pad` toward the far side (near plane)
/// and the near side (far plane) — the same as moving the planes out, at no cost.
#[inline(always)]
pub(super) fn slab_origins(ray: &Ray, pad: f32) -> ([f32; 3], [f32; 3]) {
    let o = ray.origin.to_array();
    let d = ray.dir.to_array();
    let toward = |i: usize| if d[i].is_sign_negative() { -pad } else { pad };
    (
        [0, 1, 2].map(|i| o[i] + toward(i)),
        [0, 1, 2].map(|i| o[i] - toward(i)),
    )
}

/// The reciprocal of a direction component. A zero gives a huge finite value rather
/// than infinity, so a plane through the origin gives 0 * big = 0, never 0 * inf = NaN.
#[inline(always)]
pub(super) fn inverse(x: f32) -> f32 {
    let i = 1.0 / x;
    if i.is_finite() {
        i
    } else {
        1e30f32.copysign(x)
    }
}

/// Four lanes at a time (SSE2, or whatever the target's baseline is). Each axis reads
/// its near plane from `min` or `max` by the sign of the direction, so an empty
/// (inverted) box is missed.
pub(super) struct Boxes4<const PADDED: bool = false> {
    near_origin: [Vec4; 3],
    far_origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    negative: [bool; 3],
}

impl<const PADDED: bool> Boxes4<PADDED> {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Boxes4<PADDED> {
        let o = ray.origin.to_array();
        let d = ray.dir.to_array();
        Boxes4 {
            near_origin: o.map(Vec4::splat),
            far_origin: o.map(Vec4::splat),
            inv_dir: d.map(|x| Vec4::splat(inverse(x))),
            negative: d.map(|x| x.is_sign_negative()),
        }
    }

    #[inline(always)]
    pub(super) fn padded(ray: &Ray, pad: f32) -> Boxes4<PADDED> {
        let (near, far) = slab_origins(ray, pad);
        Boxes4 {
            near_origin: near.map(Vec4::splat),
            far_origin: far.map(Vec4::splat),
            ..Boxes4::new(ray)
        }
    }
}

impl<const PADDED: bool> BoxTest for Boxes4<PADDED> {
    #[inline(always)]
    fn hit(&self, node: &Node8, t_max: f32) -> (u32, [f32; WIDTH]) {
        let mut mask = 0;
        let mut t = [0.0; WIDTH];
        for half in 0..2 {
            let mut t_near = Vec4::ZERO;
            let mut t_far = Vec4::splat(t_max);
            for axis in 0..3 {
                let (near, far) = if self.negative[axis] {
                    (node.max[axis][half], node.min[axis][half])
                } else {
                    (node.min[axis][half], node.max[axis][half])
                };
                t_near = t_near.max((near - self.near_origin[axis]) * self.inv_dir[axis]);
                // Unpadded boxes measure both planes from the one origin.
                let far_origin = if PADDED {
                    self.far_origin[axis]
                } else {
                    self.near_origin[axis]
                };
                t_far = t_far.min((far - far_origin) * self.inv_dir[axis]);
            }
            mask |= t_near.cmple(t_far * BOX_SLACK).bitmask() << (4 * half);
            t[4 * half..4 * half + 4].copy_from_slice(&t_near.to_array());
        }
        (mask, t)
    }
}

/// All eight lanes in one AVX2 register, each plane distance one fused multiply-add:
/// `plane * inv_dir - origin * inv_dir`, as Embree measures it. The product
/// `origin * inv_dir` is rounded once per ray, an error of up to half a unit in its
/// last place that no relative slack covers (it does not shrink with the distance), so
/// each axis moves its near planes nearer and its far planes farther by a few units in
/// the last place of that product. The far planes' distances come out already grown by
/// [`BOX_SLACK`] (their inverse direction and origin product scaled by it), which takes
/// a multiplication off the path from a node's load to its children. The box is never
/// culled where the subtracting test of [`Boxes4`] keeps it, and the hits, which only
/// the leaves decide, are the same. Only built inside functions compiled for AVX2 and
/// FMA (see [`Bvh::closest`]).
#[cfg(target_arch = "x86_64")]
pub(super) struct Boxes8 {
    /// Per axis, the byte offsets in a [`Node8`] of its near planes' row (the minima
    /// for a ray going up the axis, the maxima for one going down) and far planes' row.
    near_at: [usize; 3],
    far_at: [usize; 3],
    inv_dir: [std::arch::x86_64::__m256; 3],
    /// `inv_dir` grown by [`BOX_SLACK`], for the far planes.
    inv_dir_far: [std::arch::x86_64::__m256; 3],
    /// Where the near plane's distance is measured from, scaled: `origin * inv_dir`
    /// moved back by its rounding.
    near_scaled: [std::arch::x86_64::__m256; 3],
    /// The same for the far plane, with `inv_dir_far`, moved on by its rounding.
    far_scaled: [std::arch::x86_64::__m256; 3],
}

#[cfg(target_arch = "x86_64")]
impl Boxes8 {
    /// The test of `ray`; `None` where a product `origin * inv_dir` overflows (an
    /// origin beyond about 10^8 on an axis the ray does not move along), which the
    /// subtracting test of [`Boxes4`] takes instead.
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Option<Boxes8> {
        let o = ray.origin.to_array();
        Boxes8::with_origins(ray, o, o)
    }

    /// The test of boxes grown by `pad` on every side.
    #[inline(always)]
    pub(super) fn padded(ray: &Ray, pad: f32) -> Option<Boxes8> {
        let (near, far) = slab_origins(ray, pad);
        Boxes8::with_origins(ray, near, far)
    }

    #[inline(always)]
    pub(super) fn with_origins(ray: &Ray, near: [f32; 3], far: [f32; 3]) -> Option<Boxes8> {
        use std::arch::x86_64::_mm256_set1_ps;
        // The three axes at once, in one register each: the set-up is paid by every
        // ray, and a shadow ray through a small tree visits few nodes to repay it.
        let d = ray.dir;
        let inv = Vec3::ONE / d;
        // `inverse`: a zero component gives a huge finite value, not infinity.
        let inv = Vec3::select(inv.is_finite_mask(), inv, Vec3::splat(1e30).copysign(d));
        let inv_far = inv * BOX_SLACK;
        // The products rounded, then moved by units in their last place: four cover
        // the product's rounding and the plane's product's; eight on the far side
        // also cover the rounding of `inv_far`.
        let near_scaled = Vec3::from_array(near) * inv;
        let near_scaled = near_scaled + 4.0 * f32::EPSILON * near_scaled.abs();
        let far_scaled = Vec3::from_array(far) * inv_far;
        let far_scaled = far_scaled - 8.0 * f32::EPSILON * far_scaled.abs();
        if !(near_scaled.is_finite() && far_scaled.is_finite()) {
            return None;
        }
        let negative = d.is_negative_bitmask() as usize;
        let row = size_of::<[Vec4; 2]>();
        let max_row = std::mem::offset_of!(Node8, max);
        let (mut near_at, mut far_at) = ([0; 3], [0; 3]);
        for axis in 0..3 {
            let down = negative >> axis & 1;
            near_at[axis] = axis * row + down * max_row;
            far_at[axis] = axis * row + (1 - down) * max_row;
        }
        // SAFETY: reached only from AVX2 functions, on processors that run them. No
        // closures around the intrinsics: they would not inherit the caller's
        // instruction set.
        unsafe {
            Some(Boxes8 {
                near_at,
                far_at,
                inv_dir: [
                    _mm256_set1_ps(inv.x),
                    _mm256_set1_ps(inv.y),
                    _mm256_set1_ps(inv.z),
                ],
                inv_dir_far: [
                    _mm256_set1_ps(inv_far.x),
                    _mm256_set1_ps(inv_far.y),
                    _mm256_set1_ps(inv_far.z),
                ],
                near_scaled: [
                    _mm256_set1_ps(near_scaled.x),
                    _mm256_set1_ps(near_scaled.y),
                    _mm256_set1_ps(near_scaled.z),
                ],
                far_scaled: [
                    _mm256_set1_ps(far_scaled.x),
                    _mm256_set1_ps(far_scaled.y),
                    _mm256_set1_ps(far_scaled.z),
                ],
            })
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl BoxTest for Boxes8 {
    #[inline(always)]
    fn hit(&self, node: &Node8, t_max: f32) -> (u32, [f32; WIDTH]) {
        use std::arch::x86_64::*;
        let base = (node as *const Node8).cast::<u8>();
        // SAFETY: as in `new`. The offsets are those of the rows of a node, 32-byte
        // aligned in a 64-byte-aligned node.
        unsafe {
            let row = |at: usize| base.add(at).cast::<f32>();
            let n0 = _mm256_load_ps(row(self.near_at[0]));
            let n1 = _mm256_load_ps(row(self.near_at[1]));
            let n2 = _mm256_load_ps(row(self.near_at[2]));
            let f0 = _mm256_load_ps(row(self.far_at[0]));
            let f1 = _mm256_load_ps(row(self.far_at[1]));
            let f2 = _mm256_load_ps(row(self.far_at[2]));
            let n0 = _mm256_fmsub_ps(n0, self.inv_dir[0], self.near_scaled[0]);
            let n1 = _mm256_fmsub_ps(n1, self.inv_dir[1], self.near_scaled[1]);
            let n2 = _mm256_fmsub_ps(n2, self.inv_dir[2], self.near_scaled[2]);
            let f0 = _mm256_fmsub_ps(f0, self.inv_dir_far[0], self.far_scaled[0]);
            let f1 = _mm256_fmsub_ps(f1, self.inv_dir_far[1], self.far_scaled[1]);
            let f2 = _mm256_fmsub_ps(f2, self.inv_dir_far[2], self.far_scaled[2]);
            // Reduced as trees, not chains: two steps from the planes to the test.
            let t_near = _mm256_max_ps(
                _mm256_max_ps(n0, n1),
                _mm256_max_ps(n2, _mm256_setzero_ps()),
            );
            let bound = _mm256_set1_ps(t_max * BOX_SLACK);
            let t_far = _mm256_min_ps(_mm256_min_ps(f0, f1), _mm256_min_ps(f2, bound));
            let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32;
            let mut t = [0.0; WIDTH];
            _mm256_storeu_ps(t.as_mut_ptr(), t_near);
            (mask, t)
        }
    }
}
