//! Throughput measurement: how fast an intersector is built and answers the two
//! queries a Whitted renderer asks, and how long a whole classic frame takes.
//!
//! Primary rays are the camera's pinhole rays, one per pixel, closest hit only; shadow
//! rays run from the first light to each primary hit point, any hit, the way the
//! classic model casts them. Each pass is repeated until it has run for a minimum time,
//! so small scenes are measured over many passes and large ones over one.

use std::path::Path;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::accel::{Accel, AccelKind};
use crate::math::{Ray, Vec3, surface_epsilon};
use crate::render::{CameraRays, RenderSettings, Renderer};
use crate::scene::{Camera, Scene, Shape};
use crate::{Error, Result};

/// Pixels a benchmark camera may have: its rays and hit points are held at once
/// (about 50 bytes a pixel), so a frame of 65536 x 65536 would need hundreds of GB.
pub const MAX_BENCH_PIXELS: u64 = 1 << 24;

/// What to measure and how.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub accel: AccelKind,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Each ray pass repeats until it has run this long in total.
    pub min_seconds: f64,
    /// Also render and time a full classic frame with the camera's own settings.
    pub frame: bool,
    /// Image width instead of the camera's (the height follows its aspect ratio).
    pub width: Option<u32>,
}

impl Default for BenchOptions {
    fn default() -> BenchOptions {
        BenchOptions {
            accel: AccelKind::default(),
            threads: None,
            min_seconds: 1.0,
            frame: true,
            width: None,
        }
    }
}

/// The figures of one benchmark run.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchReport {
    pub accel: AccelKind,
    pub threads: usize,
    pub width: u32,
    pub height: u32,
    /// Seconds to build the intersector.
    pub build_s: f64,
    pub primitives: usize,
    /// Bytes of the shapes, their material indices and the intersector.
    pub bytes: usize,
    pub primary_mrays: f64,
    pub shadow_mrays: f64,
    /// Seconds of a full classic frame, or `None` when not asked for.
    pub frame_s: Option<f64>,
    /// Share of primary rays that hit something.
    pub hit_fraction: f64,
    /// Whether the shadow rays came from a scene light or, lacking one, the eye.
    pub light_from_scene: bool,
}

impl BenchReport {
    pub fn bytes_per_primitive(&self) -> f64 {
        self.bytes as f64 / self.primitives.max(1) as f64
    }

    /// One JSON object; the keys are stable for scripts.
    pub fn to_json(&self) -> String {
        let frame = self
            .frame_s
            .map_or_else(|| "null".to_owned(), |s| format!("{s:.6}"));
        format!(
            concat!(
                "{{\"accel\":\"{}\",\"threads\":{},\"width\":{},\"height\":{},",
                "\"build_s\":{:.6},\"primitives\":{},\"bytes\":{},",
                "\"primary_mrays\":{:.4},\"shadow_mrays\":{:.4},\"frame_s\":{},",
                "\"hit_fraction\":{:.6}}}"
            ),
            self.accel,
            self.threads,
            self.width,
            self.height,
            self.build_s,
            self.primitives,
            self.bytes,
            self.primary_mrays,
            self.shadow_mrays,
            frame,
            self.hit_fraction,
        )
    }
}

impl std::fmt::Display for BenchReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let light = if self.light_from_scene {
            "first light"
        } else {
            "the eye (the scene has no light)"
        };
        writeln!(
            f,
            "intersector  {} on {} thread{}",
            self.accel,
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        )?;
        writeln!(f, "primitives   {}", self.primitives)?;
        writeln!(f, "build        {:.3} s", self.build_s)?;
        writeln!(
            f,
            "memory       {:.1} MiB ({:.1} bytes per primitive)",
            self.bytes as f64 / (1 << 20) as f64,
            self.bytes_per_primitive()
        )?;
        writeln!(
            f,
            "primary      {:.2} Mrays/s ({}x{}, {:.1} % hit)",
            self.primary_mrays,
            self.width,
            self.height,
            100.0 * self.hit_fraction
        )?;
        write!(
            f,
            "shadow       {:.2} Mrays/s (to {light})",
            self.shadow_mrays
        )?;
        if let Some(s) = self.frame_s {
            write!(f, "\nclassic frame {s:.3} s")?;
        }
        Ok(())
    }
}

/// The camera's pinhole rays, one per pixel, row by row.
pub fn primary_rays(camera: &Camera) -> Vec<Ray> {
    let rays = CameraRays::new(camera, 1, 1);
    (0..camera.height)
        .flat_map(|y| (0..camera.width).map(move |x| (x, y)))
        .map(|(x, y)| rays.pinhole(x, y))
        .collect()
}

