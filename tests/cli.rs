//! The `prism` command end to end: renders, options, determinism and bad input.

mod common;
use common::*;
use std::fs;

/// A layer of an EXR file: its name ("" for an unnamed one) and its channels' names
/// and values, in file order.
type ExrLayer = (String, Vec<(String, Vec<f32>)>);

/// The layers of an EXR file.
fn exr_layers(path: &std::path::Path) -> Vec<ExrLayer> {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    image
        .layer_data
        .iter()
        .map(|l| {
            let name = l
                .attributes
                .layer_name
                .as_ref()
                .map_or(String::new(), |n| n.to_string());
            let channels = l
                .channel_data
                .list
                .iter()
                .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
                .collect();
            (name, channels)
        })
        .collect()
}

/// Channel `name` of a layer from [`exr_layers`].
fn exr_channel<'l>(layer: &'l ExrLayer, name: &str) -> &'l [f32] {
    &layer.1.iter().find(|(n, _)| n == name).unwrap().1
}

#[test]
fn report_command_line_and_render_subcommand_give_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.ppm");
    let b = dir.path().join("b.ppm");
    let small = ["--width", "96", "--aa", "1"];
    let o = run(prism()
        .args([example("example.objx"), example("example.cmr"), a.clone()])
        .args(small));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(prism()
        .arg("render")
        .args([example("example.objx"), example("example.cmr"), b.clone()])
        .args(small)
        .arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let img = load_rgb(&a);
    assert_eq!((img.width(), img.height()), (96, 54));
    assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
}

#[test]
fn image_is_identical_for_any_thread_count_and_intersector() {
    let dir = tempfile::tempdir().unwrap();
    let render = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let o = run(prism()
            .args([example("example.objx"), example("example.cmr"), out.clone()])
            .args(["--width", "64", "--aa", "2", "--spp", "11"])
            .args(extra));
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read(out).unwrap()
    };
    let one = render("t1.ppm", &["--threads", "1"]);
    assert_eq!(one, render("t2.ppm", &["--threads", "2"]));
    assert_eq!(
        one,
        render("t3.ppm", &["--threads", "3", "--accel", "list"])
    );
    assert_eq!(one, render("t4.ppm", &["--accel", "octree"]));
    assert_eq!(one, render("t5.ppm", &["--accel", "bvh"]));
    assert_eq!(one, render("t6.ppm", &["--accel", "bvh-copied"]));
    assert_ne!(
        one,
        render("s.ppm", &["--seed", "10"]),
        "the seed must matter with DOF"
    );
}

/// `--dof-rays` and `--aa-filter` are the older names of `--spp` and `--filter`.
#[test]
fn old_flag_names_still_work_and_mean_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let render = |name: &str, flags: &[&str]| {
        let out = dir.path().join(name);
        let o = run(prism()
            .args([example("example.objx"), example("example.cmr"), out.clone()])
            .args(["--width", "48", "--aa", "2"])
            .args(flags));
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read(out).unwrap()
    };
    let new = render("new.ppm", &["--spp", "5", "--filter", "lanczos"]);
    assert_eq!(
        new,
        render("old.ppm", &["--dof-rays", "5", "--aa-filter", "lanczos"])
    );
    assert_ne!(
        new,
        render("other.ppm", &["--spp", "5"]),
        "the filter matters"
    );
}

/// scene1 has eleven JPEG textures, decoded in parallel: on one thread or two, the same
/// texels and so the same PNG, byte for byte.
#[test]
fn a_textured_scene_gives_the_same_file_on_one_thread_and_two() {
    let Some(scene1) = seed_scene("scene1") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let render = |threads: &str| {
        let out = dir.path().join(format!("t{threads}.png"));
        let o = run(prism()
            .arg("render")
            .args([
                scene1.join("scene.objx"),
                scene1.join("scene.cmr"),
                out.clone(),
            ])
            .args(["--width", "96", "--aa", "2", "--dof-rays", "1", "--quiet"])
            .args(["--threads", threads]));
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read(out).unwrap()
    };
    let one = render("1");
    assert_eq!(one, render("2"));
    assert_eq!(one, render("3"));
}

