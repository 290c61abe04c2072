//! The colour description in the MP4 container: a `colr` box of type `nclx` in the
//! H.264 sample entry, saying what the stream's parameter set already says (BT.601,
//! limited range). Some players read only the container's tag.
//!
//! The `mp4` muxer writes no `colr` box and puts the `moov` box after the media data, so
//! the box is added to `moov` in place: no sample offset moves.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};

/// SMPTE 170M (BT.601 525) for primaries, transfer and matrix: ISO/IEC 23091-2 code 6.
const BT601: u16 = 6;
/// `colr` box: header, `nclx`, three codes, range flag.
const COLR_SIZE: usize = 8 + 4 + 2 + 2 + 2 + 1;
/// Fixed fields of a visual sample entry (`avc1`) before its child boxes.
const VISUAL_ENTRY: usize = 8 + 78;
/// Fixed fields of `stsd` (version, flags, entry count) before its entries.
const STSD_FIELDS: usize = 8 + 4 + 4;

fn size_at(buf: &[u8], at: usize) -> Option<usize> {
    let b = buf.get(at..at + 4)?;
    Some(u32::from_be_bytes([b[0], b[1], b[2], b[3]]) as usize)
}

/// The child box of type `kind` among the boxes in `buf[start..end]`: (offset, size).
fn child(buf: &[u8], start: usize, end: usize, kind: &[u8; 4]) -> Option<(usize, usize)> {
    let mut at = start;
    while at + 8 <= end {
        let size = size_at(buf, at)?;
        // 64-bit or to-the-end sizes are not written by the muxer for these boxes.
        if size < 8 || at + size > end {
            return None;
        }
        if &buf[at + 4..at + 8] == kind {
            return Some((at, size));
        }
        at += size;
    }
    None
}

/// The error for a file whose boxes are not laid out as the muxer writes them.
fn unexpected(what: &str) -> std::io::Error {
    std::io::Error::other(format!(
        "cannot tag the colour space BT.601 in the container: {what}"
    ))
}

/// Adds the BT.601 `colr` box to the MP4 in `file` (nothing if it has one). An error,
/// leaving the file as it was, if its layout is not the one the muxer writes.
pub fn tag_bt601(mut file: &File) -> std::io::Result<()> {
    let len = file.metadata()?.len() as usize;
    // Find `moov` among the top-level boxes; it must be the last.
    let mut at = 0usize;
    let mut header = [0u8; 8];
    let moov = loop {
        if at + 8 > len {
            return Err(unexpected("no moov box"));
        }
        file.seek(SeekFrom::Start(at as u64))?;
        file.read_exact(&mut header)?;
        let size = size_at(&header, 0).unwrap_or(0);
        if size < 8 {
            return Err(unexpected("a top-level box of an unexpected size"));
        }
        if &header[4..] == b"moov" {
            break (at, size);
        }
        at += size;
    };
    if moov.0 + moov.1 != len {
        return Err(unexpected("the moov box is not last"));
    }
    let mut buf = vec![0u8; moov.1];
    file.seek(SeekFrom::Start(moov.0 as u64))?;
    file.read_exact(&mut buf)?;

    // moov > trak > mdia > minf > stbl > stsd > avc1
    let mut chain = vec![(0usize, buf.len())];
    for kind in [b"trak", b"mdia", b"minf", b"stbl", b"stsd"] {
        let (start, size) = *chain.last().expect("moov");
        let Some(found) = child(&buf, start + 8, start + size, kind) else {
            return Err(unexpected(&format!(
                "no {} box",
                String::from_utf8_lossy(kind)
            )));
        };
        chain.push(found);
    }
    let (stsd, stsd_size) = *chain.last().expect("stsd");
    let Some(avc1) = child(&buf, stsd + STSD_FIELDS, stsd + stsd_size, b"avc1") else {
        return Err(unexpected("no avc1 sample entry"));
    };
    if child(&buf, avc1.0 + VISUAL_ENTRY, avc1.0 + avc1.1, b"colr").is_some() {
        return Ok(());
    }
    chain.push(avc1);

    let mut colr = Vec::with_capacity(COLR_SIZE);
    colr.extend_from_slice(&(COLR_SIZE as u32).to_be_bytes());
    colr.extend_from_slice(b"colrnclx");
    for code in [BT601; 3] {
        colr.extend_from_slice(&code.to_be_bytes());
    }
    colr.push(0); // limited range
    let insert_at = avc1.0 + avc1.1;
    buf.splice(insert_at..insert_at, colr);
    for (start, size) in chain {
        let grown = u32::try_from(size + COLR_SIZE).map_err(std::io::Error::other)?;
        buf[start..start + 4].copy_from_slice(&grown.to_be_bytes());
    }
    file.seek(SeekFrom::Start(moov.0 as u64))?;
    file.write_all(&buf)?;
    file.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unexpected_layout_is_an_error_and_the_file_is_left_as_it_was() {
        let mut tmp = tempfile::tempfile().unwrap();
        // An `ftyp` box and a `moov` box with no track.
        let mut bytes = Vec::new();
        bytes.extend_from_slice(&16u32.to_be_bytes());
        bytes.extend_from_slice(b"ftypisom\0\0\0\0");
        bytes.extend_from_slice(&8u32.to_be_bytes());
        bytes.extend_from_slice(b"moov");
        tmp.write_all(&bytes).unwrap();
        let e = tag_bt601(&tmp).unwrap_err().to_string();
        assert!(e.contains("no trak box"), "{e}");
        let mut back = Vec::new();
        tmp.seek(SeekFrom::Start(0)).unwrap();
        tmp.read_to_end(&mut back).unwrap();
        assert_eq!(back, bytes);
        // Not an MP4 at all.
        let tmp = tempfile::tempfile().unwrap();
        assert!(
            tag_bt601(&tmp)
                .unwrap_err()
                .to_string()
                .contains("no moov box")
        );
    }
}
