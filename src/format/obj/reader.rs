//! The OBJ statement reader: one pass over the lines, then the checks and fix-ups that
//! need the whole file (forward references, deferred polygons, material names,
//! smoothing normals). Large files are read in pieces on every thread ([`parallel`]),
//! to the same result.

mod parallel;

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

use super::lines::{self, Line, Lines, Token, Tokens, decode_name, parse_integer, shown};
use super::smooth::smooth_normals;
use super::triangulate::{Method, Triangulator};
use super::{GroupKind, ObjFile, ObjGroup, ObjTriangle, Warning};
use crate::format::mtl;
use crate::math::Vec3;
use crate::{Error, Result};
use rayon::prelude::*;

/// Past this many, warnings are counted in one last warning instead of kept: a file of
/// a million bad faces should not hold a million messages.
const MAX_WARNINGS: usize = 1000;

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

/// Statements Prism knows and skips, counted under their own name; anything else is
/// counted as `unknown`.
const SKIPPED_KEYWORDS: &[&str] = &[
    "l",
    "p",
    "curv",
    "curv2",
    "surf",
    "t",
    "vp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "bevel",
    "c_interp",
    "d_interp",
    "lod",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "maplib",
    "usemap",
    "call",
    "csh",
    "vw",
];

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

    /// `usemtl` followed by `name` (trimmed): the material of the faces that follow.
    fn use_material(&mut self, name: &[u8], line: usize) {
        if name.is_empty() {
            self.warn(line, NAMELESS_USEMTL);
            self.material = None;
            return;
        }
        let id = self.material_id(decode_name(name));
        self.material = Some(id);
        self.usemtl_lines.push((id, line));
    }

    /// The number of a `usemtl` name, in order of first appearance.
    fn material_id(&mut self, name: String) -> u32 {
        let next_id = self.material_names.len() as u32;
        let id = *self.material_ids.entry(name.clone()).or_insert(next_id);
        if id == next_id {
            self.material_names.push(name);
        }
        id
    }

    /// `mtllib` followed by `rest` (trimmed).
    fn material_libraries(&mut self, rest: &[u8], line: usize) -> Result<()> {
        if rest.is_empty() {
            self.warn(line, "mtllib without a file name");
        }
        for name in library_names(rest) {
            self.read_library(&name, line)?;
        }
        Ok(())
    }

    fn read_library(&mut self, name: &[u8], line: usize) -> Result<()> {
        let Some(read) = self.options.read_library.as_mut() else {
            return Ok(());
        };
        let path = self.folder.join(decode_name(name));
        if !self.libraries_read.insert(path.clone()) {
            return Ok(());
        }
        let bytes = match read(&path) {
            Ok(bytes) => bytes,
            Err(e) => {
                self.warn(
                    line,
                    format!("material library skipped, its materials are unknown: {e}"),
                );
                return Ok(());
            }
        };
        let library = mtl::parse(&bytes, &path)?;
        for warning in library.warnings {
            push_warning(
                &mut self.obj.warnings,
                &mut self.suppressed_warnings,
                warning.path,
                warning.line,
                warning.message,
            );
        }
        for (kind, count) in library.skipped {
            *self.obj.skipped.entry(format!("mtl:{kind}")).or_insert(0) += count;
        }
        for material in library.materials {
            if let Some(&first) = self.material_index.get(&material.name) {
                let first = &self.obj.materials[first as usize];
                let message = format!(
                    "material {} is defined again: the first definition ({}:{}) is kept",
                    shown(material.name.as_bytes()),
                    first.path.display(),
                    first.line
                );
                push_warning(
                    &mut self.obj.warnings,
                    &mut self.suppressed_warnings,
                    material.path.clone(),
                    material.line,
                    message,
                );
                continue;
            }
            let index = self.obj.materials.len() as u32;
            self.material_index.insert(material.name.clone(), index);
            self.obj.materials.push(material);
        }
        Ok(())
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

    /// Turns the `usemtl` names on the triangles into material indices; an unknown
    /// name gives a warning at each `usemtl` naming it and no material.
    fn resolve_materials(&mut self) {
        if self.material_names.is_empty() {
            return; // no triangle names one
        }
        let resolved: Vec<Option<u32>> = self
            .material_names
            .iter()
            .map(|name| self.material_index.get(name).copied())
            .collect();
        for (id, line) in std::mem::take(&mut self.usemtl_lines) {
            if resolved[id as usize].is_none() {
                let message = format!(
                    "usemtl names material {}, which no material library defines: its \
                     faces get the default material",
                    shown(self.material_names[id as usize].as_bytes())
                );
                self.warn(line, message);
            }
        }
        self.obj.triangles.par_iter_mut().for_each(|t| {
            t.material = t.material.and_then(|id| resolved[id as usize]);
        });
    }
}

/// An error at byte `offset` of a line.
fn error_at(path: &Path, line: &Line, offset: usize, message: impl Into<String>) -> Error {
    let (number, column) = line.place(offset);
    Error::parse_at(path, number, column, message)
}

