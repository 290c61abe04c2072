//! The OBJ statement reader: one pass over the lines, then the checks and fix-ups that
//! need the whole file (forward references, deferred polygons, material names,
//! smoothing normals). Large files are read in pieces on every thread ([`parallel`]),
//! to the same result.

mod materials;
mod messages;
mod parallel;
mod skipped;
mod values;

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

use super::lines::{self, Line, Lines, Token, Tokens};
use super::smooth::smooth_normals;
use super::triangulate::{Method, Triangulator};
use super::{GroupKind, ObjFile, ObjGroup, ObjTriangle, Warning};
use crate::error::{Error, Result};
use crate::math::Vec3;
use messages::{
    error_at, fan_fallback_message, few_corners_message, missing_attribute_message,
    missing_relative, missing_vertex, mixed_face_message, push_warning, too_many_triangles_message,
    unknown_message,
};
use skipped::skipped_kind;
pub(in crate::format) use values::number;
use values::{
    Part, corner_parts, index_value, parse_normal, parse_position, parse_smoothing, parse_texcoord,
    positive_index, push_position, run_name, short_index,
};

/// Gives the bytes of the material library at a path.
pub type ReadLibrary<'r> = &'r mut dyn FnMut(&Path) -> Result<Vec<u8>>;

pub struct Options<'r> {
    /// Where material libraries come from; `None` ignores `mtllib`.
    pub read_library: Option<ReadLibrary<'r>>,
    /// Whether to make normals for smoothing groups.
    pub smooth: bool,
}

/// Reads OBJ text; `path` names it in errors.
pub fn read(text: &[u8], path: &Path, options: Options) -> Result<ObjFile> {
    let text = lines::without_bom(text);
    if parallel::worth_it(&text) {
        let step = parallel::piece_bytes(text.len());
        return parallel::read(&text, path, options, step);
    }
    read_in_order(&text, path, options)
}

/// Reads on this thread alone, statement after statement.
fn read_in_order(text: &[u8], path: &Path, options: Options) -> Result<ObjFile> {
    let mut reader = Reader::new(path, options);
    let mut lines = Lines::new(text);
    while let Some(line) = lines.next_line() {
        reader.statement(&line)?;
    }
    reader.finish()
}

/// Reads `text` (without its byte-order mark) as [`read`] does on more than one thread,
/// cut into pieces of about `step` bytes however short the text.
#[cfg(test)]
fn read_in_pieces(text: &[u8], path: &Path, options: Options, step: usize) -> Result<ObjFile> {
    parallel::read(text, path, options, step)
}

/// Reads `text` (without its byte-order mark) as [`read`] does on one thread.
#[cfg(test)]
fn read_in_one_piece(text: &[u8], path: &Path, options: Options) -> Result<ObjFile> {
    read_in_order(text, path, options)
}

/// The kinds of index a face corner holds.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Position,
    Texcoord,
    Normal,
}

impl Kind {
    fn noun(self) -> &'static str {
        match self {
            Kind::Position => "vertex",
            Kind::Texcoord => "texture coordinate",
            Kind::Normal => "normal",
        }
    }
}

#[derive(Clone, Copy)]
struct Corner {
    v: u32,
    vt: Option<u32>,
    vn: Option<u32>,
}

/// A positive index beyond what was read when it was used: checked at the end.
struct Forward {
    index: u32,
    line: usize,
}

/// A polygon naming positions defined further down: triangulated at the end into the
/// slots reserved for it, so triangles stay in file order.
struct Deferred {
    first_triangle: usize,
    corners: std::ops::Range<usize>,
    line: usize,
}

/// The `o`/`g` run in force.
struct Run {
    name: String,
    kind: GroupKind,
    first: usize,
}

struct Reader<'p, 'r> {
    path: &'p Path,
    folder: PathBuf,
    options: Options<'r>,
    obj: ObjFile,
    suppressed_warnings: usize,
    corners: Vec<Corner>,
    polygon: Vec<Vec3>,
    local: Vec<[u32; 3]>,
    triangulator: Triangulator,
    forward: [Vec<Forward>; 3],
    deferred: Vec<Deferred>,
    deferred_corners: Vec<Corner>,
    smoothing: u32,
    /// The `usemtl` in force, as an index into `material_names`.
    material: Option<u32>,
    material_names: Vec<String>,
    material_ids: HashMap<String, u32>,
    usemtl_lines: Vec<(u32, usize)>,
    /// Material name → index in `obj.materials`.
    material_index: HashMap<String, u32>,
    libraries_read: HashSet<PathBuf>,
    run: Run,
    skipped_first_line: BTreeMap<String, usize>,
    /// Whether a face mixing corners with and without vt (0) or vn (1) was reported.
    mixed_face_warned: [bool; 2],
}

