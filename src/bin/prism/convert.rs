//! `prism convert`: a standard Wavefront OBJ mesh rewritten in the 2014 scene form.

use std::path::PathBuf;

use clap::Args;
use prism::film::output::write_atomically;
use prism::format::{obj, objx};

#[derive(Args)]
pub struct ConvertArgs {
    /// Standard Wavefront OBJ file to read (its triangles).
    pub input: PathBuf,
    /// 2014 scene file to write (`.objx`).
    pub output: PathBuf,
    #[command(flatten)]
    pub limits: crate::ReadLimits,
}

pub fn run(args: &ConvertArgs) -> prism::Result<()> {
    args.limits.apply()?;
    let is_objx = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("objx"));
    if !is_objx {
        return Err(prism::Error::file(
            &args.output,
            "expected an output file ending in .objx (convert writes the 2014 scene form)",
        ));
    }
    // The same file by any path (or a link to it): writing would destroy the input.
    let same = match (
        std::fs::canonicalize(&args.input),
        std::fs::canonicalize(&args.output),
    ) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(prism::Error::file(
            &args.output,
            "is the input file: convert does not overwrite what it reads",
        ));
    }
    let mesh = obj::load_mesh(&args.input)?;
    let source = args.input.file_name().map_or_else(
        || args.input.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    write_atomically(&args.output, |w| {
        objx::write_mesh(&mesh, &source, w)
            .map_err(|e| prism::Error::file(&args.output, format!("cannot write: {e}")))
    })
}
