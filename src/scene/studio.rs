//! The neutral studio a model that brings no light is shown in, as glTF viewers show
//! such models: a soft grey room, lighter overhead than underfoot, with a large key
//! softbox above and behind the camera's left shoulder and a weaker fill to its right.
//! Rough surfaces take their shading from it in the path model; metals and glass
//! reflect its boxes in every model, where a uniform grey gave them nothing to show.
//!
//! The image is computed, not read: a 512 × 256 equirectangular map in the camera's
//! frame (its centre column along the camera's horizontal view, its top along the
//! scene's up), from additions, multiplications and square roots alone, so every
//! machine makes the same texels.

use super::image::{ImageTexture, Texels};
use crate::math::{Vec3, cross, normalize, sin_cos};

/// Width of the studio's equirectangular image; the height is half of it.
pub const STUDIO_WIDTH: u32 = 512;

/// A softbox: a rectangle of constant radiance seen about `center`, `half_width` and
/// `half_height` the tangents of its half-angles, its edges softened over a tenth of
/// its size.
struct Softbox {
    center: Vec3,
    half_width: f32,
    half_height: f32,
    radiance: f32,
}

impl Softbox {
    /// Its radiance along `d` (unit, in the studio's frame: x right, y up, z forward).
    fn radiance(&self, d: Vec3) -> f32 {
        let facing = d.dot(self.center);
        if facing <= 0.0 {
            return 0.0;
        }
        // The box's plane, one unit along its centre; its rows horizontal.
        let side = normalize(cross(Vec3::Y, self.center));
        let rise = cross(self.center, side);
        let (s, t) = (d.dot(side) / facing, d.dot(rise) / facing);
        let edge = |x: f32, half: f32| smooth_inside(x.abs(), half, 0.1 * half);
        self.radiance * edge(s, self.half_width) * edge(t, self.half_height)
    }
}

/// 1 well inside `half`, 0 beyond `half + soft`, a smoothstep between.
fn smooth_inside(x: f32, half: f32, soft: f32) -> f32 {
    let k = ((half + soft - x) / (2.0 * soft)).clamp(0.0, 1.0);
    k * k * (3.0 - 2.0 * k)
}

/// The studio's radiance along `d` (unit; x right, y up, z forward).
pub fn studio_radiance(d: Vec3) -> Vec3 {
    // The room: 0.2 at the horizon rising to 0.4 overhead, a 0.08 floor, blended
    // over a few degrees so the horizon shows no seam in a mirror.
    let blend = smooth_inside(-d.y, 0.0, 0.05);
    let room = 0.08 + (0.12 + 0.2 * d.y.max(0.0)) * blend;
    let key = Softbox {
        center: normalize(Vec3::new(-1.0, 1.2, -0.6)),
        half_width: 0.45,
        half_height: 0.3,
        radiance: 5.0,
    };
    let fill = Softbox {
        center: normalize(Vec3::new(1.0, 0.2, -0.8)),
        half_width: 0.35,
        half_height: 0.35,
        radiance: 1.5,
    };
    Vec3::splat(room + key.radiance(d) + fill.radiance(d))
}

/// The studio as an equirectangular image: column `x` looks at azimuth
/// `(x + 0.5) / width` of a turn from behind, through the centre (forward), row `y`
/// at elevation from +90° at the top to -90° at the bottom.
pub fn studio_image() -> ImageTexture {
    let (w, h) = (STUDIO_WIDTH, STUDIO_WIDTH / 2);
    let mut texels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let elevation = (0.5 - (y as f32 + 0.5) / h as f32) * std::f32::consts::PI;
        let (up, around) = sin_cos(elevation);
        for x in 0..w {
            let azimuth = ((x as f32 + 0.5) / w as f32 - 0.5) * std::f32::consts::TAU;
            let (right, forward) = sin_cos(azimuth);
            let c = studio_radiance(Vec3::new(right * around, up, forward * around));
            texels.push([c.x, c.y, c.z, 1.0]);
        }
    }
    ImageTexture {
        name: "the default studio".into(),
        width: w,
        height: h,
        texels: Texels::RgbaF32(texels),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// What a white Lambert surface facing `n` shows under the studio: its irradiance
    /// over pi, by the midpoint rule over the image's own directions.
    fn white_lambert(n: Vec3) -> f32 {
        let (w, h) = (STUDIO_WIDTH, STUDIO_WIDTH / 2);
        let mut sum = 0.0f64;
        for y in 0..h {
            let elevation = (0.5 - (y as f32 + 0.5) / h as f32) * PI;
            let (up, around) = elevation.sin_cos();
            // Each texel's solid angle: (2 pi / w) (pi / h) cos(elevation).
            let omega = (2.0 * PI / w as f32) * (PI / h as f32) * around;
            for x in 0..w {
                let azimuth = ((x as f32 + 0.5) / w as f32 - 0.5) * 2.0 * PI;
                let d = Vec3::new(azimuth.sin() * around, up, azimuth.cos() * around);
                let cos = d.dot(n).max(0.0);
                sum += f64::from(studio_radiance(d).x * cos * omega);
            }
        }
        (sum / f64::from(PI)) as f32
    }

    #[test]
    fn a_white_floor_and_a_face_toward_the_key_are_lit_like_a_studio() {
        let key = normalize(Vec3::new(-1.0, 1.2, -0.6));
        let toward_key = white_lambert(key);
        let floor = white_lambert(Vec3::Y);
        let away = white_lambert(-key);
        // A face toward the key shows about one, the floor somewhat less, a face
        // turned away a soft fill, never black.
        assert!((0.9..1.1).contains(&toward_key), "{toward_key}");
        assert!((0.6..0.9).contains(&floor), "{floor}");
        assert!((0.1..0.4).contains(&away), "{away}");
    }

    #[test]
    fn the_image_agrees_with_the_radiance_it_samples() {
        let image = studio_image();
        assert_eq!((image.width, image.height), (512, 256));
        // Straight up, the room's ceiling; straight down, the floor; the key's centre,
        // the key over the room.
        let ceiling = image.sample_direction(Vec3::Y, Vec3::Y, Vec3::Z);
        assert!((ceiling.x - 0.4).abs() < 1e-3, "{ceiling}");
        let floor = image.sample_direction(-Vec3::Y, Vec3::Y, Vec3::Z);
        assert!((floor.x - 0.08).abs() < 1e-6, "{floor}");
        let key = normalize(Vec3::new(-1.0, 1.2, -0.6));
        // sample_direction's right is forward x up: -x here, so the image is looked
        // up with the studio's x turned.
        let seen = image.sample_direction(Vec3::new(-key.x, key.y, key.z), Vec3::Y, Vec3::Z);
        assert!((seen.x - studio_radiance(key).x).abs() < 0.05, "{seen}");
    }
}