impl<'p, 'r> Reader<'p, 'r> {
    fn new(path: &'p Path, options: Options<'r>) -> Reader<'p, 'r> {
        Reader {
            path,
            folder: path.parent().unwrap_or(Path::new("")).to_path_buf(),
            options,
            obj: ObjFile::default(),
            suppressed_warnings: 0,
            corners: Vec::new(),
            polygon: Vec::new(),
            local: Vec::new(),
            triangulator: Triangulator::default(),
            forward: Default::default(),
            deferred: Vec::new(),
            deferred_corners: Vec::new(),
            smoothing: 0,
            material: None,
            material_names: Vec::new(),
            material_ids: HashMap::new(),
            usemtl_lines: Vec::new(),
            material_index: HashMap::new(),
            libraries_read: HashSet::new(),
            run: Run {
                name: String::new(),
                kind: GroupKind::Group,
                first: 0,
            },
            skipped_first_line: BTreeMap::new(),
            mixed_face_warned: [false; 2],
        }
    }
}

impl Reader<'_, '_> {
    fn error(&self, line: &Line, offset: usize, message: impl Into<String>) -> Error {
        error_at(self.path, line, offset, message)
    }

    fn warn(&mut self, line: usize, message: impl Into<String>) {
        let path = self.path.to_path_buf();
        push_warning(
            &mut self.obj.warnings,
            &mut self.suppressed_warnings,
            path,
            line,
            message,
        );
    }

    fn statement(&mut self, line: &Line) -> Result<()> {
        let mut tokens = line.tokens();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        match keyword.bytes {
            b"v" => {
                let (values, count) = parse_position(self.path, line, tokens)?;
                push_position(&mut self.obj.positions, &mut self.obj.colors, values, count);
                Ok(())
            }
            b"vt" => {
                let uv = parse_texcoord(self.path, line, tokens)?;
                self.obj.texcoords.push(uv);
                Ok(())
            }
            b"vn" => {
                let n = parse_normal(self.path, line, tokens)?;
                self.obj.normals.push(n);
                Ok(())
            }
            b"f" | b"fo" => self.face(line, tokens),
            b"o" => {
                self.start_run(
                    GroupKind::Object,
                    run_name(tokens),
                    self.obj.triangles.len(),
                );
                Ok(())
            }
            b"g" => {
                self.start_run(GroupKind::Group, run_name(tokens), self.obj.triangles.len());
                Ok(())
            }
            b"s" => {
                self.smoothing = parse_smoothing(self.path, line, keyword, tokens)?;
                Ok(())
            }
            b"usemtl" => {
                self.use_material(
                    line.rest_from(keyword.start + keyword.bytes.len()),
                    line.number,
                );
                Ok(())
            }
            b"mtllib" => {
                let rest = line.rest_from(keyword.start + keyword.bytes.len());
                self.material_libraries(rest, line.number)
            }
            other => {
                let kind = skipped_kind(other);
                *self.obj.skipped.entry(kind.to_owned()).or_insert(0) += 1;
                if kind == "unknown" && !self.skipped_first_line.contains_key(kind) {
                    self.warn(line.number, unknown_message(other));
                }
                self.skipped_first_line
                    .entry(kind.to_owned())
                    .or_insert(line.number);
                Ok(())
            }
        }
    }

    /// The 0-based index a face corner names, from its digits `text` at byte `start`.
    #[inline]
    fn index(
        &mut self,
        line: &Line,
        token: Token,
        text: &[u8],
        start: usize,
        kind: Kind,
    ) -> Result<u32> {
        // The common case: a few digits naming something already read.
        let defined = self.defined(kind);
        if let Some(value) = short_index(text)
            && value <= defined
        {
            return Ok(value as u32 - 1);
        }
        self.index_slow(line, token, text, start, kind)
    }

    fn defined(&self, kind: Kind) -> usize {
        match kind {
            Kind::Position => self.obj.positions.len(),
            Kind::Texcoord => self.obj.texcoords.len(),
            Kind::Normal => self.obj.normals.len(),
        }
    }

    #[cold]
    fn index_slow(
        &mut self,
        line: &Line,
        token: Token,
        text: &[u8],
        start: usize,
        kind: Kind,
    ) -> Result<u32> {
        let defined = self.defined(kind);
        let value = index_value(self.path, line, token, text, start, kind)?;
        let index = if value > 0 {
            positive_index(self.path, line, text, start, kind, value)?
        } else {
            let resolved = defined as i64 + value;
            if resolved < 0 {
                return Err(self.error(line, start, missing_relative(kind, text, defined)));
            }
            resolved as u32
        };
        if index as usize >= defined {
            let (number, _) = line.place(start);
            self.forward[kind as usize].push(Forward {
                index,
                line: number,
            });
        }
        Ok(index)
    }

