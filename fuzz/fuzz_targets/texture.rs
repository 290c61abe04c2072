//! The texture and background image decoders (`format::image_file::decode_texture`, what
//! `read_texture` runs on a file's bytes) on arbitrary bytes. The first byte picks the
//! file name's extension, which sends `.hdr` and `.exr` to the linear reader and the rest
//! to the 8-bit decoders by content, and the encoding; the rest is the file.
//!
//! The pixel limit is 2^16 rather than `MAX_TEXTURE_PIXELS`: a legitimate texture at the
//! real limit takes up to 1 GiB (f32 RGBA), above the harness's `-malloc_limit_mb`,
//! whereas at 2^16 pixels the largest legitimate buffer is 1 MiB, so any allocation the
//! malloc limit catches is one the pixel limit failed to bound.
#![no_main]
use libfuzzer_sys::fuzz_target;
use prism::format::image_file::{Encoding, decode_texture};
use prism::scene::Texels;

const MAX_PIXELS: u64 = 1 << 16;

const NAMES: [&str; 8] = [
    "t.png", "t.jpg", "t.bmp", "t.tga", "t.ppm", "t.hdr", "t.exr", "t.tex",
];

fuzz_target!(|data: &[u8]| {
    let Some((&select, file)) = data.split_first() else {
        return;
    };
    let name = NAMES[usize::from(select & 7)];
    let encoding = match (select >> 3) % 3 {
        0 => Encoding::Srgb,
        1 => Encoding::Linear,
        _ => Encoding::Mask,
    };
    let Ok(texture) = decode_texture(file, name, encoding, MAX_PIXELS) else {
        return;
    };
    let pixels = u64::from(texture.width) * u64::from(texture.height);
    assert!(
        pixels > 0 && pixels <= MAX_PIXELS,
        "{}x{}",
        texture.width,
        texture.height
    );
    let texels = match &texture.texels {
        Texels::Rgba8 { texels, .. } => texels.len(),
        Texels::RgbaF32(texels) => texels.len(),
    };
    assert_eq!(texels as u64, pixels);
    if let Texels::RgbaF32(texels) = &texture.texels {
        assert!(texels.iter().flatten().all(|v| v.is_finite()));
    }
});
