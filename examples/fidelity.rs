//! How faithfully Prism reproduces the figures of the 2014 course report.
//!
//! `cargo run --release --example fidelity -- [--full] [--out DIR]`
//!
//! The six reference crops in `shared/seed-scenes/Ray-Tracing/report/` are pieces of the
//! author's renders at reduced size: scene0's at 960 x 540 (a quarter of the 3840 x 2160
//! frame of `scene.cmr`), scene1's at 1920 x 1080. For each crop this renders the scene at
//! a range of frame widths (same field of view: the retina scale follows the width), finds
//! the crop by template matching (zero-mean NCC of luma) and reports the best width, the
//! offset of the crop in that frame, NCC, PSNR and SSIM.
//!
//! - `org`, `aa`: scene0 with its camera file, anti-aliasing 1 and 4.
//! - `org1`, `aa1`, `org2`, `dof2`: scene1, not as `scene.cmr` shows it: the figures are a
//!   frame of the author's animation; [`scene1_pose`] is the camera and marble placement
//!   found by the search described in `docs/fidelity.md`. `dof2` uses depth of field,
//!   rendered only over the window where `org2` was found, at anti-aliasing 1, with 32 lens
//!   rays (128 with `--full`, which also adds a corner-ray `dof2` row).
//!
//! Rows marked `corners` emulate the 2014 program's camera rays through pixel *corners*
//! (SPEC 3.1; Prism uses centres): a frame one pixel wider and taller at the same retina
//! scale has its pixel centres exactly on the corners of the smaller frame's pixels. The
//! width search for them is a narrow one around the width found for the plain row.
//!
//! Side-by-side images (Prism left, report right, absolute difference x4 below) are written
//! to `--out` (default `target/fidelity`).

use prism::compare::{RgbImage, crop, match_template, mean_abs_diff, psnr, ssim};
use prism::format::{load_camera, load_scene};
use prism::math::Vec3;
use prism::render::{Region, RenderSettings, Renderer};
use prism::scene::{Camera, Scene, Shape};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn seed_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/seed-scenes/Ray-Tracing")
}

/// An owned 8-bit RGB image.
#[derive(Clone)]
struct Rgb {
    width: u32,
    height: u32,
    data: Vec<u8>,
}

