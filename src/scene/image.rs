//! Images read at texture coordinates: bilinear filtering, repeat or clamp, 8-bit
//! texels decoded from sRGB (colour maps) or read as linear (alpha, normal maps), and
//! float texels (HDR environment maps) as they are.

use super::material::{TextureSlot, srgb_channel_to_linear};
use crate::math::{Vec3, cross};
use glam::Vec4;
use std::sync::LazyLock;

/// Texels of an image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// 8-bit RGBA; `srgb` says whether the colour channels are sRGB-encoded (alpha
    /// never is).
    Rgba8 {
        /// `width * height` texels, row-major.
        texels: Vec<[u8; 4]>,
        /// Whether R, G and B are sRGB-encoded (colour maps) rather than linear.
        srgb: bool,
    },
    /// Linear float RGBA.
    RgbaF32(Vec<[f32; 4]>),
}

/// A decoded image, read by image albedos, material maps and environment backgrounds.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    /// Where it came from, for messages and `prism info`.
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height` texels, row-major from the top row.
    pub texels: Texels,
}

/// sRGB byte to linear float, once for all 256 values.
static SRGB_TO_LINEAR: LazyLock<[f32; 256]> =
    LazyLock::new(|| std::array::from_fn(|i| srgb_channel_to_linear(i as f32 / 255.0)));

impl ImageTexture {
    /// The linear RGBA value of texel `(x, y)`.
    #[inline]
    pub fn texel(&self, x: u32, y: u32) -> Vec4 {
        let i = y as usize * self.width as usize + x as usize;
        match &self.texels {
            Texels::Rgba8 { texels, srgb } => {
                let t = texels[i];
                let a = f32::from(t[3]) / 255.0;
                if *srgb {
                    let lut = &*SRGB_TO_LINEAR;
                    Vec4::new(
                        lut[t[0] as usize],
                        lut[t[1] as usize],
                        lut[t[2] as usize],
                        a,
                    )
                } else {
                    Vec4::new(
                        f32::from(t[0]) / 255.0,
                        f32::from(t[1]) / 255.0,
                        f32::from(t[2]) / 255.0,
                        a,
                    )
                }
            }
            Texels::RgbaF32(texels) => Vec4::from_array(texels[i]),
        }
    }

    /// Bilinearly filtered value at `(u, v)`: u runs left to right, v bottom to top (as
    /// OBJ and PLY texture coordinates do); texel centres sit at half-integers.
    pub fn sample(&self, u: f32, v: f32, clamp: bool) -> Vec4 {
        self.sample_axes(u, v, clamp, clamp)
    }

    /// [`ImageTexture::sample`] with the edge rule chosen per axis.
    fn sample_axes(&self, u: f32, v: f32, clamp_x: bool, clamp_y: bool) -> Vec4 {
        let (w, h) = (self.width as f32, self.height as f32);
        let x = u * w - 0.5;
        let y = (1.0 - v) * h - 0.5;
        if !x.is_finite() || !y.is_finite() {
            return self.texel(0, 0);
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let ix = |i: f32| index(i, self.width, clamp_x);
        let iy = |i: f32| index(i, self.height, clamp_y);
        let (xa, xb, ya, yb) = (ix(x0), ix(x0 + 1.0), iy(y0), iy(y0 + 1.0));
        let top = self.texel(xa, ya).lerp(self.texel(xb, ya), fx);
        let bottom = self.texel(xa, yb).lerp(self.texel(xb, yb), fx);
        top.lerp(bottom, fy)
    }

    /// The value seen through a slot's transform.
    #[inline]
    pub fn sample_slot(&self, slot: &TextureSlot, uv: [f32; 2]) -> Vec4 {
        let (u, v) = match slot.matrix {
            None => (
                uv[0] * slot.scale[0] + slot.offset[0],
                uv[1] * slot.scale[1] + slot.offset[1],
            ),
            Some([[a, b], [c, d]]) => (
                a * uv[0] + b * uv[1] + slot.offset[0],
                c * uv[0] + d * uv[1] + slot.offset[1],
            ),
        };
        self.sample(u, v, slot.clamp)
    }

    /// Equirectangular lookup of direction `d` (unit), with `up` the image's vertical
    /// axis: the top row looks up, the centre column looks along `forward`.
    pub fn sample_direction(&self, d: Vec3, up: Vec3, forward: Vec3) -> Vec3 {
        let right = cross(forward, up);
        let y = d.dot(up).clamp(-1.0, 1.0);
        let phi = d.dot(right).atan2(d.dot(forward));
        let u = 0.5 + phi / std::f32::consts::TAU;
        let v = 0.5 + y.asin() / std::f32::consts::PI;
        // Around the horizon the image repeats; over the poles it does not.
        let c = self.sample_axes(u, v, false, true);
        Vec3::new(c.x, c.y, c.z)
    }
}

/// A texel index along an axis of `n` texels: repeated or clamped to the edge.
#[inline]
fn index(i: f32, n: u32, clamp: bool) -> u32 {
    let n_f = n as f32;
    if clamp {
        i.clamp(0.0, n_f - 1.0) as u32
    } else {
        // rem_euclid of a huge float is still in range; guard the top edge rounding.
        (i.rem_euclid(n_f) as u32).min(n - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2 x 2: top row red, green; bottom row blue, white (linear 8-bit).
    fn quad(srgb: bool) -> ImageTexture {
        ImageTexture {
            name: "t".into(),
            width: 2,
            height: 2,
            texels: Texels::Rgba8 {
                texels: vec![
                    [255, 0, 0, 255],
                    [0, 255, 0, 255],
                    [0, 0, 255, 255],
                    [255, 255, 255, 0],
                ],
                srgb,
            },
        }
    }

    #[test]
    fn texel_centres_give_their_texel_and_midpoints_the_mean() {
        let t = quad(false);
        // Top-left texel centre: u = 1/4, v = 3/4.
        assert_eq!(t.sample(0.25, 0.75, true), Vec4::new(1.0, 0.0, 0.0, 1.0));
        assert_eq!(t.sample(0.75, 0.25, true), Vec4::new(1.0, 1.0, 1.0, 0.0));
        // The image centre averages all four.
        assert_eq!(t.sample(0.5, 0.5, true), Vec4::new(0.5, 0.5, 0.5, 0.75));
        // Halfway between red and green along the top row.
        assert_eq!(t.sample(0.5, 0.75, true), Vec4::new(0.5, 0.5, 0.0, 1.0));
    }

    #[test]
    fn repeat_wraps_and_clamp_holds_the_edge() {
        let t = quad(false);
        // u = 0 lies between the left texel and (wrapped) the right one.
        assert_eq!(t.sample(0.0, 0.75, false), Vec4::new(0.5, 0.5, 0.0, 1.0));
        assert_eq!(t.sample(0.0, 0.75, true), Vec4::new(1.0, 0.0, 0.0, 1.0));
        assert_eq!(t.sample(1.25, 0.75, false), t.sample(0.25, 0.75, false));
        assert_eq!(t.sample(-0.75, -0.25, false), t.sample(0.25, 0.75, false));
        // Far and non-finite coordinates stay in range.
        for u in [1e30, -1e30, f32::NAN, f32::INFINITY] {
            let _ = t.sample(u, 0.5, false);
            let _ = t.sample(0.5, u, true);
        }
    }

    #[test]
    fn srgb_texels_are_decoded_to_linear() {
        let mut t = quad(true);
        if let Texels::Rgba8 { texels, .. } = &mut t.texels {
            texels[0] = [188, 0, 255, 255];
        }
        let c = t.texel(0, 0);
        // sRGB 188/255 is linear 0.5029...
        assert!((c.x - 0.502_886).abs() < 1e-5, "{c}");
        assert_eq!((c.y, c.z, c.w), (0.0, 1.0, 1.0));
    }

    #[test]
    fn equirectangular_directions() {
        let t = ImageTexture {
            name: "env".into(),
            width: 4,
            height: 2,
            texels: Texels::RgbaF32((0..8).map(|i| [i as f32, 0.0, 0.0, 1.0]).collect()),
        };
        let (up, fwd) = (Vec3::Y, -Vec3::Z);
        // Straight up is the top row; straight down the bottom row.
        assert!(t.sample_direction(Vec3::Y, up, fwd).x < 4.0);
        assert!(t.sample_direction(-Vec3::Y, up, fwd).x >= 4.0 - 1e-6);
        // Forward is the centre column: between texels 1 and 2 of a row.
        let c = t.sample_direction(fwd, up, fwd);
        assert!((c.x - 3.5).abs() < 1e-5, "{c}");
    }
}
