//! The ray dump of `prism bench --dump`: the triangles, rays and Prism's own answers as
//! raw little-endian arrays, for another ray tracer (Embree, in `benches/`) to cast the
//! same rays and be compared with.

use super::{BenchOptions, bench_light, prepare, primary_rays, shadow_ray};
use crate::accel::{Accel, AccelKind};
use crate::error::{Error, Result};
use crate::math::Ray;
use crate::scene::{Camera, Scene, Shape};
use rayon::prelude::*;
use std::path::Path;

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
    /// The intersector whose answers `hits.bin` and `occluded.u8` hold.
    pub accel: AccelKind,
    /// Image width in pixels: primary rays per row of `rays.f32`.
    pub width: u32,
    /// Image height in pixels: rows of primary rays.
    pub height: u32,
    /// Triangles in `triangles.f32`, in shape order.
    pub triangles: usize,
    /// Primary rays in `rays.f32`: one per pixel, `width x height`.
    pub rays: usize,
    /// Shadow rays in `shadow.f32`: one per primary hit (none for a hit on the light).
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
                "the eye, as the scene has no light"
            }
        )
    }
}

/// Writes the rays [`run`](super::run) casts, for another ray tracer to cast them too:
/// the files of [`write_ray_dump`] for the primary rays (row by row, `width` rays a
/// row), and
///
/// - `shadow.f32`: per shadow ray its origin, unit direction and the end of its
///   segment (7 floats), one for each primary hit in ray order, from the light to the
///   hit point, exactly as [`run`](super::run) times them;
/// - `occluded.u8`: per shadow ray 1 when this intersector finds it blocked, else 0;
/// - `meta.json`: [`DumpSummary::to_json`], which gives the image width and height
///   (for grouping rays into tiles) and the counts.
///
/// The camera and intersector are chosen by `options` as for [`run`](super::run) (its
/// width, its intersector; the threads only speed the writing). `dir` is created if
/// missing.
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
    let accel = Accel::build_scene(options.accel, scene);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Triangle};

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
