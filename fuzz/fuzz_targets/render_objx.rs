//! The whole pipeline: an arbitrary 2014 scene, the example's materials (served from
//! memory, with a texture from a folder of the harness's own) and a fixed camera,
//! rendered at 8x8 with one ray per pixel on one thread, once with each BVH layout:
//! the two images must be the same, bit for bit.
#![no_main]
use libfuzzer_sys::fuzz_target;
use prism::accel::AccelKind;
use prism::format::{cmr, objx};
use prism::render::{RenderSettings, Renderer};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

static FOLDER: OnceLock<tempfile::TempDir> = OnceLock::new();

const MATERIALS: &str = include_str!("../../scenes/example/example.mtlx");
const CAMERA: &str = include_str!("../../scenes/example/example.cmr");

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let folder = FOLDER.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let checker = include_bytes!("../../scenes/example/checker.ppm");
        std::fs::write(dir.path().join("checker.ppm"), checker).unwrap();
        dir
    });
    let path = folder.path().join("scene.objx");
    let Ok(scene) = objx::parse(text, &path, |_| Ok(MATERIALS.to_owned())) else {
        return;
    };
    let camera = cmr::parse(CAMERA, &folder.path().join("camera.cmr")).unwrap();
    let threads = thread_count();
    let settings = RenderSettings {
        width: Some(8),
        height: Some(8),
        aa: Some(1),
        spp: Some(1),
        threads: Some(1),
        ..RenderSettings::default()
    };
    let render = |accel| {
        let settings = RenderSettings {
            accel,
            ..settings.clone()
        };
        let renderer = Renderer::new(&scene, &camera, settings).unwrap();
        renderer.render(&()).unwrap().0
    };
    let image = render(AccelKind::Bvh);
    assert_eq!((image.width, image.height), (8, 8));
    let bits = |i: &prism::film::Image| -> Vec<u32> {
        i.pixels.iter().flatten().map(|x| x.to_bits()).collect()
    };
    assert_eq!(bits(&image), bits(&render(AccelKind::BvhCopied)));
    // The renderer's pool does not join its worker when dropped. Until the worker has
    // exited, its thread-local destructors hold memory that LeakSanitizer, run by
    // libFuzzer when an input's mallocs and frees do not balance, now and then reports
    // as a leak.
    let deadline = Instant::now() + Duration::from_secs(1);
    while thread_count() > threads && Instant::now() < deadline {
        std::thread::sleep(Duration::from_micros(50));
    }
});

/// The threads of this process.
fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").map_or(0, |d| d.count())
}
