//! The text layer OBJ and MTL share: reading a bounded regular file, decoding it, cutting
//! it into logical lines (comments dropped, `\` continuations joined) and tokens that
//! remember their column, and reading numbers the way C's `strtod` writes them.
//!
//! Everything works on bytes: names that are not UTF-8 are decoded as Latin-1 only when
//! they are kept, and no line is copied unless it continues onto the next one.

use std::borrow::Cow;
use std::ops::Range;
use std::path::Path;

use crate::error::{Error, Result};

/// The largest OBJ or MTL file read: 2 GiB. Every index then fits in a `u32` with room
/// to spare, and a mistaken path to a disk image fails at once instead of filling memory.
pub const MAX_FILE_BYTES: u64 = 2 << 30;

/// Reads a whole regular file of at most `max` bytes. A directory, FIFO or device would
/// fail late or block forever, so they are refused before opening.
pub fn read_file(path: &Path, max: u64) -> Result<Vec<u8>> {
    crate::util::file::read_regular(path, max)
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))
}

/// The text without a UTF-8 byte-order mark; UTF-16 text (with its mark, as some
/// Windows tools write) is converted to UTF-8 so it reads like any other file.
pub fn without_bom(bytes: &[u8]) -> Cow<'_, [u8]> {
    let utf16 = |big_endian: bool| {
        let units = bytes[2..].chunks_exact(2).map(|pair| {
            let pair = [pair[0], pair[1]];
            if big_endian {
                u16::from_be_bytes(pair)
            } else {
                u16::from_le_bytes(pair)
            }
        });
        let text: String = char::decode_utf16(units)
            .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
            .collect();
        Cow::Owned(text.into_bytes())
    };
    match bytes {
        [0xEF, 0xBB, 0xBF, rest @ ..] => Cow::Borrowed(rest),
        [0xFE, 0xFF, ..] => utf16(true),
        [0xFF, 0xFE, ..] => utf16(false),
        _ => Cow::Borrowed(bytes),
    }
}

/// A name as text: UTF-8 when it is, else Latin-1 (every byte one character), which is
/// what older Windows exporters wrote.
pub fn decode_name(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(text) => text.to_owned(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// A token shown in a message: decoded, control characters escaped, long ones shortened.
pub fn shown(bytes: &[u8]) -> String {
    super::super::text::shown(&decode_name(bytes))
}

pub fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | 0x0b | 0x0c)
}

/// `bytes` without leading and trailing white space.
pub fn trim(bytes: &[u8]) -> &[u8] {
    let start = bytes
        .iter()
        .position(|&b| !is_space(b))
        .unwrap_or(bytes.len());
    let end = bytes
        .iter()
        .rposition(|&b| !is_space(b))
        .map_or(start, |i| i + 1);
    &bytes[start..end]
}

/// Cuts text into logical lines: `#` starts a comment anywhere, and a line whose last
/// byte is `\` (outside a comment) continues on the next one, the two joined by a space.
pub struct Lines<'a> {
    rest: &'a [u8],
    next_number: usize,
    joined: Vec<u8>,
    /// For a joined line: where each physical line starts in `joined`, and its number.
    segments: Vec<(usize, usize)>,
}

