//! The reader on every thread, for large files, giving exactly what the one-thread
//! reader gives: the same [`ObjFile`], the same warnings in the same order (and the same
//! count past the cap), and the same first error.
//!
//! The text is cut into pieces at line ends (`\` continuations kept whole). Each piece
//! is read on its own: vertices in full, faces as the indices they name (a negative one
//! counted from the piece's own vertices), and everything whose effect depends on what
//! came before (`usemtl`, `s`, `o`/`g`, `mtllib`, warnings reported once) as events.
//! One pass in file order then links the pieces: where each piece's vertices and
//! triangles start, which material and smoothing group its first faces inherit, and
//! where a negative index reaching back past its piece lands. The triangles are then
//! built piece by piece in parallel, straight into the final array, and a last pass in
//! file order replays the events: libraries are read, warnings emitted and the first
//! error returned exactly where the one-thread reader would have met them.

mod faces;
mod link;
mod piece;
mod replay;
mod triangles;

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::messages::{fan_fallback_message, missing_attribute_message, missing_vertex};
use super::{Kind, ObjFile, ObjTriangle, Options, Reader, Result};
use crate::format::obj::lines::{count_newlines, piece_ranges};
use crate::math::Vec3;
use link::link_pieces;
use piece::{Piece, read_piece};
use replay::replay;
use triangles::build;

/// Smaller files stay on one thread: they take a few milliseconds either way, and
/// setting up pieces and waking threads would be a larger share of that. (At 1.1 MB,
/// a height field still reads 1.4× as fast on two threads.)
const MIN_BYTES: usize = 1 << 20;

/// Whether `text` is read on more than one thread.
pub fn worth_it(text: &[u8]) -> bool {
    // Line numbers and indices within a piece are kept as u32.
    text.len() >= MIN_BYTES && text.len() < u32::MAX as usize && rayon::current_num_threads() > 1
}

/// The size of a piece: a few per thread, so a thread that finishes early takes
/// another, but not so small that their setup shows.
pub fn piece_bytes(len: usize) -> usize {
    (len / (4 * rayon::current_num_threads())).clamp(64 << 10, 8 << 20)
}

/// Reads `text` (without its byte-order mark) in pieces of about `step` bytes.
pub fn read(text: &[u8], path: &Path, options: Options, step: usize) -> Result<ObjFile> {
    let ranges = piece_ranges(text, step);
    let newlines: Vec<usize> = ranges
        .par_iter()
        .map(|r| count_newlines(&text[r.clone()]))
        .collect();
    let mut first_line = 1;
    let starts: Vec<usize> = newlines
        .iter()
        .map(|n| {
            let first = first_line;
            first_line += n;
            first
        })
        .collect();
    // A piece after one that failed need not be read: the earlier error wins.
    let first_failed = AtomicUsize::new(usize::MAX);
    let mut pieces: Vec<Piece> = ranges
        .par_iter()
        .zip(&starts)
        .enumerate()
        .map(|(k, (range, &first))| {
            if first_failed.load(Ordering::Relaxed) < k {
                return Piece::default();
            }
            let piece = read_piece(&text[range.clone()], first, path);
            if piece.error.is_some() {
                first_failed.fetch_min(k, Ordering::Relaxed);
            }
            piece
        })
        .collect();
    let mut reader = Reader::new(path, options);
    let link = link_pieces(&pieces, &mut reader);

    // An error is certain once a piece failed, a negative index reaches before the file
    // or the triangles are too many: the replay finds which comes first, and building
    // the triangles would be wasted.
    let failing =
        pieces.iter().any(|p| p.error.is_some()) || link.reach_error || link.limit.is_some();
    let mut built = Vec::new();
    if !failing {
        if pieces.iter().any(|p| !p.colors.is_empty()) {
            let mut colors = Vec::with_capacity(link.totals[0]);
            for p in &mut pieces {
                if p.colors.is_empty() {
                    colors.resize(colors.len() + p.positions.len(), Vec3::ONE);
                } else {
                    colors.append(&mut p.colors);
                }
            }
            reader.obj.colors = colors;
        }
        reader.obj.positions = concat(&mut pieces, |p| &mut p.positions);
        reader.obj.texcoords = concat(&mut pieces, |p| &mut p.texcoords);
        reader.obj.normals = concat(&mut pieces, |p| &mut p.normals);
        let mut triangles = Vec::with_capacity(link.triangles);
        triangles.par_extend(rayon::iter::repeat_n(UNSET, link.triangles));
        let mut slots = Vec::with_capacity(pieces.len());
        let mut rest = triangles.as_mut_slice();
        for p in &pieces {
            let (mine, others) = rest.split_at_mut(p.triangles);
            slots.push(mine);
            rest = others;
        }
        let positions = &reader.obj.positions;
        built = pieces
            .par_iter_mut()
            .zip(slots)
            .zip(&link.pieces)
            .map(|((piece, slots), at)| build(piece, at, link.totals, positions, slots))
            .collect();
        reader.obj.triangles = triangles;
    }
    replay(&mut pieces, &link, &built, &mut reader)?;
    debug_assert!(!failing, "the replay returns the error the pieces hold");

    // What the one-thread reader checks at the end, in its order.
    let positions = link.totals[0];
    if let Some((line, index)) = built.iter().find_map(|b| b.missing[0]) {
        return Err(missing_vertex(path, line, index, positions));
    }
    for kind in [Kind::Texcoord, Kind::Normal] {
        let k = kind as usize;
        if let Some((line, index)) = built.iter().find_map(|b| b.missing[k]) {
            reader.warn(line, missing_attribute_message(kind, index, link.totals[k]));
        }
    }
    for b in &built {
        for &(line, corners) in &b.deferred_fans {
            reader.warn(line, fan_fallback_message(corners));
        }
        reader.suppressed_warnings += b.deferred_suppressed;
    }
    reader.conclude()
}

/// Moves every piece's elements of one kind into one array, in order.
fn concat<T>(pieces: &mut [Piece], of: impl Fn(&mut Piece) -> &mut Vec<T>) -> Vec<T> {
    let total = pieces.iter_mut().map(|p| of(p).len()).sum();
    let mut all = Vec::with_capacity(total);
    for p in pieces {
        all.append(of(p));
    }
    all
}

/// What a triangle slot holds until its face is built: the slots must exist before the
/// pieces can share them out, and each is overwritten.
const UNSET: ObjTriangle = ObjTriangle {
    v: [0; 3],
    vt: None,
    vn: None,
    material: None,
    smoothing: 0,
};

#[cfg(test)]
mod tests;