#[test]
fn region_is_the_same_window_of_the_full_frame() {
    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full.png");
    let part = dir.path().join("part.png");
    for filter in ["area", "lanczos"] {
        let common = ["--width", "80", "--aa", "3", "--aa-filter", filter];
        let o = run(prism()
            .args([
                example("example.objx"),
                example("example.cmr"),
                full.clone(),
            ])
            .args(common));
        assert!(o.status.success(), "{}", stderr(&o));
        let o = run(prism()
            .args([
                example("example.objx"),
                example("example.cmr"),
                part.clone(),
            ])
            .args(common)
            .args(["--region", "30,10,25,20"]));
        assert!(o.status.success(), "{}", stderr(&o));
        let full = load_rgb(&full);
        let part = load_rgb(&part);
        assert_eq!((part.width(), part.height()), (25, 20));
        for y in 0..20 {
            for x in 0..25 {
                assert_eq!(
                    part.get_pixel(x, y),
                    full.get_pixel(30 + x, 10 + y),
                    "{filter} at {x},{y}"
                );
            }
        }
    }
}

#[test]
fn stats_prints_one_line_of_figures() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(prism()
        .args([
            example("example.objx"),
            example("example.cmr"),
            dir.path().join("s.bmp"),
        ])
        .args(["--width", "32", "--stats", "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert_eq!(out.lines().count(), 1, "{out}");
    assert!(
        out.contains("rays ") && out.contains("seconds ") && out.contains("Mrays/s "),
        "{out}"
    );
}

#[test]
fn help_documents_every_option() {
    let o = run(prism().arg("--help"));
    assert!(o.status.success());
    let help = String::from_utf8(o.stdout).unwrap();
    for opt in [
        "--width",
        "--height",
        "--region",
        "--aa",
        "--aa-filter",
        "--dof-rays",
        "--threads",
        "--seed",
        "--quiet",
        "--stats",
        "--accel",
        "--denoise",
    ] {
        assert!(help.contains(opt), "{opt} missing from --help");
    }
}

/// Runs prism on a scene written into a temp folder; returns (exit code, stderr) and
/// checks that no output file was left.
fn fails(objx: &str, mtlx: &str, cmr: &str, extra: &[&str]) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("s.objx"), objx).unwrap();
    fs::write(dir.path().join("s.mtlx"), mtlx).unwrap();
    fs::write(dir.path().join("s.cmr"), cmr).unwrap();
    let out = dir.path().join("out.png");
    let o = run(prism()
        .args([
            dir.path().join("s.objx"),
            dir.path().join("s.cmr"),
            out.clone(),
        ])
        .args(extra));
    assert!(!out.exists(), "a failed run left an output file");
    let leftovers: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(leftovers.len(), 3, "a failed run left files behind");
    (o.status.code().unwrap_or(-1), stderr(&o))
}

const MTL: &str = "newmtl m 255 0 0 1 1 0 1 1 0 0 0\n";
const CMR: &str = "0 0 0\n90 0\n1\n1\n8 8\n0.1\n1 0\n1 1\n";

#[test]
fn malformed_scene_reports_file_line_and_expectation_with_exit_2() {
    let cases = [
        (
            "mtllib s.mtlx\nusemtl m\nv 0 0 0\nf 0 -2\n",
            "s.objx:4:",
            "radius",
        ),
        (
            "mtllib s.mtlx\nv 0 0 0\nv 1 0 0\nf 0 1 7\n",
            "s.objx:4:",
            "out of range",
        ),
        ("mtllib s.mtlx\nbogus 1 2\n", "s.objx:2:", "unknown keyword"),
        ("mtllib s.mtlx\nv 0 zero 0\n", "s.objx:2:", "zero"),
        ("mtllib s.mtlx\nusemtl nope\n", "s.objx:2:", "nope"),
        ("mtllib missing.mtlx\n", "s.objx:1:", "missing.mtlx"),
        (
            "mtllib s.mtlx\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 2 0\nf 0 1 2 3\n",
            "s.objx:6:",
            "rectangle",
        ),
    ];
    for (objx, place, word) in cases {
        let (code, err) = fails(objx, MTL, CMR, &[]);
        assert_eq!(code, 2, "{objx}: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(
            err.contains(place) && err.contains(word),
            "{objx}\n=> {err}"
        );
    }
}

