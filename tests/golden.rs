//! Small renders of the bundled scenes against stored images, within a tolerance.
//!
//! `PRISM_BLESS=1 cargo test --test golden` rewrites the stored images after an
//! intended change; look at them before committing.

mod common;
use common::*;
use prism::compare::{RgbImage, mean_abs_diff, psnr, ssim};
use std::path::Path;

fn check_golden(name: &str, args: &[&std::ffi::OsStr]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join(format!("{name}.png"));
    let o = run(prism().args(args).arg(&out).arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let golden = repo().join("tests/golden").join(format!("{name}.png"));
    if std::env::var_os("PRISM_BLESS").is_some() {
        std::fs::copy(&out, &golden).unwrap();
        return;
    }
    compare(&out, &golden);
}

fn compare(actual: &Path, golden: &Path) {
    let a = load_rgb(actual);
    let g = load_rgb(golden);
    assert_eq!(a.dimensions(), g.dimensions());
    let (w, h) = a.dimensions();
    let a = RgbImage::new(w, h, a.as_raw());
    let g = RgbImage::new(w, h, g.as_raw());
    let (p, s, m) = (psnr(&a, &g), ssim(&a, &g), mean_abs_diff(&a, &g));
    // Bit-identical on the machine that blessed it; the margin allows another CPU's
    // last-bit differences in transcendental functions to move a few edge pixels.
    assert!(
        p > 40.0 && s > 0.98 && m < 1.0,
        "{}: psnr {p:.2} ssim {s:.4} mean diff {m:.3}",
        golden.display()
    );
}

#[test]
fn example_scene_with_anti_aliasing() {
    let (scene, camera) = (example("example.objx"), example("example.cmr"));
    check_golden(
        "example",
        &[
            scene.as_os_str(),
            camera.as_os_str(),
            "--width".as_ref(),
            "160".as_ref(),
        ],
    );
}

#[test]
fn example_scene_with_depth_of_field_and_lanczos() {
    let (scene, camera) = (example("example.objx"), example("example.cmr"));
    let args: Vec<&std::ffi::OsStr> = vec![
        scene.as_os_str(),
        camera.as_os_str(),
        "--width".as_ref(),
        "120".as_ref(),
        "--dof-rays".as_ref(),
        "16".as_ref(),
        "--aa-filter".as_ref(),
        "lanczos".as_ref(),
        "--seed".as_ref(),
        "3".as_ref(),
    ];
    check_golden("example-dof", &args);
}

/// A scene file of the repository rendered small with `prism render`, against its
/// stored image. Scenes that read the models beside the repository skip without them.
fn check_scene_golden(name: &str, scene: &str, size: (u32, u32)) {
    check_scene_golden_with(name, scene, size, &[]);
}

/// [`check_scene_golden`] with more options for `prism render`.
fn check_scene_golden_with(name: &str, scene: &str, size: (u32, u32), more: &[&str]) {
    let path = repo().join(scene);
    let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    if text.contains("../shared/models") && !repo().join("../shared/models").is_dir() {
        skipped(format_args!(
            "{scene} reads ../shared/models, which is absent"
        ));
        return;
    }
    let (w, h) = (size.0.to_string(), size.1.to_string());
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "render".as_ref(),
        path.as_os_str(),
        "--width".as_ref(),
        w.as_ref(),
        "--height".as_ref(),
        h.as_ref(),
    ];
    args.extend(more.iter().map(std::ffi::OsStr::new));
    check_golden(name, &args);
}

#[test]
fn whitted_showcase() {
    check_scene_golden("showcase", "scenes/showcase/showcase.toml", (128, 72));
}

/// The path model on the showcase: light bouncing between the floor, the spheres and
/// the glass (16 samples a pixel, so the golden holds its noise too: the samples are
/// the same on every machine).
#[test]
fn path_traced_showcase() {
    check_scene_golden_with(
        "showcase-path",
        "scenes/showcase/showcase.toml",
        (128, 72),
        &["--integrator", "path", "--spp", "16", "--aa", "1"],
    );
}

#[test]
fn smooth_low_polygon_sphere_has_no_terminator_steps() {
    check_scene_golden("terminator", "tests/data/terminator/scene.toml", (64, 64));
}

#[test]
fn cornell_box() {
    check_scene_golden(
        "cornell-box",
        "scenes/cornell-box/cornell-box.toml",
        (64, 64),
    );
}

#[test]
fn textured_spot() {
    check_scene_golden("spot", "scenes/spot/spot.toml", (96, 54));
}

#[test]
fn porcelain_bunny() {
    check_scene_golden("bunny", "scenes/bunny/bunny.toml", (96, 54));
}

#[test]
fn glass_dragon() {
    check_scene_golden("dragon", "scenes/dragon/dragon.toml", (96, 54));
}

/// A scene built and exported by Blender 3.4 (`scenes/blender/make-scene.py`): its
/// camera, point light and sun, glass and gold, at Blender's derived exposure.
#[test]
fn blender_export() {
    check_scene_golden(
        "blender-export",
        "scenes/blender/blender-export.glb",
        (160, 100),
    );
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