/// One logical line: its text without the comment, and where it came from.
pub struct Line<'l> {
    pub text: &'l [u8],
    /// The 1-based number of the (first) physical line.
    pub number: usize,
    segments: &'l [(usize, usize)],
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a [u8]) -> Lines<'a> {
        Lines::numbered_from(text, 1)
    }

    /// Lines of a piece of a file that starts at line `first`: places still name the
    /// file's lines.
    pub fn numbered_from(text: &'a [u8], first: usize) -> Lines<'a> {
        Lines {
            rest: text,
            next_number: first,
            joined: Vec::new(),
            segments: Vec::new(),
        }
    }

    /// The next physical line, without its line end, and its comment cut off; and
    /// whether it ends with a continuation backslash (which is dropped).
    fn physical(&mut self) -> Option<(&'a [u8], bool)> {
        if self.rest.is_empty() {
            return None;
        }
        // One scan finds the line end or the comment, whichever comes first.
        let stop = find_newline_or_hash(self.rest);
        let (content, commented, after) = match stop {
            Some(i) if self.rest[i] == b'#' => {
                let end = self.rest[i..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(self.rest.len(), |j| i + j);
                (&self.rest[..i], true, end)
            }
            Some(i) => (&self.rest[..i], false, i),
            None => (self.rest, false, self.rest.len()),
        };
        self.rest = self.rest.get(after + 1..).unwrap_or(&[]);
        self.next_number += 1;
        if commented {
            return Some((content, false));
        }
        let line = content.strip_suffix(b"\r").unwrap_or(content);
        Some(match line.strip_suffix(b"\\") {
            Some(head) => (head, true),
            None => (line, false),
        })
    }

    pub fn next_line(&mut self) -> Option<Line<'_>> {
        let number = self.next_number;
        let (first, continues) = self.physical()?;
        if !continues {
            return Some(Line {
                text: first,
                number,
                segments: &[],
            });
        }
        self.joined.clear();
        self.segments.clear();
        self.segments.push((0, number));
        self.joined.extend_from_slice(first);
        let mut continues = true;
        while continues {
            let line_number = self.next_number;
            let Some((next, more)) = self.physical() else {
                break;
            };
            self.joined.push(b' ');
            self.segments.push((self.joined.len(), line_number));
            self.joined.extend_from_slice(next);
            continues = more;
        }
        Some(Line {
            text: &self.joined,
            number,
            segments: &self.segments,
        })
    }
}

impl Line<'_> {
    /// The physical line and 1-based column (in characters) of byte `offset` of the text.
    pub fn place(&self, offset: usize) -> (usize, usize) {
        let (start, number) = self
            .segments
            .iter()
            .rev()
            .find(|(start, _)| *start <= offset)
            .copied()
            .unwrap_or((0, self.number));
        let before = &self.text[start..offset.min(self.text.len())];
        // UTF-8 continuation bytes do not start a character.
        let column = 1 + before.iter().filter(|&&b| b & 0xC0 != 0x80).count();
        (number, column)
    }

    /// Whether the line was joined from several physical lines.
    pub fn is_joined(&self) -> bool {
        !self.segments.is_empty()
    }

    pub fn tokens(&self) -> Tokens<'_> {
        Tokens {
            text: self.text,
            pos: 0,
        }
    }

    /// The text from byte `offset` to the end, trimmed: a name that may hold spaces.
    pub fn rest_from(&self, offset: usize) -> &[u8] {
        trim(&self.text[offset.min(self.text.len())..])
    }
}

/// A token and the byte offset of its first byte in the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Token<'l> {
    pub bytes: &'l [u8],
    pub start: usize,
}

/// The white-space separated tokens of a line.
#[derive(Clone)]
pub struct Tokens<'l> {
    text: &'l [u8],
    pos: usize,
}

impl<'l> Iterator for Tokens<'l> {
    type Item = Token<'l>;

    fn next(&mut self) -> Option<Token<'l>> {
        let text = self.text;
        let mut pos = self.pos;
        while pos < text.len() && is_space(text[pos]) {
            pos += 1;
        }
        if pos == text.len() {
            self.pos = pos;
            return None;
        }
        let start = pos;
        while pos < text.len() && !is_space(text[pos]) {
            pos += 1;
        }
        self.pos = pos;
        Some(Token {
            bytes: &text[start..pos],
            start,
        })
    }
}

impl<'l> Tokens<'l> {
    /// Byte offset just past the last token read: where a missing one would have been.
    pub fn offset(&self) -> usize {
        self.pos
    }
}