#[test]
fn malformed_materials_and_cameras_are_reported_too() {
    let scene = "mtllib s.mtlx\n";
    let (code, err) = fails(
        scene,
        "# header\nnewmtl m 255 0 0 1 1 0 1 1 0 0 0 nothere.png\n",
        CMR,
        &[],
    );
    assert_eq!(code, 2);
    assert!(
        err.contains("s.mtlx:2:") && err.contains("nothere.png"),
        "{err}"
    );
    // An image file that is not an image.
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("junk.png"), "not a png").unwrap();
    fs::write(
        dir.path().join("s.mtlx"),
        "newmtl m 255 0 0 1 1 0 1 1 0 0 0 junk.png\n",
    )
    .unwrap();
    fs::write(dir.path().join("s.objx"), scene).unwrap();
    fs::write(dir.path().join("s.cmr"), CMR).unwrap();
    let out = dir.path().join("o.png");
    let o = run(prism().args([
        dir.path().join("s.objx"),
        dir.path().join("s.cmr"),
        out.clone(),
    ]));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("s.mtlx:1:") && stderr(&o).contains("junk.png"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());

    let (code, err) = fails(scene, &format!("{MTL}{MTL}"), CMR, &[]);
    assert_eq!(code, 2);
    assert!(err.contains("s.mtlx:2:") && err.contains("m"), "{err}");
    let (code, err) = fails(scene, MTL, "0 0 0\n90 0\n1\n1\n8 8\n", &[]);
    assert_eq!(code, 2);
    assert!(err.contains("s.cmr:5:"), "{err}");
    let (code, err) = fails(scene, MTL, "0 0 0\n90 0\n1\n1\n8 nan\n0.1\n1 0\n1 1\n", &[]);
    assert_eq!(code, 2);
    assert!(err.contains("s.cmr:5:"), "{err}");
}

#[test]
fn bad_options_and_outputs_exit_2_without_output() {
    let scene = "mtllib s.mtlx\n";
    let (code, err) = fails(scene, MTL, CMR, &["--width", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("width"), "{err}");
    let (code, err) = fails(
        scene,
        MTL,
        CMR,
        &["--aa", "16", "--dof-rays", "65536", "--width", "60000"],
    );
    assert_eq!(code, 2);
    assert!(err.contains("limit"), "{err}");
    let (code, _) = fails(scene, MTL, CMR, &["--aa-filter", "sinc"]);
    assert_eq!(code, 2);
    let (code, _) = fails(scene, MTL, CMR, &["--region", "1,2"]);
    assert_eq!(code, 2);

    let dir = tempfile::tempdir().unwrap();
    for out in [dir.path().join("x.webp"), dir.path().join("nodir/x.png")] {
        let o = run(prism().args([example("example.objx"), example("example.cmr"), out.clone()]));
        assert_eq!(o.status.code(), Some(2));
        assert!(!out.exists());
    }
    let o = run(prism().arg("only-one-arg"));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("Usage"), "{}", stderr(&o));
}

/// The path model's samples depend on (seed, pixel, sample) alone: the same EXR bytes
/// on one thread and three (a shadow ray toward every light, or toward one the light
/// tree draws), a region equal to its window of the full frame, and another seed
/// another image.
#[test]
fn a_path_traced_image_is_the_same_on_any_thread_count_and_in_any_window() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/showcase/showcase.toml");
    let render = |name: &str, more: &[&str]| {
        let out = dir.path().join(name);
        let o = run(prism()
            .arg("render")
            .arg(&scene)
            .arg(&out)
            .args([
                "--integrator",
                "path",
                "--width",
                "48",
                "--spp",
                "4",
                "--quiet",
            ])
            .args(["--exr-precision", "float"])
            .args(more));
        assert!(o.status.success(), "{}", stderr(&o));
        out
    };
    let one = fs::read(render("t1.exr", &["--threads", "1"])).unwrap();
    assert_eq!(
        one,
        fs::read(render("t3.exr", &["--threads", "3"])).unwrap()
    );
    assert_ne!(one, fs::read(render("s1.exr", &["--seed", "1"])).unwrap());
    // A light drawn from the tree too.
    let tree = ["--light-sampling", "tree"];
    let one = fs::read(render(
        "tree1.exr",
        &[&tree[..], &["--threads", "1"]].concat(),
    ))
    .unwrap();
    let three = fs::read(render(
        "tree3.exr",
        &[&tree[..], &["--threads", "3"]].concat(),
    ))
    .unwrap();
    assert_eq!(one, three);
    let full = load_rgb(&render("full.png", &[]));
    let part = load_rgb(&render("part.png", &["--region", "10,5,20,12"]));
    for y in 0..12 {
        for x in 0..20 {
            assert_eq!(
                part.get_pixel(x, y),
                full.get_pixel(10 + x, 5 + y),
                "{x},{y}"
            );
        }
    }
}

