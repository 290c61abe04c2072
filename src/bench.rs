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

use crate::accel::{Accel, AccelKind, Hit, PACKET_RAYS};
use crate::math::{Ray, Vec3};
use crate::render::{CameraRays, RenderSettings, Renderer, TILE_COLUMNS, TILE_ROWS};
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
    /// Of `bytes`, those of the intersector (nodes and leaves).
    pub accel_bytes: usize,
    pub primary_mrays: f64,
    pub shadow_mrays: f64,
    /// The same rays traced as packets of [`PACKET_RAYS`] (4 x 4 pixel tiles; the
    /// shadow rays of a tile's hits together).
    pub primary_packet_mrays: f64,
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

/// Writes what another ray tracer needs to cast the same rays at the same triangles,
/// and this intersector's answers, as raw little-endian arrays in `dir`:
/// `triangles.f32` (3 corners x 3 floats per triangle, in shape order), `rays.f32`
/// (origin and unit direction, 6 floats per ray) and `hits.bin` (per ray the shape
/// index as i32, -1 for a miss, then the distance as f32). `benches/embree.py` reads
/// them. Every shape must be a triangle.
pub fn write_ray_dump(dir: &Path, scene: &Scene, rays: &[Ray], accel: &Accel) -> Result<()> {
    let triangles = triangle_bytes(scene)?;
    let hits = closest_hits(accel, rays);
    write_primary_dump(dir, triangles, rays, &hits)
}

/// What [`write_bench_dump`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct DumpSummary {
    pub accel: AccelKind,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub rays: usize,
    pub shadow_rays: usize,
    /// Share of primary rays that hit something.
    pub hit_fraction: f64,
    /// Whether the shadow rays came from a scene light or, lacking one, the eye.
    pub light_from_scene: bool,
}

impl DumpSummary {
    /// One JSON object, the contents of `meta.json`; the keys are stable for scripts.
    pub fn to_json(&self) -> String {
        format!(
            concat!(
                "{{\"accel\":\"{}\",\"width\":{},\"height\":{},\"triangles\":{},",
                "\"rays\":{},\"shadow_rays\":{},\"hit_fraction\":{:.6},",
                "\"light_from_scene\":{}}}"
            ),
            self.accel,
            self.width,
            self.height,
            self.triangles,
            self.rays,
            self.shadow_rays,
            self.hit_fraction,
            self.light_from_scene,
        )
    }
}

impl std::fmt::Display for DumpSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} triangles, {} primary rays ({}x{}, {:.1} % hit), {} shadow rays to {}",
            self.triangles,
            self.rays,
            self.width,
            self.height,
            100.0 * self.hit_fraction,
            self.shadow_rays,
            if self.light_from_scene {
                "the first light"
            } else {
                "the eye (the scene has no light)"
            }
        )
    }
}

/// Writes the rays [`run`] casts, for another ray tracer to cast them too: the files of
/// [`write_ray_dump`] for the primary rays (row by row, `width` rays a row), and
///
/// - `shadow.f32`: per shadow ray its origin, unit direction and the end of its
///   segment (7 floats), one for each primary hit in ray order, from the light to the
///   hit point, exactly as [`run`] times them;
/// - `occluded.u8`: per shadow ray 1 when this intersector finds it blocked, else 0;
/// - `meta.json`: [`DumpSummary::to_json`], which gives the image width and height
///   (for grouping rays into tiles) and the counts.
///
/// The camera and intersector are chosen by `options` as for [`run`] (its width, its
/// intersector; the threads only speed the writing). `dir` is created if missing.
/// Every shape must be a triangle.
pub fn write_bench_dump(
    dir: &Path,
    scene: &Scene,
    camera: &Camera,
    options: &BenchOptions,
) -> Result<DumpSummary> {
    let triangles = triangle_bytes(scene)?;
    let (renderer, pool) = prepare(scene, camera, options)?;
    let camera = renderer.camera();
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::file(dir, format!("cannot create the folder: {e}")))?;
    let accel = Accel::build(options.accel, &scene.shapes);
    let rays = primary_rays(camera);
    let hits = pool.install(|| closest_hits(&accel, &rays));
    write_primary_dump(dir, triangles, &rays, &hits)?;

    let (light, light_from_scene) = bench_light(scene, camera);
    let shadow: Vec<(Ray, f32)> = rays
        .iter()
        .zip(&hits)
        .filter_map(|(ray, hit)| hit.and_then(|(_, t)| shadow_ray(light, ray.at(t))))
        .collect();
    let occluded: Vec<u8> = pool.install(|| {
        shadow
            .par_iter()
            .map(|(ray, t_max)| u8::from(accel.occluded(ray, *t_max, |_| true)))
            .collect()
    });
    let mut shadow_bytes = Vec::with_capacity(shadow.len() * 28);
    for (ray, t_max) in &shadow {
        let floats = ray.origin.to_array().into_iter().chain(ray.dir.to_array());
        for x in floats.chain([*t_max]) {
            shadow_bytes.extend(x.to_le_bytes());
        }
    }
    let summary = DumpSummary {
        accel: options.accel,
        width: camera.width,
        height: camera.height,
        triangles: scene.shapes.len(),
        rays: rays.len(),
        shadow_rays: shadow.len(),
        hit_fraction: hits.iter().flatten().count() as f64 / rays.len().max(1) as f64,
        light_from_scene,
    };
    write_files(
        dir,
        [
            ("shadow.f32", shadow_bytes),
            ("occluded.u8", occluded),
            ("meta.json", format!("{}\n", summary.to_json()).into_bytes()),
        ],
    )?;
    Ok(summary)
}

