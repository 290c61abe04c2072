//! End to end: standard OBJ files render as their authors meant them, `prism info`
//! reports them, and bad files fail cleanly.

mod common;

use common::prism;
use std::path::Path;

/// A lone triangle at +x (facing +z), white, under a light on the +z side.
const RIGHT_TRIANGLE: &str = "v 0.5 -0.5 0\nv 1.5 -0.5 0\nv 1 0.5 0\nf 1 2 3\n";

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn luminance_by_half(path: &Path) -> (u64, u64) {
    let img = image::open(path).unwrap().to_rgb8();
    let (w, _) = img.dimensions();
    let (mut left, mut right) = (0u64, 0u64);
    for (x, _, p) in img.enumerate_pixels() {
        let l = p.0.iter().map(|&c| u64::from(c)).sum::<u64>();
        if x < w / 2 { left += l } else { right += l }
    }
    (left, right)
}

#[test]
fn a_triangle_at_plus_x_seen_from_plus_z_is_on_the_right() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let out = dir.path().join("t.png");
    let status = prism()
        .args(["render"])
        .arg(&obj)
        .arg(&out)
        .args(["--look-from", "0,0,5", "--look-at", "0,0,0", "--fov", "60"])
        .args(["--width", "64", "--height", "32", "--quiet"])
        .status()
        .unwrap();
    assert!(status.success());
    let (left, right) = luminance_by_half(&out);
    // The background is grey on both sides; the lit triangle adds to the right only.
    assert!(right > left + 64 * 10, "left {left}, right {right}");
}

#[test]
fn a_model_without_camera_renders_with_the_default_view() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let out = dir.path().join("t.png");
    let status = prism()
        .arg("render")
        .arg(&obj)
        .arg(&out)
        .args(["--width", "48", "--quiet"])
        .status()
        .unwrap();
    assert!(status.success());
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (48, 27));
    // The model is framed: its pixels differ from the background's.
    let corner = *img.get_pixel(0, 0);
    let center = *img.get_pixel(24, 13);
    assert_ne!(corner, center);
}

#[test]
fn info_prints_the_counts_as_json() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "q.obj",
        "mtllib nowhere.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n\
         vt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\nl 1 2\n",
    );
    let out = prism()
        .arg("info")
        .arg(&obj)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["dialect"], "obj");
    assert_eq!(json["vertices"], 4);
    assert_eq!(json["normals"], 1);
    assert_eq!(json["texcoords"], 1);
    assert_eq!(json["triangles"], 2);
    assert_eq!(json["objects"], 1);
    assert_eq!(json["lights"], 0);
    assert_eq!(
        json["bounds"],
        serde_json::json!([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    );
    let warnings = json["warnings"].as_array().unwrap();
    // The missing library and the skipped line statement.
    assert!(warnings.len() >= 2, "{warnings:?}");
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("q.obj:1:")),
        "{warnings:?}"
    );
}

#[test]
fn malformed_numbers_are_file_line_column_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "bad.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 zero\nf 1 2 3\n",
    );
    let out = dir.path().join("bad.png");
    let result = prism().arg("render").arg(&obj).arg(&out).output().unwrap();
    assert_eq!(result.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("bad.obj:3:7:"), "{stderr}");
    assert!(!out.exists());
    let info = prism().arg("info").arg(&obj).output().unwrap();
    assert_eq!(info.status.code(), Some(2));
}

#[test]
fn linear_outputs_hold_radiance_and_agree_with_the_developed_image() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let common = [
        "--look-from",
        "0,0,5",
        "--look-at",
        "0,0,0",
        "--width",
        "16",
        "--height",
        "8",
    ];
    for ext in ["exr", "hdr", "png"] {
        let out = dir.path().join(format!("t.{ext}"));
        let status = prism()
            .arg("render")
            .arg(&obj)
            .arg(&out)
            .args(common)
            .arg("--quiet")
            .status()
            .unwrap();
        assert!(status.success(), "{ext}");
    }
    let exr = prism::film::read_linear_image(&dir.path().join("t.exr")).unwrap();
    let hdr = prism::film::read_linear_image(&dir.path().join("t.hdr")).unwrap();
    let png = image::open(dir.path().join("t.png")).unwrap().to_rgb8();
    assert_eq!((exr.width, exr.height), (16, 8));
    let develop = prism::film::Develop::display();
    for (i, (e, h)) in exr.pixels.iter().zip(&hdr.pixels).enumerate() {
        for c in 0..3 {
            // Half precision and RGBE's shared exponent.
            assert!(
                (e[c] - h[c]).abs() <= 0.01 * e[c].max(h[c]) + 1e-3,
                "{e:?} {h:?}"
            );
            let expected = (develop.channel(e[c]) * 255.0).round();
            let got = f32::from(png.as_raw()[i * 3 + c]);
            assert!(
                (expected - got).abs() <= 1.0,
                "pixel {i}: {expected} vs {got}"
            );
        }
    }
}

#[test]
fn prism_alone_lists_its_commands() {
    let out = prism().output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for command in ["render", "animate", "info", "bench", "convert"] {
        assert!(
            text.lines().any(|l| l.trim_start().starts_with(command)),
            "{command} missing:\n{text}"
        );
    }
}

