//! One piece read on its own: its vertices in full, its faces as the indices they name,
//! and what depends on the statements before it as events.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use super::faces::{Faces, HAS_VN, HAS_VT, LOCAL, RawCorner};
use crate::error::{Error, Result};
use crate::format::obj::GroupKind;
use crate::format::obj::lines::{Line, Lines, Token, Tokens, decode_name};
use crate::format::obj::reader::Kind;
use crate::format::obj::reader::messages::MAX_WARNINGS;
use crate::format::obj::reader::skipped::skipped_kind;
use crate::format::obj::reader::values::{
    Part, corner_parts, index_value, parse_normal, parse_position, parse_smoothing, parse_texcoord,
    positive_index, push_position, run_name, short_index,
};
use crate::math::Vec3;

/// Something that happened at a statement, in file order. `face` is the number of the
/// piece's faces read before it (events of a face carry that face's own number), which
/// places events among the faces.
pub(super) struct Event {
    pub(super) face: u32,
    pub(super) what: What,
}

pub(super) enum What {
    /// A face of fewer than 3 corners, dropped.
    FewCorners {
        line: usize,
        n: usize,
    },
    /// The piece's first face mixing corners with and without vt (0) or vn (1): warned
    /// unless an earlier piece had one.
    Mixed {
        line: usize,
        which: usize,
    },
    /// The piece's first unknown statement: warned unless an earlier piece had one.
    Unknown {
        line: usize,
        keyword: Vec<u8>,
    },
    /// A negative index reaching back before the piece: it exists only if the pieces
    /// before hold enough.
    Reach(Box<Reach>),
    /// `usemtl`: a name numbered in [`Piece::materials`], or none.
    UseMaterial {
        line: usize,
        name: Option<u32>,
    },
    /// `mtllib` and the rest of its line.
    Libraries {
        line: usize,
        rest: Vec<u8>,
    },
    /// `o` or `g`, after the piece's first `triangles` triangles.
    Run {
        kind: GroupKind,
        name: String,
        triangles: usize,
    },
    Smoothing(u32),
}

pub(super) struct Reach {
    /// The number of the corner in the piece.
    pub(super) corner: usize,
    pub(super) kind: Kind,
    pub(super) value: i64,
    /// The piece's elements of this kind read before it.
    pub(super) defined: usize,
    pub(super) line: usize,
    pub(super) column: usize,
    pub(super) text: Vec<u8>,
}

/// What one piece says, read without the rest of the file.
#[derive(Default)]
pub(super) struct Piece {
    pub(super) positions: Vec<Vec3>,
    pub(super) colors: Vec<Vec3>,
    pub(super) texcoords: Vec<[f32; 2]>,
    pub(super) normals: Vec<Vec3>,
    pub(super) faces: Faces,
    /// The corners of the face being read.
    corners: Vec<RawCorner>,
    /// Corners on a later physical line than their statement's first: (corner, line),
    /// for the line a missing index is reported at.
    pub(super) corner_lines: Vec<(u32, u32)>,
    pub(super) triangles: usize,
    pub(super) events: Vec<Event>,
    /// `usemtl` names in order of first appearance in the piece.
    pub(super) materials: Vec<String>,
    material_ids: HashMap<String, u32>,
    /// Skipped statements by kind: (count, first line).
    pub(super) skipped: BTreeMap<&'static str, (usize, usize)>,
    /// Dropped-face warnings past the cap: each has [`MAX_WARNINGS`] warnings before it
    /// in this piece alone, so it is suppressed whatever came before.
    few_corner_warnings: usize,
    pub(super) suppressed: usize,
    mixed_seen: [bool; 2],
    unknown_seen: bool,
    /// The first error; nothing after it was read.
    pub(super) error: Option<Error>,
}

pub(super) fn read_piece(text: &[u8], first_line: usize, path: &Path) -> Piece {
    let mut piece = Piece::default();
    let mut lines = Lines::numbered_from(text, first_line);
    while let Some(line) = lines.next_line() {
        if let Err(e) = piece.statement(path, &line) {
            piece.error = Some(e);
            break;
        }
    }
    piece
}

impl Piece {
    fn event(&mut self, what: What) {
        self.events.push(Event {
            face: self.faces.count,
            what,
        });
    }

