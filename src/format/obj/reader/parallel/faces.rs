//! The faces of a piece, packed into varints as they are read and unpacked as its
//! triangles are built.

/// A face corner as written. An index with the [`LOCAL`] bit of its kind counts from the
/// first element of that kind in the piece (a negative index); the others are 0-based
/// indices into the file's.
#[derive(Clone, Copy, Default)]
pub(super) struct RawCorner {
    pub(super) index: [u32; 3],
    pub(super) flags: u8,
}

pub(super) const HAS_VT: u8 = 1;
pub(super) const HAS_VN: u8 = 2;
pub(super) const LOCAL: [u8; 3] = [4, 8, 16];

/// The faces of a piece, packed into bytes: per face its number of corners, its (first
/// physical) line and how many positions the piece had read before it, each as the
/// difference from the face before; then per corner a byte of flags and its indices.
/// Every number is a LEB128 varint: an index into a million vertices takes 3 bytes, a
/// line or count difference 1. Plain structs would take four times the memory, and
/// fresh memory is what the kernel hands over page by page, slowly.
#[derive(Default)]
pub(super) struct Faces {
    bytes: Vec<u8>,
    pub(super) count: u32,
    /// Corners in all faces so far: the number of the next one.
    pub(super) corners: usize,
    last_line: usize,
    last_positions: usize,
}

/// A face read back from [`Faces`].
pub(super) struct Face {
    pub(super) line: usize,
    /// The piece's positions read before it.
    pub(super) positions: usize,
    /// The number of its first corner in the piece.
    pub(super) first_corner: usize,
}

impl Faces {
    pub(super) fn push(&mut self, line: usize, positions: usize, corners: &[RawCorner]) {
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

    pub(super) fn reader(&self) -> FaceReader<'_> {
        FaceReader {
            bytes: &self.bytes,
            at: 0,
            line: 0,
            positions: 0,
            corners: 0,
        }
    }
}

pub(super) struct FaceReader<'a> {
    bytes: &'a [u8],
    at: usize,
    line: usize,
    positions: usize,
    corners: usize,
}

impl FaceReader<'_> {
    /// The next face, its corners into `corners`.
    #[inline(always)]
    pub(super) fn next(&mut self, corners: &mut Vec<RawCorner>) -> Option<Face> {
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