    fn face(&mut self, line: &Line, tokens: Tokens) -> Result<()> {
        let mut corners = std::mem::take(&mut self.corners);
        corners.clear();
        let result = self.face_corners(line, tokens, &mut corners);
        let result = result.and_then(|()| self.add_face(line, &corners));
        self.corners = corners;
        result
    }

    fn face_corners(
        &mut self,
        line: &Line,
        tokens: Tokens,
        corners: &mut Vec<Corner>,
    ) -> Result<()> {
        for token in tokens {
            let [v_part, vt_part, vn_part] = corner_parts(self.path, line, token)?;
            let (v_text, v_start) = v_part.unwrap_or((&[], token.start));
            let v = self.index(line, token, v_text, v_start, Kind::Position)?;
            let mut optional = |part: Option<Part>, kind| match part {
                Some((text, at)) if !text.is_empty() => {
                    self.index(line, token, text, at, kind).map(Some)
                }
                _ => Ok(None),
            };
            let vt = optional(vt_part, Kind::Texcoord)?;
            let vn = optional(vn_part, Kind::Normal)?;
            corners.push(Corner { v, vt, vn });
        }
        Ok(())
    }

    fn add_face(&mut self, line: &Line, corners: &[Corner]) -> Result<()> {
        let n = corners.len();
        if n < 3 {
            self.warn(line.number, few_corners_message(n));
            return Ok(());
        }
        let (all, any) = corner_attributes(corners);
        for k in 0..2 {
            if any[k] && !all[k] && !self.mixed_face_warned[k] {
                self.mixed_face_warned[k] = true;
                self.warn(line.number, mixed_face_message(k));
            }
        }
        if self.obj.triangles.len() + (n - 2) > triangle_limit() {
            return Err(self.error(line, 0, too_many_triangles_message()));
        }
        let template = ObjTriangle {
            v: [0; 3],
            vt: all[0].then_some([0; 3]),
            vn: all[1].then_some([0; 3]),
            material: self.material,
            smoothing: self.smoothing,
        };
        let first = self.obj.triangles.len();
        if n == 3 {
            self.obj
                .triangles
                .push(triangle_of(&template, corners, [0, 1, 2]));
        } else if corners
            .iter()
            .all(|c| (c.v as usize) < self.obj.positions.len())
        {
            self.obj.triangles.resize(first + n - 2, template);
            self.split_polygon(corners, first, line.number);
        } else {
            self.obj.triangles.resize(first + n - 2, template);
            let start = self.deferred_corners.len();
            self.deferred_corners.extend_from_slice(corners);
            self.deferred.push(Deferred {
                first_triangle: first,
                corners: start..self.deferred_corners.len(),
                line: line.number,
            });
        }
        Ok(())
    }

    /// Triangulates a polygon whose positions are all known into the `n - 2` slots from
    /// `first`, which hold its material and smoothing group already.
    fn split_polygon(&mut self, corners: &[Corner], first: usize, line: usize) {
        let method = split_polygon(
            &mut self.triangulator,
            &mut self.polygon,
            &mut self.local,
            &self.obj.positions,
            corners,
            &mut self.obj.triangles[first..first + corners.len() - 2],
        );
        if method == Method::FanFallback {
            self.warn(line, fan_fallback_message(corners.len()));
        }
    }

    /// Ends the run in force at triangle `end` and starts another there.
    fn start_run(&mut self, kind: GroupKind, name: String, at: usize) {
        self.close_run(at);
        self.run = Run {
            name,
            kind,
            first: at,
        };
    }

    fn close_run(&mut self, end: usize) {
        if end > self.run.first {
            self.obj.groups.push(ObjGroup {
                name: std::mem::take(&mut self.run.name),
                kind: self.run.kind,
                triangles: self.run.first..end,
            });
        }
    }

