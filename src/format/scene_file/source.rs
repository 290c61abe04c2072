//! One scene file's text and path: byte offsets from TOML spans become the
//! `file:line:column` every message starts with.

use crate::error::Error;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

pub struct Source {
    pub path: PathBuf,
    pub text: String,
}

impl Source {
    /// 1-based line and column (in characters) of byte `offset`.
    pub fn line_column(&self, offset: usize) -> (usize, usize) {
        let mut end = offset.min(self.text.len());
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        let before = &self.text[..end];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = 1 + before.bytes().filter(|&b| b == b'\n').count();
        (line, 1 + before[line_start..].chars().count())
    }

    pub fn error_at(&self, span: Range<usize>, message: impl Into<String>) -> Error {
        let (line, column) = self.line_column(span.start);
        Error::parse_at(&self.path, line, column, message)
    }

    pub fn error<T>(&self, at: &Spanned<T>, message: impl Into<String>) -> Error {
        self.error_at(at.span(), message)
    }

    /// A TOML syntax or type error, at the place the parser points to.
    pub fn toml_error(&self, e: &toml::de::Error) -> Error {
        let message = e.message().trim_end().replace('\n', "; ");
        self.error_at(e.span().unwrap_or(0..0), message)
    }

    /// `name` as the file names it, resolved against the file's folder.
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.folder().join(name)
    }

    pub fn folder(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new(""))
    }
}

/// Checks that `path` names a regular file (not a directory, FIFO or device, which
/// could block or never end), with an error at the key that names it.
pub fn regular_file(
    source: &Source,
    at: &Spanned<String>,
    path: &Path,
) -> crate::error::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(source.error(
            at,
            format!(
                "expected a regular file, found {} is not one",
                path.display()
            ),
        )),
        Err(e) => Err(source.error(at, format!("cannot open {}: {e}", path.display()))),
    }
}

/// Refuses the first of `given` (key, where it starts) that `allowed` does not list:
/// `` `key` does not apply to a WHAT, which takes `a`, `b` ``.
pub fn refuse_foreign_keys(
    source: &Source,
    given: Vec<(&'static str, std::ops::Range<usize>)>,
    allowed: &[&str],
    what: &str,
) -> crate::error::Result<()> {
    match given.into_iter().find(|(n, _)| !allowed.contains(n)) {
        None => Ok(()),
        Some((name, span)) => {
            let takes: Vec<String> = allowed.iter().map(|k| format!("`{k}`")).collect();
            Err(source.error_at(
                span,
                format!(
                    "{} does not apply to a {what}, which takes {}",
                    crate::util::text::shown(name),
                    takes.join(", ")
                ),
            ))
        }
    }
}
