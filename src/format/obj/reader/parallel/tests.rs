//! The reader in pieces against the reader in one: the same file, the same warnings and
//! the same first error, wherever the pieces are cut.

use std::collections::HashMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use proptest::prelude::*;

use super::super::{Options, ReadLibrary, read_in_one_piece, read_in_pieces};
use crate::error::Error;
use crate::format::obj::ObjFile;

const LIBRARIES: &[(&str, &str)] = &[
    (
        "lib.mtl",
        "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\nPr 0.5\n",
    ),
    ("more.mtl", "newmtl c\nnewmtl a\nfoo 1\n"),
    ("broken.mtl", "newmtl d\nKd x\n"),
];

/// Reading `text` in pieces of `step` bytes, or in one piece (`None`); with material
/// libraries and smoothing normals (`full`), or the geometry alone.
fn outcome(text: &[u8], step: Option<usize>, full: bool) -> Result<ObjFile, String> {
    let files: HashMap<PathBuf, &str> = LIBRARIES
        .iter()
        .map(|(name, text)| (Path::new("dir").join(name), *text))
        .collect();
    let mut read = |path: &Path| {
        files
            .get(path)
            .map(|text| text.as_bytes().to_vec())
            .ok_or_else(|| Error::file(path, "cannot read: not found"))
    };
    let options = Options {
        read_library: full.then_some(&mut read as ReadLibrary),
        smooth: full,
    };
    let path = Path::new("dir/m.obj");
    let result = match step {
        Some(step) => read_in_pieces(text, path, options, step),
        None => read_in_one_piece(text, path, options),
    };
    result.map_err(|e| e.to_string())
}

/// Asserts that every cut gives what one piece gives, and returns that.
fn same_in_pieces(text: &str, steps: &[usize]) -> Result<ObjFile, String> {
    for full in [false, true] {
        let whole = outcome(text.as_bytes(), None, full);
        for &step in steps {
            let pieces = outcome(text.as_bytes(), Some(step), full);
            assert!(
                pieces == whole,
                "pieces of {step} bytes (full {full}) differ on\n{text}\n\
                 in pieces: {pieces:#?}\nin one: {whole:#?}"
            );
        }
    }
    outcome(text.as_bytes(), None, true)
}

const STEPS: &[usize] = &[1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 1000, 1 << 20];

const GRID: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n";
/// A concave dart (ear clipped) and a pentagram (crossing itself: split as a fan).
const SHAPES: &str = "v 0 0 0\nv 2 0 0\nv 1 1 0\nv 2 2 0\nv 0 2 0\n\
                      v 0 1 0\nv 0.588 -0.809 0\nv -0.951 0.309 0\nv 0.951 0.309 0\n\
                      v -0.588 -0.809 0\n";

/// A concave polygon of more corners than are ear clipped, which is split as a fan with
/// a warning: its vertices, and a face naming them as vertex `first` on.
fn comb(first: usize) -> (String, String) {
    let n = crate::format::obj::MAX_EAR_CLIPPED_CORNERS + 6;
    let mut vertices = String::new();
    let mut face = "f".to_owned();
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let r = if k % 2 == 0 { 2.0 } else { 1.0 };
        writeln!(vertices, "v {:.4} {:.4} 0", r * a.cos(), r * a.sin()).unwrap();
        write!(face, " {}", first + k).unwrap();
    }
    face.push('\n');
    (vertices, face)
}

