//! What a statement's values say: the numbers of `v`, `vt`, `vn` and `s`, the name of an
//! `o` or `g`, and the indices of a face corner.

use std::path::Path;

use super::Kind;
use super::messages::error_at;
use crate::error::{Error, Result};
use crate::format::obj::lines::{self, Line, Token, Tokens, decode_name, parse_integer, shown};
use crate::math::Vec3;

/// `v x y z [w]` or `v x y z r g b`: the values and how many there are (3, 4 or 6).
// Both readers call the statement parsers once a line; inlined, their results stay in
// registers (a separate call made the one-thread reader 8 % slower).
#[inline(always)]
pub(super) fn parse_position(
    path: &Path,
    line: &Line,
    tokens: Tokens,
) -> Result<([f32; 6], usize)> {
    const WHAT: [&str; 6] = [
        "the x coordinate",
        "the y coordinate",
        "the z coordinate",
        "w (or the red of a vertex colour)",
        "the green of the vertex colour",
        "the blue of the vertex colour",
    ];
    let mut values = [0.0f32; 6];
    let mut count = 0;
    let mut end = tokens.offset();
    for token in tokens {
        if count == values.len() {
            return Err(error_at(
                path,
                line,
                token.start,
                format!(
                    "expected x y z, x y z w or x y z r g b after v, found a 7th value {}",
                    shown(token.bytes)
                ),
            ));
        }
        values[count] = number(path, line, token, WHAT[count])?;
        count += 1;
        end = token.start + token.bytes.len();
    }
    match count {
        3 | 4 | 6 => Ok((values, count)),
        0..=2 => Err(error_at(
            path,
            line,
            end,
            format!(
                "expected 3 coordinates after v (v x y z), {} is missing",
                WHAT[count]
            ),
        )),
        _ => Err(error_at(
            path,
            line,
            end,
            "expected x y z, x y z w or x y z r g b after v, found 5 values: the blue of \
             the vertex colour is missing",
        )),
    }
}

/// Adds a position, and its colour once any vertex has one (the others white).
#[inline(always)]
pub(super) fn push_position(
    positions: &mut Vec<Vec3>,
    colors: &mut Vec<Vec3>,
    values: [f32; 6],
    count: usize,
) {
    if count == 6 {
        if colors.is_empty() {
            colors.resize(positions.len(), Vec3::ONE);
        }
        colors.push(Vec3::new(values[3], values[4], values[5]));
    } else if !colors.is_empty() {
        colors.push(Vec3::ONE);
    }
    positions.push(Vec3::new(values[0], values[1], values[2]));
}

/// `vt u [v [w]]`.
#[inline(always)]
pub(super) fn parse_texcoord(path: &Path, line: &Line, mut tokens: Tokens) -> Result<[f32; 2]> {
    let mut uv = [0.0f32; 2];
    let mut count = 0;
    for token in tokens.by_ref() {
        match count {
            0 => uv[0] = number(path, line, token, "u")?,
            1 => uv[1] = number(path, line, token, "v")?,
            2 => {
                number(path, line, token, "w")?;
            }
            _ => {
                return Err(error_at(
                    path,
                    line,
                    token.start,
                    format!(
                        "expected at most 3 values after vt (vt u v w), found a 4th {}",
                        shown(token.bytes)
                    ),
                ));
            }
        }
        count += 1;
    }
    if count == 0 {
        return Err(error_at(
            path,
            line,
            tokens.offset(),
            "expected a texture coordinate after vt (vt u [v [w]]), found the end of the line",
        ));
    }
    Ok(uv)
}

/// `vn x y z`.
#[inline(always)]
pub(super) fn parse_normal(path: &Path, line: &Line, mut tokens: Tokens) -> Result<Vec3> {
    let mut n = [0.0f32; 3];
    for (slot, axis) in n.iter_mut().zip(["x", "y", "z"]) {
        let Some(token) = tokens.next() else {
            return Err(error_at(
                path,
                line,
                tokens.offset(),
                format!("expected 3 values after vn (vn x y z), the {axis} is missing"),
            ));
        };
        *slot = number(path, line, token, &format!("the normal's {axis}"))?;
    }
    if let Some(extra) = tokens.next() {
        return Err(error_at(
            path,
            line,
            extra.start,
            format!(
                "expected 3 values after vn (vn x y z), found a 4th {}",
                shown(extra.bytes)
            ),
        ));
    }
    Ok(Vec3::from_array(n))
}

