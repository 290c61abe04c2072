//! `prism render`: one still image from a scene and a camera.

use clap::Args;
use prism::accel::AccelKind;
use prism::film::output::check_output_path;
use prism::film::resample::Filter;
use prism::film::write_image;
use prism::render::{Region, RenderSettings, Renderer};
use std::path::PathBuf;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (.objx); mtllib and texture paths resolve against its folder.
    #[arg(required = true)]
    pub scene: Option<PathBuf>,
    /// Camera file (.cmr).
    #[arg(required = true)]
    pub camera: Option<PathBuf>,
    /// Output image; the extension picks the format: png, bmp, jpg, ppm, tga.
    #[arg(required = true)]
    pub output: Option<PathBuf>,
    /// Image width in pixels; the field of view is kept (alone, the height follows the
    /// camera's aspect ratio).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Render only the window X,Y,W,H of the full frame, written as a W x H image.
    #[arg(long, value_name = "X,Y,W,H")]
    pub region: Option<Region>,
    /// Anti-aliasing: render K times larger per axis and resample down.
    #[arg(long, value_name = "K")]
    pub aa: Option<u32>,
    /// Resampling filter for anti-aliasing.
    #[arg(long, value_name = "FILTER", default_value = "area", value_parser = ["nearest", "bilinear", "area", "bicubic", "lanczos"])]
    pub aa_filter: String,
    /// Camera rays per pixel; more than 1 turns on depth of field.
    #[arg(long, value_name = "N")]
    pub dof_rays: Option<u32>,
    /// Intersector.
    #[arg(long, default_value = "bvh", value_parser = crate::accel_parser())]
    pub accel: AccelKind,
    /// Worker threads (default: every core). The image does not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Seed of the lens samples; the same seed gives the same image.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Print one line of figures: rays traced, seconds, million rays per second.
    #[arg(long)]
    pub stats: bool,
}

pub fn run(args: &RenderArgs) -> prism::Result<()> {
    let (Some(scene_path), Some(camera_path), Some(output)) =
        (&args.scene, &args.camera, &args.output)
    else {
        unreachable!("clap requires the three paths");
    };
    // Refuse a bad output path before spending time on the render.
    check_output_path(output)?;
    let scene = prism::format::load_scene(scene_path)?;
    let camera = prism::format::load_camera(camera_path)?;
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        aa: args.aa,
        filter: args
            .aa_filter
            .parse::<Filter>()
            .map_err(prism::Error::Settings)?,
        dof_rays: args.dof_rays,
        region: args.region,
        seed: args.seed,
        threads: args.threads,
        accel: args.accel,
        ..RenderSettings::default()
    };
    let renderer = Renderer::new(&scene, &camera, settings)?;
    let bar = crate::progress_bar(renderer.rows_to_trace(), args.quiet);
    let (image, stats) = renderer.render(&|n| bar.inc(n))?;
    bar.finish_and_clear();
    write_image(&image, output)?;
    if args.stats {
        println!(
            "rays {}  seconds {:.3}  Mrays/s {:.2}",
            stats.rays,
            stats.elapsed.as_secs_f64(),
            stats.mrays_per_second()
        );
    }
    Ok(())
}