#[test]
fn files_read_the_same_in_pieces() {
    // After the grid (6 vertices) and before anything else.
    let (comb_vertices, comb_face) = comb(7);
    let cases: Vec<String> = vec![
        String::new(),
        "\n\n# nothing\n".into(),
        "v 1 2 3".into(),
        "v 1 2 3\\".into(),
        // Every index form, negative indices near and far, groups and switches.
        format!(
            "{GRID}vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 0 -1\n\
             g first\ns 1\nusemtl a\nf 1/1 2/2 3/3\nf 1//1 3//1 4//2\n\
             o thing\nf -6/-3/-2 -5/-2/-1 -4/-1/-1 -3/-1/-1\nusemtl b\ns off\n\
             v 3 0 0\nv 3 1 0\nf -1 -2 -4 -3\ng \nf 2 5 6 3\ng a b  c\n\
             usemtl nowhere\ns 2\nf 1 2 3 4\nf -8 -7 -6\nmtllib lib.mtl\n"
        ),
        // Libraries: found, missing, named twice, with spaces, and usemtl before them.
        format!(
            "usemtl a\nmtllib lib.mtl missing.mtl\n{GRID}f 1 2 3\nmtllib\nmtllib lib.mtl\n\
             usemtl c\nf 1 3 4\nmtllib more.mtl\nusemtl\nf 2 5 6\nusemtl a\nf 1 2 3\n"
        ),
        // A library that fails, after and before other errors.
        format!("{GRID}f 1 2 3\nmtllib broken.mtl\nf 1 2 3\n"),
        format!("{GRID}f 1 2\nv 1 2\nmtllib broken.mtl\n"),
        format!("{GRID}mtllib broken.mtl\nf 1 2 -9\n"),
        // Faces naming what comes later, or never.
        format!("f 1 2 3 4\nf 1/1 2/1 3/1\n{GRID}vt 0 0\n"),
        format!("{GRID}f 1/1/1 2/2/1 3/3/1\nvt 0 0\nvn 0 0 1\nf 1/5 2/1 3/1 4/1\n"),
        format!("f 1/2/3 2/2/3 3/2/3 4/2/3\n{GRID}vt 0 0\nvn 0 0 1\n"),
        format!("f 7 8 9 10\n{SHAPES}f 1 2 3\n"),
        format!("{GRID}f 1 2 7\n"),
        format!("{GRID}f 1 7\nf 1 2 3\n"),
        format!("{GRID}f 1 2 3 7\nf 1 2 3\nf 1 2 8 3\n"),
        format!("{GRID}f 1 2 \\\n 3 \\\r\n  9\n"),
        format!("{GRID}f 1/1 2/1 \\\n 3/4\nvt 0 0\n"),
        // Polygons ear clipped and split as fans, now and at the end of the file.
        format!("{SHAPES}f 1 2 3 4 5\nf 6 7 8 9 10\ns 1\nf 10 9 8 7 6\nf 5 4 3 2 1\n"),
        format!("f 1 2 3 4 5\nf 6 7 8 9 10\n{SHAPES}f 6 7 8 9 10\nf 11 1 2 3\n"),
        format!("{GRID}{comb_vertices}{comb_face}f 1 2 3\n{comb_face}"),
        format!("{GRID}{comb_face}f 1 2 3\n{comb_face}{comb_vertices}vt 0 0\n"),
        // Negative indices reaching before the file, in various places.
        "v 0 0 0\nf -1 -2 -3\n".into(),
        format!("{GRID}f -1 -2 -7\nf 0 1 2\n"),
        format!("{GRID}f 1 2 3\nv 1\nf -1 -2 -9\n"),
        format!("{GRID}vt 0 0\nf 1/-2 2/1 3/1\n"),
        format!("{GRID}vn 0 0 1\nf 1//1 2//-1 3//-2\n"),
        // The first error in the file wins.
        format!("{GRID}f 1 2 3\nv 1 2\nf 1 2 3\nf 0 1 2\nvt\n"),
        format!("{GRID}s x\n{GRID}v 1 2\n"),
        format!("{GRID}f 1/2/3/4 1 2\n{GRID}f a b c\n"),
        format!("{GRID}f 1 2 99999999999\n"),
        format!("{GRID}f 1 2 4294967297\n"),
        format!("{GRID}f 1 2 3 \\\n 4 0\n"),
        format!("{GRID}v 1 2 3 4 5\nv nan 1 2\n"),
        // Colours in some pieces only.
        format!("{GRID}v 0 0 1 1 0 0\n{GRID}v 1 1 1 0.5 0.5 0.5\nf 1 2 13 14\n"),
        // Skipped statements, mixed faces and dropped faces, once per file.
        format!(
            "{GRID}l 1 2\nfoo bar\nvt 0 0\nvn 0 0 1\nf 1/1 2 3\nf 1//1 2 3\np 1\n\
             bar\nf 1 2\nf 1/1 2 3/1\ncurv 0 1 1 2\nfoo\nf\nf 1//1 2//1 3\nl 2 3\n"
        ),
        // Continuations, comments and Windows line ends.
        format!(
            "{}f 1 \\\r\n 2 \\\n 3 # the end \\\nf 1 2 \\ # not continued\n\
             g a \\\n b\r\nf 3 \\\r\n\\\n 4 5\r\n# \\\nf 1 2 3\\",
            GRID.replace('\n', "\r\n")
        ),
    ];
    let mut fans = 0;
    for text in &cases {
        if let Ok(obj) = same_in_pieces(text, STEPS) {
            fans += obj
                .warnings
                .iter()
                .filter(|w| w.message.contains("split as a fan"))
                .count();
        }
    }
    assert!(fans >= 2, "the polygons split as fans are checked too");
}