/// Writes what another ray tracer needs to cast the same rays at the same triangles,
/// and this intersector's answers, as raw little-endian arrays in `dir`:
/// `triangles.f32` (3 corners x 3 floats per triangle, in shape order), `rays.f32`
/// (origin and unit direction, 6 floats per ray) and `hits.bin` (per ray the shape
/// index as i32, -1 for a miss, then the distance as f32). `benches/embree.py` reads
/// them. Every shape must be a triangle.
pub fn write_ray_dump(dir: &Path, scene: &Scene, rays: &[Ray], accel: &Accel) -> Result<()> {
    let mut triangles = Vec::with_capacity(scene.shapes.len() * 36);
    for (i, shape) in scene.shapes.iter().enumerate() {
        let Shape::Triangle(t) = shape else {
            return Err(Error::Settings(format!(
                "shape {i} is not a triangle: only triangle meshes can be exported"
            )));
        };
        for v in t.v {
            triangles.extend(v.to_array().iter().flat_map(|x| x.to_le_bytes()));
        }
    }
    let mut ray_bytes = Vec::with_capacity(rays.len() * 24);
    let mut hit_bytes = Vec::with_capacity(rays.len() * 8);
    for ray in rays {
        for x in ray.origin.to_array().iter().chain(&ray.dir.to_array()) {
            ray_bytes.extend(x.to_le_bytes());
        }
        let (shape, t) = accel
            .closest(ray, f32::INFINITY)
            .map_or((-1, f32::INFINITY), |h| (h.shape as i32, h.t));
        hit_bytes.extend(shape.to_le_bytes());
        hit_bytes.extend(t.to_le_bytes());
    }
    for (name, bytes) in [
        ("triangles.f32", triangles),
        ("rays.f32", ray_bytes),
        ("hits.bin", hit_bytes),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes)
            .map_err(|e| Error::file(&path, format!("cannot write: {e}")))?;
    }
    Ok(())
}

/// Million rays per second finding the closest hit of every ray on the current rayon
/// pool, the passes repeated until `min_seconds` have passed.
pub fn closest_hit_mrays(accel: &Accel, rays: &[Ray], min_seconds: f64) -> f64 {
    let mut hits = vec![false; rays.len()];
    repeat_for(Duration::from_secs_f64(min_seconds), || {
        hits.par_iter_mut()
            .zip(rays)
            .with_min_len(64)
            .for_each(|(out, ray)| *out = accel.closest(ray, f32::INFINITY).is_some());
        rays.len()
    })
    .mrays()
}

/// The shadow ray the classic model casts for point `p` and a light: from the light
/// toward `p`, stopping just short of it. `None` when `p` is the light.
pub fn shadow_ray(light: Vec3, p: Vec3) -> Option<(Ray, f32)> {
    let to_point = p - light;
    let dist = to_point.length();
    (dist > 0.0).then(|| {
        let ray = Ray {
            origin: light,
            dir: to_point / dist,
        };
        (ray, dist - surface_epsilon(p))
    })
}

/// Measures `scene` seen by `camera`.
pub fn run(scene: &Scene, camera: &Camera, options: &BenchOptions) -> Result<BenchReport> {
    let settings = RenderSettings {
        width: options.width,
        threads: options.threads,
        accel: options.accel,
        ..RenderSettings::default()
    };
    // Checks the thread count (among the rest) before any thread starts.
    let renderer = Renderer::new(scene, camera, settings)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::Settings(format!("cannot start threads: {e}")))?;
    let (w, h) = (renderer.camera().width, renderer.camera().height);
    if u64::from(w) * u64::from(h) > MAX_BENCH_PIXELS {
        return Err(Error::Settings(format!(
            "a benchmark casts one ray per pixel and keeps them all: {w}x{h} is more than \
             {MAX_BENCH_PIXELS} pixels; choose a smaller --width"
        )));
    }
    let mut report = pool.install(|| measure_rays(scene, renderer.camera(), options));
    if options.frame {
        let start = Instant::now();
        renderer.render(&|_| {})?;
        report.frame_s = Some(start.elapsed().as_secs_f64());
    }
    Ok(report)
}

fn measure_rays(scene: &Scene, camera: &Camera, options: &BenchOptions) -> BenchReport {
    let start = Instant::now();
    let accel = Accel::build(options.accel, &scene.shapes);
    let build_s = start.elapsed().as_secs_f64();
    let bytes = scene.shapes.len() * size_of::<Shape>()
        + scene.material_of.len() * size_of::<u32>()
        + accel.memory_bytes();

    let rays = primary_rays(camera);
    let min = Duration::from_secs_f64(options.min_seconds);
    let mut hits: Vec<Option<Vec3>> = vec![None; rays.len()];
    let primary_s = repeat_for(min, || {
        hits.par_iter_mut()
            .zip(&rays)
            .with_min_len(64)
            .for_each(|(out, ray)| {
                *out = accel.closest(ray, f32::INFINITY).map(|h| ray.at(h.t));
            });
        rays.len()
    });
    let points: Vec<Vec3> = hits.iter().flatten().copied().collect();

    let (light, light_from_scene) = match scene.lights.first() {
        Some(l) => (l.position, true),
        None => (camera.eye, false),
    };
    let shadow_s = repeat_for(min, || {
        points
            .par_iter()
            .with_min_len(64)
            .filter(|&&p| {
                shadow_ray(light, p)
                    .is_some_and(|(ray, t_max)| accel.occluded(&ray, t_max, |_| true))
            })
            .count();
        points.len()
    });

    BenchReport {
        accel: options.accel,
        threads: rayon::current_num_threads(),
        width: camera.width,
        height: camera.height,
        build_s,
        primitives: scene.shapes.len(),
        bytes,
        primary_mrays: primary_s.mrays(),
        shadow_mrays: shadow_s.mrays(),
        frame_s: None,
        hit_fraction: points.len() as f64 / rays.len().max(1) as f64,
        light_from_scene,
    }
}

