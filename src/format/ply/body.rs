//! Reading the values of the body one at a time, whatever the encoding: ASCII tokens
//! (errors at line:column) or binary fields of either byte order (errors at a byte
//! offset). Every read checks that the bytes are there, so a truncated file is an error
//! and never a panic.

use std::path::Path;

use super::header::{Encoding, Scalar};
use crate::error::{Error, Result};
use crate::util::text::shown;

/// What is being read, for messages: `property y of vertex 3`.
#[derive(Clone, Copy)]
pub struct Field<'a> {
    pub element: &'a str,
    pub row: u32,
    pub property: &'a str,
}

impl std::fmt::Display for Field<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "property {} of {} {}",
            shown(self.property),
            shown(self.element),
            self.row
        )
    }
}

pub enum Values<'a> {
    Ascii(AsciiValues<'a>),
    Binary(BinaryValues<'a>),
}

impl<'a> Values<'a> {
    pub fn new(encoding: Encoding, bytes: &'a [u8], body_start: usize, path: &'a Path) -> Self {
        match encoding {
            Encoding::Ascii => Values::Ascii(AsciiValues::new(bytes, body_start, path)),
            Encoding::LittleEndian | Encoding::BigEndian => Values::Binary(BinaryValues {
                bytes,
                offset: body_start,
                big_endian: encoding == Encoding::BigEndian,
                path,
            }),
        }
    }

    /// The next value, of type `ty`, widened to f64 (exact for every PLY type).
    pub fn scalar(&mut self, ty: Scalar, field: Field) -> Result<f64> {
        match self {
            Values::Ascii(a) => a.scalar(ty, field),
            Values::Binary(b) => b.scalar(ty, field),
        }
    }

    /// The length of a list, checked against what is left of the file.
    pub fn list_length(&mut self, ty: Scalar, item: Scalar, field: Field) -> Result<u32> {
        let at = self.place();
        let value = self.scalar(ty, field)?;
        if value < 0.0 {
            return Err(self.error_at(
                at,
                format!("expected a list length >= 0 for {field}, found {value}"),
            ));
        }
        let length = value as u32;
        // Every item takes at least its size in binary, two bytes in ASCII.
        let item_bytes = match self {
            Values::Ascii(_) => 2,
            Values::Binary(_) => item.size() as u64,
        };
        let needed = u64::from(length) * item_bytes;
        if needed > self.remaining() as u64 + 1 {
            return Err(self.error_at(
                at,
                format!(
                    "expected a list length that fits in the file for {field}: {length} \
                     items need at least {needed} bytes, found {} left",
                    self.remaining()
                ),
            ));
        }
        Ok(length)
    }

    /// Passes over the `length` items of a list that is not kept; binary items are
    /// skipped in one step (the length was checked against the file's size).
    pub fn skip_items(&mut self, item: Scalar, length: u32, field: Field) -> Result<()> {
        match self {
            Values::Ascii(a) => (0..length).try_for_each(|_| a.scalar(item, field).map(drop)),
            Values::Binary(b) => b.take(item.size() * length as usize, field).map(drop),
        }
    }

    /// Passes over a value that is not kept; binary values are not decoded.
    pub fn skip(&mut self, ty: Scalar, field: Field) -> Result<()> {
        match self {
            Values::Ascii(a) => a.scalar(ty, field).map(drop),
            Values::Binary(b) => b.take(ty.size(), field).map(drop),
        }
    }

    /// Where the next value starts: a byte offset, which [`Values::error_at`] turns
    /// into a line and column for ASCII.
    pub fn place(&mut self) -> usize {
        match self {
            Values::Ascii(a) => a.next_token_start(),
            Values::Binary(b) => b.offset,
        }
    }

    pub fn error_at(&self, place: usize, message: impl Into<String>) -> Error {
        match self {
            Values::Ascii(a) => a.error_at(place, message),
            Values::Binary(b) => b.error_at(place, message),
        }
    }

    fn remaining(&self) -> usize {
        match self {
            Values::Ascii(a) => a.bytes.len() - a.offset,
            Values::Binary(b) => b.bytes.len() - b.offset,
        }
    }

    /// A warning for data after the last row, if there is any.
    pub fn trailing(&mut self) -> Option<String> {
        match self {
            Values::Ascii(a) => {
                let start = a.next_token_start();
                (start < a.bytes.len()).then(|| {
                    let (line, column) = a.line_column(start);
                    format!("text after the last element is ignored, from {line}:{column}")
                })
            }
            Values::Binary(b) => {
                let left = b.bytes.len() - b.offset;
                (left > 0).then(|| {
                    format!(
                        "{left} bytes after the last element are ignored, from byte {}",
                        b.offset
                    )
                })
            }
        }
    }
}

/// Whitespace-separated tokens. Rows need not be one per line: only the order counts.
pub struct AsciiValues<'a> {
    bytes: &'a [u8],
    offset: usize,
    path: &'a Path,
    /// Line number and start of the line `offset` is on, advanced as tokens are read,
    /// so that a place on the current line costs nothing to locate.
    line: usize,
    line_start: usize,
    body_start: usize,
    body_first_line: usize,
}

