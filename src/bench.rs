//! Throughput measurement: how fast an intersector is built and answers the two
//! queries a Whitted renderer asks, and how long a whole classic frame takes.
//!
//! Primary rays are the camera's pinhole rays, one per pixel, closest hit only; shadow
//! rays run from the first light to each primary hit point, any hit, the way the
//! classic model casts them. Each pass is repeated until it has run for a minimum time,
//! so small scenes are measured over many passes and large ones over one.

use std::time::{Duration, Instant};

use rayon::prelude::*;
use std::hint::black_box;

use crate::accel::{Accel, AccelKind, Hit, PACKET_RAYS};
use crate::error::{Error, Result};
use crate::math::{Ray, Vec3};
use crate::render::{CameraRays, RenderSettings, Renderer, TILE_COLUMNS, TILE_ROWS};
use crate::scene::{Camera, Scene};

mod dump;

pub use dump::{DumpSummary, write_bench_dump, write_ray_dump};

/// Pixels a benchmark camera may have: its rays and hit points are held at once
/// (about 50 bytes a pixel), so a frame of 65536 x 65536 would need hundreds of GB.
pub const MAX_BENCH_PIXELS: u64 = 1 << 24;

/// What to measure and how.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// The intersector to build and measure.
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
    /// The intersector measured.
    pub accel: AccelKind,
    /// Worker threads the ray passes ran on.
    pub threads: usize,
    /// Width in pixels of the frame the primary rays cover (one ray per pixel).
    pub width: u32,
    /// Height in pixels of that frame.
    pub height: u32,
    /// Seconds to build the intersector.
    pub build_s: f64,
    /// Shapes in the scene (triangles, spheres, rectangles).
    pub primitives: usize,
    /// Bytes of the shapes, their material indices and the intersector.
    pub bytes: usize,
    /// Of `bytes`, those of the intersector (nodes and leaves).
    pub accel_bytes: usize,
    /// Million primary rays per second, one closest-hit query at a time.
    pub primary_mrays: f64,
    /// Million shadow rays per second, one any-hit query at a time.
    pub shadow_mrays: f64,
    /// The same rays traced as packets of [`PACKET_RAYS`] (4 x 4 pixel tiles; the
    /// shadow rays of a tile's hits together).
    pub primary_packet_mrays: f64,
    /// [`BenchReport::shadow_mrays`] for the shadow rays traced as packets.
    pub shadow_packet_mrays: f64,
    /// The instructions the BVH ran on (`avx2` or `sse2`).
    pub simd: &'static str,
    /// Seconds of a full classic frame, or `None` when not asked for.
    pub frame_s: Option<f64>,
    /// Share of primary rays that hit something.
    pub hit_fraction: f64,
    /// Whether the shadow rays came from a scene light or, lacking one, the eye.
    pub light_from_scene: bool,
}

impl BenchReport {
    /// `bytes` over `primitives`: the scene's memory per shape, intersector included.
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
                "\"build_s\":{:.6},\"primitives\":{},\"bytes\":{},\"accel_bytes\":{},",
                "\"primary_mrays\":{:.4},\"shadow_mrays\":{:.4},",
                "\"primary_packet_mrays\":{:.4},\"shadow_packet_mrays\":{:.4},",
                "\"simd\":\"{}\",\"frame_s\":{},",
                "\"hit_fraction\":{:.6}}}"
            ),
            self.accel,
            self.threads,
            self.width,
            self.height,
            self.build_s,
            self.primitives,
            self.bytes,
            self.accel_bytes,
            self.primary_mrays,
            self.shadow_mrays,
            self.primary_packet_mrays,
            self.shadow_packet_mrays,
            self.simd,
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
            "the eye, as the scene has no light"
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
            "memory       {:.1} MiB ({:.1} bytes per primitive: shapes {:.1}, intersector {:.1})",
            self.bytes as f64 / (1 << 20) as f64,
            self.bytes_per_primitive(),
            (self.bytes - self.accel_bytes) as f64 / self.primitives.max(1) as f64,
            self.accel_bytes as f64 / self.primitives.max(1) as f64,
        )?;
        writeln!(
            f,
            "primary      {:.2} Mrays/s ({}x{}, {:.1} % hit)",
            self.primary_mrays,
            self.width,
            self.height,
            100.0 * self.hit_fraction
        )?;
        writeln!(
            f,
            "shadow       {:.2} Mrays/s (to {light})",
            self.shadow_mrays
        )?;
        writeln!(
            f,
            "packets      {:.2} Mrays/s primary, {:.2} shadow ({PACKET_RAYS} rays, {})",
            self.primary_packet_mrays, self.shadow_packet_mrays, self.simd
        )?;
        write!(
            f,
            "             {:.2}x and {:.2}x single rays",
            self.primary_packet_mrays / self.primary_mrays.max(1e-9),
            self.shadow_packet_mrays / self.shadow_mrays.max(1e-9)
        )?;
        if let Some(s) = self.frame_s {
            write!(f, "\nclassic frame {s:.3} s")?;
        }
        Ok(())
    }
}