#[test]
fn the_warning_cap_counts_the_same_in_pieces() {
    // The polygon's first face is met before its vertices: it is split at the end.
    let (comb_vertices, comb_face) = comb(17);
    let mut text = format!("{GRID}{SHAPES}{comb_face}{comb_vertices}");
    for k in 0..1500 {
        if k % 100 == 0 {
            text.push_str(&comb_face);
        }
        match k % 7 {
            1 => text.push_str("usemtl\n"),
            2 => text.push_str("foo\n"),
            _ => text.push_str("f 1 2\n"),
        }
    }
    text.push_str("mtllib missing.mtl\nusemtl nowhere\nf 1 2 3\n");
    let obj = same_in_pieces(&text, &[1, 7, 100, 3000, 1 << 20]).unwrap();
    let last = obj.warnings.last().unwrap();
    assert!(last.message.starts_with("and ") && obj.warnings.len() == 1001);
    // One piece holding more than the cap of dropped faces.
    let text = format!(
        "{GRID}{SHAPES}{comb_vertices}{}{comb_face}foo\n",
        "f 1\n".repeat(2500)
    );
    same_in_pieces(&text, &[1, 4000, 1 << 20]).unwrap();
}

#[test]
fn pieces_of_one_line_each_read_a_large_file_the_same() {
    let mut text = String::new();
    let n = 30;
    for j in 0..=n {
        for i in 0..=n {
            writeln!(text, "v {i} {j} {}", (i * j) % 7).unwrap();
            writeln!(text, "vt {} {}", i as f32 / n as f32, j as f32 / n as f32).unwrap();
        }
    }
    for j in 0..n {
        if j % 5 == 0 {
            writeln!(
                text,
                "g row{j}\ns {}\nusemtl {}",
                j % 3,
                ["a", "b", "c"][j % 3]
            )
            .unwrap();
        }
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let b = a + n + 1;
            if (i + j) % 4 == 0 {
                // Relative to the last vertex read.
                let last = ((n + 1) * (n + 1)) as i64;
                let r = |k: usize| k as i64 - last - 1;
                writeln!(text, "f {} {} {}", r(a), r(a + 1), r(b + 1)).unwrap();
            } else {
                writeln!(
                    text,
                    "f {a}/{a} {}/{} {}/{} {b}/{b}",
                    a + 1,
                    a + 1,
                    b + 1,
                    b + 1
                )
                .unwrap();
            }
        }
    }
    text.insert_str(0, "mtllib lib.mtl more.mtl\n");
    same_in_pieces(&text, &[1, 64, 4096]).unwrap();
}