#[test]
fn fuzz_findings_are_refused_cleanly() {
    // Each file under fuzz/findings once crashed or hung a reader; now each is a
    // clean error (exit 2) or loads.
    let dir = common::repo().join("fuzz/findings");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            continue;
        }
        seen += 1;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if TEXTURE_EXTENSIONS.contains(&ext) {
            // Scene files name textures; `prism info` would read this one as a scene.
            texture_is_refused_or_whole(&path);
            continue;
        }
        let out = prism().arg("info").arg(&path).output().unwrap();
        let code = out.status.code();
        assert!(
            code == Some(0) || code == Some(2),
            "{}: {:?}\n{}",
            path.display(),
            code,
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
    assert!(seen > 0, "no findings in {}", dir.display());
}

/// Extensions of the image files that `fuzz/findings` may hold, from the `texture` target.
const TEXTURE_EXTENSIONS: [&str; 8] = ["png", "jpg", "bmp", "tga", "ppm", "hdr", "exr", "tex"];

/// The `texture` fuzz target's property: reading `path` as a texture is an error, or a
/// non-empty texture within the limit with one texel per pixel.
fn texture_is_refused_or_whole(path: &Path) {
    use prism::format::image_file::{Encoding, MAX_TEXTURE_PIXELS, read_texture};
    use prism::scene::Texels;
    let Ok(texture) = read_texture(path, Encoding::Linear) else {
        return;
    };
    let pixels = u64::from(texture.width) * u64::from(texture.height);
    let texels = match &texture.texels {
        Texels::Rgba8 { texels, .. } => texels.len(),
        Texels::RgbaF32(texels) => texels.len(),
    };
    assert!(
        pixels > 0 && pixels <= MAX_TEXTURE_PIXELS && texels as u64 == pixels,
        "{}: {}x{}, {texels} texels",
        path.display(),
        texture.width,
        texture.height
    );
}

#[cfg(target_os = "linux")]
#[test]
fn proc_files_named_by_a_scene_neither_block_nor_leak() {
    // /proc/self/environ is a regular file of size 0 that reads as the environment;
    // /proc/kmsg blocks until the kernel logs. Prism reads what their size says: nothing.
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "p.obj",
        "mtllib /proc/self/environ\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    );
    let out = prism()
        .arg("info")
        .arg(&obj)
        .env("PRISM_SECRET_FOR_TEST", "do-not-echo")
        .output()
        .unwrap();
    assert!(out.status.success());
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!all.contains("do-not-echo"), "{all}");
    if Path::new("/proc/kmsg").exists() {
        let obj = write(
            dir.path(),
            "k.obj",
            "mtllib /proc/kmsg\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        );
        let out = prism().arg("info").arg(&obj).output().unwrap();
        assert!(out.status.code().is_some(), "finished, without hanging");
    }
}

#[cfg(unix)]
#[test]
fn an_output_folder_that_cannot_be_written_is_refused_before_rendering() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let locked = dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    if std::fs::write(locked.join("probe"), b"").is_ok() {
        skipped("this user writes into read-only folders (root)");
        return;
    }
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let out = prism()
        .arg("render")
        .arg(&obj)
        .arg(locked.join("t.png"))
        // Enough work that failing afterwards would be noticed.
        .args(["--width", "4000", "--aa", "4"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("cannot write into"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}

#[test]
fn an_environment_image_lights_a_path_render_and_needs_its_file() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let sky = dir.path().join("sky.png");
    image::RgbImage::from_pixel(16, 8, image::Rgb([200, 200, 255]))
        .save(&sky)
        .unwrap();
    let out = dir.path().join("t.png");
    let render = |extra: &[&str]| {
        prism()
            .args(["render"])
            .arg(&obj)
            .arg(&out)
            .args([
                "--integrator",
                "path",
                "--spp",
                "4",
                "--width",
                "32",
                "--height",
                "16",
            ])
            .args(extra)
            .args(["--quiet"])
            .output()
            .unwrap()
    };
    let lit = render(&[
        "--environment",
        sky.to_str().unwrap(),
        "--environment-strength",
        "2",
    ]);
    assert!(
        lit.status.success(),
        "{}",
        String::from_utf8_lossy(&lit.stderr)
    );
    let (left, right) = luminance_by_half(&out);
    assert!(left > 0 && right > 0, "{left} {right}");
    let orphan = render(&["--environment-rotate", "30"]);
    assert!(!orphan.status.success());
    assert!(String::from_utf8_lossy(&orphan.stderr).contains("--environment"));
}

#[test]
fn a_materialx_material_dresses_a_model_and_a_2014_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", RIGHT_TRIANGLE);
    let red = write(
        dir.path(),
        "red.mtlx",
        r#"<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="red" type="surfaceshader">
    <input name="base_color" type="color3" value="1, 0, 0" />
    <input name="specular_weight" type="float" value="0" />
  </open_pbr_surface>
</materialx>"#,
    );
    let out = dir.path().join("t.png");
    let render = |material: &std::path::Path| {
        prism()
            .args(["render"])
            .arg(&obj)
            .arg(&out)
            .args(["--look-from", "0,0,5", "--look-at", "0,0,0", "--fov", "60"])
            .args(["--width", "32", "--height", "16", "--quiet", "--material"])
            .arg(material)
            .output()
            .unwrap()
    };
    let o = render(&red);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    let lit = img
        .pixels()
        .filter(|p| u32::from(p.0[0]) > 2 * u32::from(p.0[1]) + 10)
        .count();
    assert!(lit > 10, "red pixels: {lit}");
    let old = write(
        dir.path(),
        "old.mtlx",
        "newmtl red 255 0 0 1 1 0 1 1 0 0 0\n",
    );
    let o = render(&old);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("expected a MaterialX document"));
}
