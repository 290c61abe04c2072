//! The events of every piece replayed in file order, as the one-thread reader meets them.

use super::link::Link;
use super::piece::{Piece, What};
use super::triangles::Built;
use crate::error::{Error, Result};
use crate::format::obj::reader::Reader;
use crate::format::obj::reader::messages::{
    NAMELESS_USEMTL, fan_fallback_message, few_corners_message, missing_relative,
    mixed_face_message, too_many_triangles_message, unknown_message,
};

/// The events of every piece in file order, with the warnings found building triangles
/// in their place: warnings, runs, material libraries and the first error, as the
/// one-thread reader meets them.
pub(super) fn replay(
    pieces: &mut [Piece],
    link: &Link,
    built: &[Built],
    reader: &mut Reader,
) -> Result<()> {
    let path = reader.path;
    for (k, piece) in pieces.iter_mut().enumerate() {
        let error = piece.error.take();
        let piece = &*piece;
        let at = &link.pieces[k];
        let limit = link.limit.filter(|&(p, _, _)| p == k);
        let no_fans = Vec::new();
        let fans = built.get(k).map_or(&no_fans, |b| &b.fans);
        let mut fans = fans.iter().peekable();
        // What faces before `face` did after their own events.
        let mut faces_before = |reader: &mut Reader, face: usize| -> Result<()> {
            if let Some((_, f, line)) = limit
                && f < face
            {
                return Err(Error::parse_at(path, line, 1, too_many_triangles_message()));
            }
            while let Some(&&(f, line, n)) = fans.peek()
                && (f as usize) < face
            {
                reader.warn(line, fan_fallback_message(n));
                fans.next();
            }
            Ok(())
        };
        for event in &piece.events {
            faces_before(reader, event.face as usize)?;
            match &event.what {
                What::FewCorners { line, n } => reader.warn(*line, few_corners_message(*n)),
                What::Mixed { line, which } => {
                    if !reader.mixed_face_warned[*which] {
                        reader.mixed_face_warned[*which] = true;
                        reader.warn(*line, mixed_face_message(*which));
                    }
                }
                What::Unknown { line, keyword } => {
                    if !reader.skipped_first_line.contains_key("unknown") {
                        reader.warn(*line, unknown_message(keyword));
                    }
                }
                What::Reach(reach) => {
                    let defined = at.index[reach.kind as usize] + reach.defined;
                    if defined as i64 + reach.value < 0 {
                        let message = missing_relative(reach.kind, &reach.text, defined);
                        return Err(Error::parse_at(path, reach.line, reach.column, message));
                    }
                }
                What::UseMaterial { line, name: None } => reader.warn(*line, NAMELESS_USEMTL),
                What::UseMaterial {
                    line,
                    name: Some(n),
                } => reader.usemtl_lines.push((at.materials[*n as usize], *line)),
                What::Libraries { line, rest } => reader.material_libraries(rest, *line)?,
                What::Run {
                    kind,
                    name,
                    triangles,
                } => reader.start_run(*kind, name.clone(), at.triangles + triangles),
                What::Smoothing(_) => {}
            }
        }
        faces_before(reader, usize::MAX)?;
        reader.suppressed_warnings += piece.suppressed + built.get(k).map_or(0, |b| b.suppressed);
        if let Some(e) = error {
            return Err(e);
        }
        for (&kind, &(count, line)) in &piece.skipped {
            *reader.obj.skipped.entry(kind.to_owned()).or_insert(0) += count;
            reader
                .skipped_first_line
                .entry(kind.to_owned())
                .or_insert(line);
        }
    }
    Ok(())
}