    fn finish(mut self) -> Result<ObjFile> {
        // Positions named before they were defined must exist by now.
        let positions = self.obj.positions.len();
        if let Some(f) = self.forward[Kind::Position as usize]
            .iter()
            .find(|f| f.index as usize >= positions)
        {
            return Err(missing_vertex(self.path, f.line, f.index, positions));
        }
        // Missing texture coordinates and normals only cost the face its vt or vn, as
        // in the other readers (files that name normals they never wrote exist).
        for kind in [Kind::Texcoord, Kind::Normal] {
            let defined = self.defined(kind);
            let Some(f) = self.forward[kind as usize]
                .iter()
                .find(|f| f.index as usize >= defined)
            else {
                continue;
            };
            let (line, index) = (f.line, f.index);
            self.warn(line, missing_attribute_message(kind, index, defined));
            for t in &mut self.obj.triangles {
                let field = if kind == Kind::Texcoord {
                    &mut t.vt
                } else {
                    &mut t.vn
                };
                if field.is_some_and(|ids| ids.iter().any(|&i| i as usize >= defined)) {
                    *field = None;
                }
            }
            for c in &mut self.deferred_corners {
                let field = if kind == Kind::Texcoord {
                    &mut c.vt
                } else {
                    &mut c.vn
                };
                if field.is_some_and(|i| i as usize >= defined) {
                    *field = None;
                }
            }
        }
        let deferred = std::mem::take(&mut self.deferred);
        let deferred_corners = std::mem::take(&mut self.deferred_corners);
        for polygon in deferred {
            let corners = &deferred_corners[polygon.corners];
            let slots = &mut self.obj.triangles[polygon.first_triangle..][..corners.len() - 2];
            // Corners whose vt or vn went missing above take the whole face's away.
            for slot in slots.iter_mut() {
                if corners.iter().any(|c| c.vt.is_none()) {
                    slot.vt = None;
                }
                if corners.iter().any(|c| c.vn.is_none()) {
                    slot.vn = None;
                }
            }
            self.split_polygon(corners, polygon.first_triangle, polygon.line);
        }
        self.conclude()
    }

    /// What is left once every triangle is in place: the last run, materials, smoothing
    /// normals and the summary warnings.
    fn conclude(mut self) -> Result<ObjFile> {
        self.close_run(self.obj.triangles.len());
        self.resolve_materials();
        if self.options.smooth {
            smooth_normals(
                &self.obj.positions,
                &mut self.obj.triangles,
                &mut self.obj.normals,
            );
        }
        for (kind, &line) in &self.skipped_first_line {
            let count = self.obj.skipped[kind];
            let message = match kind.as_str() {
                "unknown" => format!("{count} unknown statements skipped"),
                _ => format!("{count} `{kind}` statements skipped: Prism renders only faces"),
            };
            let path = self.path.to_path_buf();
            push_warning(
                &mut self.obj.warnings,
                &mut self.suppressed_warnings,
                path,
                line,
                message,
            );
        }
        if self.suppressed_warnings > 0 {
            let last = Warning {
                path: self.path.to_path_buf(),
                line: 0,
                message: format!("and {} more warnings", self.suppressed_warnings),
            };
            self.obj.warnings.push(last);
        }
        Ok(self.obj)
    }
}

/// Whether all and whether any corners have a texture coordinate (0) and a normal (1).
fn corner_attributes(corners: &[Corner]) -> ([bool; 2], [bool; 2]) {
    (
        [
            corners.iter().all(|c| c.vt.is_some()),
            corners.iter().all(|c| c.vn.is_some()),
        ],
        [
            corners.iter().any(|c| c.vt.is_some()),
            corners.iter().any(|c| c.vn.is_some()),
        ],
    )
}

/// The most triangles a file may give: the scene's limit, or in tests, which cannot
/// write 2^28 triangles, a small one.
fn triangle_limit() -> usize {
    #[cfg(test)]
    if let Some(limit) = TEST_TRIANGLE_LIMIT.get() {
        return limit;
    }
    crate::scene::MAX_SHAPES
}

#[cfg(test)]
thread_local! {
    static TEST_TRIANGLE_LIMIT: std::cell::Cell<Option<usize>> = const { std::cell::Cell::new(None) };
}

/// Triangulates a polygon whose positions are all known into `slots` (`n - 2` of them),
/// which hold its material and smoothing group already.
fn split_polygon(
    triangulator: &mut Triangulator,
    polygon: &mut Vec<Vec3>,
    local: &mut Vec<[u32; 3]>,
    positions: &[Vec3],
    corners: &[Corner],
    slots: &mut [ObjTriangle],
) -> Method {
    polygon.clear();
    polygon.extend(corners.iter().map(|c| positions[c.v as usize]));
    local.clear();
    let method = triangulator.triangulate(polygon, local);
    for (slot, local) in slots.iter_mut().zip(local.iter()) {
        *slot = triangle_of(slot, corners, *local);
    }
    method
}

fn triangle_of(template: &ObjTriangle, corners: &[Corner], local: [u32; 3]) -> ObjTriangle {
    let c = local.map(|i| corners[i as usize]);
    ObjTriangle {
        v: c.map(|c| c.v),
        vt: template.vt.map(|_| c.map(|c| c.vt.unwrap_or(0))),
        vn: template.vn.map(|_| c.map(|c| c.vn.unwrap_or(0))),
        ..*template
    }
}
