//! `prism animate`: every frame of an animation file, as numbered images or a video.

use clap::Args;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use prism::accel::AccelKind;
use prism::anim::Animation;
use prism::anim::job::{self, FrameObserver};
use prism::anim::output::{Output, VideoFormat, parse_frame_range};
use prism::anim::video;
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(Args)]
pub struct AnimateArgs {
    /// Animation file (.toml); its scene and camera paths resolve against its folder.
    pub animation: PathBuf,
    /// A folder (numbered PNG frames), a file name with %04d (numbered images), or a
    /// video: .mp4 (H.264), .gif, .apng or .png (animated PNG).
    pub output: PathBuf,
    /// Render only these frames: A..B (B excluded), A..=B, A.., ..B or N; from 0.
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// Intersector.
    #[arg(long, default_value = "bvh", value_parser = crate::accel_parser())]
    pub accel: AccelKind,
    /// Worker threads (default: every core). The frames do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Keep the numbered frames a video was made from (in OUTPUT.frames/).
    #[arg(long)]
    pub keep_frames: bool,
    /// No progress bars and no notes.
    #[arg(long, short)]
    pub quiet: bool,
    /// Print figures: frames rendered and skipped, render and encode seconds, file size.
    #[arg(long)]
    pub stats: bool,
    /// Memory budget (e.g. 512M, 4G): frames whose estimate is larger are refused
    /// before the first starts. Default: half of the machine's memory.
    #[arg(long, value_name = "SIZE", value_parser = crate::parse_memory)]
    pub max_memory: Option<u64>,
    /// Denoise each frame with Intel Open Image Denoise, guided by its albedo and
    /// normal passes, before its file is written (a Prism built with the `oidn`
    /// feature; docs/output.md). Also `[render] denoise = true` in the file.
    #[arg(long)]
    pub denoise: bool,
    #[command(flatten)]
    pub limits: crate::ReadLimits,
}

pub fn run(args: &AnimateArgs, interrupt: &crate::Interrupt) -> prism::Result<()> {
    // Refuse a bad output path before loading anything.
    let output = Output::from_path(&args.output)?;
    args.limits.apply()?;
    let mut anim = Animation::load(&args.animation)?;
    anim.settings.threads = args.threads;
    anim.settings.max_memory = args.max_memory;
    anim.settings.accel = args.accel;
    anim.denoise |= args.denoise;
    if anim.denoise {
        // Refused now, before any frame is rendered.
        prism::film::denoise::check_available()?;
    }
    anim.cancel = Some(std::sync::Arc::clone(&interrupt.stop));
    let frames = match &args.frames {
        Some(text) => parse_frame_range(text, anim.frames)?,
        None => 0..anim.frames,
    };
    job::check(&anim, frames.clone(), &output)?;
    if let Output::Video { path, .. } = &output
        && job::video_is_current(&anim, path)
    {
        if !args.quiet {
            eprintln!(
                "note: {} is already this animation's film: nothing to do",
                path.display()
            );
        }
        return Ok(());
    }

    // The bar and its ETA count only the frames to render, not those an earlier run
    // left (skipped in no time, they would make the ETA far too short).
    let pattern = output.frames();
    let to_render = frames
        .clone()
        .filter(|&k| !pattern.path_of(k).is_file())
        .count();
    let bars = Bars::new(to_render as u64, args.quiet);
    let observer = FrameObserver {
        frame_start: &|k, rows| bars.frame_start(k, rows),
        rows: &|n| bars.frame.inc(n),
        frame_done: &|_, skipped| {
            if !skipped {
                bars.all.inc(1)
            }
        },
    };
    let report = match job::render_frames(&anim, frames.clone(), output.frames(), &observer) {
        Err(prism::Error::Interrupted) => {
            bars.finish();
            let kept = frames
                .clone()
                .filter(|&k| pattern.path_of(k).is_file())
                .count();
            eprintln!(
                "interrupted: {kept} finished frames are kept in {} (no partial frame); \
                 run the same command again to resume",
                pattern.dir.display()
            );
            return Err(prism::Error::Interrupted);
        }
        other => other?,
    };
    if args.stats {
        println!(
            "frames {} rendered, {} skipped  render seconds {:.3}  rays {}",
            report.rendered, report.skipped, report.seconds, report.rays
        );
    }
    if let Output::Video { path, format, .. } = &output {
        // A range of a video's frames (one machine's share) is encoded only once every
        // frame of the animation is in the folder; until then the frames stay.
        let missing = job::missing_frames(pattern, anim.frames);
        if missing > 0 {
            bars.finish();
            if !args.quiet {
                eprintln!(
                    "note: {missing} of the animation's {} frames are not in {} yet: {} is \
                     made by the run that completes them",
                    anim.frames,
                    pattern.dir.display(),
                    path.display()
                );
            }
            return Ok(());
        }
        let all = 0..anim.frames;
        bars.encoding(all.len() as u64);
        let (info, seconds) = job::encode_frames(&anim, all.clone(), &output, &|| bars.all.inc(1))?;
        job::mark_video_current(&anim, path)?;
        bars.finish();
        if !args.keep_frames {
            job::remove_frames(pattern, all);
        }
        if args.stats {
            println!(
                "encoded {} frames  encode seconds {seconds:.3}  bytes {}  fps {}",
                info.frames, info.bytes, info.fps
            );
        }
        if *format == VideoFormat::Gif
            && !args.quiet
            && let Some(note) = video::gif_timing_note(anim.fps)
        {
            eprintln!("note: {}: {note}", path.display());
        }
    } else {
        bars.finish();
    }
    Ok(())
}

/// A bar over frames with ETA, and beneath it the bar of the frame being rendered.
struct Bars {
    all: ProgressBar,
    frame: ProgressBar,
    multi: MultiProgress,
}

impl Bars {
    fn new(frames: u64, quiet: bool) -> Bars {
        let multi = MultiProgress::new();
        if quiet || !std::io::stderr().is_terminal() {
            multi.set_draw_target(ProgressDrawTarget::hidden());
        }
        let all = multi.add(ProgressBar::new(frames));
        all.set_style(
            ProgressStyle::with_template(
                "{msg:9} [{elapsed_precise}] {wide_bar} {pos}/{len} frames, eta {eta}",
            )
            .expect("static template"),
        );
        all.set_message("rendering");
        let frame = multi.add(ProgressBar::new(1));
        frame.set_style(
            ProgressStyle::with_template("{prefix:>11} {wide_bar} {percent:>3}%")
                .expect("static template"),
        );
        Bars { all, frame, multi }
    }

    fn frame_start(&self, k: u32, rows: u64) {
        self.frame.reset();
        self.frame.set_length(rows);
        self.frame.set_prefix(format!("frame {k}"));
    }

    fn encoding(&self, frames: u64) {
        self.frame.finish_and_clear();
        self.all.reset();
        self.all.set_length(frames);
        self.all.set_message("encoding");
    }

    fn finish(&self) {
        self.frame.finish_and_clear();
        self.all.finish_and_clear();
        let _ = self.multi.clear();
    }
}