/// Pixel indices (row-major) in tiles of [`TILE_COLUMNS`] x [`TILE_ROWS`], the packets
/// renders and the benchmark trace; tiles at the right and bottom edges hold fewer.
pub fn tile_packets(width: u32, height: u32) -> Vec<Vec<u32>> {
    let (columns, rows) = (TILE_COLUMNS as u32, TILE_ROWS as u32);
    let mut tiles = Vec::new();
    for y0 in (0..height).step_by(TILE_ROWS) {
        for x0 in (0..width).step_by(TILE_COLUMNS) {
            let tile: Vec<u32> = (y0..(y0 + rows).min(height))
                .flat_map(|y| (x0..(x0 + columns).min(width)).map(move |x| y * width + x))
                .collect();
            tiles.push(tile);
        }
    }
    tiles
}

/// The camera's pinhole rays, one per pixel, row by row.
pub fn primary_rays(camera: &Camera) -> Vec<Ray> {
    let rays = CameraRays::new(camera, 1, 1);
    (0..camera.height)
        .flat_map(|y| (0..camera.width).map(move |x| (x, y)))
        .map(|(x, y)| rays.pinhole(x, y))
        .collect()
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
pub use crate::render::shadows::from_light as shadow_ray;

/// Measures `scene` seen by `camera`.
pub fn run(scene: &Scene, camera: &Camera, options: &BenchOptions) -> Result<BenchReport> {
    let (renderer, pool) = prepare(scene, camera, options)?;
    let mut report = pool.install(|| measure_rays(scene, renderer.camera(), options));
    if options.frame {
        let start = Instant::now();
        renderer.render(&())?;
        report.frame_s = Some(start.elapsed().as_secs_f64());
    }
    Ok(report)
}

/// The renderer (whose camera has the width asked for) and the thread pool of a run,
/// refusing a camera whose rays would not fit in memory.
fn prepare<'a>(
    scene: &'a Scene,
    camera: &Camera,
    options: &BenchOptions,
) -> Result<(Renderer<'a>, rayon::ThreadPool)> {
    let settings = RenderSettings {
        width: options.width,
        threads: options.threads,
        accel: options.accel,
        ..RenderSettings::default()
    };
    // Checks the thread count (among the rest) before any thread starts.
    let renderer = Renderer::new(scene, camera, settings)?;
    let pool = crate::render::workers::pool(options.threads)?;
    let (w, h) = (renderer.camera().width, renderer.camera().height);
    if u64::from(w) * u64::from(h) > MAX_BENCH_PIXELS {
        return Err(Error::Settings(format!(
            "a benchmark casts one ray per pixel and keeps them all: {w}x{h} is more than \
             {MAX_BENCH_PIXELS} pixels; choose a smaller --width"
        )));
    }
    Ok((renderer, pool))
}

/// Where shadow rays start: the first light, or the eye when the scene has none (then
/// `false`).
fn bench_light(scene: &Scene, camera: &Camera) -> (Vec3, bool) {
    match scene.lights.first() {
        Some(l) => (l.position, true),
        None => (camera.eye, false),
    }
}

