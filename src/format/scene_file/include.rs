//! `include = ["shared.toml", ...]`: the files a scene file names, read depth first so
//! what an included file defines comes before what the including file defines.

use super::raw::RawFile;
use super::source::{Source, regular_file};
use crate::error::Result;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Includes may nest this deep: enough for any sensible library of shared files.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Files one scene may read in all, so a diamond of includes cannot grow exponentially.
pub const MAX_FILES: usize = 256;
/// Largest scene file read: far beyond any hand-written scene.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// One parsed file with the text its spans point into.
pub struct Document {
    pub source: Source,
    pub raw: RawFile,
}

/// Parses the file `text` read from `path` and every file it includes, includes first.
pub fn read_all(text: String, path: &Path) -> Result<Vec<Document>> {
    let mut out = Vec::new();
    let mut stack = Vec::new();
    let source = Source {
        path: path.to_path_buf(),
        text,
    };
    visit(source, &mut stack, &mut out)?;
    Ok(out)
}

/// Reads a scene file, refusing anything but a regular file of reasonable size.
pub fn read_text(path: &Path) -> std::result::Result<String, String> {
    let bytes = crate::util::file::read_regular(path, MAX_FILE_BYTES)
        .map_err(|e| format!("cannot read: {e}"))?;
    String::from_utf8(bytes).map_err(|_| "cannot read: not UTF-8 text".to_string())
}

fn visit(source: Source, stack: &mut Vec<PathBuf>, out: &mut Vec<Document>) -> Result<()> {
    let raw: RawFile = toml::from_str(&source.text).map_err(|e| source.toml_error(&e))?;
    if !stack.is_empty() {
        refuse_main_only_sections(&source, &raw)?;
    }
    stack.push(source.path.canonicalize().unwrap_or(source.path.clone()));
    for name in &raw.include {
        let path = source.resolve(name.get_ref());
        let error = |m: String| source.error(name, m);
        if stack.len() > MAX_INCLUDE_DEPTH {
            return Err(error(format!(
                "includes nest more than {MAX_INCLUDE_DEPTH} files deep"
            )));
        }
        regular_file(&source, name, &path)?;
        let canonical = path
            .canonicalize()
            .map_err(|e| error(format!("cannot open {}: {e}", path.display())))?;
        if stack.contains(&canonical) {
            return Err(error(format!(
                "include cycle: {} is already being read (it includes itself, directly or not)",
                path.display()
            )));
        }
        if out.len() + stack.len() >= MAX_FILES {
            return Err(error(format!(
                "more than {MAX_FILES} files included in all"
            )));
        }
        let text = read_text(&path).map_err(|m| error(format!("{}: {m}", path.display())))?;
        visit(Source { path, text }, stack, out)?;
    }
    stack.pop();
    out.push(Document { source, raw });
    Ok(())
}

/// An included file shares materials, lights and objects; the camera, render settings,
/// ambient light, background and tracks belong to the scene, so only its own file says them.
fn refuse_main_only_sections(source: &Source, raw: &RawFile) -> Result<()> {
    fn check<T>(source: &Source, at: Option<&Spanned<T>>, what: &str) -> Result<()> {
        match at {
            Some(at) => Err(source.error(
                at,
                format!(
                    "[{what}] belongs in the main scene file: an included file holds \
                     materials, lights and objects"
                ),
            )),
            None => Ok(()),
        }
    }
    check(source, raw.camera.as_ref(), "camera")?;
    check(source, raw.render.as_ref(), "render")?;
    check(source, raw.ambient.as_ref(), "ambient")?;
    check(source, raw.background.as_ref(), "background")?;
    check(source, raw.track.first(), "[track]")
}