/// The corners of every shape, refusing any that is not a triangle before the rays
/// are cast, since other ray tracers are compared on triangle meshes only.
fn triangle_bytes(scene: &Scene) -> Result<Vec<u8>> {
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
    Ok(triangles)
}

/// The shape index and distance of every ray's closest hit, on the current rayon pool.
fn closest_hits(accel: &Accel, rays: &[Ray]) -> Vec<Option<(u32, f32)>> {
    rays.par_iter()
        .with_min_len(64)
        .map(|ray| accel.closest(ray, f32::INFINITY).map(|h| (h.shape, h.t)))
        .collect()
}

fn write_primary_dump(
    dir: &Path,
    triangles: Vec<u8>,
    rays: &[Ray],
    hits: &[Option<(u32, f32)>],
) -> Result<()> {
    let mut ray_bytes = Vec::with_capacity(rays.len() * 24);
    let mut hit_bytes = Vec::with_capacity(rays.len() * 8);
    for (ray, hit) in rays.iter().zip(hits) {
        for x in ray.origin.to_array().iter().chain(&ray.dir.to_array()) {
            ray_bytes.extend(x.to_le_bytes());
        }
        let (shape, t) = hit.map_or((-1, f32::INFINITY), |(s, t)| (s as i32, t));
        hit_bytes.extend(shape.to_le_bytes());
        hit_bytes.extend(t.to_le_bytes());
    }
    write_files(
        dir,
        [
            ("triangles.f32", triangles),
            ("rays.f32", ray_bytes),
            ("hits.bin", hit_bytes),
        ],
    )
}

