//! `prism bench`: intersector throughput on a scene and camera.

use std::path::PathBuf;

use clap::Args;
use prism::accel::AccelKind;
use prism::bench::{self, BenchOptions};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file: a 2014 `.objx`, or a standard `.obj` (its triangles).
    pub scene: PathBuf,
    /// Camera file (`.cmr`): one primary ray per pixel of its resolution.
    pub camera: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: every core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Intersector.
    #[arg(long, default_value = "bvh", value_parser = crate::accel_parser())]
    pub accel: AccelKind,
    /// Repeat each ray pass until it has run this many seconds.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    pub seconds: f64,
    /// Image width instead of the camera's; the height keeps its aspect ratio.
    #[arg(long, value_name = "W")]
    pub width: Option<u32>,
    /// Skip the full classic frame.
    #[arg(long)]
    pub no_frame: bool,
    /// Measure nothing: write the triangles, the primary and shadow rays and this
    /// intersector's answers into DIR for another ray tracer (`benches/embree3.sh`).
    #[arg(long, value_name = "DIR")]
    pub dump: Option<PathBuf>,
}

pub fn run(args: &BenchArgs) -> prism::Result<()> {
    if !(args.seconds.is_finite() && args.seconds >= 0.0) {
        return Err(prism::Error::Settings(format!(
            "expected --seconds >= 0, found {}",
            args.seconds
        )));
    }
    prism::render::check_threads(args.threads)?;
    let scene = prism::format::load_scene(&args.scene)?;
    let camera = prism::format::load_camera(&args.camera)?;
    let options = BenchOptions {
        accel: args.accel,
        threads: args.threads,
        min_seconds: args.seconds,
        frame: !args.no_frame,
        width: args.width,
    };
    if let Some(dir) = &args.dump {
        let summary = bench::write_bench_dump(dir, &scene, &camera, &options)?;
        if args.json {
            println!("{}", summary.to_json());
        } else {
            println!("wrote {}: {summary}", dir.display());
        }
        return Ok(());
    }
    let report = bench::run(&scene, &camera, &options)?;
    if args.json {
        println!("{}", report.to_json());
    } else {
        println!("{report}");
    }
    Ok(())
}
