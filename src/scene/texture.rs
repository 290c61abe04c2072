//! Image textures and the four ways the 2014 format fits an image onto a surface.

use super::shape::SurfaceCoords;
use crate::math::Vec3;

/// How an image covers a surface (report section 2.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FillMode {
    /// Repeat the image; one texel covers `scale` world units.
    Tile {
        /// Side of one texel in world units (of the shape's planar frame).
        scale: f32,
    },
    /// Map the image onto the shape's extent, distorting its aspect ratio.
    Stretch,
    /// Scale uniformly so the whole image shows, centred; the rest of the surface keeps
    /// the material colour.
    Fit,
    /// Scale uniformly so the image covers the whole extent, centred; the overflow is cut.
    Crop,
}

/// An 8-bit RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels, at least 1.
    pub width: u32,
    /// Height in texels, at least 1.
    pub height: u32,
    /// `width * height` 8-bit RGB texels, row-major from the top row.
    pub texels: Vec<[u8; 3]>,
    /// How the image is laid onto the surfaces that use it.
    pub fill: FillMode,
}

impl Texture {
    /// A texture of `width x height` texels, top row first. Panics when `texels` does not
    /// hold exactly that many or either side is zero.
    pub fn new(width: u32, height: u32, texels: Vec<[u8; 3]>, fill: FillMode) -> Texture {
        assert_eq!(texels.len(), width as usize * height as usize);
        assert!(width > 0 && height > 0);
        Texture {
            width,
            height,
            texels,
            fill,
        }
    }

    /// Column and row of the texel seen at `c`, or `None` where a `Fit` image leaves the
    /// surface uncovered. Image x runs along columns and y along rows, origin top-left.
    pub fn texel_index(&self, c: &SurfaceCoords) -> Option<(u32, u32)> {
        let (cols, rows) = (self.width as f32, self.height as f32);
        match self.fill {
            FillMode::Tile { scale } => Some((
                wrap(floor(c.x / scale), self.width),
                wrap(floor(c.y / scale), self.height),
            )),
            FillMode::Stretch => Some((
                clamp_index((c.x - c.x0) / c.len_x * cols, self.width),
                clamp_index((c.y - c.y0) / c.len_y * rows, self.height),
            )),
            FillMode::Fit | FillMode::Crop => {
                let sx = c.len_x / cols;
                let sy = c.len_y / rows;
                // World units per texel.
                let s = if self.fill == FillMode::Fit {
                    sx.min(sy)
                } else {
                    sx.max(sy)
                };
                let off_x = (c.len_x - cols * s) * 0.5;
                let off_y = (c.len_y - rows * s) * 0.5;
                let col = floor((c.x - c.x0 - off_x) / s);
                let row = floor((c.y - c.y0 - off_y) / s);
                if self.fill == FillMode::Fit
                    && !((0.0..cols).contains(&col) && (0.0..rows).contains(&row))
                {
                    return None;
                }
                Some((clamp_index(col, self.width), clamp_index(row, self.height)))
            }
        }
    }

    /// Colour (0..1 per channel) at `c`, or `None` outside a `Fit` image.
    pub fn lookup(&self, c: &SurfaceCoords) -> Option<Vec3> {
        let (col, row) = self.texel_index(c)?;
        let [r, g, b] = self.texels[row as usize * self.width as usize + col as usize];
        Some(Vec3::new(
            UNIT[r as usize],
            UNIT[g as usize],
            UNIT[b as usize],
        ))
    }
}

/// `v / 255` for every 8-bit `v`, the very quotients (const evaluation divides as IEEE
/// 754 does at run time): three loads instead of conversions and a division at each
/// texel read.
static UNIT: [f32; 256] = {
    let mut t = [0.0; 256];
    let mut v = 0;
    while v < 256 {
        t[v] = v as f32 / 255.0;
        v += 1;
    }
    t
};

/// `x.floor()` without a call into libm (baseline x86-64 has no rounding instruction,
/// and texel lookups were 3 % of a 2014 render); equal to it except that -0 gives +0,
/// which indexes the same texel.
#[inline]
fn floor(x: f32) -> f32 {
    // From 2^23 up every f32 is an integer already (and NaN and infinities pass).
    if x.abs() < 8_388_608.0 {
        let t = x as i32 as f32;
        if t > x { t - 1.0 } else { t }
    } else {
        x
    }
}

/// `v mod n` for a whole number `v`; the saturating cast keeps huge and non-finite
/// coordinates in range (NaN becomes 0).
fn wrap(v: f32, n: u32) -> u32 {
    (v as i64).rem_euclid(i64::from(n)) as u32
}