fn write_files<const N: usize>(dir: &Path, files: [(&str, Vec<u8>); N]) -> Result<()> {
    for (name, bytes) in files {
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
pub use crate::render::shadows::from_light as shadow_ray;

/// Measures `scene` seen by `camera`.
pub fn run(scene: &Scene, camera: &Camera, options: &BenchOptions) -> Result<BenchReport> {
    let (renderer, pool) = prepare(scene, camera, options)?;
    let mut report = pool.install(|| measure_rays(scene, renderer.camera(), options));
    if options.frame {
        let start = Instant::now();
        renderer.render(&|_| {})?;
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
    let accel = Accel::build(options.accel, &scene.shapes);
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
        shadow_packets
            .par_iter()
            .with_min_len(8)
            .map(|(r, l)| accel.occluded_packet(r, l, |_| true).count_ones())
            .sum::<u32>();
        shadow_rays
    });

    BenchReport {
        primary_packet_mrays: primary_packet_s.mrays(),
        shadow_packet_mrays: shadow_packet_s.mrays(),
        simd: match &accel {
            Accel::Bvh(b) => b.simd().name(),
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
    use crate::scene::{Light, Material, Sphere, Triangle};

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

    /// The example scene with each rectangle split into two triangles and the spheres
    /// left out, since a dump holds triangles only; its camera and light are kept.
    fn example_as_triangles() -> (Scene, Scene, Camera) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/example");
        let example = crate::format::load_scene(&dir.join("example.objx")).unwrap();
        let camera = crate::format::load_camera(&dir.join("example.cmr")).unwrap();
        let mut scene = Scene {
            materials: vec![Material::default_white()],
            lights: example.lights.clone(),
            ..Scene::default()
        };
        for shape in example.shapes.iter() {
            match shape {
                Shape::Triangle(t) => scene.push_shape(Shape::Triangle(t), 0),
                Shape::Rectangle(r) => {
                    for v in [[r.v[0], r.v[1], r.v[2]], [r.v[0], r.v[2], r.v[3]]] {
                        scene.push_shape(Shape::Triangle(Triangle { v }), 0);
                    }
                }
                Shape::Sphere(_) => {}
            }
        }
        (example, scene, camera)
    }

    fn floats(bytes: &[u8]) -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn a_dump_has_the_documented_sizes_and_prisms_own_answers() {
        let (example, scene, camera) = example_as_triangles();
        assert_eq!(scene.shapes.len(), 7, "3 rectangles and a triangle");
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("dump");
        let options = BenchOptions {
            width: Some(64),
            threads: Some(2),
            ..BenchOptions::default()
        };

        // The spheres are refused before anything is written.
        let e = write_bench_dump(&dir, &example, &camera, &options).unwrap_err();
        assert!(e.to_string().contains("not a triangle"), "{e}");
        assert!(!dir.exists());

        let summary = write_bench_dump(&dir, &scene, &camera, &options).unwrap();
        let (w, h) = (summary.width, summary.height);
        assert_eq!(w, 64);
        assert_eq!(summary.rays, (w * h) as usize);
        assert!(summary.light_from_scene);
        assert!(summary.hit_fraction > 0.5 && summary.shadow_rays > 0);
        let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
        let (triangles, rays, hits) = (read("triangles.f32"), read("rays.f32"), read("hits.bin"));
        let (shadow, occluded) = (read("shadow.f32"), read("occluded.u8"));
        assert_eq!(triangles.len(), 36 * scene.shapes.len());
        assert_eq!(rays.len(), 24 * summary.rays);
        assert_eq!(hits.len(), 8 * summary.rays);
        assert_eq!(shadow.len(), 28 * summary.shadow_rays);
        assert_eq!(occluded.len(), summary.shadow_rays);
        let meta = String::from_utf8(read("meta.json")).unwrap();
        assert_eq!(meta, format!("{}\n", summary.to_json()));
        assert!(
            meta.contains(&format!("\"width\":64,\"height\":{h},")),
            "{meta}"
        );
        let Shape::Triangle(first) = scene.shapes.get(0) else {
            unreachable!()
        };
        assert_eq!(floats(&triangles)[..3], first.v[0].to_array());

        // The rays are the camera's, row by row, and each answer is Prism's own.
        let accel = Accel::build(AccelKind::Bvh, &scene.shapes);
        let expected = primary_rays(&camera.with_resolution(w, h));
        let (rays, shadow) = (floats(&rays), floats(&shadow));
        let light = scene.lights[0].position;
        let mut shadow_index = 0;
        let mut checked_shadows = 0;
        for (i, ray) in expected.iter().enumerate() {
            let hit = accel.closest(ray, f32::INFINITY);
            if i % 37 == 0 {
                let r = &rays[6 * i..6 * i + 6];
                assert_eq!(r[..3], ray.origin.to_array(), "ray {i}");
                assert_eq!(r[3..], ray.dir.to_array(), "ray {i}");
                let shape = i32::from_le_bytes(hits[8 * i..8 * i + 4].try_into().unwrap());
                let t = f32::from_le_bytes(hits[8 * i + 4..8 * i + 8].try_into().unwrap());
                match hit {
                    Some(hit) => assert_eq!((shape, t), (hit.shape as i32, hit.t), "ray {i}"),
                    None => assert_eq!((shape, t), (-1, f32::INFINITY), "ray {i}"),
                }
            }
            let Some(hit) = hit else { continue };
            // Shadow rays follow the hits in ray order, from the light to the hit.
            if i % 37 == 0 {
                let (ray, t_max) = shadow_ray(light, ray.at(hit.t)).unwrap();
                let s = &shadow[7 * shadow_index..7 * shadow_index + 7];
                assert_eq!(s[..3], ray.origin.to_array());
                assert_eq!(s[3..6], ray.dir.to_array());
                assert_eq!(s[6], t_max);
                let blocked = accel.occluded(&ray, t_max, |_| true);
                assert_eq!(occluded[shadow_index], u8::from(blocked));
                checked_shadows += 1;
            }
            shadow_index += 1;
        }
        assert_eq!(shadow_index, summary.shadow_rays);
        assert!(checked_shadows > 10);
    }
}