impl Rgb {
    fn view(&self) -> RgbImage<'_> {
        RgbImage::new(self.width, self.height, &self.data)
    }

    fn load(path: &Path) -> Rgb {
        let img = image::open(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgb8();
        Rgb {
            width: img.width(),
            height: img.height(),
            data: img.into_raw(),
        }
    }

    fn save(&self, path: &Path) {
        image::save_buffer(
            path,
            &self.data,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

/// A camera and marble placement for scene1.
pub struct Pose {
    pub eye: Vec3,
    pub theta_deg: f32,
    pub phi_deg: f32,
    pub focal_length: f32,
    /// Centres of marble0..marble4 (radius 15, materials `marble0`..`marble4`).
    pub marbles: [Vec3; 5],
}

/// Marble centres as `scene1/scene.objx` states them (vertices 64..68).
const FILE_MARBLES: [[f32; 3]; 5] = [
    [54.5636, -21.1098, 275.436],
    [-67.2896, -6.40616, 403.696],
    [31.6648, 0.0, 214.253],
    [0.0, 60.2716, 456.362],
    [-158.891, -18.806, 330.0],
];

/// Centre of scene1's glass sphere, about which the animation turns everything.
const GLASS_CENTRE: [f64; 3] = [0.0, 0.0, 330.0];

/// `v` turned by `deg` degrees about the axis `k` (right-hand rule), Rodrigues' formula.
fn rotate(v: [f64; 3], k: [f64; 3], deg: f64) -> [f64; 3] {
    let n = (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
    let k = k.map(|c| c / n);
    let (s, c) = deg.to_radians().sin_cos();
    let dot = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    let cross = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    std::array::from_fn(|i| v[i] * c + cross[i] * s + k[i] * dot * (1.0 - c))
}

/// The pose of the report's scene1 figures (`docs/fidelity.md`, "scene1"): one frame of
/// the author's animation, found by template matching and exact to the digits given.
///
/// - Camera: relative to `scene.cmr` it has turned -42 degrees about the vertical axis
///   through the glass sphere's centre C = (0, 0, 330) (phi 64.5 -> 22.5). It looks
///   straight at C from 360.75 away, 19 degrees above it (theta 109), and focuses on C:
///   f = |eye - C|, the convention of `scene.cmr`, whose f is its eye's distance to C.
/// - Marbles: each has turned on its shell about its own axis through C (right-hand
///   rule): marble0 -97.2 degrees about (1,0,1), marble1 -42 about (1,1,1), marble2 -97.2
///   about (0,1,0), marble3 -42 about (1,0,0), marble4 -63 about (0,0,1).
pub fn scene1_pose() -> Pose {
    const TURNS: [([f64; 3], f64); 5] = [
        ([1.0, 0.0, 1.0], -97.2),
        ([1.0, 1.0, 1.0], -42.0),
        ([0.0, 1.0, 0.0], -97.2),
        ([1.0, 0.0, 0.0], -42.0),
        ([0.0, 0.0, 1.0], -63.0),
    ];
    let c = GLASS_CENTRE;
    let to_vec = |p: [f64; 3]| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
    let marbles = std::array::from_fn(|i| {
        let offset = std::array::from_fn(|j| f64::from(FILE_MARBLES[i][j]) - c[j]);
        let (axis, deg) = TURNS[i];
        let p = rotate(offset, axis, deg);
        to_vec(std::array::from_fn(|j| c[j] + p[j]))
    });
    let (distance, elevation, azimuth) = (360.75f64, 19f64.to_radians(), 202.5f64.to_radians());
    let eye = [
        distance * elevation.cos() * azimuth.cos(),
        distance * elevation.cos() * azimuth.sin(),
        c[2] + distance * elevation.sin(),
    ];
    Pose {
        eye: to_vec(eye),
        theta_deg: 109.0,
        phi_deg: 22.5,
        focal_length: distance as f32,
        marbles,
    }
}

/// `scene` with its marbles moved and `camera` with the pose's eye, angles and focus.
fn apply_pose(scene: &Scene, camera: &Camera, pose: &Pose) -> (Scene, Camera) {
    let mut scene = scene.clone();
    for (file, new) in FILE_MARBLES.iter().zip(pose.marbles) {
        let file = Vec3::from_array(*file);
        let (i, mut sphere) = scene
            .shapes
            .iter()
            .enumerate()
            .find_map(|(i, s)| match s {
                Shape::Sphere(sp) if (sp.center - file).length() < 1e-2 => Some((i, sp)),
                _ => None,
            })
            .unwrap_or_else(|| panic!("scene1 has no marble at {file}"));
        sphere.center = new;
        scene.shapes.set(i, Shape::Sphere(sphere));
    }
    let mut camera = camera.clone();
    camera.eye = pose.eye;
    camera.theta_deg = pose.theta_deg;
    camera.phi_deg = pose.phi_deg;
    camera.focal_length = pose.focal_length;
    (scene, camera)
}

/// How to render one crop.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Job {
    aa: u32,
    rays: u32,
    /// Camera rays through pixel corners, as the 2014 program traced them.
    corners: bool,
}

impl Job {
    const PLAIN: Job = Job {
        aa: 1,
        rays: 1,
        corners: false,
    };

    fn corners(self) -> Job {
        Job {
            corners: true,
            ..self
        }
    }
}

/// Frame height for a width: the camera's aspect, rounded as the renderer does.
fn frame_height(camera: &Camera, width: u32) -> u32 {
    let h = u64::from(camera.height) * u64::from(width);
    ((h + u64::from(camera.width) / 2) / u64::from(camera.width)) as u32
}

/// Renders `region` (default: all) of the `width` x `frame_height` frame.
fn render(scene: &Scene, camera: &Camera, width: u32, job: Job, region: Option<Region>) -> Rgb {
    let height = frame_height(camera, width);
    let mut cam = camera.with_resolution(width, height);
    if job.corners {
        // One more pixel each way at the same retina scale: the screen grows by one pixel
        // pitch, so these pixel centres are the corners of the width x height frame's.
        cam.width += 1;
        cam.height += 1;
    }
    let region = region.unwrap_or(Region {
        x: 0,
        y: 0,
        width,
        height,
    });
    let settings = RenderSettings {
        aa: Some(job.aa),
        spp: Some(job.rays),
        region: Some(region),
        ..Default::default()
    };
    let renderer = Renderer::new(scene, &cam, settings).expect("valid render settings");
    let (img, _) = renderer.render(&()).expect("render");
    Rgb {
        width: img.width,
        height: img.height,
        data: img.to_rgb8(),
    }
}

/// Where a crop was found and how well it agrees.
#[derive(Clone)]
struct Found {
    width: u32,
    height: u32,
    x: u32,
    y: u32,
    ncc: f64,
    psnr: f64,
    ssim: f64,
    mad: f64,
    /// The matched window of the render.
    window: Vec<u8>,
}

/// One scene seen by one camera, with whole frames kept for reuse by several crops.
struct View<'a> {
    scene: &'a Scene,
    camera: &'a Camera,
    frames: RefCell<HashMap<(u32, Job), Rgb>>,
}

impl View<'_> {
    fn frame(&self, width: u32, job: Job) -> Rgb {
        let mut frames = self.frames.borrow_mut();
        frames
            .entry((width, job))
            .or_insert_with(|| render(self.scene, self.camera, width, job, None))
            .clone()
    }

    /// Renders the frame at `width` (or only a window around `guess`, the expected top-left
    /// of the crop, `margin` pixels larger each way), finds `tpl` in it and scores it.
    fn try_width(
        &self,
        tpl: &Rgb,
        width: u32,
        job: Job,
        guess: Option<(f64, f64)>,
        margin: u32,
    ) -> Option<Found> {
        let height = frame_height(self.camera, width);
        if tpl.width > width || tpl.height > height {
            return None;
        }
        let region = guess.map(|(gx, gy)| {
            let place = |g: f64, max: u32| {
                (g - f64::from(margin)).round().clamp(0.0, f64::from(max)) as u32
            };
            let (x0, y0) = (place(gx, width - tpl.width), place(gy, height - tpl.height));
            Region {
                x: x0,
                y: y0,
                width: (tpl.width + 2 * margin).min(width - x0),
                height: (tpl.height + 2 * margin).min(height - y0),
            }
        });
        let img = match region {
            Some(r) => render(self.scene, self.camera, width, job, Some(r)),
            None => self.frame(width, job),
        };
        let m = match_template(&img.view(), &tpl.view());
        let window = crop(&img.view(), m.x, m.y, tpl.width, tpl.height);
        let (a, b) = (RgbImage::new(tpl.width, tpl.height, &window), tpl.view());
        let (ox, oy) = region.map_or((0, 0), |r| (r.x, r.y));
        Some(Found {
            width,
            height,
            x: ox + m.x,
            y: oy + m.y,
            ncc: m.ncc,
            psnr: psnr(&a, &b),
            ssim: ssim(&a, &b),
            mad: mean_abs_diff(&a, &b),
            window,
        })
    }

    /// Whole frames at the `coarse` widths, then every width within `fine` of the best
    /// (windows around the predicted position).
    fn search(
        &self,
        tpl: &Rgb,
        coarse: impl IntoIterator<Item = u32>,
        fine: u32,
        job: Job,
    ) -> Found {
        let coarse = coarse
            .into_iter()
            .map(|w| self.try_width(tpl, w, job, None, 0));
        self.refine(tpl, &best_of(coarse), fine, job)
    }

    /// Every width within `fine` of `start`'s, rendering windows where the crop should be.
    fn refine(&self, tpl: &Rgb, start: &Found, fine: u32, job: Job) -> Found {
        let widths = start.width.saturating_sub(fine)..=start.width + fine;
        let found = widths.map(|w| {
            let guess = predict(start, self.camera, w, tpl);
            self.try_width(tpl, w, job, Some(guess), 8)
        });
        best_of(found)
    }
}

/// The best by NCC.
fn best_of(found: impl IntoIterator<Item = Option<Found>>) -> Found {
    found
        .into_iter()
        .flatten()
        .reduce(|a, b| if b.ncc > a.ncc { b } else { a })
        .expect("at least one width fits the crop")
}

/// Where the top-left of a crop found at `f` lies in a frame `width` wide: the image
/// scales about the frame's centre.
fn predict(f: &Found, camera: &Camera, width: u32, tpl: &Rgb) -> (f64, f64) {
    let r = f64::from(width) / f64::from(f.width);
    let height = f64::from(frame_height(camera, width));
    let (tw, th) = (f64::from(tpl.width), f64::from(tpl.height));
    let cx = f64::from(f.x) + tw / 2.0 - f64::from(f.width) / 2.0;
    let cy = f64::from(f.y) + th / 2.0 - f64::from(f.height) / 2.0;
    (
        cx * r + f64::from(width) / 2.0 - tw / 2.0,
        cy * r + height / 2.0 - th / 2.0,
    )
}

/// Writes `<name>-prism.png` and `<name>-side.png`: Prism | report over |difference| x 4.
fn write_images(dir: &Path, name: &str, tpl: &Rgb, found: &Found) {
    let (w, h) = (tpl.width as usize, tpl.height as usize);
    let mut out = vec![0u8; 4 * w * h * 3];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) * 3;
            for c in 0..3 {
                let (p, r) = (found.window[i + c], tpl.data[i + c]);
                out[(y * 2 * w + x) * 3 + c] = p;
                out[(y * 2 * w + w + x) * 3 + c] = r;
                out[((y + h) * 2 * w + x) * 3 + c] = p.abs_diff(r).saturating_mul(4);
            }
        }
    }
    let side = Rgb {
        width: 2 * tpl.width,
        height: 2 * tpl.height,
        data: out,
    };
    side.save(&dir.join(format!("{name}-side.png")));
    let prism = Rgb {
        width: tpl.width,
        height: tpl.height,
        data: found.window.clone(),
    };
    prism.save(&dir.join(format!("{name}-prism.png")));
}

