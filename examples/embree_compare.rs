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
//! `benches/embree3.sh` compares against native Embree 3 instead, on the same threads,
//! with shadow rays and 16-ray packets too.

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
    let embree = || -> Result<(f64, String), Box<dyn std::error::Error>> {
        let out = Command::new("python3")
            .arg(&script)
            .arg(dir.path())
            .args(["--seconds", &seconds.to_string()])
            .output()?;
        if !out.status.success() {
            return Err(String::from_utf8_lossy(&out.stderr).into_owned().into());
        }
        let json = String::from_utf8(out.stdout)?;
        let mrays = field(&json, "embree_mrays").ok_or("no embree_mrays")?;
        Ok((mrays, json))
    };
    let cores = std::thread::available_parallelism()?.get();
    let on = |threads: usize| -> Result<f64, Box<dyn std::error::Error>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        Ok(pool.install(|| closest_hit_mrays(&accel, &rays, seconds)))
    };

    println!(
        "{} triangles, {} rays ({}x{}); Mrays/s per round, the two interleaved so \
         machine noise hits both",
        scene.shapes.len(),
        rays.len(),
        camera.width,
        camera.height
    );
    let mut ratios = Vec::new();
    let mut agreement = String::new();
    for round in 1..=3 {
        let (embree_mrays, json) = embree()?;
        let prism_mrays = on(1)?;
        let ratio = prism_mrays / embree_mrays;
        println!(
            "round {round}: embree 1 thread {embree_mrays:6.2}  prism 1 thread \
             {prism_mrays:6.2}  ratio {ratio:.3}"
        );
        ratios.push(ratio);
        agreement = json;
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "median ratio prism/embree, one thread each: {:.3}",
        ratios[1]
    );
    let (one, all) = (on(1)?, on(cores)?);
    println!(
        "prism {cores} threads {all:.2} vs 1 thread {one:.2}: parallel efficiency {:.3}",
        all / one / cores as f64
    );
    println!("agreement: {agreement}");
    Ok(())
}

/// A number field of a flat JSON object.
fn field(json: &str, key: &str) -> Option<f64> {
    let start = json.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = json[start..].trim_start();
    let end = rest.find([',', '}'])?;
    rest[..end].trim().parse().ok()
}