    fn statement(&mut self, path: &Path, line: &Line) -> Result<()> {
        let mut tokens = line.tokens();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        match keyword.bytes {
            b"v" => {
                let (values, count) = parse_position(path, line, tokens)?;
                push_position(&mut self.positions, &mut self.colors, values, count);
            }
            b"vt" => self.texcoords.push(parse_texcoord(path, line, tokens)?),
            b"vn" => self.normals.push(parse_normal(path, line, tokens)?),
            b"f" | b"fo" => self.face(path, line, tokens)?,
            b"o" | b"g" => {
                let kind = if keyword.bytes == b"o" {
                    GroupKind::Object
                } else {
                    GroupKind::Group
                };
                let name = run_name(tokens);
                let triangles = self.triangles;
                self.event(What::Run {
                    kind,
                    name,
                    triangles,
                });
            }
            b"s" => {
                let group = parse_smoothing(path, line, keyword, tokens)?;
                self.event(What::Smoothing(group));
            }
            b"usemtl" => {
                let name = line.rest_from(keyword.start + keyword.bytes.len());
                let name = (!name.is_empty()).then(|| {
                    let name = decode_name(name);
                    let next = self.materials.len() as u32;
                    let id = *self.material_ids.entry(name.clone()).or_insert(next);
                    if id == next {
                        self.materials.push(name);
                    }
                    id
                });
                self.event(What::UseMaterial {
                    line: line.number,
                    name,
                });
            }
            b"mtllib" => {
                let rest = line.rest_from(keyword.start + keyword.bytes.len()).to_vec();
                self.event(What::Libraries {
                    line: line.number,
                    rest,
                });
            }
            other => {
                let kind = skipped_kind(other);
                let entry = self.skipped.entry(kind).or_insert((0, line.number));
                entry.0 += 1;
                if kind == "unknown" && !self.unknown_seen {
                    self.unknown_seen = true;
                    self.event(What::Unknown {
                        line: line.number,
                        keyword: other.to_vec(),
                    });
                }
            }
        }
        Ok(())
    }

    fn face(&mut self, path: &Path, line: &Line, tokens: Tokens) -> Result<()> {
        self.corners.clear();
        self.face_corners(path, line, tokens)?;
        let corners = &self.corners;
        let n = corners.len();
        let has = |flag| corners.iter().map(move |c| c.flags & flag != 0);
        let all = [has(HAS_VT).all(|b| b), has(HAS_VN).all(|b| b)];
        let any = [has(HAS_VT).any(|b| b), has(HAS_VN).any(|b| b)];
        if n < 3 {
            if self.few_corner_warnings < MAX_WARNINGS {
                self.few_corner_warnings += 1;
                self.event(What::FewCorners {
                    line: line.number,
                    n,
                });
            } else {
                self.suppressed += 1;
            }
        } else {
            for k in 0..2 {
                if any[k] && !all[k] && !self.mixed_seen[k] {
                    self.mixed_seen[k] = true;
                    self.event(What::Mixed {
                        line: line.number,
                        which: k,
                    });
                }
            }
            self.triangles += n - 2;
        }
        // Kept however few its corners: they are checked against the file's vertices.
        self.faces
            .push(line.number, self.positions.len(), &self.corners);
        Ok(())
    }

    fn face_corners(&mut self, path: &Path, line: &Line, tokens: Tokens) -> Result<()> {
        for token in tokens {
            let [v_part, vt_part, vn_part] = corner_parts(path, line, token)?;
            let mut corner = RawCorner::default();
            let (v_text, v_start) = v_part.unwrap_or((&[], token.start));
            self.index(
                path,
                line,
                token,
                (v_text, v_start),
                Kind::Position,
                &mut corner,
            )?;
            for (part, kind, flag) in [
                (vt_part, Kind::Texcoord, HAS_VT),
                (vn_part, Kind::Normal, HAS_VN),
            ] {
                if let Some(part) = part
                    && !part.0.is_empty()
                {
                    self.index(path, line, token, part, kind, &mut corner)?;
                    corner.flags |= flag;
                }
            }
            if line.is_joined() {
                let (number, _) = line.place(token.start);
                if number != line.number {
                    let corner = self.faces.corners + self.corners.len();
                    self.corner_lines.push((corner as u32, number as u32));
                }
            }
            self.corners.push(corner);
        }
        Ok(())
    }

    /// Sets the index of `kind` in `corner` from its digits `text` at byte `start`.
    #[inline(always)]
    fn index(
        &mut self,
        path: &Path,
        line: &Line,
        token: Token,
        part: Part,
        kind: Kind,
        corner: &mut RawCorner,
    ) -> Result<()> {
        // The common case: a few digits.
        if let Some(value) = short_index(part.0) {
            corner.index[kind as usize] = value as u32 - 1;
            return Ok(());
        }
        self.index_slow(path, line, token, part, kind, corner)
    }

    #[cold]
    fn index_slow(
        &mut self,
        path: &Path,
        line: &Line,
        token: Token,
        (text, start): Part,
        kind: Kind,
        corner: &mut RawCorner,
    ) -> Result<()> {
        let k = kind as usize;
        let value = index_value(path, line, token, text, start, kind)?;
        if value > 0 {
            corner.index[k] = positive_index(path, line, text, start, kind, value)?;
            return Ok(());
        }
        let defined = match kind {
            Kind::Position => self.positions.len(),
            Kind::Texcoord => self.texcoords.len(),
            Kind::Normal => self.normals.len(),
        };
        corner.flags |= LOCAL[k];
        let local = defined as i64 + value;
        if local >= 0 {
            corner.index[k] = local as u32;
        } else {
            let (number, column) = line.place(start);
            let reach = Reach {
                corner: self.faces.corners + self.corners.len(),
                kind,
                value,
                defined,
                line: number,
                column,
                text: text.to_vec(),
            };
            self.event(What::Reach(Box::new(reach)));
        }
        Ok(())
    }
}