struct Row {
    crop: &'static str,
    label: String,
    scene: &'static str,
    job: Job,
    found: Found,
    seconds: f64,
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let full = args.iter().any(|a| a == "--full");
    let out_dir = args
        .iter()
        .position(|a| a == "--out")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fidelity"));
    let dir = seed_dir();
    if !dir.is_dir() {
        eprintln!("{} is absent: nothing to compare against", dir.display());
        return;
    }
    std::fs::create_dir_all(&out_dir).expect("output directory");
    let report = |n: &str| Rgb::load(&dir.join("report").join(format!("{n}.png")));
    let load = |s: &str| {
        let d = dir.join(s);
        (
            load_scene(&d.join("scene.objx")).expect("scene"),
            load_camera(&d.join("scene.cmr")).expect("camera"),
        )
    };
    let (scene0, camera0) = load("scene0");
    let (scene1_file, camera1_file) = load("scene1");
    let (scene1, camera1) = apply_pose(&scene1_file, &camera1_file, &scene1_pose());
    let view0 = View {
        scene: &scene0,
        camera: &camera0,
        frames: RefCell::default(),
    };
    let view1 = View {
        scene: &scene1,
        camera: &camera1,
        frames: RefCell::default(),
    };
    let plain = Job::PLAIN;
    let aa4 = Job { aa: 4, ..plain };
    let dof = Job {
        rays: if full { 128 } else { 32 },
        ..plain
    };

