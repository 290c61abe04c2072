//! `prism render --display`: the image streamed to tev as it forms. A stand-in tev
//! server on 127.0.0.1 reads tev's packets and reassembles the image, which must equal
//! the EXR the same command writes, value for value.

mod common;
use common::*;
use std::io::Read;
use std::net::TcpListener;

/// What the stand-in viewer saw: the image's name and size, its pixels, the number of
/// update packets.
struct Seen {
    name: String,
    width: usize,
    height: usize,
    pixels: Vec<f32>,
    updates: usize,
}

fn cstr(b: &[u8], at: &mut usize) -> String {
    let end = *at
        + b[*at..]
            .iter()
            .position(|&c| c == 0)
            .expect("a NUL-terminated string");
    let s = String::from_utf8(b[*at..end].to_vec()).unwrap();
    *at = end + 1;
    s
}

fn i32_at(b: &[u8], at: &mut usize) -> i32 {
    let v = i32::from_le_bytes(b[*at..*at + 4].try_into().unwrap());
    *at += 4;
    v
}

fn i64_at(b: &[u8], at: &mut usize) -> i64 {
    let v = i64::from_le_bytes(b[*at..*at + 8].try_into().unwrap());
    *at += 8;
    v
}

/// Serves one connection as tev would, until the client closes it.
fn stand_in_tev(listener: TcpListener) -> Seen {
    let (mut conn, _) = listener.accept().unwrap();
    let mut bytes = Vec::new();
    conn.read_to_end(&mut bytes).unwrap();
    let mut seen = Seen {
        name: String::new(),
        width: 0,
        height: 0,
        pixels: Vec::new(),
        updates: 0,
    };
    let mut at = 0;
    while at < bytes.len() {
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let p = &bytes[at..at + len];
        let mut i = 5;
        match p[4] {
            4 => {
                i += 1; // grab focus
                seen.name = cstr(p, &mut i);
                seen.width = i32_at(p, &mut i) as usize;
                seen.height = i32_at(p, &mut i) as usize;
                let n = i32_at(p, &mut i);
                let names: Vec<String> = (0..n).map(|_| cstr(p, &mut i)).collect();
                assert_eq!(names, ["R", "G", "B"]);
                seen.pixels = vec![f32::NAN; seen.width * seen.height * 3];
            }
            6 => {
                i += 1;
                assert_eq!(cstr(p, &mut i), seen.name);
                let n = i32_at(p, &mut i) as usize;
                let names: Vec<String> = (0..n).map(|_| cstr(p, &mut i)).collect();
                let (x, y, w, h) = (
                    i32_at(p, &mut i) as usize,
                    i32_at(p, &mut i) as usize,
                    i32_at(p, &mut i) as usize,
                    i32_at(p, &mut i) as usize,
                );
                let offsets: Vec<i64> = (0..n).map(|_| i64_at(p, &mut i)).collect();
                let strides: Vec<i64> = (0..n).map(|_| i64_at(p, &mut i)).collect();
                let data: Vec<f32> = p[i..]
                    .chunks(4)
                    .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                    .collect();
                assert_eq!(data.len(), w * h * n);
                for (c, name) in names.iter().enumerate() {
                    let channel = ["R", "G", "B"].iter().position(|k| k == name).unwrap();
                    for k in 0..w * h {
                        let v = data[offsets[c] as usize + k * strides[c] as usize];
                        let (px, py) = (x + k % w, y + k / w);
                        seen.pixels[(py * seen.width + px) * 3 + channel] = v;
                    }
                }
                seen.updates += 1;
            }
            other => panic!("unexpected packet type {other}"),
        }
        at += len;
    }
    seen
}

#[test]
fn the_streamed_image_is_the_exr_the_render_writes() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let viewer = std::thread::spawn(move || stand_in_tev(listener));
    let dir = tempfile::tempdir().unwrap();
    let exr = dir.path().join("shown.exr");
    let o = run(prism()
        .arg("render")
        .args([example("example.objx"), example("example.cmr"), exr.clone()])
        .args(["--width", "96", "--aa", "2", "--exr-precision", "float"])
        .args(["--display", &address, "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let seen = viewer.join().unwrap();
    let written = prism::film::read_linear_image(&exr).unwrap();
    assert_eq!(seen.name, "shown.exr");
    assert_eq!((seen.width, seen.height), (96, 54));
    let flat: Vec<f32> = written.pixels.iter().flatten().copied().collect();
    assert_eq!(seen.pixels.len(), flat.len());
    let same = seen
        .pixels
        .iter()
        .zip(&flat)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(same, "the streamed pixels differ from the EXR's");
    // Streamed as the bands finished, not once at the end.
    assert!(seen.updates >= 2, "{} updates", seen.updates);
}

#[test]
fn an_unreachable_viewer_is_an_error_before_anything_is_written() {
    // A port just freed: nothing listens there.
    let address = {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().to_string()
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let o = run(prism()
        .arg("render")
        .args([example("example.objx"), example("example.cmr"), out.clone()])
        .args(["--width", "32", "--display", &address]));
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("cannot connect to tev at") && e.contains(&address),
        "{e}"
    );
    assert!(!out.exists());
}
