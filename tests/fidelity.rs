//! Regression against the 2014 report's figures. `examples/fidelity.rs` found the frame
//! widths, crop offsets and the scene1 pose used here; `docs/fidelity.md` explains them.
//! Each check renders only a window a few pixels larger than the reference crop, at the
//! frame width where the crop maps 1:1 onto rendered pixels, finds the crop in it, and
//! checks its position, PSNR and SSIM. Skipped (passing) when the seed scenes are absent.

mod common;
use prism::compare::{RgbImage, crop, match_template, psnr, ssim};
use prism::format::{load_camera, load_scene};
use prism::math::Vec3;
use prism::render::{Region, RenderSettings, Renderer};
use prism::scene::{Camera, Scene, Shape};
use std::path::Path;

/// Slack around the expected crop position, in pixels.
const MARGIN: u32 = 4;

struct Expect {
    /// Frame width; the height follows the camera's 16:9.
    width: u32,
    /// Emulate the 2014 program's rays through pixel corners (Prism uses centres).
    corners: bool,
    /// Top-left of the crop in that frame.
    x: u32,
    y: u32,
    min_psnr: f64,
    min_ssim: f64,
}

/// Renders the window around the expected position, locates the crop and scores it.
fn check(scene: &Scene, camera: &Camera, reference: &Path, e: &Expect) {
    let reference_img = common::load_rgb(reference);
    let (tw, th) = reference_img.dimensions();
    // Rounded as the renderer rounds a width-only override.
    let (ch, cw) = (u64::from(camera.height), u64::from(camera.width));
    let height = ((ch * u64::from(e.width) + cw / 2) / cw) as u32;
    let mut cam = camera.with_resolution(e.width, height);
    if e.corners {
        // One more pixel each way at the same retina scale: these pixel centres are the
        // corners of the width x height frame's pixels.
        cam.width += 1;
        cam.height += 1;
    }
    let region = Region {
        x: e.x - MARGIN,
        y: e.y - MARGIN,
        width: tw + 2 * MARGIN,
        height: th + 2 * MARGIN,
    };
    let settings = RenderSettings {
        aa: Some(1),
        spp: Some(1),
        region: Some(region),
        ..Default::default()
    };
    let (img, _) = Renderer::new(scene, &cam, settings)
        .unwrap()
        .render(&())
        .unwrap();
    let data = img.to_rgb8();
    let view = RgbImage::new(img.width, img.height, &data);
    let t = RgbImage::new(tw, th, reference_img.as_raw());
    let m = match_template(&view, &t);
    let (x, y) = (region.x + m.x, region.y + m.y);
    let window = crop(&view, m.x, m.y, tw, th);
    let w = RgbImage::new(tw, th, &window);
    let (p, s) = (psnr(&w, &t), ssim(&w, &t));
    let name = reference.file_name().unwrap().to_string_lossy();
    let mode = if e.corners { "corners" } else { "centres" };
    eprintln!(
        "{name} ({mode}, width {}): at ({x}, {y}), NCC {:.4}, PSNR {p:.2} dB, SSIM {s:.4}",
        e.width, m.ncc
    );
    assert!(
        x.abs_diff(e.x) <= 1 && y.abs_diff(e.y) <= 1,
        "{name} ({mode}): crop found at ({x}, {y}), expected ({}, {})",
        e.x,
        e.y
    );
    assert!(
        p > e.min_psnr,
        "{name} ({mode}): PSNR {p:.2} dB <= {}",
        e.min_psnr
    );
    assert!(
        s > e.min_ssim,
        "{name} ({mode}): SSIM {s:.4} <= {}",
        e.min_ssim
    );
}

fn load(dir: &Path) -> (Scene, Camera) {
    (
        load_scene(&dir.join("scene.objx")).unwrap(),
        load_camera(&dir.join("scene.cmr")).unwrap(),
    )
}

#[test]
fn scene0_matches_the_report_figure_without_anti_aliasing() {
    let Some(dir) = common::seed_scene("scene0") else {
        return;
    };
    let (scene, camera) = load(&dir);
    let org = dir.join("../report/org.png");
    // The figure is a 960 x 540 render through pixel corners. Measured: at (440, 290),
    // PSNR 35.04 dB, SSIM 0.9861 (93 % of channel values within 1 level).
    let exact = Expect {
        width: 960,
        corners: true,
        x: 440,
        y: 290,
        min_psnr: 34.0,
        min_ssim: 0.98,
    };
    check(&scene, &camera, &org, &exact);
    // Prism's own pixel centres: half a pixel off, best matched by a 961-wide frame.
    // Measured: at (440, 290), PSNR 25.30 dB, SSIM 0.8536.
    let centres = Expect {
        width: 961,
        corners: false,
        x: 440,
        y: 290,
        min_psnr: 24.5,
        min_ssim: 0.83,
    };
    check(&scene, &camera, &org, &centres);
}

/// Marble centres as `scene1/scene.objx` states them (vertices 64..68).
const FILE_MARBLES: [[f32; 3]; 5] = [
    [54.5636, -21.1098, 275.436],
    [-67.2896, -6.40616, 403.696],
    [31.6648, 0.0, 214.253],
    [0.0, 60.2716, 456.362],
    [-158.891, -18.806, 330.0],
];

/// The animation frame the scene1 figures show (`scene1_pose` in examples/fidelity.rs,
/// which derives these numbers from turns about the glass sphere's centre (0, 0, 330)):
/// the camera, 360.75 from that centre, 19 degrees above it, phi 22.5, and the marbles.
const POSE_EYE: [f32; 3] = [-315.1314, -130.5317, 447.4487];
const POSE_MARBLES: [[f32; 3]; 5] = [
    [-21.6480, -73.9106, 351.6476],
    [-80.9512, 49.7053, 361.2462],
    [110.8656, 0.0, 375.9221],
    [0.0, 129.3432, 383.5757],
    [-88.8913, 133.0352, 330.0],
];

#[test]
fn scene1_matches_the_report_figure_at_the_animation_pose() {
    let Some(dir) = common::seed_scene("scene1") else {
        return;
    };
    let (mut scene, mut camera) = load(&dir);
    for (file, new) in FILE_MARBLES.iter().zip(POSE_MARBLES) {
        let file = Vec3::from_array(*file);
        let (i, mut marble) = scene
            .shapes
            .iter()
            .enumerate()
            .find_map(|(i, s)| match s {
                Shape::Sphere(sp) if (sp.center - file).length() < 1e-2 => Some((i, sp)),
                _ => None,
            })
            .expect("scene1 has its five marbles");
        marble.center = Vec3::from_array(new);
        scene.shapes.set(i, Shape::Sphere(marble));
    }
    camera.eye = Vec3::from_array(POSE_EYE);
    camera.theta_deg = 109.0;
    camera.phi_deg = 22.5;
    // org1 is a piece of a 1920 x 1080 render through pixel corners. Measured: at
    // (1027, 369), PSNR 38.78 dB, SSIM 0.9802 (at the cmr's own camera and marbles
    // the figure is not found at all: NCC below 0.4).
    let exact = Expect {
        width: 1920,
        corners: true,
        x: 1027,
        y: 369,
        min_psnr: 37.5,
        min_ssim: 0.97,
    };
    check(&scene, &camera, &dir.join("../report/org1.png"), &exact);
}