    let mut rows: Vec<Row> = Vec::new();
    let mut run = |crop: &'static str, scene: &'static str, job: Job, f: &dyn Fn(&Rgb) -> Found| {
        let tpl = report(crop);
        let t = Instant::now();
        let found = f(&tpl);
        let seconds = t.elapsed().as_secs_f64();
        let label = if job.corners {
            format!("{crop} (corners)")
        } else {
            crop.to_string()
        };
        let file = label.replace(" (corners)", "-corners");
        write_images(&out_dir, &file, &tpl, &found);
        eprintln!(
            "{label}: width {} at ({}, {}), NCC {:.4}, PSNR {:.2}, SSIM {:.4}, {seconds:.1} s",
            found.width, found.x, found.y, found.ncc, found.psnr, found.ssim
        );
        rows.push(Row {
            crop,
            label,
            scene,
            job,
            found: found.clone(),
            seconds,
        });
        found
    };
    // Where a crop found at `f` would sit; searched within 8 px at `f`'s width +-`fine`.
    let near = |view: &View, tpl: &Rgb, f: &Found, fine: u32, job: Job| {
        let start = Found {
            ncc: f64::NEG_INFINITY,
            ..f.clone()
        };
        view.refine(tpl, &start, fine, job)
    };

    // scene0: whole frames 940..=1010 in steps of 5, then every width within 4 of the best.
    let org = run("org", "scene0", plain, &|tpl| {
        view0.search(tpl, (940..=1010).step_by(5), 4, plain)
    });
    run("org", "scene0", plain.corners(), &|tpl| {
        near(&view0, tpl, &org, 2, plain.corners())
    });
    run("aa", "scene0", aa4, &|tpl| near(&view0, tpl, &org, 1, aa4));

