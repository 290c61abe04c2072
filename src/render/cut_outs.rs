//! The first surface along a ray that its alpha map does not cut out: what every
//! physically based model (and every pass) shades.

use crate::accel::{Accel, Hit};
use crate::math::{Ray, offset_origin};
use crate::scene::{Scene, Surface, SurfacePoint};

/// Cut-outs a ray passes through before the next surface is taken as final: bounds the
/// work of a ray that meets a stack of leaves.
pub const MAX_CUT_OUTS: u32 = 64;

/// The first surface along `ray` not cut out, with its distance from the ray's origin
/// and its shading point; `closest` is the ray's closest hit where it is known (found
/// in a packet). `surfaces[m]` shades material `m`.
#[inline]
pub fn first_uncut(
    scene: &Scene,
    accel: &Accel,
    surfaces: &[Surface],
    ray: &Ray,
    closest: Option<Option<Hit>>,
) -> Option<(Hit, SurfacePoint)> {
    let mut r = *ray;
    let mut travelled = 0.0;
    let mut known = closest;
    for _ in 0..MAX_CUT_OUTS {
        let hit = match known.take() {
            Some(hit) => hit,
            None => accel.closest(&r, f32::INFINITY),
        }?;
        let s = &surfaces[scene.material_index(hit.id()) as usize];
        let uv = s.reads_texture_coords();
        let t = travelled + hit.t;
        if s.alpha_map.is_none() {
            // Made where it is returned: a shading point is two hundred bytes to copy.
            let sp = scene.surface_point(hit.id(), &r, hit.t, uv);
            return Some((Hit { t, ..hit }, sp));
        }
        let sp = scene.surface_point(hit.id(), &r, hit.t, uv);
        if !scene.cut_out(s, &sp) {
            return Some((Hit { t, ..hit }, sp));
        }
        travelled += hit.t;
        r.origin = offset_origin(sp.p, sp.ng, r.dir);
    }
    None
}