impl<'a> AsciiValues<'a> {
    fn new(bytes: &'a [u8], body_start: usize, path: &'a Path) -> Self {
        let line = 1 + bytes[..body_start].iter().filter(|&&b| b == b'\n').count();
        AsciiValues {
            bytes,
            offset: body_start,
            path,
            line,
            line_start: body_start,
            body_start,
            body_first_line: line,
        }
    }

    fn skip_whitespace(&mut self) {
        while let Some(&b) = self.bytes.get(self.offset) {
            if b == b'\n' {
                self.line += 1;
                self.line_start = self.offset + 1;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.offset += 1;
        }
    }

    fn next_token_start(&mut self) -> usize {
        self.skip_whitespace();
        self.offset
    }

    fn scalar(&mut self, ty: Scalar, field: Field) -> Result<f64> {
        self.skip_whitespace();
        let start = self.offset;
        let len = self.bytes[start..]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(self.bytes.len() - start);
        if len == 0 {
            return Err(self.error_at(
                start,
                format!(
                    "expected a {} for {field}, found the end of the file",
                    ty.name()
                ),
            ));
        }
        self.offset += len;
        let raw = &self.bytes[start..start + len];
        let token = std::str::from_utf8(raw).unwrap_or("");
        let value = match ty.integer_range() {
            Some((lo, hi)) => token
                .parse::<i64>()
                .ok()
                .filter(|v| (lo..=hi).contains(v))
                .map(|v| v as f64),
            // An f32 read as f32: through f64 it could round twice.
            None if ty == Scalar::F32 => token.parse::<f32>().ok().map(f64::from),
            None => token.parse::<f64>().ok(),
        };
        value.ok_or_else(|| {
            let range = match ty.integer_range() {
                Some((lo, hi)) => format!(" ({lo} to {hi})"),
                None => String::new(),
            };
            self.error_at(
                start,
                format!(
                    "expected a {}{range} for {field}, found {}",
                    ty.name(),
                    shown(&String::from_utf8_lossy(raw))
                ),
            )
        })
    }

    /// 1-based line and column (in characters) of a byte offset in the body.
    fn line_column(&self, place: usize) -> (usize, usize) {
        let (line, line_start) = if place >= self.line_start {
            (self.line, self.line_start)
        } else {
            let before = &self.bytes[self.body_start..place];
            let newlines = before.iter().filter(|&&b| b == b'\n').count();
            let start = before
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(self.body_start, |i| self.body_start + i + 1);
            (self.body_first_line + newlines, start)
        };
        let column = 1 + String::from_utf8_lossy(&self.bytes[line_start..place])
            .chars()
            .count();
        (line, column)
    }

    fn error_at(&self, place: usize, message: impl Into<String>) -> Error {
        let (line, column) = self.line_column(place);
        Error::parse_at(self.path, line, column, message)
    }
}

pub struct BinaryValues<'a> {
    bytes: &'a [u8],
    offset: usize,
    big_endian: bool,
    path: &'a Path,
}

impl BinaryValues<'_> {
    fn take(&mut self, n: usize, field: Field) -> Result<&[u8]> {
        let start = self.offset;
        let Some(bytes) = start
            .checked_add(n)
            .and_then(|end| self.bytes.get(start..end))
        else {
            return Err(self.error_at(
                start,
                format!(
                    "expected {n} bytes for {field}, found {} before the end of the file",
                    self.bytes.len() - start
                ),
            ));
        };
        self.offset += n;
        Ok(bytes)
    }

    fn scalar(&mut self, ty: Scalar, field: Field) -> Result<f64> {
        let big_endian = self.big_endian;
        let b = self.take(ty.size(), field)?;
        macro_rules! decode {
            ($t:ty) => {{
                let array = b.try_into().expect("take returned the type's size");
                f64::from(if big_endian {
                    <$t>::from_be_bytes(array)
                } else {
                    <$t>::from_le_bytes(array)
                })
            }};
        }
        Ok(match ty {
            Scalar::I8 => decode!(i8),
            Scalar::U8 => decode!(u8),
            Scalar::I16 => decode!(i16),
            Scalar::U16 => decode!(u16),
            Scalar::I32 => decode!(i32),
            Scalar::U32 => decode!(u32),
            Scalar::F32 => decode!(f32),
            Scalar::F64 => decode!(f64),
        })
    }

    fn error_at(&self, place: usize, message: impl Into<String>) -> Error {
        Error::file(self.path, format!("byte {place}: {}", message.into()))
    }
}
