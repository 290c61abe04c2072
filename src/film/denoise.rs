//! Denoising a finished render with Intel Open Image Denoise (OIDN): its `RT` filter, a
//! network trained on path-traced images, guided by the albedo and normal passes
//! ([`crate::options::Aov`]) so that the edges and textures they show stay sharp while
//! the noise between them goes. It is post-processing of the film: linear radiance in,
//! linear radiance out, before development.
//!
//! OIDN is a C++ library, linked only when Prism is built with the `oidn` feature;
//! without it [`denoise`] returns an error that says how to build a Prism that has it.
//! Nothing denoises unless asked: a render's image is never changed otherwise.

use super::Image;
use crate::error::{Error, Result};

/// Whether this Prism can denoise: built with the `oidn` feature.
pub const AVAILABLE: bool = cfg!(feature = "oidn");

/// Why a Prism without the `oidn` feature cannot denoise, and how to get one that can.
const WITHOUT_OIDN: &str = "this Prism was built without Intel Open Image Denoise \
    (OIDN). Build it with the `oidn` feature and OIDN_DIR naming a folder that holds \
    lib/libOpenImageDenoise.so: `OIDN_DIR=/path/to/oidn cargo build --release --features \
    oidn` (the `pyoidn` wheel from PyPI ships the library in pyoidn/oidn/lib), and put \
    that lib folder on LD_LIBRARY_PATH to run it; see Denoising in docs/output.md";

/// Ok when this Prism can denoise, else the error [`denoise`] would give: a front end
/// asks before it renders, so a render is not spent on an image that cannot be written.
pub fn check_available() -> Result<()> {
    if AVAILABLE {
        Ok(())
    } else {
        Err(Error::Denoise(WITHOUT_OIDN.into()))
    }
}

/// `image` (linear radiance, as a render makes it) denoised, guided by the `albedo` and
/// `normal` passes of the same render when they are given (the image's size each;
/// normals only with the albedo, as OIDN takes them).
///
/// The colour is HDR (radiance, unbounded). The passes are not taken as noise-free
/// (OIDN's `cleanAux` stays off): they are averaged over the image's own samples, so at
/// a few samples a pixel they are as rough as those samples wherever a pixel holds
/// more than one surface or colour (edges, distant textures, depth of field), and
/// trusting them there leaves that roughness in the image (on the showcase at 4
/// samples, 13 % more error than with `cleanAux` off).
///
/// `threads` caps the CPU threads OIDN runs on, as a render's own are capped; `None`
/// lets it use every core.
pub fn denoise(
    image: &Image,
    albedo: Option<&Image>,
    normal: Option<&Image>,
    threads: Option<usize>,
) -> Result<Image> {
    check_available()?;
    for (name, pass) in [("albedo", albedo), ("normal", normal)] {
        if let Some(pass) = pass
            && (pass.width, pass.height) != (image.width, image.height)
        {
            return Err(Error::Denoise(format!(
                "the {name} pass is {}x{}, the image {}x{}",
                pass.width, pass.height, image.width, image.height
            )));
        }
    }
    if normal.is_some() && albedo.is_none() {
        return Err(Error::Denoise(
            "a normal pass guides the denoiser only with an albedo pass".into(),
        ));
    }
    filter(image, albedo, normal, threads)
}

/// OIDN's `RT` filter over the checked images.
#[cfg(feature = "oidn")]
fn filter(
    image: &Image,
    albedo: Option<&Image>,
    normal: Option<&Image>,
    threads: Option<usize>,
) -> Result<Image> {
    let failed = |e: oidn::Error| Error::Denoise(format!("Open Image Denoise failed: {e}"));
    // OIDN wants finite, non-negative colours (a Lanczos or bicubic filter rings below
    // zero beside a bright edge; one NaN would spread over the network's whole field)
    // and albedos within 0..1.
    let colour = flat(image, |v| if v.is_finite() { v.max(0.0) } else { 0.0 });
    let (w, h) = (image.width as usize, image.height as usize);
    let device = device(threads)?;
    let mut rt = oidn::RayTracing::try_new(&device).map_err(failed)?;
    rt.hdr(true).clean_aux(false).image_dimensions(w, h);
    if let Some(albedo) = albedo {
        let albedo = flat(albedo, |v| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        });
        let albedo = device.create_buffer(&albedo).map_err(failed)?;
        match normal {
            Some(normal) => {
                let normal = flat(normal, |v| if v.is_finite() { v } else { 0.0 });
                let normal = device.create_buffer(&normal).map_err(failed)?;
                rt.albedo_normal_buffer(albedo, normal).map_err(failed)?;
            }
            None => {
                rt.albedo_buffer(albedo).map_err(failed)?;
            }
        }
    }
    let mut out = vec![0.0f32; colour.len()];
    rt.filter(&colour, &mut out).map_err(failed)?;
    let pixels = out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Image::new(image.width, image.height, pixels))
}

