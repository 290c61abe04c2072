//! Errors a user can cause: each names the file, the line and what was expected.

use std::path::{Path, PathBuf};

/// An error Prism reports to the user: bad input, an unusable file, settings that cannot
/// be rendered, or a stop on request.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Malformed content at a known place in a file.
    #[error("{}:{line}: {message}", shown_path(path))]
    Parse {
        /// The file, as given (shown shortened if absurdly long).
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What was wrong and what was expected, with long words cut.
        message: String,
    },
    /// Malformed content at a known line and column (1-based, in characters) of a file.
    #[error("{}:{line}:{column}: {message}", shown_path(path))]
    ParseAt {
        /// The file, as given (shown shortened if absurdly long).
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// 1-based column, counted in characters.
        column: usize,
        /// What was wrong and what was expected, with long words cut.
        message: String,
    },
    /// A file that cannot be opened, read or written.
    #[error("{}: {message}", shown_path(path))]
    File {
        /// The file, as given (shown shortened if absurdly long).
        path: PathBuf,
        /// Why it failed: usually the operating system's error.
        message: String,
    },
    /// Malformed content of a scene given as data (Python's dicts), at `place` in it.
    #[error("{place}: {message}")]
    Data {
        /// Where in the data: `scene`, a table such as `objects[2]`, or a named mesh.
        place: String,
        /// What was wrong and what was expected.
        message: String,
    },
    /// Settings that cannot be rendered (resolution, sample counts, region...).
    #[error("{0}")]
    Settings(String),
    /// Denoising was asked for and cannot be done: this Prism was built without Open
    /// Image Denoise, or the library failed.
    #[error("cannot denoise: {0}")]
    Denoise(String),
    /// The work was stopped on request (Ctrl-C, a cancelled Python call).
    #[error("interrupted")]
    Interrupted,
}

impl Error {
    /// An [`Error::Parse`] at `line` (1-based) of `path`, its message bounded.
    pub fn parse(path: &Path, line: usize, message: impl Into<String>) -> Error {
        Error::Parse {
            path: path.to_path_buf(),
            line,
            message: bounded(message.into()),
        }
    }

    /// An [`Error::ParseAt`] at `line` and `column` (1-based, in characters) of `path`,
    /// its message bounded.
    pub fn parse_at(path: &Path, line: usize, column: usize, message: impl Into<String>) -> Error {
        Error::ParseAt {
            path: path.to_path_buf(),
            line,
            column,
            message: bounded(message.into()),
        }
    }

    /// An [`Error::File`] for `path`, with `message` (an `io::Error`, say) as its bounded
    /// text.
    pub fn file(path: &Path, message: impl std::fmt::Display) -> Error {
        Error::File {
            path: path.to_path_buf(),
            message: bounded(message.to_string()),
        }
    }
}

/// Longest word (run without spaces) a message keeps whole: names, tokens and paths
/// quoted from a file are cut to a short excerpt, whoever built the message (a 50 MB
/// material name must not come back as a 50 MB error).
const MAX_WORD_CHARS: usize = 512;
/// What is kept of a longer word.
const EXCERPT_CHARS: usize = 60;
/// Longest message kept.
const MAX_MESSAGE_CHARS: usize = 4096;

/// `message` with long words shortened, control characters escaped and its length
/// bounded.
pub fn bounded(message: String) -> String {
    bounded_words(message, MAX_WORD_CHARS)
}

fn bounded_words(message: String, max_word: usize) -> String {
    let clean = message.chars().count() <= max_word && !message.chars().any(char::is_control);
    if clean {
        return message;
    }
    let mut out = String::new();
    for (i, word) in message.split(' ').enumerate() {
        if i > 0 {
            out.push(' ');
        }
        let long = word.chars().nth(max_word).is_some();
        let kept = if long { EXCERPT_CHARS } else { max_word };
        for c in word.chars().take(kept) {
            if c.is_control() {
                out.extend(c.escape_default());
            } else {
                out.push(c);
            }
        }
        if long {
            out.push_str("...");
        }
        if out.len() > MAX_MESSAGE_CHARS {
            out.push_str(" ...");
            break;
        }
    }
    out
}

/// A path in a message: whole unless longer than any path a system opens (4096).
fn shown_path(path: &Path) -> String {
    bounded_words(path.display().to_string(), 4096)
}

/// Prism's result type: errors are [`Error`] unless said otherwise.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_words_are_cut_to_an_excerpt_and_control_characters_escaped() {
        let name = "a".repeat(5_000_000);
        let e = Error::parse(
            Path::new("m.mtl"),
            3,
            format!("unknown field `{name}`, expected x"),
        );
        let shown = e.to_string();
        assert_eq!(
            shown,
            format!("m.mtl:3: unknown field `{}... expected x", "a".repeat(59))
        );
        let e = Error::file(Path::new("f"), "bell \u{7} and\nnewline");
        assert_eq!(e.to_string(), "f: bell \\u{7} and\\nnewline");
        let words = vec!["word"; 10_000].join(" ");
        let e = Error::file(Path::new("f"), &words);
        assert!(e.to_string().len() < MAX_MESSAGE_CHARS + 100);
        let short = "f: a short message stays as it is";
        assert_eq!(Error::file(Path::new("f"), &short[3..]).to_string(), short);
        let path = "p".repeat(10_000);
        let e = Error::file(Path::new(&path), "cannot read");
        assert_eq!(e.to_string(), format!("{}...: cannot read", "p".repeat(60)));
    }
}
