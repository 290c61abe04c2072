//! `prism preview`: the scene in the browser as it forms, with the camera in hand and
//! re-rendered when a file it reads is saved. The library's `preview::Preview` does the
//! work; this starts it, prints its address and waits for Ctrl-C.

use crate::render::JobArgs;
use clap::Args;
use std::net::IpAddr;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::Duration;

#[derive(Args)]
pub struct PreviewArgs {
    /// Scene file (any dialect `prism render` reads); files beside it are watched.
    pub scene: PathBuf,
    /// An optional 2014 camera file (.cmr).
    pub camera_path: Option<PathBuf>,
    /// Port to listen on (default: a free one).
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// Address to listen on. Anything but loopback lets other machines see the scene.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Denoise every full-size pass (Intel Open Image Denoise, guided by the albedo and
    /// normal passes); needs a Prism built with the `oidn` feature.
    #[arg(long)]
    pub denoise: bool,
    #[command(flatten)]
    pub job: JobArgs,
    #[command(flatten)]
    pub limits: crate::ReadLimits,
}

pub fn run(args: &PreviewArgs, interrupt: &crate::Interrupt) -> prism::Result<()> {
    args.limits.apply()?;
    if args.camera_path.is_some() && args.job.camera.is_some() {
        return Err(prism::Error::Settings(
            "a camera file is given twice: as a path and with --camera".into(),
        ));
    }
    let camera = args.camera_path.clone().or(args.job.camera.clone());
    let mut options = args.job.options(camera)?;
    if args.denoise {
        options.render.denoise = Some(true);
    }
    prism::render::check_threads(args.job.threads)?;
    if !args.bind.is_loopback() {
        eprintln!(
            "warning: listening on {}: other machines on the network can see this scene",
            args.bind
        );
    }
    let preview = prism::preview::Preview::start(&args.scene, options, args.bind, args.port)?;
    println!("{}", preview.url());
    if args.open {
        open_in_browser(preview.url());
    }
    eprintln!("previewing {} (Ctrl-C to stop)", args.scene.display());
    while !interrupt.stop.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(100));
    }
    preview.stop();
    eprintln!("stopped");
    Ok(())
}

/// Asks the desktop to open `url`; says so if it cannot.
fn open_in_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        eprintln!("warning: cannot open a browser ({opener}: {e}): open {url} yourself");
    }
}