fn clamp_index(v: f32, n: u32) -> u32 {
    if v.is_nan() {
        return 0;
    }
    (v.max(0.0) as u32).min(n - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_table_is_the_quotient_bit_for_bit() {
        for v in 0..=255u8 {
            let divided = Vec3::new(f32::from(v), 0.0, 0.0) / 255.0;
            assert_eq!(UNIT[v as usize].to_bits(), divided.x.to_bits(), "{v}");
        }
    }

    #[test]
    fn wrap_is_the_euclidean_remainder() {
        let values = [
            0.0,
            -0.0,
            1.0,
            5.0,
            6.0,
            7.0,
            -1.0,
            -6.0,
            -7.0,
            1e9,
            -1e9,
            4_294_967_295.0,
            4_294_967_296.0,
            1e30,
            -1e30,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        for n in [1, 6, 7, u32::MAX] {
            for &v in &values {
                let w = wrap(v, n);
                assert!(w < n, "{v} mod {n}");
                if v.is_finite() && v.abs() < 1e15 {
                    // v - w is a multiple of n.
                    assert_eq!((f64::from(v) - f64::from(w)).rem_euclid(f64::from(n)), 0.0);
                }
            }
        }
        assert_eq!(wrap(-1.0, 6), 5);
        assert_eq!(wrap(-7.0, 6), 5);
        assert_eq!(wrap(f32::NAN, 6), 0);
    }

    #[test]
    fn floor_is_libm_floor() {
        let mut x = -3.0e7f32;
        let mut checked = 0;
        while x < 3.0e7 {
            for v in [x, -x, x.next_up(), x.next_down(), x + 0.5, x - 0.5] {
                assert!(floor(v) == v.floor(), "{v}");
            }
            // Shrinking toward zero, creeping through it, then growing.
            x = if x < -1.0 {
                x * 0.93
            } else if x < 1.0 {
                x + 0.123
            } else {
                x * 1.07
            };
            checked += 1;
        }
        assert!(checked > 100);
        for v in [
            0.0,
            -0.0,
            -0.25,
            0.999_999_9,
            -1.0,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
        ] {
            assert!(floor(v) == v.floor(), "{v}");
        }
        assert!(floor(f32::NAN).is_nan());
    }

    /// A 4x2 image whose texel (col, row) has red = col and green = row.
    fn grid(fill: FillMode) -> Texture {
        let mut t = Vec::new();
        for row in 0..2u8 {
            for col in 0..4u8 {
                t.push([col, row, 0]);
            }
        }
        Texture::new(4, 2, t, fill)
    }

    fn at(x: f32, y: f32, len_x: f32, len_y: f32) -> SurfaceCoords {
        SurfaceCoords {
            x,
            y,
            x0: 0.0,
            y0: 0.0,
            len_x,
            len_y,
        }
    }

    #[test]
    fn tile_repeats_every_scale_units_and_wraps_negatives() {
        let t = grid(FillMode::Tile { scale: 0.5 });
        assert_eq!(t.texel_index(&at(0.0, 0.0, 1.0, 1.0)), Some((0, 0)));
        assert_eq!(t.texel_index(&at(1.6, 0.6, 1.0, 1.0)), Some((3, 1)));
        assert_eq!(t.texel_index(&at(2.1, 1.1, 1.0, 1.0)), Some((0, 0)));
        assert_eq!(t.texel_index(&at(-0.1, -0.1, 1.0, 1.0)), Some((3, 1)));
    }

    #[test]
    fn stretch_maps_extent_onto_image() {
        let t = grid(FillMode::Stretch);
        assert_eq!(t.texel_index(&at(0.0, 0.0, 8.0, 8.0)), Some((0, 0)));
        assert_eq!(t.texel_index(&at(7.99, 7.99, 8.0, 8.0)), Some((3, 1)));
        assert_eq!(t.texel_index(&at(8.0, 8.0, 8.0, 8.0)), Some((3, 1)));
        assert_eq!(t.texel_index(&at(4.5, 3.9, 8.0, 8.0)), Some((2, 0)));
    }

    #[test]
    fn fit_letterboxes_and_crop_cuts() {
        // Extent 8 x 8, image 4 x 2: fit gives 2 units per texel, image rows span
        // y in [2, 6); crop gives 4 units per texel, columns span x in [-4, 12).
        let fit = grid(FillMode::Fit);
        assert_eq!(fit.texel_index(&at(1.0, 1.0, 8.0, 8.0)), None);
        assert_eq!(fit.texel_index(&at(1.0, 2.5, 8.0, 8.0)), Some((0, 0)));
        assert_eq!(fit.texel_index(&at(7.0, 5.5, 8.0, 8.0)), Some((3, 1)));
        let crop = grid(FillMode::Crop);
        assert_eq!(crop.texel_index(&at(0.0, 0.0, 8.0, 8.0)), Some((1, 0)));
        assert_eq!(crop.texel_index(&at(7.9, 7.9, 8.0, 8.0)), Some((2, 1)));
        assert_eq!(crop.texel_index(&at(3.9, 3.9, 8.0, 8.0)), Some((1, 0)));
    }

    #[test]
    fn lookup_returns_unit_range_colour() {
        let t = grid(FillMode::Stretch);
        let c = t.lookup(&at(7.0, 7.0, 8.0, 8.0)).unwrap();
        assert_eq!(c, Vec3::new(3.0 / 255.0, 1.0 / 255.0, 0.0));
    }
}