    // scene1 at the animation pose: about half the 3840 frame.
    let org2 = run("org2", "scene1", plain, &|tpl| {
        view1.search(tpl, (1880..=1960).step_by(20), 4, plain)
    });
    let org2_corners = run("org2", "scene1", plain.corners(), &|tpl| {
        near(&view1, tpl, &org2, 2, plain.corners())
    });
    let org1 = run("org1", "scene1", plain, &|tpl| {
        view1.search(tpl, (1880..=1960).step_by(20), 4, plain)
    });
    run("org1", "scene1", plain.corners(), &|tpl| {
        near(&view1, tpl, &org1, 2, plain.corners())
    });
    run("aa1", "scene1", aa4, &|tpl| {
        near(&view1, tpl, &org1, 1, aa4)
    });
    // Depth of field is costly: only the window where org2 was found, a few pixels larger.
    let dof_at = |tpl: &Rgb, at: &Found, job: Job| {
        let guess = Some((at.x.into(), at.y.into()));
        view1
            .try_width(tpl, at.width, job, guess, 3)
            .expect("the crop fits")
    };
    run("dof2", "scene1", dof, &|tpl| dof_at(tpl, &org2, dof));
    if full {
        let job = dof.corners();
        run("dof2", "scene1", job, &|tpl| {
            dof_at(tpl, &org2_corners, job)
        });
    }

    println!(
        "| crop | size | scene | AA | DOF rays | frame | 3840 / width | offset | NCC | PSNR dB | SSIM | mean abs diff | s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let f = &r.found;
        let tpl = report(r.crop);
        println!(
            "| {} | {}x{} | {} | {} | {} | {}x{} | {:.3} | ({}, {}) | {:.4} | {:.2} | {:.4} | {:.2} | {:.1} |",
            r.label,
            tpl.width,
            tpl.height,
            if r.scene == "scene1" {
                "scene1 (pose)"
            } else {
                "scene0"
            },
            r.job.aa,
            r.job.rays,
            f.width,
            f.height,
            3840.0 / f64::from(f.width),
            f.x,
            f.y,
            f.ncc,
            f.psnr,
            f.ssim,
            f.mad,
            r.seconds
        );
    }
    let pose = scene1_pose();
    println!(
        "\nscene1 pose: eye {:.4} theta {} phi {} focal length {}",
        pose.eye, pose.theta_deg, pose.phi_deg, pose.focal_length
    );
    for (i, m) in pose.marbles.iter().enumerate() {
        println!("  marble{i} centre {m:.4}");
    }
    println!("side-by-side images: {}", out_dir.display());
}