/// `v x y z [w]` or `v x y z r g b`: the values and how many there are (3, 4 or 6).
// Both readers call the statement parsers once a line; inlined, their results stay in
// registers (a separate call made the one-thread reader 8 % slower).
#[inline(always)]
fn parse_position(path: &Path, line: &Line, tokens: Tokens) -> Result<([f32; 6], usize)> {
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
fn push_position(
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
fn parse_texcoord(path: &Path, line: &Line, mut tokens: Tokens) -> Result<[f32; 2]> {
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
fn parse_normal(path: &Path, line: &Line, mut tokens: Tokens) -> Result<Vec3> {
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
fn parse_smoothing(path: &Path, line: &Line, keyword: Token, mut tokens: Tokens) -> Result<u32> {
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
fn run_name(tokens: Tokens) -> String {
    let mut name = String::new();
    for token in tokens {
        if !name.is_empty() {
            name.push(' ');
        }
        name.push_str(&decode_name(token.bytes));
    }
    name
}

/// What a statement Prism does not read is counted as.
fn skipped_kind(keyword: &[u8]) -> &'static str {
    std::str::from_utf8(keyword)
        .ok()
        .and_then(|k| SKIPPED_KEYWORDS.iter().find(|&&known| known == k))
        .copied()
        .unwrap_or("unknown")
}

/// A part of a face corner: its text and the byte offset of that in the line.
type Part<'l> = (&'l [u8], usize);

/// The up to three `/`-separated parts of a face corner.
#[inline(always)]
fn corner_parts<'l>(path: &Path, line: &Line, token: Token<'l>) -> Result<[Option<Part<'l>>; 3]> {
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
fn short_index(text: &[u8]) -> Option<usize> {
    if text.is_empty() || text.len() > 9 || !text.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let value = text
        .iter()
        .fold(0usize, |n, &d| n * 10 + (d - b'0') as usize);
    (value >= 1).then_some(value)
}

/// The signed, non-zero number a face corner index is written as.
fn index_value(
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
fn positive_index(
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

/// The error for a negative index reaching before the first element of its kind.
fn missing_relative(kind: Kind, text: &[u8], defined: usize) -> String {
    format!(
        "{} index {} does not exist: -1 is the last of the {defined} read so far",
        kind.noun(),
        shown(text)
    )
}

/// The error for a vertex named but never defined; `file:line:` as before, since
/// `prism convert`'s callers match this text.
fn missing_vertex(path: &Path, line: usize, index: u32, positions: usize) -> Error {
    Error::parse(
        path,
        line,
        format!(
            "vertex {} does not exist: the file defines {positions}",
            index as u64 + 1
        ),
    )
}

fn missing_attribute_message(kind: Kind, index: u32, defined: usize) -> String {
    let noun = kind.noun();
    format!(
        "{noun} {} does not exist (the file defines {defined}): faces naming missing \
         {noun}s get none (reported for the first only)",
        index as u64 + 1
    )
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

fn few_corners_message(n: usize) -> String {
    format!("a face needs at least 3 vertices, found {n}: the face is dropped")
}

fn mixed_face_message(k: usize) -> String {
    let what = ["texture coordinates", "normals"][k];
    format!(
        "a face gives {what} for some corners only: it gets none (this is reported for the \
         first such face only)"
    )
}

fn too_many_triangles_message() -> String {
    format!(
        "expected at most {} triangles in a scene, found more",
        triangle_limit()
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

// The bounding volume hierarchy takes more triangles than a scene may hold, so the
// scene's limit is the only one a face can reach.
const _: () = assert!(crate::scene::MAX_SHAPES <= crate::accel::MAX_SHAPES);

fn fan_fallback_message(corners: usize) -> String {
    format!(
        "a concave polygon of {corners} vertices crosses itself or is too large to clip: it \
         is split as a fan, which may cover area outside it"
    )
}

fn unknown_message(keyword: &[u8]) -> String {
    format!(
        "unknown statement {} skipped (the count of unknown statements is in the summary)",
        shown(keyword)
    )
}

const NAMELESS_USEMTL: &str =
    "usemtl without a name: the faces that follow get the default material";

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

fn push_warning(
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

fn triangle_of(template: &ObjTriangle, corners: &[Corner], local: [u32; 3]) -> ObjTriangle {
    let c = local.map(|i| corners[i as usize]);
    ObjTriangle {
        v: c.map(|c| c.v),
        vt: template.vt.map(|_| c.map(|c| c.vt.unwrap_or(0))),
        vn: template.vn.map(|_| c.map(|c| c.vn.unwrap_or(0))),
        ..*template
    }
}

/// The file names of an `mtllib` line: separated by white space, with `\ ` standing for
/// a space inside a name.
fn library_names(rest: &[u8]) -> Vec<Vec<u8>> {
    let mut names = Vec::new();
    let mut name = Vec::new();
    let mut bytes = rest.iter().copied().peekable();
    while let Some(b) = bytes.next() {
        if b == b'\\' && bytes.peek() == Some(&b' ') {
            name.push(b' ');
            bytes.next();
        } else if lines::is_space(b) {
            if !name.is_empty() {
                names.push(std::mem::take(&mut name));
            }
        } else {
            name.push(b);
        }
    }
    if !name.is_empty() {
        names.push(name);
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_names_split_on_unescaped_spaces() {
        let names = library_names(br"a.mtl  my\ lib\ 2.mtl	c\d.mtl");
        assert_eq!(
            names,
            [
                b"a.mtl".to_vec(),
                b"my lib 2.mtl".to_vec(),
                br"c\d.mtl".to_vec()
            ]
        );
    }
}
