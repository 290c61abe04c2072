//! The PLY header: the encoding, then elements with their row counts and properties.
//!
//! The header is read as lines of bytes so that a binary body right after
//! `end_header` is never decoded; only the lines that matter must be UTF-8 (`comment`
//! and `obj_info` lines are skipped as bytes, some writers put Latin-1 there).

use std::path::Path;

use crate::error::{Error, Result};
use crate::util::text::shown;

/// Longer headers are refused: real ones are a few hundred bytes, and the bound keeps a
/// file of random bytes from being scanned line by line for an `end_header`.
pub const MAX_HEADER_BYTES: usize = 64 * 1024;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// A scalar type, under either of its two names (`uchar` or `uint8`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The range of an integer type; `None` for floats.
    pub fn integer_range(self) -> Option<(i64, i64)> {
        Some(match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PropertyKind {
    Scalar(Scalar),
    /// A length of an integer type, then that many items.
    List {
        length: Scalar,
        item: Scalar,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Property {
    pub name: String,
    pub kind: PropertyKind,
    /// The `property` line, to blame it when the type does not suit the name.
    pub line: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub name: String,
    pub rows: u32,
    pub properties: Vec<Property>,
    /// Where the `element` line is, to blame it when its rows cannot fit in the file.
    pub line: usize,
    pub count_column: usize,
}

impl Element {
    pub fn property(&self, name: &str) -> Option<usize> {
        self.properties.iter().position(|p| p.name == name)
    }

    /// The fewest bytes a row can take: every scalar, and every list empty. In ASCII
    /// each value is at least one character and one separator (the file's very last
    /// value may go without, hence `body_bytes + 1` where this is compared).
    pub fn min_row_bytes(&self, encoding: Encoding) -> u64 {
        self.properties
            .iter()
            .map(|p| match (encoding, p.kind) {
                (Encoding::Ascii, _) => 2,
                (_, PropertyKind::Scalar(s)) => s.size() as u64,
                (_, PropertyKind::List { length, .. }) => length.size() as u64,
            })
            .sum()
    }
}

#[derive(Debug, PartialEq)]
pub struct Header {
    pub encoding: Encoding,
    pub elements: Vec<Element>,
    /// Offset of the first byte after `end_header`'s line end.
    pub body_start: usize,
}

/// One header line: its bytes without the line end, its number and where it starts.
struct Line<'a> {
    bytes: &'a [u8],
    number: usize,
}

impl Line<'_> {
    fn error(&self, path: &Path, token: Option<&Token>, message: impl Into<String>) -> Error {
        let column = token.map_or(1, |t| t.column);
        Error::parse_at(path, self.number, column, message)
    }
}

/// A word of a header line and its 1-based column, in characters.
struct Token<'a> {
    text: &'a str,
    column: usize,
}

fn tokens(text: &str) -> Vec<Token<'_>> {
    let mut out = Vec::new();
    let mut column = 0;
    let mut start: Option<(usize, usize)> = None;
    for (i, c) in text.char_indices() {
        column += 1;
        match (c.is_whitespace(), start) {
            (false, None) => start = Some((i, column)),
            (true, Some((s, col))) => {
                out.push(Token {
                    text: &text[s..i],
                    column: col,
                });
                start = None;
            }
            _ => {}
        }
    }
    if let Some((s, col)) = start {
        out.push(Token {
            text: &text[s..],
            column: col,
        });
    }
    out
}

