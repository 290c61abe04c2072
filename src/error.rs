//! Errors a user can cause: each names the file, the line and what was expected.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Malformed content at a known place in a file.
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// Malformed content at a known line and column (1-based, in characters) of a file.
    #[error("{}:{line}:{column}: {message}", path.display())]
    ParseAt {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// A file that cannot be opened, read or written.
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    /// Settings that cannot be rendered (resolution, sample counts, region...).
    #[error("{0}")]
    Settings(String),
    /// The work was stopped on request (Ctrl-C, a cancelled Python call).
    #[error("interrupted")]
    Interrupted,
}

impl Error {
    pub fn parse(path: &Path, line: usize, message: impl Into<String>) -> Error {
        Error::Parse {
            path: path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    pub fn parse_at(path: &Path, line: usize, column: usize, message: impl Into<String>) -> Error {
        Error::ParseAt {
            path: path.to_path_buf(),
            line,
            column,
            message: message.into(),
        }
    }

    pub fn file(path: &Path, message: impl std::fmt::Display) -> Error {
        Error::File {
            path: path.to_path_buf(),
            message: message.to_string(),
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
