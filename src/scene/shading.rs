//! What a surface looks like at a hit, for every physically based model: its albedo,
//! its maps, its normal map and alpha cut-out, and what escaping rays see.

use super::material::srgb_to_linear;
use super::{Albedo, Background, Scene, ShapeId, Surface, SurfacePoint, TextureSlot};
use crate::math::{Vec3, cross};

impl Scene {
    /// The colour of an optional map at the hit (white without one).
    #[inline]
    pub fn map(&self, slot: &Option<TextureSlot>, sp: &SurfacePoint) -> Vec3 {
        match slot {
            Some(slot) => {
                let c = self.images[slot.image as usize].sample_slot(slot, sp.uv);
                Vec3::new(c.x, c.y, c.z)
            }
            None => Vec3::ONE,
        }
    }

    /// The shading normal bent by a tangent-space normal map (texel `2 c - 1` in the
    /// frame of dP/du, N x dP/du and N). `sp.n` as it was where the surface has no
    /// tangent or the map would turn it past the geometric surface.
    pub fn normal_mapped(
        &self,
        sp: &SurfacePoint,
        shape: ShapeId,
        slot: &TextureSlot,
        scale: f32,
    ) -> Vec3 {
        let n = sp.n;
        let Some(dpdu) = self.dpdu(shape) else {
            return n;
        };
        let t = (dpdu - n * n.dot(dpdu)).normalize_or_zero();
        if t == Vec3::ZERO {
            return n;
        }
        let b = cross(n, t);
        let c = self.images[slot.image as usize].sample_slot(slot, sp.uv);
        let mut m = Vec3::new(c.x, c.y, c.z) * 2.0 - Vec3::ONE;
        if scale != 1.0 {
            m.x *= scale;
            m.y *= scale;
        }
        let bent = (t * m.x + b * m.y + n * m.z).normalize_or_zero();
        if bent.dot(sp.ng) > 0.0 { bent } else { n }
    }

    /// Whether `s`'s alpha map cuts the surface out at the hit: rays pass there.
    #[inline]
    pub fn cut_out(&self, s: &Surface, sp: &SurfacePoint) -> bool {
        let Some(slot) = &s.alpha_map else {
            return false;
        };
        self.images[slot.image as usize].sample_slot(slot, sp.uv).w < s.alpha_cutoff
    }

    /// The albedo C at a hit.
    pub fn albedo(&self, s: &Surface, sp: &SurfacePoint, shape: ShapeId) -> Vec3 {
        match &s.albedo {
            Albedo::Color(c) => *c,
            Albedo::Image { slot, tint } => {
                let c = self.images[slot.image as usize].sample_slot(slot, sp.uv);
                Vec3::new(c.x, c.y, c.z) * *tint
            }
            Albedo::Checker { a, b, scale } => {
                // Read just inside the surface: a plane lying on a cube face (a floor
                // at y = 0) would otherwise flip cells with the rounding of each hit.
                let scale = scale.max(f32::MIN_POSITIVE);
                let inside = sp.p - sp.ng * (scale * 1e-3);
                let q = (inside / scale).floor();
                let sum = q.x + q.y + q.z;
                // `sum` is a whole number (not a costly `rem_euclid` away from its
                // parity), and every float from 2^24 up is even.
                let even = if sum.abs() < 16_777_216.0 {
                    (sum as i32) & 1 == 0
                } else {
                    sum.is_finite()
                };
                if even { *a } else { *b }
            }
            Albedo::Classic => srgb_to_linear(self.surface_color_at(shape, sp.p)),
        }
    }

    /// The radiance a ray along `d` that escapes the scene sees.
    pub fn background(&self, d: Vec3) -> Vec3 {
        match &self.background {
            Background::Black => Vec3::ZERO,
            Background::Color(c) => *c,
            Background::Environment {
                image,
                up,
                forward,
                intensity,
            } => self.images[*image as usize].sample_direction(d, *up, *forward) * *intensity,
        }
    }
}
