//! The `prism` command: arguments, progress and messages. The work is in the library.

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use prism::accel::AccelKind;
use prism::film::output::check_output_path;
use prism::film::resample::Filter;
use prism::film::write_image;
use prism::render::{Region, RenderSettings, Renderer};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

/// Prism renders scenes of the 2014 ray-tracer formats (.objx scene, .mtlx materials,
/// .cmr camera) into images, Whitted style.
///
/// `prism SCENE CAMERA OUTPUT` is the report's command line; `prism render SCENE CAMERA
/// OUTPUT [OPTIONS]` is the same with a name. Options override the camera file.
#[derive(Parser)]
#[command(
    name = "prism",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    render: RenderArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene and camera to an image file.
    Render(RenderArgs),
}

#[derive(Args)]
struct RenderArgs {
    /// Scene file (.objx); mtllib and texture paths resolve against its folder.
    #[arg(required = true)]
    scene: Option<PathBuf>,
    /// Camera file (.cmr).
    #[arg(required = true)]
    camera: Option<PathBuf>,
    /// Output image; the extension picks the format: png, bmp, jpg, ppm, tga.
    #[arg(required = true)]
    output: Option<PathBuf>,
    /// Image width in pixels; the field of view is kept (alone, the height follows the
    /// camera's aspect ratio).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    height: Option<u32>,
    /// Render only the window X,Y,W,H of the full frame, written as a W x H image.
    #[arg(long, value_name = "X,Y,W,H")]
    region: Option<Region>,
    /// Anti-aliasing: render K times larger per axis and resample down.
    #[arg(long, value_name = "K")]
    aa: Option<u32>,
    /// Resampling filter for anti-aliasing.
    #[arg(long, value_name = "FILTER", default_value = "area", value_parser = ["nearest", "bilinear", "area", "bicubic", "lanczos"])]
    aa_filter: String,
    /// Camera rays per pixel; more than 1 turns on depth of field.
    #[arg(long, value_name = "N")]
    dof_rays: Option<u32>,
    /// Intersector.
    #[arg(long, default_value = "octree", value_parser = ["list", "octree"])]
    accel: String,
    /// Worker threads (default: every core). The image does not depend on it.
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Seed of the lens samples; the same seed gives the same image.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
    /// Print one line of figures: rays traced, seconds, million rays per second.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let args = match cli.command {
        Some(Command::Render(a)) => a,
        None => cli.render,
    };
    match render(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn render(args: &RenderArgs) -> prism::Result<()> {
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
        accel: args
            .accel
            .parse::<AccelKind>()
            .map_err(prism::Error::Settings)?,
    };
    let renderer = Renderer::new(&scene, &camera, settings)?;
    let bar = progress_bar(renderer.rows_to_trace(), args.quiet);
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

fn progress_bar(rows: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(rows);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% eta {eta}",
        )
        .expect("static template"),
    );
    bar
}