fn measure_rays(scene: &Scene, camera: &Camera, options: &BenchOptions) -> BenchReport {
    let start = Instant::now();
    let accel = Accel::build_scene(options.accel, scene);
    let build_s = start.elapsed().as_secs_f64();
    let accel_bytes = accel.memory_bytes();
    let bytes =
        scene.shapes.memory_bytes() + scene.material_of.len() * size_of::<u32>() + accel_bytes;

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

    let (light, light_from_scene) = bench_light(scene, camera);
    // Made before the clock starts, as the packets' are (and Embree's in
    // benches/embree3.sh): the passes time the traversal, not the normalising.
    let shadow_rays_single: Vec<(Ray, f32)> = points
        .iter()
        .filter_map(|&p| shadow_ray(light, p))
        .collect();
    let shadow_s = repeat_for(min, || {
        black_box(
            shadow_rays_single
                .par_iter()
                .with_min_len(64)
                .filter(|(ray, t_max)| accel.occluded(ray, *t_max, |_| true))
                .count(),
        );
        shadow_rays_single.len()
    });

    // Packets: 4 x 4 pixel tiles, and the shadow rays of each tile's hits together.
    let tiles = tile_packets(camera.width, camera.height);
    let tiled: Vec<Ray> = tiles.iter().flatten().map(|&i| rays[i as usize]).collect();
    let mut offsets = Vec::with_capacity(tiles.len() + 1);
    offsets.push(0);
    for t in &tiles {
        offsets.push(offsets.last().unwrap() + t.len());
    }
    let mut packet_hits: Vec<Option<Hit>> = vec![None; tiled.len()];
    let primary_packet_s = repeat_for(min, || {
        packet_hits
            .par_chunks_mut(PACKET_RAYS)
            .zip(tiled.par_chunks(PACKET_RAYS))
            .with_min_len(8)
            .for_each(|(out, packet)| accel.closest_packet(packet, f32::INFINITY, out));
        tiled.len()
    });
    // Each tile's hit points become one shadow packet (of up to sixteen rays).
    let mut shadow_packets: Vec<(Vec<Ray>, Vec<f32>)> = Vec::new();
    for w in offsets.windows(2) {
        let (rs, ls): (Vec<Ray>, Vec<f32>) = (w[0]..w[1])
            .filter_map(|i| packet_hits[i].map(|h| tiled[i].at(h.t)))
            .filter_map(|p| shadow_ray(light, p))
            .unzip();
        if !rs.is_empty() {
            shadow_packets.push((rs, ls));
        }
    }
    let shadow_rays: usize = shadow_packets.iter().map(|(r, _)| r.len()).sum();
    let shadow_packet_s = repeat_for(min, || {
        black_box(
            shadow_packets
                .par_iter()
                .with_min_len(8)
                .map(|(r, l)| accel.occluded_packet(r, l, |_| true).count_ones())
                .sum::<u32>(),
        );
        shadow_rays
    });

    BenchReport {
        primary_packet_mrays: primary_packet_s.mrays(),
        shadow_packet_mrays: shadow_packet_s.mrays(),
        simd: match &accel.world {
            crate::accel::Intersector::Bvh(b) => b.simd().name(),
            _ => "none",
        },
        accel: options.accel,
        threads: rayon::current_num_threads(),
        width: camera.width,
        height: camera.height,
        build_s,
        primitives: scene.shapes.len(),
        bytes,
        accel_bytes,
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

    #[test]
    fn tiles_cover_every_pixel_once_four_by_four() {
        let tiles = tile_packets(5, 6);
        assert_eq!(
            tiles[0],
            [0, 1, 2, 3, 5, 6, 7, 8, 10, 11, 12, 13, 15, 16, 17, 18]
        );
        assert_eq!(tiles[1], [4, 9, 14, 19]);
        assert_eq!(tiles[2], [20, 21, 22, 23, 25, 26, 27, 28]);
        assert_eq!(tiles[3], [24, 29]);
        let mut all: Vec<u32> = tiles.concat();
        all.sort_unstable();
        assert_eq!(all, (0..30).collect::<Vec<u32>>());
        assert!(tiles.iter().all(|t| t.len() <= PACKET_RAYS));
    }
    use crate::scene::{Light, Material, Shape, Sphere};

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
            spp: 1,
            aa: 1,
            up: None,
            projection: crate::scene::Projection::Perspective,
            shift: [0.0, 0.0],
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
            .filter(|r| scene.shapes.get(0).intersect(r, f32::INFINITY).is_some())
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
