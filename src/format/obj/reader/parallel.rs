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

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::{
    Corner, GroupKind, Kind, Line, Lines, MAX_WARNINGS, NAMELESS_USEMTL, ObjFile, ObjTriangle,
    Options, Part, Reader, Result, Token, Tokens, corner_attributes, corner_parts,
    fan_fallback_message, few_corners_message, index_value, missing_attribute_message,
    missing_relative, missing_vertex, mixed_face_message, parse_normal, parse_position,
    parse_smoothing, parse_texcoord, positive_index, push_position, run_name, short_index,
    skipped_kind, split_polygon, too_many_triangles_message, triangle_limit, triangle_of,
    unknown_message,
};
use crate::Error;
use crate::format::obj::lines::{count_newlines, decode_name, piece_ranges};
use crate::format::obj::triangulate::{Method, Triangulator};
use crate::math::Vec3;

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

/// A face corner as written. An index with the [`LOCAL`] bit of its kind counts from the
/// first element of that kind in the piece (a negative index); the others are 0-based
/// indices into the file's.
#[derive(Clone, Copy, Default)]
struct RawCorner {
    index: [u32; 3],
    flags: u8,
}

const HAS_VT: u8 = 1;
const HAS_VN: u8 = 2;
const LOCAL: [u8; 3] = [4, 8, 16];

/// The faces of a piece, packed into bytes: per face its number of corners, its (first
/// physical) line and how many positions the piece had read before it, each as the
/// difference from the face before; then per corner a byte of flags and its indices.
/// Every number is a LEB128 varint: an index into a million vertices takes 3 bytes, a
/// line or count difference 1. Plain structs would take four times the memory, and
/// fresh memory is what the kernel hands over page by page, slowly.
#[derive(Default)]
struct Faces {
    bytes: Vec<u8>,
    count: u32,
    /// Corners in all faces so far: the number of the next one.
    corners: usize,
    last_line: usize,
    last_positions: usize,
}

/// A face read back from [`Faces`].
struct Face {
    line: usize,
    /// The piece's positions read before it.
    positions: usize,
    /// The number of its first corner in the piece.
    first_corner: usize,
}

impl Faces {
    fn push(&mut self, line: usize, positions: usize, corners: &[RawCorner]) {
        let out = &mut self.bytes;
        put_varint(out, corners.len() as u32);
        put_varint(out, (line - self.last_line) as u32);
        put_varint(out, (positions - self.last_positions) as u32);
        for c in corners {
            out.push(c.flags);
            put_varint(out, c.index[0]);
            if c.flags & HAS_VT != 0 {
                put_varint(out, c.index[1]);
            }
            if c.flags & HAS_VN != 0 {
                put_varint(out, c.index[2]);
            }
        }
        self.count += 1;
        self.corners += corners.len();
        self.last_line = line;
        self.last_positions = positions;
    }

    fn reader(&self) -> FaceReader<'_> {
        FaceReader {
            bytes: &self.bytes,
            at: 0,
            line: 0,
            positions: 0,
            corners: 0,
        }
    }
}

struct FaceReader<'a> {
    bytes: &'a [u8],
    at: usize,
    line: usize,
    positions: usize,
    corners: usize,
}

impl FaceReader<'_> {
    /// The next face, its corners into `corners`.
    #[inline(always)]
    fn next(&mut self, corners: &mut Vec<RawCorner>) -> Option<Face> {
        if self.at == self.bytes.len() {
            return None;
        }
        let n = self.varint();
        self.line += self.varint() as usize;
        self.positions += self.varint() as usize;
        corners.clear();
        for _ in 0..n {
            let flags = self.bytes[self.at];
            self.at += 1;
            let mut corner = RawCorner {
                index: [self.varint(), 0, 0],
                flags,
            };
            if flags & HAS_VT != 0 {
                corner.index[1] = self.varint();
            }
            if flags & HAS_VN != 0 {
                corner.index[2] = self.varint();
            }
            corners.push(corner);
        }
        let face = Face {
            line: self.line,
            positions: self.positions,
            first_corner: self.corners,
        };
        self.corners += n as usize;
        Some(face)
    }

    #[inline]
    fn varint(&mut self) -> u32 {
        let b = self.bytes[self.at];
        self.at += 1;
        if b < 0x80 {
            return b as u32;
        }
        let mut value = (b & 0x7f) as u32;
        let mut shift = 7;
        loop {
            let b = self.bytes[self.at];
            self.at += 1;
            value |= ((b & 0x7f) as u32) << shift;
            if b < 0x80 {
                return value;
            }
            shift += 7;
        }
    }
}

