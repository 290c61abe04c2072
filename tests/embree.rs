//! Cross-check against Embree: Prism's BVH and Embree (`rtcIntersect1`, through the
//! `embreex` Python package and `benches/embree.py`) cast the bunny camera's 921 600
//! pinhole rays at the Stanford bunny; they must agree on hit or miss, and on the
//! triangle or its distance, for all but a 1e-4 share of the pixels.
//!
//! Skipped, with the reason printed, when the bunny (`../shared/models`), python3 or
//! embreex is missing; CI installs embreex.

use std::path::Path;
use std::process::Command;

use prism::accel::{Accel, AccelKind};
use prism::bench::{primary_rays, write_ray_dump};

#[test]
fn bvh_hits_agree_with_embree_on_the_bunny() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = root.join("../shared/models/stanford-bunny/stanford-bunny.obj");
    if !mesh.is_file() {
        skipped(format_args!("{} is absent", mesh.display()));
        return;
    }
    let scene = prism::format::load_scene(&mesh).unwrap();
    let camera = prism::format::load_camera(&root.join("benches/bunny.cmr")).unwrap();
    let accel = Accel::build(AccelKind::Bvh, &scene.shapes);
    let rays = primary_rays(&camera);
    let dir = tempfile::tempdir().unwrap();
    write_ray_dump(dir.path(), &scene, &rays, &accel).unwrap();

    let run = Command::new("python3")
        .arg(root.join("benches/embree.py"))
        .arg(dir.path())
        .args(["--seconds", "0"])
        .output();
    let out = match run {
        Err(e) => {
            skipped(format_args!("cannot run python3: {e}"));
            return;
        }
        Ok(out) if out.status.code() == Some(3) => {
            skipped(String::from_utf8_lossy(&out.stderr).trim());
            return;
        }
        Ok(out) => out,
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "embree.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let number = |key: &str| -> f64 {
        let at = stdout.find(&format!("\"{key}\": ")).expect(key) + key.len() + 4;
        let rest = &stdout[at..];
        rest[..rest.find([',', '}']).unwrap()].parse().unwrap()
    };
    assert_eq!(number("rays"), rays.len() as f64);
    let fraction = number("disagree_fraction");
    eprintln!("Embree agreement: {stdout}");
    assert!(fraction < 1e-4, "{stdout}");
    // The camera frames the bunny so about two thirds of the rays hit it.
    let hits = number("hit_fraction");
    assert!((0.6..0.75).contains(&hits), "{stdout}");
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