/// Cuts text into pieces of about `step` bytes that [`Lines`] reads as it reads the
/// whole: each cut follows a `\n` ending a physical line that does not continue. The
/// pieces cover the text in order; the last may be short.
pub fn piece_ranges(text: &[u8], step: usize) -> Vec<Range<usize>> {
    let mut pieces = Vec::new();
    let mut start = 0;
    while start < text.len() {
        // The first byte a cut may follow.
        let mut from = start + step.max(1) - 1;
        let end = loop {
            let Some(i) = text
                .get(from..)
                .and_then(|rest| rest.iter().position(|&b| b == b'\n'))
            else {
                break text.len();
            };
            let newline = from + i;
            let line_start = text[start..newline]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(start, |j| start + j + 1);
            if !continues(&text[line_start..newline]) {
                break newline + 1;
            }
            from = newline + 1;
        };
        pieces.push(start..end);
        start = end;
    }
    pieces
}

/// Whether a physical line (without its `\n`) goes on to the next, as
/// [`Lines::physical`] decides it: a comment anywhere stops it.
fn continues(line: &[u8]) -> bool {
    !line.contains(&b'#') && line.strip_suffix(b"\r").unwrap_or(line).ends_with(b"\\")
}

/// How many `\n` the bytes hold. A block of 255 bytes cannot overflow a u8 count, and
/// a count kept in one byte is what the compiler turns into 16 bytes an instruction.
pub fn count_newlines(bytes: &[u8]) -> usize {
    bytes
        .chunks(255)
        .map(|block| block.iter().fold(0u8, |n, &b| n + (b == b'\n') as u8) as usize)
        .sum()
}

/// The first `\n` or `#` in `bytes`, eight bytes at a time.
fn find_newline_or_hash(bytes: &[u8]) -> Option<usize> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGHS: u64 = 0x8080_8080_8080_8080;
    let has_zero = |x: u64| x.wrapping_sub(ONES) & !x & HIGHS;
    let mut chunks = bytes.chunks_exact(8);
    let mut offset = 0;
    for chunk in &mut chunks {
        let word = u64::from_le_bytes(chunk.try_into().unwrap_or([0; 8]));
        if has_zero(word ^ (ONES * b'\n' as u64)) | has_zero(word ^ (ONES * b'#' as u64)) != 0 {
            break;
        }
        offset += 8;
    }
    bytes[offset..]
        .iter()
        .position(|&b| b == b'\n' || b == b'#')
        .map(|i| offset + i)
}

/// A decimal number as `strtod` reads it (`1`, `-2.5`, `.5`, `5.`, `+1e-001`), as an
/// f64; `None` for anything else, including hexadecimal floats, `nan` and `inf`.
pub fn parse_f64(s: &[u8]) -> Option<f64> {
    let (negative, body) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let mut i = 0;
    let mut mantissa: u64 = 0;
    let mut digits = 0usize; // significant digits kept in `mantissa`
    let mut exponent: i64 = 0;
    let mut any_digit = false;
    let mut exact = true;
    while i < body.len() && body[i].is_ascii_digit() {
        any_digit = true;
        push_digit(
            body[i],
            &mut mantissa,
            &mut digits,
            &mut exponent,
            &mut exact,
        );
        i += 1;
    }
    if i < body.len() && body[i] == b'.' {
        i += 1;
        while i < body.len() && body[i].is_ascii_digit() {
            any_digit = true;
            push_digit(
                body[i],
                &mut mantissa,
                &mut digits,
                &mut exponent,
                &mut exact,
            );
            exponent -= 1;
            i += 1;
        }
    }
    if !any_digit {
        return None;
    }
    if i < body.len() && (body[i] == b'e' || body[i] == b'E') {
        i += 1;
        let exp_negative = match body.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut e: i64 = 0;
        while i < body.len() && body[i].is_ascii_digit() {
            e = (e * 10 + (body[i] - b'0') as i64).min(1 << 20);
            i += 1;
        }
        if i == start {
            return None;
        }
        exponent += if exp_negative { -e } else { e };
    }
    if i != body.len() {
        return None;
    }
    // Clinger's fast path: a mantissa below 2^53 times an exact power of ten is
    // rounded once, correctly. Everything else goes to the standard library.
    let value = if exact && mantissa < (1 << 53) && (-22..=22).contains(&exponent) {
        let power = POWERS_OF_TEN[exponent.unsigned_abs() as usize];
        if exponent < 0 {
            mantissa as f64 / power
        } else {
            mantissa as f64 * power
        }
    } else {
        std::str::from_utf8(body).ok()?.parse::<f64>().ok()?
    };
    Some(if negative { -value } else { value })
}

