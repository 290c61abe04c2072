//! The `prism` command: arguments, progress and messages. The work is in the library.

mod animate;
mod bench;
mod convert;
mod info;
mod preview;
mod render;

use bench::BenchArgs;
use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand};
use convert::ConvertArgs;
use indicatif::{ProgressBar, ProgressStyle};
use prism::accel::AccelKind;
use render::RenderArgs;
use std::io::IsTerminal;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Prism: a ray tracer for the scenes your tools export (glTF 2.0, OBJ/MTL, PLY, Prism
/// scene files) and the 2014 course formats (.objx, .mtlx, .cmr), with a physically based
/// Whitted model and the 2014 program's own.
///
/// `prism render SCENE OUTPUT [OPTIONS]` renders a scene (see `prism render --help`);
/// `prism SCENE [CAMERA] OUTPUT` is the same, the 2014 program's command line.
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
    /// Render a scene (glTF, OBJ, PLY, a scene file or the 2014 formats) to an image file.
    Render(Box<RenderArgs>),
    /// Measure intersector build time, memory and rays per second on a scene.
    Bench(BenchArgs),
    /// Rewrite a standard Wavefront OBJ mesh as a 2014 scene file.
    Convert(ConvertArgs),
    /// Render every frame of an animation file to numbered images or a video.
    Animate(animate::AnimateArgs),
    /// Print what Prism reads in a scene file: dialect, counts, bounds, warnings.
    Info(info::InfoArgs),
    /// Render a scene in the browser as it forms: camera in hand, re-rendered on save.
    Preview(Box<preview::PreviewArgs>),
}

/// What `prism` alone prints: the commands, a line each.
const COMMANDS: &str = "\
Prism: a ray tracer for glTF, OBJ, PLY and Prism scene files, and the 2014 formats.

Usage: prism <COMMAND> [ARGS]...   (prism <COMMAND> --help for its options)

Commands:
  render    Render a scene (.gltf, .glb, .obj, .ply, .toml or .objx) to an image
  preview   Render a scene in the browser as it forms, re-rendered on save
  animate   Render every frame of an animation to images or a video
  info      Print what Prism reads in a scene file: counts, bounds, warnings
  bench     Measure intersector build time, memory and rays per second
  convert   Rewrite a Wavefront OBJ mesh as a 2014 scene file

prism SCENE CAMERA OUTPUT is the 2014 program's command line (= prism render).
";

/// Ctrl-C and SIGTERM: set by the signal handlers, read by the work, which stops,
/// leaves no partial file, and exits 128 + the signal's number.
pub(crate) struct Interrupt {
    pub stop: Arc<AtomicBool>,
    exit_code: Arc<AtomicUsize>,
}

impl Interrupt {
    fn install() -> Interrupt {
        let stop = Arc::new(AtomicBool::new(false));
        let exit_code = Arc::new(AtomicUsize::new(0));
        #[cfg(unix)]
        for (signal, code) in [
            (signal_hook::consts::SIGINT, 130),
            (signal_hook::consts::SIGTERM, 143),
        ] {
            // Without the handlers a signal ends the process at once, which is still
            // safe (outputs are written atomically); with them the work stops cleanly.
            let _ = signal_hook::flag::register_usize(signal, Arc::clone(&exit_code), code);
            let _ = signal_hook::flag::register(signal, Arc::clone(&stop));
        }
        Interrupt { stop, exit_code }
    }

    fn exit_code(&self) -> u8 {
        match self.exit_code.load(Ordering::Relaxed) {
            0 => 130,
            code => code as u8,
        }
    }
}

fn main() -> ExitCode {
    if std::env::args_os().len() <= 1 {
        print!("{COMMANDS}");
        return ExitCode::SUCCESS;
    }
    let cli = Cli::parse();
    let interrupt = Interrupt::install();
    let animating = matches!(cli.command, Some(Command::Animate(_)));
    let outcome = match cli.command {
        Some(Command::Render(args)) => render::run(&args, &interrupt),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Convert(args)) => convert::run(&args),
        Some(Command::Animate(args)) => animate::run(&args, &interrupt),
        Some(Command::Info(args)) => info::run(&args),
        Some(Command::Preview(args)) => preview::run(&args, &interrupt),
        None => render::run(&cli.render, &interrupt),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        // `animate` says itself which frames it kept.
        Err(prism::Error::Interrupted) => {
            if !animating {
                eprintln!("interrupted: nothing was written");
            }
            ExitCode::from(interrupt.exit_code())
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Options every command that reads scene files takes.
#[derive(clap::Args, Clone, Debug, Default)]
pub(crate) struct ReadLimits {
    /// Refuse to read any file outside DIR (after resolving `..` and symbolic links):
    /// for services that render scene files from others.
    #[arg(long, value_name = "DIR")]
    pub restrict_paths: Option<std::path::PathBuf>,
}

impl ReadLimits {
    /// Puts the limits in force for the rest of the process.
    pub fn apply(&self) -> prism::Result<()> {
        if let Some(dir) = &self.restrict_paths {
            prism::util::file::restrict_reads_to(dir)
                .map_err(|e| prism::Error::Settings(format!("--restrict-paths: {e}")))?;
        }
        Ok(())
    }
}

/// `--max-memory`: a size such as 512M or 4G.
pub(crate) fn parse_memory(s: &str) -> Result<u64, String> {
    prism::render::memory::parse_size(s)
}

/// `--accel`: clap checks and lists the intersector names, so commands get the kind.
pub(crate) fn accel_parser() -> impl clap::builder::TypedValueParser<Value = AccelKind> {
    clap::builder::PossibleValuesParser::new(AccelKind::ALL.map(AccelKind::name))
        .map(|name| name.parse().expect("clap accepts only listed names"))
}

pub(crate) fn progress_bar(rows: u64, quiet: bool) -> ProgressBar {
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