/// The device to denoise on. Without a thread cap, the default device: the fastest
/// there is, a GPU where OIDN has one, else the CPU on all its cores. With one, the CPU
/// on that many threads (OIDN's `numThreads`, which only its CPU device takes: a cap
/// asks for a share of this machine's cores).
#[cfg(feature = "oidn")]
fn device(threads: Option<usize>) -> Result<oidn::Device> {
    let failed = |e: oidn::Error| Error::Denoise(format!("Open Image Denoise failed: {e}"));
    let Some(threads) = threads else {
        return oidn::Device::new().map_err(failed);
    };
    let threads = i32::try_from(threads).unwrap_or(i32::MAX);
    // SAFETY: the handle is checked for null before use, set and committed before it
    // is wrapped (as `from_raw` asks), and released on the error path; the parameter
    // name is a NUL-terminated literal.
    unsafe {
        use oidn::sys::*;
        let raw = oidnNewDevice(OIDNDeviceType_OIDN_DEVICE_TYPE_CPU);
        if raw.is_null() {
            // No device to ask why; a device made another way would not keep the cap.
            return Err(Error::Denoise(
                "Open Image Denoise could not make a CPU device".into(),
            ));
        }
        oidnSetDeviceInt(raw, c"numThreads".as_ptr(), threads);
        oidnCommitDevice(raw);
        let device = oidn::Device::from_raw(raw);
        device.get_error().map_err(failed)?;
        Ok(device)
    }
}

/// Never called: [`check_available`] refuses first.
#[cfg(not(feature = "oidn"))]
fn filter(_: &Image, _: Option<&Image>, _: Option<&Image>, _: Option<usize>) -> Result<Image> {
    Err(Error::Denoise(WITHOUT_OIDN.into()))
}

/// The image's channels in one run, as OIDN's three-float pixels, each through `f`.
#[cfg(feature = "oidn")]
fn flat(image: &Image, f: impl Fn(f32) -> f32) -> Vec<f32> {
    image.pixels.iter().flatten().map(|&v| f(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(not(feature = "oidn"))]
    #[test]
    fn without_oidn_the_error_says_how_to_build_a_prism_that_has_it() {
        let image = Image::new(1, 1, vec![[0.5; 3]]);
        let e = denoise(&image, None, None, None).unwrap_err().to_string();
        assert!(
            e.starts_with("cannot denoise: this Prism was built without"),
            "{e}"
        );
        for needle in ["--features oidn", "OIDN_DIR", "pyoidn", "LD_LIBRARY_PATH"] {
            assert!(e.contains(needle), "{needle}: {e}");
        }
        assert!(check_available().is_err());
    }

    /// A smooth signal (a gradient of radiance 0.2 to 1.8) under seeded noise of
    /// standard deviation 0.3: the denoised image is far nearer the signal than the
    /// noisy one, with and without flat passes to guide it.
    #[cfg(feature = "oidn")]
    #[test]
    fn a_noisy_gradient_comes_back_near_the_gradient() {
        use rand_core::Rng;
        let (w, h) = (96u32, 64u32);
        let truth: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let t = 0.2 + 1.6 * (i % w) as f32 / (w - 1) as f32;
                [t, 0.8 * t, 0.6 * t]
            })
            .collect();
        let mut rng = rand_pcg::Pcg32::new(0xde_0153, 7);
        let mut uniform = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
        // Twelve uniforms less six: near-normal, standard deviation 1.
        let mut normal_noise = || (0..12).map(|_| uniform()).sum::<f32>() - 6.0;
        let noisy: Vec<[f32; 3]> = truth
            .iter()
            .map(|p| p.map(|v| (v + 0.3 * normal_noise()).max(0.0)))
            .collect();
        let rmse = |a: &[[f32; 3]]| {
            let sum: f64 = a
                .iter()
                .zip(&truth)
                .flat_map(|(p, q)| (0..3).map(move |c| f64::from(p[c] - q[c]).powi(2)))
                .sum();
            (sum / (a.len() * 3) as f64).sqrt()
        };
        let noisy = Image::new(w, h, noisy);
        let before = rmse(&noisy.pixels);
        let grey = Image::new(w, h, vec![[0.5; 3]; (w * h) as usize]);
        let facing = Image::new(w, h, vec![[0.0, 0.0, 1.0]; (w * h) as usize]);
        let guides = [(None, None), (Some(&grey), Some(&facing))];
        for ((albedo, normal), threads) in guides.into_iter().zip([None, Some(1)]) {
            let denoised = denoise(&noisy, albedo, normal, threads).unwrap();
            assert_eq!((denoised.width, denoised.height), (w, h));
            let after = rmse(&denoised.pixels);
            assert!(before > 0.25, "{before}");
            assert!(after < before / 5.0, "RMSE {before} -> {after}");
        }
    }

    #[cfg(feature = "oidn")]
    #[test]
    fn passes_of_another_size_or_normals_alone_are_refused() {
        let image = Image::new(4, 4, vec![[0.5; 3]; 16]);
        let small = Image::new(2, 2, vec![[0.5; 3]; 4]);
        let e = denoise(&image, Some(&small), None, None)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "cannot denoise: the albedo pass is 2x2, the image 4x4");
        let e = denoise(&image, None, Some(&image), None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("only with an albedo pass"), "{e}");
    }

    /// A render's thread cap reaches the denoiser: its CPU device runs on that many.
    #[cfg(feature = "oidn")]
    #[test]
    fn a_thread_cap_makes_a_cpu_device_of_that_many_threads() {
        for n in [1, 2] {
            let device = device(Some(n)).unwrap();
            // SAFETY: a live, committed device and a NUL-terminated name.
            let got = unsafe { oidn::sys::oidnGetDeviceInt(device.raw(), c"numThreads".as_ptr()) };
            assert_eq!(got, n as i32);
        }
    }
}