fn push_digit(b: u8, mantissa: &mut u64, digits: &mut usize, exponent: &mut i64, exact: &mut bool) {
    let d = (b - b'0') as u64;
    if *digits == 0 && d == 0 {
        return; // leading zeros do not count
    }
    if *digits < 19 {
        *mantissa = *mantissa * 10 + d;
        *digits += 1;
    } else {
        // Digits beyond 19 do not fit: scale instead, and leave it to the slow path.
        *exponent += 1;
        *exact = false;
    }
}

const POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Whether a token that is not a number names a non-finite value (`nan`, `-inf`,
/// `infinity`, MSVC's `1.#INF`...), so the message can say "finite".
pub fn names_non_finite(s: &[u8]) -> bool {
    let lower = s.to_ascii_lowercase();
    let body = lower.strip_prefix(b"-").or(lower.strip_prefix(b"+"));
    let body = body.unwrap_or(&lower);
    body.starts_with(b"nan") || body.starts_with(b"inf") || body.windows(2).any(|w| w == b".#")
}

/// An integer of at most 18 digits with an optional sign: face indices and the like.
pub fn parse_integer(s: &[u8]) -> Option<i64> {
    let (negative, digits) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value * 10 + (b - b'0') as i64;
    }
    Some(if negative { -value } else { value })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn logical(text: &str) -> Vec<(usize, String)> {
        let mut lines = Lines::new(text.as_bytes());
        let mut out = Vec::new();
        while let Some(line) = lines.next_line() {
            out.push((line.number, String::from_utf8_lossy(line.text).into_owned()));
        }
        out
    }

    #[test]
    fn comments_are_cut_anywhere_and_backslashes_continue_lines() {
        assert_eq!(
            logical("v 1 2 3 # tail\r\nf 1 \\\n 2 \\\r\n3\n# only\nx \\ # not a continuation\n"),
            vec![
                (1, "v 1 2 3 ".to_owned()),
                (2, "f 1   2  3".to_owned()),
                (5, String::new()),
                (6, "x \\ ".to_owned()),
            ]
        );
        // A backslash on the last line joins nothing.
        assert_eq!(logical("v 1\\"), vec![(1, "v 1".to_owned())]);
    }

    #[test]
    fn places_in_joined_lines_name_their_physical_line() {
        let text = "f 1 \\\n  é2 \\\nbad\n";
        let mut lines = Lines::new(text.as_bytes());
        let line = lines.next_line().unwrap();
        let offsets: Vec<_> = line.tokens().map(|t| line.place(t.start)).collect();
        assert_eq!(offsets, [(1, 1), (1, 3), (2, 3), (3, 1)]);
    }

    #[test]
    fn pieces_read_as_the_whole_wherever_they_are_cut() {
        let text = "v 1 2 3 # tail \\\r\nf 1 \\\n 2 \\\r\n3\n\n# only \\\nx \\ # not\ng a\\\n\\\n b\r\nv 1\\";
        let whole = logical(text);
        for step in 1..text.len() + 2 {
            let ranges = piece_ranges(text.as_bytes(), step);
            let mut at = 0;
            let mut read = Vec::new();
            for range in ranges {
                assert_eq!(range.start, at, "{step}");
                assert!(range.end > range.start);
                at = range.end;
                let piece = &text.as_bytes()[range.clone()];
                let first = 1 + count_newlines(&text.as_bytes()[..range.start]);
                let mut lines = Lines::numbered_from(piece, first);
                while let Some(line) = lines.next_line() {
                    read.push((line.number, String::from_utf8_lossy(line.text).into_owned()));
                }
            }
            assert_eq!(at, text.len());
            assert_eq!(read, whole, "pieces of {step} bytes");
        }
        assert!(piece_ranges(b"", 4).is_empty());
    }

    #[test]
    fn newlines_are_counted_in_blocks_and_remainders() {
        let text: Vec<u8> = (0..10_000u32)
            .map(|i| if i % 7 == 0 { b'\n' } else { b'a' })
            .collect();
        for len in [0, 1, 15, 16, 17, 4079, 4080, 4081, 10_000] {
            let expected = text[..len].iter().filter(|&&b| b == b'\n').count();
            assert_eq!(count_newlines(&text[..len]), expected, "{len}");
        }
    }

    #[test]
    fn numbers_read_as_strtod_writes_them() {
        let cases: [(&str, f64); 10] = [
            ("1", 1.0),
            ("-2.5", -2.5),
            (".5", 0.5),
            ("5.", 5.0),
            ("+1", 1.0),
            ("1e-001", 0.1),
            (".8e-1", 0.08),
            ("-.7e+02", -70.0),
            ("0.000000000000000000000123456789", 1.23456789e-22),
            ("12345678901234567890123", 1.2345678901234568e22),
        ];
        for (text, value) in cases {
            assert_eq!(parse_f64(text.as_bytes()), Some(value), "{text}");
        }
        for bad in [
            "", "-", ".", "e5", "1e", "1e+", "1.2.3", "3.1+e2", "0x1p3", "nan", "inf",
        ] {
            assert_eq!(parse_f64(bad.as_bytes()), None, "{bad}");
        }
        assert!(names_non_finite(b"-NaN") && names_non_finite(b"1.#IND"));
        assert!(!names_non_finite(b"abc"));
    }

    #[test]
    fn the_fast_path_agrees_with_the_standard_library() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let mantissa = state % 100_000_000_000;
            let exponent = (state >> 40) as i64 % 30 - 15;
            let text = format!("{mantissa}e{exponent}");
            assert_eq!(
                parse_f64(text.as_bytes()),
                text.parse::<f64>().ok(),
                "{text}"
            );
        }
    }

    #[test]
    fn integers_are_signed_digits() {
        assert_eq!(parse_integer(b"-12"), Some(-12));
        assert_eq!(parse_integer(b"+7"), Some(7));
        for bad in ["", "-", "1.0", "1e3", "9999999999999999999"] {
            assert_eq!(parse_integer(bad.as_bytes()), None, "{bad}");
        }
    }

    #[test]
    fn byte_order_marks_go_and_utf16_becomes_utf8() {
        assert_eq!(&*without_bom(b"\xEF\xBB\xBFv 1"), b"v 1");
        assert_eq!(&*without_bom(b"\xFE\xFF\0v\0 \x001"), b"v 1");
        assert_eq!(&*without_bom(b"\xFF\xFEv\0"), b"v");
        assert_eq!(decode_name(b"caf\xe9"), "café");
        assert_eq!(decode_name("café".as_bytes()), "café");
    }

    #[test]
    fn only_bounded_regular_files_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_file(dir.path(), 100).unwrap_err().to_string();
        assert!(e.ends_with("cannot read: not a regular file"), "{e}");
        let file = dir.path().join("big.obj");
        std::fs::write(&file, "v 0 0 0\n").unwrap();
        assert_eq!(read_file(&file, 8).unwrap(), b"v 0 0 0\n");
        let e = read_file(&file, 7).unwrap_err().to_string();
        assert!(e.contains("the file has 8 bytes, more than the 7"), "{e}");
    }
}