#[inline]
fn put_varint(out: &mut Vec<u8>, mut value: u32) {
    while value >= 0x80 {
        out.push(value as u8 | 0x80);
        value >>= 7;
    }
    out.push(value as u8);
}

/// Something that happened at a statement, in file order. `face` is the number of the
/// piece's faces read before it (events of a face carry that face's own number), which
/// places events among the faces.
struct Event {
    face: u32,
    what: What,
}

enum What {
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

struct Reach {
    /// The number of the corner in the piece.
    corner: usize,
    kind: Kind,
    value: i64,
    /// The piece's elements of this kind read before it.
    defined: usize,
    line: usize,
    column: usize,
    text: Vec<u8>,
}

/// What one piece says, read without the rest of the file.
#[derive(Default)]
struct Piece {
    positions: Vec<Vec3>,
    colors: Vec<Vec3>,
    texcoords: Vec<[f32; 2]>,
    normals: Vec<Vec3>,
    faces: Faces,
    /// The corners of the face being read.
    corners: Vec<RawCorner>,
    /// Corners on a later physical line than their statement's first: (corner, line),
    /// for the line a missing index is reported at.
    corner_lines: Vec<(u32, u32)>,
    triangles: usize,
    events: Vec<Event>,
    /// `usemtl` names in order of first appearance in the piece.
    materials: Vec<String>,
    material_ids: HashMap<String, u32>,
    /// Skipped statements by kind: (count, first line).
    skipped: BTreeMap<&'static str, (usize, usize)>,
    /// Dropped-face warnings past the cap: each has [`MAX_WARNINGS`] warnings before it
    /// in this piece alone, so it is suppressed whatever came before.
    few_corner_warnings: usize,
    suppressed: usize,
    mixed_seen: [bool; 2],
    unknown_seen: bool,
    /// The first error; nothing after it was read.
    error: Option<Error>,
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

fn read_piece(text: &[u8], first_line: usize, path: &Path) -> Piece {
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

/// Where a piece starts in the file's arrays, and the state its first faces inherit.
struct Place {
    /// Positions, texture coordinates and normals before the piece.
    index: [usize; 3],
    triangles: usize,
    /// `usemtl` numbers of the piece's names in the whole file's numbering.
    materials: Vec<u32>,
    /// The material and smoothing group in force at the piece's start, then after each
    /// change within it: (first face it applies to, state).
    states: Vec<(u32, State)>,
    /// Negative indices reaching back past the piece, resolved: (corner, kind, index),
    /// in corner order.
    reaches: Vec<(usize, usize, u32)>,
}

#[derive(Clone, Copy, Default)]
struct State {
    material: Option<u32>,
    smoothing: u32,
}

struct Link {
    pieces: Vec<Place>,
    /// Positions, texture coordinates and normals in the file.
    totals: [usize; 3],
    triangles: usize,
    /// A negative index reaches before the first element of its kind.
    reach_error: bool,
    /// The face whose triangles pass the scene's limit: (piece, face, line).
    limit: Option<(usize, usize, usize)>,
}

/// The pass in file order that tells each piece where it starts; it numbers the `usemtl`
/// names (in the reader, as it would) and resolves the negative indices that reach back
/// past their piece.
fn link_pieces(pieces: &[Piece], reader: &mut Reader) -> Link {
    let mut places = Vec::with_capacity(pieces.len());
    let mut totals = [0usize; 3];
    let mut triangles = 0;
    let mut state = State::default();
    let mut reach_error = false;
    let mut limit = None;
    for (k, piece) in pieces.iter().enumerate() {
        let materials: Vec<u32> = piece
            .materials
            .iter()
            .map(|name| reader.material_id(name.clone()))
            .collect();
        let mut states = vec![(0, state)];
        let mut reaches = Vec::new();
        for event in &piece.events {
            match &event.what {
                What::UseMaterial { name, .. } => {
                    state.material = name.map(|n| materials[n as usize]);
                    states.push((event.face, state));
                }
                What::Smoothing(group) => {
                    state.smoothing = *group;
                    states.push((event.face, state));
                }
                What::Reach(reach) => {
                    let k = reach.kind as usize;
                    let resolved = (totals[k] + reach.defined) as i64 + reach.value;
                    if resolved < 0 {
                        reach_error = true;
                    } else {
                        reaches.push((reach.corner, k, resolved as u32));
                    }
                }
                _ => {}
            }
        }
        if limit.is_none() && triangles + piece.triangles > triangle_limit() {
            let mut before = triangles;
            let mut faces = piece.faces.reader();
            let mut corners = Vec::new();
            for f in 0.. {
                let Some(face) = faces.next(&mut corners) else {
                    break;
                };
                let n = corners.len();
                if n < 3 {
                    continue;
                }
                if before + n - 2 > triangle_limit() {
                    limit = Some((k, f, face.line));
                    break;
                }
                before += n - 2;
            }
        }
        places.push(Place {
            index: totals,
            triangles,
            materials,
            states,
            reaches,
        });
        totals[0] += piece.positions.len();
        totals[1] += piece.texcoords.len();
        totals[2] += piece.normals.len();
        triangles += piece.triangles;
    }
    Link {
        pieces: places,
        totals,
        triangles,
        reach_error,
        limit,
    }
}

/// What building a piece's triangles found.
#[derive(Default)]
struct Built {
    /// Polygons split as a fan though concave: (face, line, corners), and how many more
    /// past the cap.
    fans: Vec<(u32, usize, usize)>,
    suppressed: usize,
    /// The same for polygons naming positions defined later, which the one-thread
    /// reader splits (and warns about) at the end: (line, corners).
    deferred_fans: Vec<(usize, usize)>,
    deferred_suppressed: usize,
    /// The first index of each kind past the file's last element: (line, index).
    missing: [Option<(usize, u32)>; 3],
}

/// Builds a piece's triangles into `slots`, as the one-thread reader would have once
/// at the end of the file.
fn build(
    piece: &mut Piece,
    at: &Place,
    totals: [usize; 3],
    positions: &[Vec3],
    slots: &mut [ObjTriangle],
) -> Built {
    let faces = std::mem::take(&mut piece.faces);
    let mut faces = faces.reader();
    let mut raw = Vec::new();
    let mut reaches = at.reaches.iter().peekable();
    let mut built = Built::default();
    let mut corners: Vec<Corner> = Vec::new();
    let mut triangulator = Triangulator::default();
    let mut polygon = Vec::new();
    let mut local = Vec::new();
    let mut states = at.states.iter().peekable();
    let mut state = State::default();
    let mut next_slot = 0;
    let mut next_face = 0;
    while let Some(face) = faces.next(&mut raw) {
        let f = next_face;
        next_face += 1;
        while let Some(&&(from, s)) = states.peek()
            && from as usize <= f
        {
            state = s;
            states.next();
        }
        while let Some(&&(corner, k, index)) = reaches.peek()
            && corner < face.first_corner + raw.len()
        {
            let raw = &mut raw[corner - face.first_corner];
            raw.index[k] = index;
            raw.flags &= !LOCAL[k];
            reaches.next();
        }
        if let Some(triangle) = plain_triangle(&raw, at, totals, state) {
            slots[next_slot] = triangle;
            next_slot += 1;
            continue;
        }
        let line = face.line;
        // Positions the one-thread reader had read when it met the face.
        let defined = at.index[0] + face.positions;
        let mut later = false;
        let mut missing = false;
        corners.clear();
        for (c, raw) in raw.iter().enumerate() {
            let mut index = [None; 3];
            for (k, slot) in index.iter_mut().enumerate() {
                if k > 0 && raw.flags & [0, HAS_VT, HAS_VN][k] == 0 {
                    continue;
                }
                let mut i = raw.index[k] as usize;
                if raw.flags & LOCAL[k] != 0 {
                    i += at.index[k];
                }
                if i >= totals[k] {
                    missing |= k == 0;
                    let corner = face.first_corner + c;
                    built.missing[k]
                        .get_or_insert_with(|| (corner_line(piece, corner, line), i as u32));
                }
                *slot = Some(i as u32);
            }
            let v = index[0].unwrap_or(0);
            later |= v as usize >= defined;
            corners.push(Corner {
                v,
                vt: index[1],
                vn: index[2],
            });
        }
        let n = corners.len();
        if n < 3 {
            continue;
        }
        let (all, _) = corner_attributes(&corners);
        let mut template = ObjTriangle {
            v: [0; 3],
            vt: all[0].then_some([0; 3]),
            vn: all[1].then_some([0; 3]),
            material: state.material,
            smoothing: state.smoothing,
        };
        let slots = &mut slots[next_slot..next_slot + n - 2];
        next_slot += n - 2;
        if n == 3 {
            slots[0] = triangle_of(&template, &corners, [0, 1, 2]);
            drop_missing(&mut slots[0], totals);
        } else if !later {
            slots.fill(template);
            let method = split_polygon(
                &mut triangulator,
                &mut polygon,
                &mut local,
                positions,
                &corners,
                slots,
            );
            for slot in slots.iter_mut() {
                drop_missing(slot, totals);
            }
            if method == Method::FanFallback {
                if built.fans.len() < MAX_WARNINGS {
                    built.fans.push((f as u32, line, n));
                } else {
                    built.suppressed += 1;
                }
            }
        } else if missing {
            // The file fails at its end: nothing to split.
            slots.fill(template);
        } else {
            // A corner whose vt or vn is missing takes the whole face's away.
            for c in &mut corners {
                c.vt = c.vt.filter(|&i| (i as usize) < totals[1]);
                c.vn = c.vn.filter(|&i| (i as usize) < totals[2]);
            }
            if corners.iter().any(|c| c.vt.is_none()) {
                template.vt = None;
            }
            if corners.iter().any(|c| c.vn.is_none()) {
                template.vn = None;
            }
            slots.fill(template);
            let method = split_polygon(
                &mut triangulator,
                &mut polygon,
                &mut local,
                positions,
                &corners,
                slots,
            );
            if method == Method::FanFallback {
                if built.deferred_fans.len() < MAX_WARNINGS {
                    built.deferred_fans.push((line, n));
                } else {
                    built.deferred_suppressed += 1;
                }
            }
        }
    }
    debug_assert_eq!(next_slot, slots.len());
    built
}

/// The usual face, built without the general path's bookkeeping: a triangle whose
/// corners all give the same attributes, each naming an element the file has.
#[inline]
fn plain_triangle(
    raw: &[RawCorner],
    at: &Place,
    totals: [usize; 3],
    state: State,
) -> Option<ObjTriangle> {
    let &[a, b, c] = raw else {
        return None;
    };
    let attributes = HAS_VT | HAS_VN;
    let given = (a.flags | b.flags | c.flags) & attributes;
    if a.flags & b.flags & c.flags & attributes != given {
        return None;
    }
    let indices = |k: usize| {
        let ids = [a, b, c].map(|r| {
            r.index[k] as usize
                + if r.flags & LOCAL[k] != 0 {
                    at.index[k]
                } else {
                    0
                }
        });
        ids.iter()
            .all(|&i| i < totals[k])
            .then(|| ids.map(|i| i as u32))
    };
    let optional = |k: usize, flag: u8| match given & flag {
        0 => Some(None),
        _ => indices(k).map(Some),
    };
    Some(ObjTriangle {
        v: indices(0)?,
        vt: optional(1, HAS_VT)?,
        vn: optional(2, HAS_VN)?,
        material: state.material,
        smoothing: state.smoothing,
    })
}

/// The physical line of corner `corner`, in a statement starting at `line`.
fn corner_line(piece: &Piece, corner: usize, line: usize) -> usize {
    match piece
        .corner_lines
        .binary_search_by_key(&(corner as u32), |&(c, _)| c)
    {
        Ok(i) => piece.corner_lines[i].1 as usize,
        Err(_) => line,
    }
}

/// A triangle loses its vt or vn when one of them names an element past the file's last.
fn drop_missing(t: &mut ObjTriangle, totals: [usize; 3]) {
    if t.vt
        .is_some_and(|ids| ids.iter().any(|&i| i as usize >= totals[1]))
    {
        t.vt = None;
    }
    if t.vn
        .is_some_and(|ids| ids.iter().any(|&i| i as usize >= totals[2]))
    {
        t.vn = None;
    }
}

/// The events of every piece in file order, with the warnings found building triangles
/// in their place: warnings, runs, material libraries and the first error, as the
/// one-thread reader meets them.
fn replay(pieces: &mut [Piece], link: &Link, built: &[Built], reader: &mut Reader) -> Result<()> {
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

#[cfg(test)]
mod tests;