/// The first face past the triangle limit fails where it did, whatever comes before it
/// in its piece and after it in the file.
#[test]
fn the_triangle_limit_fails_at_the_same_face_in_pieces() {
    super::super::TEST_TRIANGLE_LIMIT.set(Some(40));
    let mut text = GRID.to_owned();
    for k in 0..30 {
        match k % 5 {
            0 => text.push_str("f 1 2 3 4 5\nusemtl a\n"),
            1 => text.push_str("f 1/1 2 3\nf 1\n"),
            2 => text.push_str("f -1 -2 -3 \\\n -4\ng x\n"),
            _ => text.push_str("f 1 2 3\nfoo\n"),
        }
    }
    text.push_str("v 1\nf 1 2 -99\n");
    let result = same_in_pieces(&text, STEPS);
    assert!(result.is_err_and(|e| e.contains("expected at most 40 triangles")));
    // A face ending exactly at the limit is still read.
    let text = format!("{GRID}{}", "f 1 2 3 4\n".repeat(20));
    assert!(same_in_pieces(&text, STEPS).is_ok());
    let text = format!("{text}f 1 2 3\nv 1\n");
    let result = same_in_pieces(&text, STEPS);
    assert!(result.is_err_and(|e| e.starts_with("dir/m.obj:27:1: expected at most 40")));
    super::super::TEST_TRIANGLE_LIMIT.set(None);
}

/// One statement, as tokens: mostly well-formed, with errors now and then.
fn statement() -> impl Strategy<Value = Vec<String>> {
    let coordinate = prop_oneof![
        Just("0".to_owned()),
        Just("1".to_owned()),
        Just("-1.5".to_owned()),
        Just("0.25".to_owned()),
        (-4i32..5).prop_map(|n| n.to_string()),
    ];
    // Past the 8 of each kind the text starts with: defined later, or never.
    let index = prop_oneof![
        6 => (1i64..=12).prop_map(|n| n.to_string()),
        3 => (-8i64..0).prop_map(|n| n.to_string()),
    ];
    let corner =
        (index.clone(), index.clone(), index, 0..4u8).prop_map(|(v, t, n, form)| match form {
            0 => v,
            1 => format!("{v}/{t}"),
            2 => format!("{v}//{n}"),
            _ => format!("{v}/{t}/{n}"),
        });
    let words = |list: &'static [&'static str]| {
        prop::sample::select(list).prop_map(|line| line.split(' ').map(str::to_owned).collect())
    };
    prop_oneof![
        20 => prop::collection::vec(coordinate.clone(), 3..=3),
        2 => prop::collection::vec(coordinate.clone(), 6..=6),
        1 => prop::collection::vec(coordinate.clone(), 4..=4),
        5 => prop::collection::vec(coordinate.clone(), 2..=2)
            .prop_map(|t| [vec!["vt".to_owned()], t].concat()),
        5 => prop::collection::vec(coordinate, 3..=3)
            .prop_map(|t| [vec!["vn".to_owned()], t].concat()),
        30 => prop::collection::vec(corner, 1..7)
            .prop_map(|c| [vec!["f".to_owned()], c].concat()),
        2 => words(&["usemtl a", "usemtl b", "usemtl c", "usemtl none", "usemtl"]),
        1 => words(&["mtllib lib.mtl", "mtllib more.mtl", "mtllib missing.mtl", "mtllib"]),
        2 => words(&["g", "g a", "g a b", "o thing", "o"]),
        2 => words(&["s 1", "s 2", "s off", "s 0"]),
        2 => words(&["l 1 2", "p 1", "foo", "bar 1", "curv 0 1 1 2"]),
        1 => words(&["#", "# a comment", ""]),
        1 => words(&[
            "s x", "vt", "vn 1", "f 1/2/3/4", "mtllib broken.mtl", "f 1 0 2", "f 1 x 2",
            "f -99 1 2", "f 1/-40 2 3", "v 1 2 3 4 5",
        ]),
    ]
    .prop_map(|tokens| {
        // Bare coordinates are vertices.
        if tokens[0].parse::<f64>().is_ok() {
            [vec!["v".to_owned()], tokens].concat()
        } else {
            tokens
        }
    })
}

