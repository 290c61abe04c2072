//! Text as every stage reads and shows it: files decoded as UTF-8 (a byte-order mark
//! dropped), and tokens and paths quoted for messages so a stray byte cannot garble the
//! terminal.

use std::path::Path;

use super::limits::MAX_TEXT_BYTES;
use crate::error::{Error, Result};

/// Reads a whole file as UTF-8 text, of at most [`MAX_TEXT_BYTES`]. Only regular files
/// are read: a path naming a directory, a FIFO or a device such as `/dev/stdin` would
/// otherwise fail late or block.
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = super::file::read_regular(path, MAX_TEXT_BYTES)
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    decode(&bytes, path).map(str::to_owned)
}

/// Checks that `bytes` are UTF-8 and drops a leading byte-order mark (some editors write
/// one; it would otherwise glue itself to the first keyword). An invalid byte is an
/// error at its line and column of `path`.
pub fn decode<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str> {
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok(text.strip_prefix('\u{feff}').unwrap_or(text)),
        Err(e) => {
            let good = &bytes[..e.valid_up_to()];
            let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
            let column =
                1 + good.len() - good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            Err(Error::parse(
                path,
                line,
                format!("expected UTF-8 text, found an invalid byte at column {column}"),
            ))
        }
    }
}

/// A token as shown in a message, between backticks: control characters are escaped so a
/// stray byte cannot garble the terminal, and very long tokens are shortened.
pub fn shown(token: &str) -> String {
    const MAX_CHARS: usize = 40;
    let mut out = String::from("`");
    for (i, c) in token.chars().enumerate() {
        if i == MAX_CHARS {
            out.push_str("...");
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out.push('`');
    out
}

/// A path as shown in a message: [`shown`] of its text.
pub fn shown_path(path: &Path) -> String {
    shown(&path.to_string_lossy())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_utf8_is_an_error_with_its_line() {
        let e = decode(b"v 1 2 3\nv \xff 2 3\n", Path::new("s.objx")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.objx:2: expected UTF-8 text, found an invalid byte at column 3"
        );
        assert_eq!(decode("\u{feff}v".as_bytes(), Path::new("x")).unwrap(), "v");
    }

    #[test]
    fn shown_escapes_and_shortens() {
        assert_eq!(shown("a\u{1b}b"), "`a\\u{1b}b`");
        assert_eq!(shown(&"x".repeat(50)), format!("`{}...`", "x".repeat(40)));
    }

    #[test]
    fn reading_a_directory_or_missing_file_is_a_file_error() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_text(dir.path()).unwrap_err();
        assert!(matches!(e, Error::File { .. }), "{e}");
        let e = read_text(&dir.path().join("missing.objx")).unwrap_err();
        assert!(e.to_string().contains("cannot read: "), "{e}");
    }
}
