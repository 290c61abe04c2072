//! What the three 2014 formats share: reading a file as text, splitting it into numbered
//! lines of tokens, and turning tokens into checked numbers with messages that say what
//! was expected and what was found.

use std::path::Path;

use crate::error::{Error, Result};
pub(crate) use crate::util::text::{read_text, shown};

/// One line that holds data: its 1-based number and its whitespace-separated tokens.
pub(super) struct Line<'a> {
    pub number: usize,
    pub tokens: Vec<&'a str>,
}

/// The lines of `text` that hold data: blank lines and comment lines (first non-blank
/// character `#`) are skipped. Any whitespace separates tokens, so tabs, runs of spaces,
/// trailing spaces and CRLF line ends all read the same.
pub(super) fn data_lines(text: &str) -> impl Iterator<Item = Line<'_>> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let trimmed = line.trim_start();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            return None;
        }
        Some(Line {
            number: i + 1,
            tokens: trimmed.split_whitespace().collect(),
        })
    })
}

/// Number of the last line of `text` (1 for an empty text): where a reader that runs out
/// of values reports it.
pub(super) fn last_line(text: &str) -> usize {
    text.lines().count().max(1)
}

/// A place in a file, to build errors and parse tokens found there.
#[derive(Clone, Copy)]
pub(super) struct At<'p> {
    pub path: &'p Path,
    pub line: usize,
}

impl At<'_> {
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::parse(self.path, self.line, message)
    }

    /// A finite number that also fits in an f32 (the scene stores f32). Parsed as f64 so
    /// that the rectangle check can work on the exact decimal values of the file.
    pub fn number(&self, token: &str, what: &str) -> Result<f64> {
        let value: f64 = token.parse().map_err(|_| {
            self.error(format!(
                "expected a number for {what}, found {}",
                shown(token)
            ))
        })?;
        if !value.is_finite() {
            return Err(self.error(format!(
                "expected a finite number for {what}, found {}",
                shown(token)
            )));
        }
        if value.abs() > f32::MAX as f64 {
            return Err(self.error(format!(
                "expected a number of magnitude at most {:e} for {what}, found {}",
                f32::MAX,
                shown(token)
            )));
        }
        Ok(value)
    }

    /// A number checked against a lower bound: `> min` when `strict`, else `>= min`.
    /// A strict bound also holds for the f32 that is stored (`1e-50 > 0` but not in f32).
    pub fn number_above(&self, token: &str, what: &str, min: f64, strict: bool) -> Result<f64> {
        let value = self.number(token, what)?;
        let ok = if strict {
            value > min && value as f32 > min as f32
        } else {
            value >= min
        };
        if !ok {
            let relation = if strict { ">" } else { ">=" };
            return Err(self.error(format!(
                "expected {what} {relation} {min}, found {}",
                shown(token)
            )));
        }
        Ok(value)
    }

    /// A positive integer written with digits only (`3840`; not `12.5`, `0`, `-3`, `1e3`).
    pub fn positive_integer(&self, token: &str, what: &str) -> Result<u32> {
        let digits = token.strip_prefix('+').unwrap_or(token);
        let expected = || {
            self.error(format!(
                "expected a positive integer for {what}, found {}",
                shown(token)
            ))
        };
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(expected());
        }
        match digits.parse::<u32>() {
            Ok(0) => Err(expected()),
            Ok(n) => Ok(n),
            Err(_) => Err(self.error(format!(
                "expected a positive integer of at most {} for {what}, found {}",
                u32::MAX,
                shown(token)
            ))),
        }
    }
}

/// Converts a count or position to the u32 indices the scene stores, as an error rather
/// than a silent wrap on absurdly large inputs.
pub(super) fn index_u32(at: At, n: usize, what: &str) -> Result<u32> {
    u32::try_from(n).map_err(|_| at.error(format!("too many {what}: at most {} allowed", u32::MAX)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at() -> At<'static> {
        At {
            path: Path::new("t.txt"),
            line: 3,
        }
    }

    #[test]
    fn comments_blank_lines_and_odd_whitespace_are_handled() {
        let text = "# head\r\n\r\n  v 1\t2  3 \r\n   # indented comment\nf 0\n";
        let lines: Vec<_> = data_lines(text).map(|l| (l.number, l.tokens)).collect();
        assert_eq!(
            lines,
            vec![(3, vec!["v", "1", "2", "3"]), (5, vec!["f", "0"])]
        );
    }

    #[test]
    fn numbers_are_checked() {
        assert_eq!(at().number("-2.5e1", "x").unwrap(), -25.0);
        for bad in ["abc", "nan", "inf", "-infinity", "1e39", ""] {
            assert!(at().number(bad, "x").is_err(), "{bad}");
        }
        let e = at().number("abc", "the radius").unwrap_err().to_string();
        assert_eq!(e, "t.txt:3: expected a number for the radius, found `abc`");
        assert!(at().number_above("0", "d", 0.0, true).is_err());
        assert!(at().number_above("1e-50", "d", 0.0, true).is_err());
        assert_eq!(at().number_above("0", "f", 0.0, false).unwrap(), 0.0);
    }

    #[test]
    fn positive_integers_are_digits_only() {
        assert_eq!(at().positive_integer("3840", "w").unwrap(), 3840);
        for bad in ["12.5", "0", "-3", "1e3", "", "+", "99999999999"] {
            assert!(at().positive_integer(bad, "w").is_err(), "{bad}");
        }
    }
}
