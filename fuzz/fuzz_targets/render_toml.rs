//! The whole pipeline on a Prism scene file: arbitrary text (inputs naming paths are
//! skipped, so no file of the machine is read), resolved as the command line resolves
//! it, then rendered with the whitted model at 8x8, one ray per pixel, on one thread,
//! once with each BVH layout: the two images must be the same, bit for bit. The path
//! model renders it too (two samples a pixel, at most four bounces), with the same
//! check. Area
//! lights, glass, spot and directional lights, checkers and emitters all come from the
//! text, so every light kind's samples in lanes and every shadow path runs.
#![no_main]
use libfuzzer_sys::fuzz_target;
use prism::accel::AccelKind;
use prism::job::{JobOptions, resolve};
use prism::render::{IntegratorKind, Renderer};
use std::path::Path;
use std::time::{Duration, Instant};

/// Light samples a scene may ask for in all: 64 pixels, a few bounces, each sample a
/// shadow ray, kept to a few milliseconds an input.
const MAX_SAMPLES: u64 = 512;
const MAX_SHAPES: usize = 256;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if text.contains('/') || text.contains('\\') || text.contains("..") {
        return;
    }
    let Ok(file) =
        prism::format::scene_file::parse(text, Path::new("/nonexistent-prism/scene.toml"))
    else {
        return;
    };
    let samples: u64 = file
        .scene
        .lights
        .iter()
        .map(|l| u64::from(l.samples.max(1)))
        .sum();
    if samples > MAX_SAMPLES || file.scene.shapes.len() > MAX_SHAPES {
        return;
    }
    let threads = thread_count();
    let options = JobOptions {
        render: prism::options::RenderOptions {
            width: Some(8),
            height: Some(8),
            aa: Some(1),
            spp: Some(1),
            integrator: Some(IntegratorKind::Whitted),
            max_depth: Some(file.settings.max_depth.unwrap_or(4).min(4)),
            ..Default::default()
        },
        threads: Some(1),
        ..JobOptions::default()
    };
    let Ok(still) = resolve(file, &options) else {
        return;
    };
    let render_with = |accel, integrator, spp, max_depth| {
        let settings = prism::render::RenderSettings {
            accel,
            integrator,
            spp: Some(spp),
            max_depth,
            ..still.settings.clone()
        };
        let renderer = Renderer::new(&still.scene, &still.camera, settings).ok()?;
        Some(renderer.render(&()).ok()?.0)
    };
    let render = |accel| render_with(accel, IntegratorKind::Whitted, 1, still.settings.max_depth);
    let Some(image) = render(AccelKind::Bvh) else {
        return;
    };
    assert_eq!((image.width, image.height), (8, 8));
    let bits = |i: &prism::film::Image| -> Vec<u32> {
        i.pixels.iter().flatten().map(|x| x.to_bits()).collect()
    };
    let copied =
        render(AccelKind::BvhCopied).expect("the copied layout renders where the other did");
    assert_eq!(bits(&image), bits(&copied));
    let path = |accel| render_with(accel, IntegratorKind::Path, 2, 4);
    if let Some(image) = path(AccelKind::Bvh) {
        assert_eq!((image.width, image.height), (8, 8));
        let copied = path(AccelKind::BvhCopied).expect("the copied layout renders a path too");
        assert_eq!(bits(&image), bits(&copied));
        assert!(image.pixels.iter().flatten().all(|v| v.is_finite()));
    }
    // As in render_objx: wait for the renderer's worker to exit, so LeakSanitizer does
    // not report its thread-local memory.
    let deadline = Instant::now() + Duration::from_secs(1);
    while thread_count() > threads && Instant::now() < deadline {
        std::thread::sleep(Duration::from_micros(50));
    }
});

/// The threads of this process.
fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").map_or(0, |d| d.count())
}
