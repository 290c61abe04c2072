//! `Image`: linear RGB pixels, what a render makes and what the linear formats (EXR,
//! Radiance HDR) hold, whether a texture is read from one or a render written to one.

/// A floating-point RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels, row-major from the top-left.
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// An image of these pixels; panics unless there are `width × height` of them.
    pub fn new(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Image {
        assert_eq!(pixels.len(), width as usize * height as usize);
        Image {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at column `x`, row `y` (from the top).
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// 8-bit RGB, rounded to nearest: quantisation happens once, at the very end.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.map(quantize)).collect()
    }
}

/// 0..1 to 0..255, rounded; NaN and out-of-range values are clamped.
pub fn quantize(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantisation_rounds_and_clamps() {
        assert_eq!(quantize(0.0), 0);
        assert_eq!(quantize(1.0), 255);
        assert_eq!(quantize(0.5 / 255.0), 1);
        assert_eq!(quantize(0.49 / 255.0), 0);
        assert_eq!(quantize(-3.0), 0);
        assert_eq!(quantize(7.0), 255);
        assert_eq!(quantize(f32::NAN), 0);
    }
}
