//! The pass in file order that places each piece among the others.

use super::piece::{Piece, What};
use crate::format::obj::reader::{Reader, triangle_limit};

/// Where a piece starts in the file's arrays, and the state its first faces inherit.
pub(super) struct Place {
    /// Positions, texture coordinates and normals before the piece.
    pub(super) index: [usize; 3],
    pub(super) triangles: usize,
    /// `usemtl` numbers of the piece's names in the whole file's numbering.
    pub(super) materials: Vec<u32>,
    /// The material and smoothing group in force at the piece's start, then after each
    /// change within it: (first face it applies to, state).
    pub(super) states: Vec<(u32, State)>,
    /// Negative indices reaching back past the piece, resolved: (corner, kind, index),
    /// in corner order.
    pub(super) reaches: Vec<(usize, usize, u32)>,
}

#[derive(Clone, Copy, Default)]
pub(super) struct State {
    pub(super) material: Option<u32>,
    pub(super) smoothing: u32,
}

pub(super) struct Link {
    pub(super) pieces: Vec<Place>,
    /// Positions, texture coordinates and normals in the file.
    pub(super) totals: [usize; 3],
    pub(super) triangles: usize,
    /// A negative index reaches before the first element of its kind.
    pub(super) reach_error: bool,
    /// The face whose triangles pass the scene's limit: (piece, face, line).
    pub(super) limit: Option<(usize, usize, usize)>,
}

/// The pass in file order that tells each piece where it starts; it numbers the `usemtl`
/// names (in the reader, as it would) and resolves the negative indices that reach back
/// past their piece.
pub(super) fn link_pieces(pieces: &[Piece], reader: &mut Reader) -> Link {
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