/// `s N`, `s 0` or `s off` (0).
pub(super) fn parse_smoothing(
    path: &Path,
    line: &Line,
    keyword: Token,
    mut tokens: Tokens,
) -> Result<u32> {
    let expected = "expected a smoothing group after s (a number, 0 or off)";
    let Some(token) = tokens.next() else {
        return Err(error_at(
            path,
            line,
            keyword.start + 1,
            format!("{expected}, found the end of the line"),
        ));
    };
    if token.bytes.eq_ignore_ascii_case(b"off") {
        return Ok(0);
    }
    match parse_integer(token.bytes).and_then(|n| u32::try_from(n).ok()) {
        Some(n) => Ok(n),
        None => Err(error_at(
            path,
            line,
            token.start,
            format!("{expected}, found {}", shown(token.bytes)),
        )),
    }
}

/// The name of an `o` or `g`: its words joined by single spaces.
pub(super) fn run_name(tokens: Tokens) -> String {
    let mut name = String::new();
    for token in tokens {
        if !name.is_empty() {
            name.push(' ');
        }
        name.push_str(&decode_name(token.bytes));
    }
    name
}

/// A part of a face corner: its text and the byte offset of that in the line.
pub(super) type Part<'l> = (&'l [u8], usize);

/// The up to three `/`-separated parts of a face corner.
#[inline(always)]
pub(super) fn corner_parts<'l>(
    path: &Path,
    line: &Line,
    token: Token<'l>,
) -> Result<[Option<Part<'l>>; 3]> {
    let mut parts: [Option<Part>; 3] = [None; 3];
    let mut start = 0;
    for (k, part) in token.bytes.split(|&b| b == b'/').enumerate() {
        if k == 3 {
            return Err(error_at(
                path,
                line,
                token.start + start - 1,
                format!(
                    "expected a face corner i, i/t, i//n or i/t/n, found {}",
                    shown(token.bytes)
                ),
            ));
        }
        parts[k] = Some((part, token.start + start));
        start += part.len() + 1;
    }
    Ok(parts)
}

/// An index written as at most nine digits and not 0: the fast path of both readers.
#[inline(always)]
pub(super) fn short_index(text: &[u8]) -> Option<usize> {
    if text.is_empty() || text.len() > 9 || !text.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let value = text
        .iter()
        .fold(0usize, |n, &d| n * 10 + (d - b'0') as usize);
    (value >= 1).then_some(value)
}

/// The signed, non-zero number a face corner index is written as.
pub(super) fn index_value(
    path: &Path,
    line: &Line,
    token: Token,
    text: &[u8],
    start: usize,
    kind: Kind,
) -> Result<i64> {
    let noun = kind.noun();
    match parse_integer(text) {
        None => Err(error_at(
            path,
            line,
            start,
            format!(
                "expected a {noun} index in the face corner {} (i, i/t, i//n or i/t/n)",
                shown(token.bytes)
            ),
        )),
        Some(0) => Err(error_at(
            path,
            line,
            start,
            format!("{noun} index 0 does not exist: indices start at 1"),
        )),
        Some(value) => Ok(value),
    }
}

/// The 0-based index of a positive (1-based) one, which must fit in a u32.
pub(super) fn positive_index(
    path: &Path,
    line: &Line,
    text: &[u8],
    start: usize,
    kind: Kind,
    value: i64,
) -> Result<u32> {
    u32::try_from(value - 1).map_err(|_| {
        error_at(
            path,
            line,
            start,
            format!("{} index {} is too large", kind.noun(), shown(text)),
        )
    })
}

/// A token as a finite number that fits in an f32, or an error at its column.
pub(in crate::format) fn number(path: &Path, line: &Line, token: Token, what: &str) -> Result<f32> {
    let error = |message: String| {
        let (number, column) = line.place(token.start);
        Error::parse_at(path, number, column, message)
    };
    let Some(value) = lines::parse_f64(token.bytes) else {
        let kind = if lines::names_non_finite(token.bytes) {
            "a finite number"
        } else {
            "a number"
        };
        return Err(error(format!(
            "expected {kind} for {what}, found {}",
            shown(token.bytes)
        )));
    };
    if value.abs() > f32::MAX as f64 {
        return Err(error(format!(
            "expected a finite number of magnitude at most {:e} for {what}, found {}",
            f32::MAX,
            shown(token.bytes)
        )));
    }
    Ok(value as f32)
}
