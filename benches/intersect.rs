//! Criterion benchmarks of the three figures `prism bench` reports, on a real mesh:
//! BVH build, primary rays (closest hit) and shadow rays (any hit), and a classic frame.
//!
//! The mesh is the Stanford bunny from `../shared/models` when it is there (69 451
//! triangles), else the bundled example scene; the camera is `benches/bunny.cmr` at
//! 320x180. Run with `cargo bench --bench intersect`.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use prism::accel::{Accel, AccelKind};
use prism::bench::{primary_rays, shadow_ray};
use prism::render::{RenderSettings, Renderer};
use prism::scene::{Camera, Scene};

fn inputs() -> (String, Scene, Camera) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bunny = root.join("../shared/models/stanford-bunny/stanford-bunny.obj");
    let (name, scene_path, camera_path): (&str, PathBuf, PathBuf) = if bunny.is_file() {
        ("bunny", bunny, root.join("benches/bunny.cmr"))
    } else {
        eprintln!(
            "{} is absent: benchmarking the example scene",
            bunny.display()
        );
        let example = root.join("scenes/example");
        (
            "example",
            example.join("example.objx"),
            example.join("example.cmr"),
        )
    };
    let scene = prism::format::load_scene(&scene_path).expect("benchmark scene");
    let camera = prism::format::load_camera(&camera_path).expect("benchmark camera");
    (name.to_owned(), scene, camera.with_resolution(320, 180))
}

fn intersectors(c: &mut Criterion) {
    let (name, scene, camera) = inputs();
    let rays = primary_rays(&camera);
    let light = scene.lights.first().map_or(camera.eye, |l| l.position);

    let mut group = c.benchmark_group(format!("{name}/build"));
    group.sample_size(10);
    for kind in [AccelKind::Bvh, AccelKind::BvhCopied, AccelKind::Octree] {
        group.bench_function(kind.name(), |b| {
            b.iter(|| Accel::build(kind, black_box(&scene.shapes)))
        });
    }
    group.finish();

    for kind in [AccelKind::Bvh, AccelKind::BvhCopied, AccelKind::Octree] {
        let accel = Accel::build(kind, &scene.shapes);
        let points: Vec<_> = rays
            .iter()
            .filter_map(|r| accel.closest(r, f32::INFINITY).map(|h| r.at(h.t)))
            .collect();
        let mut group = c.benchmark_group(format!("{name}/{kind}"));
        group.sample_size(10);
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function("primary", |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| accel.closest(r, f32::INFINITY).is_some())
                    .count()
            })
        });
        group.throughput(Throughput::Elements(points.len() as u64));
        group.bench_function("shadow", |b| {
            b.iter(|| {
                points
                    .iter()
                    .filter(|&&p| {
                        shadow_ray(light, p)
                            .is_some_and(|(ray, t_max)| accel.occluded(&ray, t_max, |_| true))
                    })
                    .count()
            })
        });
        group.finish();
    }

    let mut group = c.benchmark_group(format!("{name}/frame"));
    group.sample_size(10);
    for kind in [AccelKind::Bvh, AccelKind::BvhCopied, AccelKind::Octree] {
        let settings = RenderSettings {
            accel: kind,
            threads: Some(1),
            ..RenderSettings::default()
        };
        let renderer = Renderer::new(&scene, &camera, settings).expect("settings");
        group.bench_function(kind.name(), |b| b.iter(|| renderer.render(&())));
    }
    group.finish();
}

criterion_group!(benches, intersectors);
criterion_main!(benches);