/// Statements written out after 8 vertices, texture coordinates and normals: each ends
/// in `\n` or `\r\n`, some with a comment, and some continued over lines at one of
/// their spaces.
fn obj_text() -> impl Strategy<Value = String> {
    let line = (statement(), 0..8usize, 0..4u8, prop::bool::weighted(0.1));
    prop::collection::vec(line, 0..60).prop_map(|lines| {
        let mut text = String::new();
        for k in 0..8 {
            let (a, b) = (k % 3, k * k % 5);
            writeln!(text, "v {a} {b} {}\nvt 0.{k} 0.{b}\nvn {a} 1 {k}", k % 2).unwrap();
        }
        for (tokens, cut, end, comment) in lines {
            for (k, token) in tokens.iter().enumerate() {
                if k > 0 {
                    text.push_str(if k == cut { " \\\n " } else { " " });
                }
                text.push_str(token);
            }
            if comment {
                text.push_str(" # note");
            }
            text.push_str(if end == 0 { "\r\n" } else { "\n" });
        }
        text
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        rng_seed: proptest::test_runner::RngSeed::Fixed(2024),
        cases: 400,
        ..ProptestConfig::default()
    })]

    #[test]
    fn arbitrary_files_read_the_same_in_pieces(text in obj_text(), step in 1usize..60) {
        for full in [false, true] {
            let whole = outcome(text.as_bytes(), None, full);
            let pieces = outcome(text.as_bytes(), Some(step), full);
            prop_assert_eq!(&pieces, &whole, "pieces of {} bytes, full {}", step, full);
            let one_line_each = outcome(text.as_bytes(), Some(1), full);
            prop_assert_eq!(&one_line_each, &whole, "pieces of one line, full {}", full);
        }
    }
}

/// The scans of `../shared/models` (absent from a plain clone of the repository).
fn shared_model(path: &str) -> Option<Vec<u8>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/models")
        .join(path);
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            crate::util::skipped(format_args!("{} cannot be read ({e})", path.display()));
            None
        }
    }
}

#[test]
fn the_scans_read_the_same_in_pieces() {
    for model in [
        "stanford-dragon/stanford_dragon.obj",
        "stanford-bunny/stanford-bunny.obj",
    ] {
        let Some(text) = shared_model(model) else {
            continue;
        };
        let whole = outcome(&text, None, true);
        for step in [super::piece_bytes(text.len()), 100_000] {
            assert!(
                outcome(&text, Some(step), true) == whole,
                "{model} in pieces of {step}"
            );
        }
        assert!(whole.is_ok_and(|obj| obj.triangles.len() >= 69_451));
    }
}

/// Through the public entry point: a file above the size read in pieces reads the same
/// on one thread and on two, byte-order mark and all.
#[test]
fn large_files_read_the_same_on_one_thread_and_two() {
    let mut text = "\u{feff}mtllib lib.mtl\n".to_owned();
    let n = 180;
    for j in 0..=n {
        for i in 0..=n {
            writeln!(text, "v {i} {j} {}", (i * 7 + j * 3) % 5).unwrap();
        }
    }
    for j in 0..n {
        writeln!(
            text,
            "g row{}\nusemtl {}\ns {}",
            j / 10,
            ["a", "b"][j % 2],
            j % 3
        )
        .unwrap();
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            writeln!(text, "f {a} {} {} {}", a + 1, a + n + 2, a + n + 1).unwrap();
        }
    }
    assert!(text.len() > super::MIN_BYTES);
    let read = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            crate::format::obj::parse_obj_with(text.as_bytes(), Path::new("dir/m.obj"), &mut |p| {
                let name = p.file_name().unwrap().to_str().unwrap();
                let (_, text) = LIBRARIES.iter().find(|(n, _)| *n == name).unwrap();
                Ok(text.as_bytes().to_vec())
            })
            .unwrap()
        })
    };
    let one = read(1);
    assert_eq!(one.triangles.len(), 2 * n * n);
    assert!(read(2) == one);
}
