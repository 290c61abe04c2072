//! The texts of the reader's errors and warnings, and the cap on how many warnings a
//! file keeps.

use std::path::{Path, PathBuf};

use super::{Kind, triangle_limit};
use crate::error::Error;
use crate::format::obj::Warning;
use crate::format::obj::lines::{Line, shown};

/// Past this many, warnings are counted in one last warning instead of kept: a file of
/// a million bad faces should not hold a million messages.
pub(super) const MAX_WARNINGS: usize = 1000;

/// An error at byte `offset` of a line.
pub(super) fn error_at(
    path: &Path,
    line: &Line,
    offset: usize,
    message: impl Into<String>,
) -> Error {
    let (number, column) = line.place(offset);
    Error::parse_at(path, number, column, message)
}

/// The error for a negative index reaching before the first element of its kind.
pub(super) fn missing_relative(kind: Kind, text: &[u8], defined: usize) -> String {
    format!(
        "{} index {} does not exist: -1 is the last of the {defined} read so far",
        kind.noun(),
        shown(text)
    )
}

/// The error for a vertex named but never defined; `file:line:` as before, since
/// `prism convert`'s callers match this text.
pub(super) fn missing_vertex(path: &Path, line: usize, index: u32, positions: usize) -> Error {
    Error::parse(
        path,
        line,
        format!(
            "vertex {} does not exist: the file defines {positions}",
            index as u64 + 1
        ),
    )
}

pub(super) fn missing_attribute_message(kind: Kind, index: u32, defined: usize) -> String {
    let noun = kind.noun();
    format!(
        "{noun} {} does not exist (the file defines {defined}): faces naming missing \
         {noun}s get none (reported for the first only)",
        index as u64 + 1
    )
}

pub(super) fn few_corners_message(n: usize) -> String {
    format!("a face needs at least 3 vertices, found {n}: the face is dropped")
}

pub(super) fn mixed_face_message(k: usize) -> String {
    let what = ["texture coordinates", "normals"][k];
    format!(
        "a face gives {what} for some corners only: it gets none (this is reported for the \
         first such face only)"
    )
}

pub(super) fn too_many_triangles_message() -> String {
    format!(
        "expected at most {} triangles in a scene, found more",
        triangle_limit()
    )
}

pub(super) fn fan_fallback_message(corners: usize) -> String {
    format!(
        "a concave polygon of {corners} vertices crosses itself or is too large to clip: it \
         is split as a fan, which may cover area outside it"
    )
}

pub(super) fn unknown_message(keyword: &[u8]) -> String {
    format!(
        "unknown statement {} skipped (the count of unknown statements is in the summary)",
        shown(keyword)
    )
}

pub(super) const NAMELESS_USEMTL: &str =
    "usemtl without a name: the faces that follow get the default material";

pub(super) fn push_warning(
    warnings: &mut Vec<Warning>,
    suppressed: &mut usize,
    path: PathBuf,
    line: usize,
    message: impl Into<String>,
) {
    if warnings.len() < MAX_WARNINGS {
        warnings.push(Warning {
            path,
            line,
            message: message.into(),
        });
    } else {
        *suppressed += 1;
    }
}
