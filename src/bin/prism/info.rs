//! `prism info`: what Prism reads in a scene file.

use clap::Args;
use prism::info::SceneInfo;
use std::path::PathBuf;

#[derive(Args)]
pub struct InfoArgs {
    /// Scene file: .objx, .obj, .ply or .toml.
    pub scene: PathBuf,
    /// One JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub limits: crate::ReadLimits,
}

pub fn run(args: &InfoArgs) -> prism::Result<()> {
    args.limits.apply()?;
    let file = prism::format::load(&args.scene)?;
    let info = SceneInfo::of(&file);
    if args.json {
        println!("{}", info.to_json());
    } else {
        print!("{}", info.to_text());
    }
    Ok(())
}