struct Throughput {
    rays: usize,
    seconds: f64,
}

impl Throughput {
    fn mrays(&self) -> f64 {
        if self.seconds > 0.0 {
            self.rays as f64 / self.seconds / 1e6
        } else {
            0.0
        }
    }
}

/// Runs `pass` (which returns the rays it cast) until `min` has elapsed, at least once.
fn repeat_for(min: Duration, mut pass: impl FnMut() -> usize) -> Throughput {
    let start = Instant::now();
    let mut rays = 0;
    loop {
        rays += pass();
        let elapsed = start.elapsed();
        if elapsed >= min || rays == 0 {
            return Throughput {
                rays,
                seconds: elapsed.as_secs_f64(),
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Light, Material, Sphere};

    /// A unit sphere 5 in front of the 2014 camera looking down +x, a light above.
    fn scene_and_camera() -> (Scene, Camera) {
        let mut scene = Scene {
            materials: vec![Material::default_white()],
            ..Scene::default()
        };
        scene.push_shape(
            Shape::Sphere(Sphere {
                center: Vec3::new(5.0, 0.0, 0.0),
                radius: 1.0,
            }),
            0,
        );
        scene
            .lights
            .push(Light::point(Vec3::new(5.0, 0.0, 10.0), Vec3::ONE));
        let camera = Camera {
            eye: Vec3::ZERO,
            theta_deg: 90.0,
            phi_deg: 0.0,
            medium_ior: 1.0,
            screen_distance: 1.0,
            width: 40,
            height: 40,
            retina_scale: 0.5 / 40.0,
            focal_length: 1.0,
            aperture: 0.0,
            rays_per_pixel: 1,
            aa: 1,
            up: None,
        };
        (scene, camera)
    }

    #[test]
    fn the_hit_fraction_is_the_share_of_pixels_that_see_the_sphere() {
        let (scene, camera) = scene_and_camera();
        let rays = primary_rays(&camera);
        assert_eq!(rays.len(), 1600);
        let options = BenchOptions {
            min_seconds: 0.0,
            frame: false,
            threads: Some(2),
            ..BenchOptions::default()
        };
        let report = run(&scene, &camera, &options).unwrap();
        let expected = rays
            .iter()
            .filter(|r| scene.shapes[0].intersect(r, f32::INFINITY).is_some())
            .count();
        assert!(expected > 0 && expected < 1600);
        assert_eq!(report.hit_fraction, expected as f64 / 1600.0);
        assert_eq!(report.primitives, 1);
        assert_eq!(report.threads, 2);
        assert!(report.light_from_scene);
        assert!(report.primary_mrays > 0.0 && report.shadow_mrays > 0.0);
        assert!(report.bytes >= size_of::<Shape>() + 4);
        assert_eq!(report.frame_s, None);
    }

    #[test]
    fn a_huge_camera_is_refused_before_anything_is_allocated() {
        let (scene, camera) = scene_and_camera();
        let camera = Camera {
            width: 65536,
            height: 65536,
            ..camera
        };
        let e = run(&scene, &camera, &BenchOptions::default()).unwrap_err();
        assert!(e.to_string().contains("--width"), "{e}");
        let options = BenchOptions {
            width: Some(64),
            min_seconds: 0.0,
            frame: false,
            ..BenchOptions::default()
        };
        assert_eq!(run(&scene, &camera, &options).unwrap().width, 64);
    }

    #[test]
    fn json_has_the_documented_keys() {
        let (scene, camera) = scene_and_camera();
        let options = BenchOptions {
            min_seconds: 0.0,
            accel: AccelKind::Octree,
            ..BenchOptions::default()
        };
        let report = run(&scene, &camera, &options).unwrap();
        let json = report.to_json();
        for key in [
            "\"build_s\":",
            "\"primitives\":1,",
            "\"bytes\":",
            "\"primary_mrays\":",
            "\"shadow_mrays\":",
            "\"frame_s\":",
            "\"hit_fraction\":",
            "\"accel\":\"octree\"",
        ] {
            assert!(json.contains(key), "{key} missing from {json}");
        }
        assert!(report.frame_s.is_some_and(|s| s > 0.0));
        assert!(json.starts_with('{') && json.ends_with('}'));
    }
}