/// `--aov` writes the albedo, the normal and the distance of what each pixel sees as
/// layers of the EXR, beside the image: a floor of a known colour seen from above.
#[test]
fn passes_are_layers_of_the_exr_with_the_floor_s_albedo_normal_and_distance() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("floor.toml");
    fs::write(
        &scene,
        "[camera]\nfrom = [0, 2, 0]\nat = [0, 0, 0]\nup = [0, 0, -1]\nfov = 20\n\
         [render]\nwidth = 8\nheight = 8\n\
         [[light]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 2\n\
         [[material]]\nname = \"paint\"\ncolor = [0.25, 0.5, 0.75]\n\
         [[object]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"paint\"\n",
    )
    .unwrap();
    for integrator in ["whitted", "path"] {
        let out = dir.path().join(format!("{integrator}.exr"));
        let o = run(prism()
            .arg("render")
            .arg(&scene)
            .arg(&out)
            .args(["--integrator", integrator, "--spp", "4", "--quiet"])
            .args(["--aov", "albedo,normal,depth", "--exr-precision", "float"]));
        assert!(o.status.success(), "{}", stderr(&o));
        let layers = exr_layers(&out);
        let names: Vec<&str> = layers.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["image", "albedo", "normal", "depth"]);
        let channel = |layer: usize, name: &str| exr_channel(&layers[layer], name);
        for (name, want) in [("R", 0.25), ("G", 0.5), ("B", 0.75)] {
            assert!(
                channel(1, name).iter().all(|&v| (v - want).abs() < 1e-6),
                "{name}"
            );
        }
        assert!(channel(2, "Y").iter().all(|&v| (v - 1.0).abs() < 1e-6));
        assert!(channel(2, "X").iter().all(|&v| v.abs() < 1e-6));
        // The distance grows toward the corners: 2 / cos of the ray's angle.
        let depth = channel(3, "Z");
        let centre = depth[3 * 8 + 3];
        assert!((centre - 2.0).abs() < 0.01, "{centre}");
        assert!(depth[0] > centre && depth[0] < 2.0 / (10f32.to_radians().cos().powi(2)));
        // The image is still the first part.
        assert!(channel(0, "R").iter().any(|&v| v > 0.0));
    }
    let o = run(prism()
        .arg("render")
        .arg(&scene)
        .arg(dir.path().join("out.png"))
        .args(["--aov", "albedo"]));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("OpenEXR"), "{}", stderr(&o));
    assert!(!dir.path().join("out.png").exists());
}

