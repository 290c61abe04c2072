//! Prism against Embree on the same rays: throughput ratio and hit agreement.
//!
//! ```sh
//! pip install embreex
//! cargo run --release --example embree_compare -- MESH.obj CAMERA.cmr [SECONDS]
//! ```
//!
//! Casts one pinhole ray per pixel of the camera at the mesh with Prism's BVH (on one
//! thread, then on every core) and with Embree's `rtcIntersect1` through
//! `benches/embree.py` (one thread), and prints both rates and their ratios.

use std::path::Path;
use std::process::Command;

use prism::accel::{Accel, AccelKind};
use prism::bench::{closest_hit_mrays, primary_rays, write_ray_dump};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [mesh, camera, rest @ ..] = args.as_slice() else {
        return Err("usage: embree_compare MESH.obj CAMERA.cmr [SECONDS]".into());
    };
    let seconds: f64 = rest.first().map_or(Ok(2.0), |s| s.parse())?;
    let scene = prism::format::load_scene(Path::new(mesh))?;
    let camera = prism::format::load_camera(Path::new(camera))?;
    let accel = Accel::build(AccelKind::Bvh, &scene.shapes);
    let rays = primary_rays(&camera);
    let dir = tempfile::tempdir()?;
    write_ray_dump(dir.path(), &scene, &rays, &accel)?;

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/embree.py");
    let embree = Command::new("python3")
        .arg(&script)
        .arg(dir.path())
        .args(["--seconds", &seconds.to_string()])
        .output()?;
    if !embree.status.success() {
        return Err(format!("{}", String::from_utf8_lossy(&embree.stderr)).into());
    }
    let json = String::from_utf8(embree.stdout)?;
    let embree_mrays: f64 = field(&json, "embree_mrays").ok_or("no embree_mrays")?;

    let cores = std::thread::available_parallelism()?.get();
    let mut prism = Vec::new();
    for threads in [1, cores] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        prism.push(pool.install(|| closest_hit_mrays(&accel, &rays, seconds)));
    }
    println!(
        "{} triangles, {} rays ({}x{})",
        scene.shapes.len(),
        rays.len(),
        camera.width,
        camera.height
    );
    println!("embree  1 thread : {embree_mrays:8.2} Mrays/s");
    println!(
        "prism   1 thread : {:8.2} Mrays/s  ({:.2}x embree)",
        prism[0],
        prism[0] / embree_mrays
    );
    println!(
        "prism   {cores} threads: {:8.2} Mrays/s  ({:.2}x embree on 1 thread, parallel efficiency {:.3})",
        prism[1],
        prism[1] / embree_mrays,
        prism[1] / prism[0] / cores as f64
    );
    println!("agreement: {json}");
    Ok(())
}

/// A number field of a flat JSON object.
fn field(json: &str, key: &str) -> Option<f64> {
    let start = json.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = json[start..].trim_start();
    let end = rest.find([',', '}'])?;
    rest[..end].trim().parse().ok()
}
