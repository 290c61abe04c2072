//! A piece's triangles built into its share of the final array.

use super::faces::{HAS_VN, HAS_VT, LOCAL, RawCorner};
use super::link::{Place, State};
use super::piece::Piece;
use crate::format::obj::ObjTriangle;
use crate::format::obj::reader::messages::MAX_WARNINGS;
use crate::format::obj::reader::{Corner, corner_attributes, split_polygon, triangle_of};
use crate::format::obj::triangulate::{Method, Triangulator};
use crate::math::Vec3;

/// What building a piece's triangles found.
#[derive(Default)]
pub(super) struct Built {
    /// Polygons split as a fan though concave: (face, line, corners), and how many more
    /// past the cap.
    pub(super) fans: Vec<(u32, usize, usize)>,
    pub(super) suppressed: usize,
    /// The same for polygons naming positions defined later, which the one-thread
    /// reader splits (and warns about) at the end: (line, corners).
    pub(super) deferred_fans: Vec<(usize, usize)>,
    pub(super) deferred_suppressed: usize,
    /// The first index of each kind past the file's last element: (line, index).
    pub(super) missing: [Option<(usize, u32)>; 3],
}

/// Builds a piece's triangles into `slots`, as the one-thread reader would have once
/// at the end of the file.
pub(super) fn build(
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