/// `--aov alpha,background` writes coverage and the background seen straight: a ball
/// on a blue sky, whose image less the background is the ball on a transparent film.
#[test]
fn alpha_and_background_passes_take_the_sky_out_of_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("ball.toml");
    fs::write(
        &scene,
        "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nfov = 40\n\
         [render]\nwidth = 16\nheight = 16\n\
         [background]\ncolor = [0.2, 0.4, 0.8]\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -1, -1]\n\
         [[object]]\ntype = \"sphere\"\nradius = 1\n",
    )
    .unwrap();
    let out = dir.path().join("ball.exr");
    let o = run(prism()
        .arg("render")
        .arg(&scene)
        .arg(&out)
        .args(["--integrator", "path", "--spp", "4", "--quiet"])
        .args(["--aov", "alpha,background", "--exr-precision", "float"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let layers = exr_layers(&out);
    let names: Vec<&str> = layers.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["image", "alpha", "background"]);
    let alpha = exr_channel(&layers[1], "A");
    let (image_b, sky_b) = (exr_channel(&layers[0], "B"), exr_channel(&layers[2], "B"));
    let centre = 8 * 16 + 8;
    assert_eq!((alpha[0], alpha[centre]), (0.0, 1.0));
    assert!(
        alpha.iter().any(|&a| a > 0.0 && a < 1.0),
        "the ball's outline"
    );
    assert_eq!((image_b[0], sky_b[0]), (0.8, 0.8));
    assert_eq!(sky_b[centre], 0.0);
}

/// The albedo pass looks through perfect mirrors and glass to the first surface with a
/// colour of its own, tinted by what it passed (a denoiser reads a mirror's reflection
/// as the mirror's texture): a mirror floor showing a red ceiling, a glass pane over a
/// blue floor.
#[test]
fn the_albedo_pass_shows_what_mirrors_and_glass_show() {
    let dir = tempfile::tempdir().unwrap();
    let camera = "[camera]\nfrom = [0, 2, 0]\nat = [0, 0, 0]\nup = [0, 0, -1]\nfov = 20\n\
                  [render]\nwidth = 4\nheight = 4\n\
                  [[light]]\ntype = \"point\"\nposition = [0, 3, 0]\n";
    let cases = [
        (
            "mirror",
            "[[object]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\n\
             material = { color = [0, 0, 0], diffuse = 0, reflection = 0.5 }\n\
             [[object]]\ntype = \"plane\"\npoint = [0, 4, 0]\nnormal = [0, -1, 0]\n\
             material = { color = [0.8, 0.2, 0.1] }\n",
            [0.4, 0.1, 0.05],
        ),
        (
            "glass",
            "[[object]]\ntype = \"plane\"\npoint = [0, 1, 0]\nnormal = [0, 1, 0]\n\
             material = { color = [0, 0, 0], diffuse = 0, transmission = 0.5, ior = 1.5, \
             fresnel = true }\n\
             [[object]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\n\
             material = { color = [0.25, 0.5, 0.75] }\n",
            [0.125, 0.25, 0.375],
        ),
    ];
    for (name, objects, want) in cases {
        let scene = dir.path().join(format!("{name}.toml"));
        fs::write(&scene, format!("{camera}{objects}")).unwrap();
        for integrator in ["whitted", "path"] {
            let out = dir.path().join(format!("{name}-{integrator}.exr"));
            let o = run(prism()
                .arg("render")
                .arg(&scene)
                .arg(&out)
                .args(["--integrator", integrator, "--quiet"])
                .args(["--aov", "albedo", "--exr-precision", "float"]));
            assert!(o.status.success(), "{}", stderr(&o));
            let layers = exr_layers(&out);
            for (channel, want) in ["R", "G", "B"].into_iter().zip(want) {
                for &v in exr_channel(&layers[1], channel) {
                    assert!(
                        (v - want).abs() < 1e-6,
                        "{name} {integrator} {channel}: {v}"
                    );
                }
            }
        }
    }
}

fn showcase() -> std::path::PathBuf {
    repo().join("scenes/showcase/showcase.toml")
}

/// A Prism built without Open Image Denoise refuses `--denoise` before it renders,
/// saying how to build one that has it, and writes nothing.
#[cfg(not(feature = "oidn"))]
#[test]
fn without_oidn_denoise_is_refused_with_how_to_build_it_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["out.png", "out.exr"] {
        let out = dir.path().join(name);
        let o = run(prism()
            .arg("render")
            .arg(showcase())
            .arg(&out)
            .args(["--width", "32", "--integrator", "path", "--spp", "4"])
            .args(["--denoise", "--quiet"]));
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.starts_with(
                "error: cannot denoise: this Prism was built without Intel Open Image Denoise"
            ),
            "{e}"
        );
        assert!(
            e.contains("--features oidn") && e.contains("OIDN_DIR"),
            "{e}"
        );
        assert!(!out.exists());
    }
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// `--denoise` writes the denoised image in any format; with `--aov` the EXR's image
/// is the denoised one and its passes are those of the render as before.
#[cfg(feature = "oidn")]
#[test]
fn denoise_writes_the_denoised_image_and_the_passes_as_before() {
    let dir = tempfile::tempdir().unwrap();
    let render = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let o = run(prism()
            .arg("render")
            .arg(showcase())
            .arg(&out)
            .args([
                "--width",
                "64",
                "--aa",
                "1",
                "--integrator",
                "path",
                "--spp",
                "4",
            ])
            .args(["--exr-precision", "float", "--quiet"])
            .args(extra));
        assert!(o.status.success(), "{}", stderr(&o));
        out
    };
    let png = render("denoised.png", &["--denoise"]);
    let noisy = render("noisy.png", &[]);
    let (a, b) = (load_rgb(&png), load_rgb(&noisy));
    assert_eq!(a.dimensions(), (64, 36));
    assert_ne!(a, b);
    // Each layer's name and all its values, channel after channel.
    let layers = |path: &std::path::Path| -> Vec<(String, Vec<f32>)> {
        exr_layers(path)
            .into_iter()
            .map(|(name, channels)| (name, channels.into_iter().flat_map(|(_, v)| v).collect()))
            .collect()
    };
    let aov = ["--aov", "albedo,normal,depth"];
    let plain = layers(&render("plain.exr", &aov));
    let denoised = layers(&render(
        "denoised.exr",
        &[&aov[..], &["--denoise"]].concat(),
    ));
    let names = |l: &[(String, Vec<f32>)]| l.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&denoised), ["image", "albedo", "normal", "depth"]);
    assert_ne!(denoised[0].1, plain[0].1);
    assert_eq!(denoised[1..], plain[1..]);
    // Passes not asked for are rendered for the denoiser but not written.
    let depth_only = layers(&render("depth.exr", &["--aov", "depth", "--denoise"]));
    assert_eq!(names(&depth_only), ["image", "depth"]);
    assert_eq!(depth_only[0].1, denoised[0].1);
}