/// Reads the header at the start of `bytes`.
pub fn parse(bytes: &[u8], path: &Path) -> Result<Header> {
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut offset = 0;
    let mut number = 0;
    loop {
        number += 1;
        let rest = &bytes[offset..];
        let Some(end) = rest.iter().take(MAX_HEADER_BYTES).position(|&b| b == b'\n') else {
            if offset + rest.len() >= MAX_HEADER_BYTES {
                return Err(Error::parse_at(
                    path,
                    number,
                    1,
                    format!(
                        "expected `end_header` within the first {MAX_HEADER_BYTES} bytes, \
                         found a longer header"
                    ),
                ));
            }
            let found = if number == 1 {
                "found no line end".to_owned()
            } else {
                "found the end of the file".to_owned()
            };
            return Err(Error::parse_at(
                path,
                number,
                1,
                format!("expected a header ending with `end_header`, {found}"),
            ));
        };
        let raw = &rest[..end];
        let line = Line {
            bytes: raw.strip_suffix(b"\r").unwrap_or(raw),
            number,
        };
        offset += end + 1;
        if offset > MAX_HEADER_BYTES {
            return Err(line.error(
                path,
                None,
                format!(
                    "expected `end_header` within the first {MAX_HEADER_BYTES} bytes, \
                     found a longer header"
                ),
            ));
        }
        if number == 1 {
            if line.bytes != b"ply" {
                let found = shown(&String::from_utf8_lossy(line.bytes));
                return Err(line.error(
                    path,
                    None,
                    format!("expected `ply` on the first line, found {found}"),
                ));
            }
            continue;
        }
        let keyword_end = line
            .bytes
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(line.bytes.len());
        if matches!(&line.bytes[..keyword_end], b"comment" | b"obj_info") {
            continue;
        }
        let text = std::str::from_utf8(line.bytes).map_err(|e| {
            let column = 1 + String::from_utf8_lossy(&line.bytes[..e.valid_up_to()])
                .chars()
                .count();
            Error::parse_at(
                path,
                number,
                column,
                "expected UTF-8 text in the header, found an invalid byte",
            )
        })?;
        let words = tokens(text);
        let Some(keyword) = words.first() else {
            continue;
        };
        let args = &words[1..];
        match keyword.text {
            "format" => {
                if encoding.is_some() {
                    return Err(line.error(
                        path,
                        Some(keyword),
                        "expected one `format` line, found a second",
                    ));
                }
                encoding = Some(format_line(path, &line, keyword, args)?);
            }
            "element" => {
                let [name, count] = args else {
                    return Err(line.error(
                        path,
                        args.get(2).or(Some(keyword)),
                        format!(
                            "expected `element NAME COUNT`, found {} words after `element`",
                            args.len()
                        ),
                    ));
                };
                if elements.iter().any(|e| e.name == name.text) {
                    return Err(line.error(
                        path,
                        Some(name),
                        format!(
                            "expected each element once, found {} again",
                            shown(name.text)
                        ),
                    ));
                }
                elements.push(Element {
                    name: name.text.to_owned(),
                    rows: row_count(path, &line, count)?,
                    properties: Vec::new(),
                    line: number,
                    count_column: count.column,
                });
            }
            "property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(line.error(
                        path,
                        Some(keyword),
                        "expected an `element` line before the first `property`",
                    ));
                };
                let property = property_line(path, &line, keyword, args)?;
                if element.property(&property.name).is_some() {
                    let name = args.last().unwrap_or(keyword);
                    return Err(line.error(
                        path,
                        Some(name),
                        format!(
                            "expected each property of element {} once, found {} again",
                            shown(&element.name),
                            shown(&property.name)
                        ),
                    ));
                }
                element.properties.push(property);
            }
            "end_header" => {
                if let Some(extra) = args.first() {
                    return Err(line.error(
                        path,
                        Some(extra),
                        format!(
                            "expected nothing after `end_header`, found {}",
                            shown(extra.text)
                        ),
                    ));
                }
                let encoding = encoding.ok_or_else(|| {
                    line.error(
                        path,
                        Some(keyword),
                        "expected a `format` line before `end_header`",
                    )
                })?;
                return Ok(Header {
                    encoding,
                    elements,
                    body_start: offset,
                });
            }
            other => {
                return Err(line.error(
                    path,
                    Some(keyword),
                    format!(
                        "expected format, element, property, comment, obj_info or \
                         end_header, found {}",
                        shown(other)
                    ),
                ));
            }
        }
    }
}

fn format_line(path: &Path, line: &Line, keyword: &Token, args: &[Token]) -> Result<Encoding> {
    let [name, version] = args else {
        return Err(line.error(
            path,
            args.get(2).or(Some(keyword)),
            format!(
                "expected `format ENCODING 1.0`, found {} words after `format`",
                args.len()
            ),
        ));
    };
    let encoding = match name.text {
        "ascii" => Encoding::Ascii,
        "binary_little_endian" => Encoding::LittleEndian,
        "binary_big_endian" => Encoding::BigEndian,
        other => {
            return Err(line.error(
                path,
                Some(name),
                format!(
                    "expected ascii, binary_little_endian or binary_big_endian, found {}",
                    shown(other)
                ),
            ));
        }
    };
    if version.text != "1.0" {
        return Err(line.error(
            path,
            Some(version),
            format!("expected version 1.0, found {}", shown(version.text)),
        ));
    }
    Ok(encoding)
}

fn row_count(path: &Path, line: &Line, count: &Token) -> Result<u32> {
    let expected = |what: &str| {
        line.error(
            path,
            Some(count),
            format!(
                "expected {what} for the row count, found {}",
                shown(count.text)
            ),
        )
    };
    if count.text.is_empty() || !count.text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(expected("a whole number"));
    }
    let limit = crate::scene::MAX_SHAPES;
    match count.text.parse::<u32>() {
        Ok(n) if n as usize <= limit => Ok(n),
        _ => Err(expected(&format!(
            "a whole number of at most {limit} (the most shapes a scene may hold)"
        ))),
    }
}

fn scalar(path: &Path, line: &Line, word: &Token) -> Result<Scalar> {
    Scalar::from_name(word.text).ok_or_else(|| {
        line.error(
            path,
            Some(word),
            format!(
                "expected a type (char, uchar, short, ushort, int, uint, float, double, \
                 or int8 ... float64), found {}",
                shown(word.text)
            ),
        )
    })
}

fn property_line(path: &Path, line: &Line, keyword: &Token, args: &[Token]) -> Result<Property> {
    let wrong_arity = |at: Option<&Token>, form: &str| {
        line.error(
            path,
            at.or(Some(keyword)),
            format!(
                "expected `{form}`, found {} words after `property`",
                args.len()
            ),
        )
    };
    match args {
        [list, rest @ ..] if list.text == "list" => {
            let [length, item, name] = rest else {
                return Err(wrong_arity(
                    rest.get(3),
                    "property list LENGTH_TYPE ITEM_TYPE NAME",
                ));
            };
            let length_type = scalar(path, line, length)?;
            if !length_type.is_integer() {
                return Err(line.error(
                    path,
                    Some(length),
                    format!(
                        "expected an integer type for a list's length, found {}",
                        shown(length.text)
                    ),
                ));
            }
            Ok(Property {
                name: name.text.to_owned(),
                kind: PropertyKind::List {
                    length: length_type,
                    item: scalar(path, line, item)?,
                },
                line: line.number,
            })
        }
        [ty, name] => Ok(Property {
            name: name.text.to_owned(),
            kind: PropertyKind::Scalar(scalar(path, line, ty)?),
            line: line.number,
        }),
        _ => Err(wrong_arity(args.get(2), "property TYPE NAME")),
    }
}
