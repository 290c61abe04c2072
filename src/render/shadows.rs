//! Shadow answers found ahead: the camera rays of a packet trace their hits' shadow rays
//! toward each light together, one packet per light, and shading then reads the answers
//! instead of tracing those rays one at a time.
//!
//! An answer is the one the shading model would have found for the same ray, so the
//! image does not change; a shadow ray nobody traced ahead is traced when it is needed.

use crate::accel::{Accel, PACKET_RAYS};
use crate::math::{Ray, Vec3, surface_epsilon};

/// Lights a camera hit holds answers for: the first this many of the scene.
pub const KNOWN_LIGHTS: usize = 32;

/// Whether the shadow ray of one camera hit toward light `j` is blocked, for the lights
/// traced ahead.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KnownShadows {
    known: u32,
    blocked: u32,
}

impl KnownShadows {
    /// Nothing known: every shadow ray is traced when it is needed.
    pub const NONE: KnownShadows = KnownShadows {
        known: 0,
        blocked: 0,
    };

    /// Whether the shadow ray toward light `light` is blocked, if it was traced ahead.
    #[inline]
    pub fn blocked(&self, light: usize) -> Option<bool> {
        (light < KNOWN_LIGHTS && self.known >> light & 1 == 1)
            .then(|| self.blocked >> light & 1 == 1)
    }

    fn set(&mut self, light: usize, blocked: bool) {
        self.known |= 1 << light;
        self.blocked |= u32::from(blocked) << light;
    }
}

/// For each of the first `lights` lights (at most [`KNOWN_LIGHTS`]), traces as one
/// packet the shadow rays `ray(i, light)` gives for hits `i < known.len()` (a ray and
/// the distance it must cover; `None` where the hit needs none or its model traces it
/// alone), and records each answer in `known[i]`.
pub fn trace_ahead(
    accel: &Accel,
    lights: usize,
    known: &mut [KnownShadows],
    ray: impl Fn(usize, usize) -> Option<(Ray, f32)>,
    blocks: impl Fn(u32) -> bool + Copy,
) {
    debug_assert!(known.len() <= PACKET_RAYS);
    let mut batch = [super::NO_RAY; PACKET_RAYS];
    let mut t_max = [0.0f32; PACKET_RAYS];
    let mut owner = [0usize; PACKET_RAYS];
    for light in 0..lights.min(KNOWN_LIGHTS) {
        let mut n = 0;
        for i in 0..known.len() {
            if let Some((r, t)) = ray(i, light) {
                batch[n] = r;
                t_max[n] = t;
                owner[n] = i;
                n += 1;
            }
        }
        if n == 0 {
            continue;
        }
        // The classic model's scenes hold no instances (a scene of them is flattened
        // for it), so every shape is the scene's own.
        let blocked = accel.occluded_packet(&batch[..n], &t_max[..n], |s| blocks(s.shape));
        for (k, &i) in owner[..n].iter().enumerate() {
            known[i].set(light, blocked >> k & 1 == 1);
        }
    }
}

/// The classic model's shadow ray of a point light at `light` for the point `p`, and
/// the distance it must cover: from the light toward `p`, stopping just short of it.
/// `None` when `p` is the light. Such rays toward nearby points share their origin,
/// which makes their packets tight.
#[inline]
pub fn from_light(light: Vec3, p: Vec3) -> Option<(Ray, f32)> {
    let to_point = p - light;
    let dist = to_point.length();
    if dist == 0.0 {
        return None;
    }
    let ray = Ray {
        origin: light,
        dir: to_point / dist,
    };
    Some((ray, dist - surface_epsilon(p)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vec3, normalize};
    use crate::scene::{Shape, Shapes, Sphere};

    /// A unit sphere 5 along +z.
    fn ball_ahead() -> Shapes {
        Shapes::from(vec![Shape::Sphere(Sphere {
            center: Vec3::new(0.0, 0.0, 5.0),
            radius: 1.0,
        })])
    }

    #[test]
    fn answers_are_those_of_single_rays_and_only_for_rays_traced() {
        let shapes = ball_ahead();
        let accel = Accel::build(crate::accel::AccelKind::Bvh, &shapes);
        // Rays from the origin fanning across the sphere: the middle ones are blocked
        // before t = 10 (light 0), none before t = 3 (light 1); ray 2 is not traced
        // toward light 1.
        let dir = |i: usize| normalize(Vec3::new(i as f32 * 0.1 - 0.3, 0.0, 1.0));
        let mut known = [KnownShadows::NONE; 7];
        trace_ahead(
            &accel,
            2,
            &mut known,
            |i, light| {
                (light == 0 || i != 2).then(|| {
                    let t = if light == 0 { 10.0 } else { 3.0 };
                    (Ray::new(Vec3::ZERO, dir(i)), t)
                })
            },
            |_| true,
        );
        for (i, k) in known.iter().enumerate() {
            let single = accel.occluded(&Ray::new(Vec3::ZERO, dir(i)), 10.0, |_| true);
            assert_eq!(k.blocked(0), Some(single), "ray {i}");
            assert_eq!(k.blocked(1), (i != 2).then_some(false), "ray {i}");
            assert_eq!(k.blocked(2), None);
        }
        assert_eq!(known[3].blocked(0), Some(true));
        assert_eq!(known[0].blocked(0), Some(false));
    }

    #[test]
    fn lights_past_the_first_thirty_two_are_left_to_be_traced_alone() {
        let shapes = ball_ahead();
        let accel = Accel::build(crate::accel::AccelKind::Bvh, &shapes);
        let mut known = [KnownShadows::NONE; 3];
        let asked = std::cell::Cell::new(0);
        trace_ahead(
            &accel,
            40,
            &mut known,
            |_, light| {
                asked.set(asked.get().max(light));
                Some((Ray::new(Vec3::ZERO, Vec3::Z), 10.0))
            },
            |_| true,
        );
        assert_eq!(asked.get(), KNOWN_LIGHTS - 1);
        for k in &known {
            assert_eq!(k.blocked(KNOWN_LIGHTS - 1), Some(true));
            assert_eq!(k.blocked(KNOWN_LIGHTS), None);
            assert_eq!(k.blocked(39), None);
        }
    }
}
