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
