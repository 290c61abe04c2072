use super::*;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// One typed value of a PLY body, to write the same rows in every encoding.
#[derive(Clone, Copy, Debug)]
enum V {
    I8(i8),
    U8(u8),
    I16(i16),
    U16(u16),
    I32(i32),
    U32(u32),
    F32(f32),
    F64(f64),
}

const ENCODINGS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

/// A whole file: `ply`, the format line, `header` (element and property lines), then
/// each row of `rows` (lists written flat: length then items).
fn file(encoding: &str, header: &str, rows: &[Vec<V>]) -> Vec<u8> {
    let mut out = format!("ply\nformat {encoding} 1.0\n{header}end_header\n").into_bytes();
    for row in rows {
        if encoding == "ascii" {
            let words: Vec<String> = row
                .iter()
                .map(|v| match *v {
                    V::I8(x) => x.to_string(),
                    V::U8(x) => x.to_string(),
                    V::I16(x) => x.to_string(),
                    V::U16(x) => x.to_string(),
                    V::I32(x) => x.to_string(),
                    V::U32(x) => x.to_string(),
                    V::F32(x) => x.to_string(),
                    V::F64(x) => x.to_string(),
                })
                .collect();
            out.extend(words.join(" ").bytes());
            out.push(b'\n');
            continue;
        }
        let big = encoding == "binary_big_endian";
        for v in row {
            macro_rules! put {
                ($x:expr) => {
                    if big {
                        out.extend($x.to_be_bytes())
                    } else {
                        out.extend($x.to_le_bytes())
                    }
                };
            }
            match *v {
                V::I8(x) => put!(x),
                V::U8(x) => put!(x),
                V::I16(x) => put!(x),
                V::U16(x) => put!(x),
                V::I32(x) => put!(x),
                V::U32(x) => put!(x),
                V::F32(x) => put!(x),
                V::F64(x) => put!(x),
            }
        }
    }
    out
}

fn parse_bytes(bytes: &[u8]) -> Result<PlyMesh> {
    parse(bytes, Path::new("m.ply"))
}

fn error_of(bytes: &[u8]) -> String {
    parse_bytes(bytes).unwrap_err().to_string()
}

fn v3(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

const QUAD_HEADER: &str = "comment a unit quad\nobj_info made by hand\n\
    element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
    property float nx\nproperty float ny\nproperty float nz\n\
    property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
    property float u\nproperty float v\n\
    element edge 2\nproperty int vertex1\nproperty list uchar short path\n\
    element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n\
    property list int double weights\n";

fn quad_rows() -> Vec<Vec<V>> {
    use V::*;
    let vertex = |x, y, rgb: [u8; 3], u, v| {
        vec![
            F32(x),
            F32(y),
            F32(0.0),
            F32(0.0),
            F32(0.0),
            F32(1.0),
            U8(rgb[0]),
            U8(rgb[1]),
            U8(rgb[2]),
            U8(7),
            F32(u),
            F32(v),
        ]
    };
    vec![
        vertex(0.0, 0.0, [255, 0, 0], 0.0, 0.0),
        vertex(1.5, 0.0, [0, 51, 255], 1.0, 0.0),
        vertex(1.5, -2.25, [0, 0, 0], 1.0, 1.0),
        vertex(0.0, -2.25, [102, 102, 102], 0.0, 0.25),
        vec![I32(0), U8(2), I16(1), I16(-2)],
        vec![I32(1), U8(0)],
        vec![
            U8(9),
            U8(4),
            I32(0),
            I32(1),
            I32(2),
            I32(3),
            I32(1),
            F64(0.5),
        ],
        vec![U8(0), U8(2), I32(3), I32(1), I32(0)],
    ]
}

#[test]
fn a_quad_with_every_attribute_reads_the_same_in_every_encoding() {
    for encoding in ENCODINGS {
        let mesh = parse_bytes(&file(encoding, QUAD_HEADER, &quad_rows())).unwrap();
        let expected = PlyMesh {
            positions: vec![
                v3(0.0, 0.0, 0.0),
                v3(1.5, 0.0, 0.0),
                v3(1.5, -2.25, 0.0),
                v3(0.0, -2.25, 0.0),
            ],
            normals: vec![v3(0.0, 0.0, 1.0); 4],
            colors: vec![
                v3(1.0, 0.0, 0.0),
                v3(0.0, 0.2, 1.0),
                v3(0.0, 0.0, 0.0),
                v3(0.4, 0.4, 0.4),
            ],
            texcoords: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.25]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            warnings: vec![
                "element `edge` (2 rows) is not read".to_owned(),
                "dropped 1 face(s) of fewer than 3 vertices".to_owned(),
            ],
        };
        assert_eq!(mesh, expected, "{encoding}");
    }
}

#[test]
fn a_pentagon_fans_from_its_first_vertex() {
    let text = "ply\r\nformat ascii 1.0\r\nelement vertex 5\r\n\
                property double x\r\nproperty double y\r\nproperty double z\r\n\
                element face 1\r\nproperty list uint8 uint32 vertex_index\r\nend_header\r\n\
                0 0 0\r\n2 0 0\r\n3 1 0\r\n1 2 0\r\n-1 1 0\r\n5 0 1 2 3 4\r\n";
    let mesh = parse_bytes(text.as_bytes()).unwrap();
    assert_eq!(mesh.triangles, [[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    assert_eq!(mesh.positions[4], v3(-1.0, 1.0, 0.0));
    assert!(mesh.normals.is_empty() && mesh.colors.is_empty() && mesh.texcoords.is_empty());
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
}

#[test]
fn every_type_name_reads_and_integer_colours_scale_by_their_maximum() {
    let header = "element vertex 1\nproperty int8 x\nproperty uint16 y\nproperty float64 z\n\
                  property short red\nproperty ushort green\nproperty float blue\n\
                  property char s\nproperty uint t\nproperty int32 extra\n";
    use V::*;
    let row = vec![
        I8(-128),
        U16(65535),
        F64(0.125),
        I16(32767),
        U16(0),
        F32(2.5),
        I8(-3),
        U32(4_000_000_000),
        I32(-1),
    ];
    for encoding in ENCODINGS {
        let mesh = parse_bytes(&file(encoding, header, std::slice::from_ref(&row))).unwrap();
        assert_eq!(mesh.positions, [v3(-128.0, 65535.0, 0.125)], "{encoding}");
        assert_eq!(mesh.colors, [v3(1.0, 0.0, 2.5)], "{encoding}");
        assert_eq!(mesh.texcoords, [[-3.0, 4e9]], "{encoding}");
    }
}

#[test]
fn partial_attribute_sets_are_ignored_with_a_warning() {
    let header = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
                  property float nx\nproperty float ny\nproperty float texture_u\n\
                  property float texture_v\n";
    let row = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0].map(V::F32).to_vec();
    let mesh = parse_bytes(&file("ascii", header, &[row])).unwrap();
    assert!(mesh.normals.is_empty());
    assert_eq!(mesh.texcoords, [[5.0, 6.0]]);
    assert_eq!(
        mesh.warnings,
        ["vertex properties nx ny nz are ignored: `nz` is missing"]
    );
}

#[test]
fn trailing_data_and_empty_files_are_not_errors() {
    let mesh = parse_bytes(b"ply\nformat binary_little_endian 1.0\nend_header\nxyz").unwrap();
    assert_eq!(
        mesh.warnings,
        ["3 bytes after the last element are ignored, from byte 47"]
    );
    let mesh = parse_bytes(b"ply\nformat ascii 1.0\nelement edge 0\nend_header\n\n 7").unwrap();
    assert_eq!(
        mesh.warnings,
        ["text after the last element is ignored, from 6:2"]
    );
    assert_eq!(
        parse_bytes(b"ply\nformat ascii 1.0\nend_header\n").unwrap(),
        PlyMesh::default()
    );
}

#[test]
fn header_errors_name_line_and_column() {
    let long_comment = format!("ply\ncomment {}\n", "x".repeat(MAX_HEADER));
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (
            b"plx\n".to_vec(),
            "m.ply:1:1: expected `ply` on the first line, found `plx`",
        ),
        (
            b"ply".to_vec(),
            "m.ply:1:1: expected a header ending with `end_header`, found no line end",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 0\n".to_vec(),
            "m.ply:4:1: expected a header ending with `end_header`, found the end of the file",
        ),
        (
            b"ply\nformat  binary_middle_endian 1.0\n".to_vec(),
            "m.ply:2:9: expected ascii, binary_little_endian or binary_big_endian, found \
             `binary_middle_endian`",
        ),
        (
            b"ply\nformat ascii 2.0\n".to_vec(),
            "m.ply:2:14: expected version 1.0, found `2.0`",
        ),
        (
            b"ply\nformat ascii 1.0\nformat ascii 1.0\n".to_vec(),
            "m.ply:3:1: expected one `format` line, found a second",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex -1\n".to_vec(),
            "m.ply:3:16: expected a whole number for the row count, found `-1`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 4294967296\n".to_vec(),
            "m.ply:3:16: expected a whole number of at most 268435456 (the most shapes a \
             scene may hold) for the row count, found `4294967296`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement face 268435457\n".to_vec(),
            "m.ply:3:14: expected a whole number of at most 268435456 (the most shapes a \
             scene may hold) for the row count, found `268435457`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex\n".to_vec(),
            "m.ply:3:1: expected `element NAME COUNT`, found 1 words after `element`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement a 0\nelement a 0\n".to_vec(),
            "m.ply:4:9: expected each element once, found `a` again",
        ),
        (
            b"ply\nformat ascii 1.0\nproperty float x\n".to_vec(),
            "m.ply:3:1: expected an `element` line before the first `property`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement v 0\nproperty flaot x\n".to_vec(),
            "m.ply:4:10: expected a type (char, uchar, short, ushort, int, uint, float, \
             double, or int8 ... float64), found `flaot`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement v 0\nproperty list float int i\n".to_vec(),
            "m.ply:4:15: expected an integer type for a list's length, found `float`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement v 0\nproperty list uchar int\n".to_vec(),
            "m.ply:4:1: expected `property list LENGTH_TYPE ITEM_TYPE NAME`, found 3 words \
             after `property`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement v 0\nproperty float x\nproperty int x\n".to_vec(),
            "m.ply:5:14: expected each property of element `v` once, found `x` again",
        ),
        (
            b"ply\nformat ascii 1.0\nelemnt v 0\n".to_vec(),
            "m.ply:3:1: expected format, element, property, comment, obj_info or end_header, \
             found `elemnt`",
        ),
        (
            b"ply\nformat ascii 1.0\nend_header now\n".to_vec(),
            "m.ply:3:12: expected nothing after `end_header`, found `now`",
        ),
        (
            b"ply\nend_header\n".to_vec(),
            "m.ply:2:1: expected a `format` line before `end_header`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement \xe9 0\n".to_vec(),
            "m.ply:3:9: expected UTF-8 text in the header, found an invalid byte",
        ),
        (
            long_comment.into_bytes(),
            "m.ply:2:1: expected `end_header` within the first 65536 bytes, found a longer header",
        ),
        (
            b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n\
              property float y\nproperty float z\nend_header\n01234567890123456789012"
                .to_vec(),
            "m.ply:3:16: expected a row count that fits in the file: 2 rows of element \
             `vertex` take at least 24 bytes, found 23 bytes after the header for all elements",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              end_header\n1 2\n"
                .to_vec(),
            "m.ply:3:1: expected properties x, y and z in element `vertex`, found no `z`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
              property list uchar float z\nend_header\n"
                .to_vec(),
            "m.ply:6:1: expected a scalar type for vertex property `z`, found a list",
        ),
        (
            b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int indices\n\
              end_header\n"
                .to_vec(),
            "m.ply:3:1: expected a list property vertex_indices (or vertex_index) in element \
             `face`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement face 0\nproperty int vertex_indices\nend_header\n"
                .to_vec(),
            "m.ply:4:1: expected a list for `vertex_indices`, found a scalar",
        ),
        (
            b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar float vertex_indices\n\
              end_header\n"
                .to_vec(),
            "m.ply:4:1: expected an integer type for the items of `vertex_indices`, found float",
        ),
    ];
    for (bytes, expected) in cases {
        assert_eq!(
            error_of(&bytes),
            expected,
            "{:?}",
            String::from_utf8_lossy(&bytes)
        );
    }
}

const MAX_HEADER: usize = header::MAX_HEADER_BYTES;

const TRIANGLE_HEADER: &str = "element vertex 3\nproperty float x\nproperty float y\n\
    property float z\nelement face 1\nproperty list char int vertex_indices\n";

fn triangle_rows(z: f32, list: Vec<V>) -> Vec<Vec<V>> {
    use V::F32;
    vec![
        vec![F32(0.0), F32(0.0), F32(0.0)],
        vec![F32(1.0), F32(0.0), F32(z)],
        vec![F32(0.0), F32(1.0), F32(0.0)],
        list,
    ]
}

#[test]
fn ascii_body_errors_name_line_and_column() {
    let head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
                property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let cases = [
        (
            "0 0 0 1 2 3\n 0  abc 0 1 2 3\n3 0 1 1\n",
            "m.ply:14:5: expected a float for property `y` of `vertex` 1, found `abc`",
        ),
        (
            "0 0 0 1 2 3\n0 0 0 1 256 3\n3 0 1 1\n",
            "m.ply:14:9: expected a uchar (0 to 255) for property `green` of `vertex` 1, \
             found `256`",
        ),
        (
            "0 0 0 1 2 3\n0 0 inf 1 2 3\n3 0 1 1\n",
            "m.ply:14:5: expected a finite number (in f32) for property `z` of `vertex` 1, \
             found inf",
        ),
        (
            "0 0 0 1 2 3\n0 0 1e39 1 2 3\n3 0 1 1\n",
            "m.ply:14:5: expected a finite number (in f32) for property `z` of `vertex` 1, \
             found inf",
        ),
        (
            "0 0 0 1 2 3\n0 0 0 1 2 3\n3 0 1 2\n",
            "m.ply:15:7: expected a vertex index from 0 to 1 for property `vertex_indices` of \
             `face` 0, found 2",
        ),
        (
            "0 0 0 1 2 3\n0 0 0 1 2 3\n3 0 -1 1\n",
            "m.ply:15:5: expected a vertex index from 0 to 1 for property `vertex_indices` of \
             `face` 0, found -1",
        ),
        (
            "0 0 0 1 2 3\n0 0 0 1 2 3\n3 0 1\n",
            "m.ply:16:1: expected a int for property `vertex_indices` of `face` 0, found the \
             end of the file",
        ),
        (
            "0 0 0 1 2 3\n0 0 0 1 2 3\n9 0 1\n",
            "m.ply:15:1: expected a list length that fits in the file for property \
             `vertex_indices` of `face` 0: 9 items need at least 18 bytes, found 5 left",
        ),
    ];
    for (body, expected) in cases {
        let bytes = format!("{head}{body}").into_bytes();
        assert_eq!(error_of(&bytes), expected, "{body:?}");
    }
}

#[test]
fn binary_body_errors_name_the_byte_offset() {
    use V::*;
    // The header is 168 bytes (3 fewer big-endian); each vertex row 12, so the face row
    // starts at byte 204.
    let header_len = file("binary_little_endian", TRIANGLE_HEADER, &[]).len();
    assert_eq!(header_len, 168);
    let cases = [
        (
            triangle_rows(f32::NAN, vec![I8(3), I32(0), I32(1), I32(2)]),
            "m.ply: byte 188: expected a finite number (in f32) for property `z` of `vertex` 1, \
             found NaN",
        ),
        (
            triangle_rows(0.0, vec![I8(3), I32(0), I32(3), I32(2)]),
            "m.ply: byte 209: expected a vertex index from 0 to 2 for property \
             `vertex_indices` of `face` 0, found 3",
        ),
        (
            triangle_rows(0.0, vec![I8(-1), I32(0), I32(1), I32(2)]),
            "m.ply: byte 204: expected a list length >= 0 for property `vertex_indices` of \
             `face` 0, found -1",
        ),
        (
            triangle_rows(0.0, vec![I8(4), I32(0), I32(1), I32(2)]),
            "m.ply: byte 204: expected a list length that fits in the file for property \
             `vertex_indices` of `face` 0: 4 items need at least 16 bytes, found 12 left",
        ),
    ];
    for (rows, expected) in cases {
        for (encoding, big) in [("binary_little_endian", false), ("binary_big_endian", true)] {
            let bytes = file(encoding, TRIANGLE_HEADER, &rows);
            let expected = if big {
                expected
                    .replace("188", "185")
                    .replace("209", "206")
                    .replace("204", "201")
            } else {
                expected.to_owned()
            };
            assert_eq!(error_of(&bytes), expected);
        }
    }
}

#[test]
fn truncated_binary_data_is_an_error_at_the_end() {
    use V::*;
    let header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 1\nproperty list uchar int vertex_indices\n";
    let rows = triangle_rows(0.0, vec![U8(3), I32(0), I32(1), I32(2)]);
    let whole = file("binary_little_endian", header, &rows);
    assert_eq!(parse_bytes(&whole).unwrap().triangles, [[0, 1, 2]]);
    for cut in 1..=13 {
        let short = &whole[..whole.len() - cut];
        let e = error_of(short);
        let row_check = e.contains("expected a row count that fits in the file");
        let list_check = e.contains("expected a list length that fits in the file");
        let take_check = e.contains("before the end of the file");
        assert!(row_check || list_check || take_check, "cut {cut}: {e}");
    }
    // Cut inside the last index: the length fits the minimum, not the items.
    let e = error_of(&whole[..whole.len() - 2]);
    assert_eq!(
        e,
        "m.ply: byte 205: expected a list length that fits in the file for property \
         `vertex_indices` of `face` 0: 3 items need at least 12 bytes, found 10 left"
    );
}

#[test]
fn a_skipped_binary_list_that_runs_past_the_end_is_an_error() {
    use V::*;
    let header = "element material 1\nproperty list uint short names\n";
    let bytes = file("binary_big_endian", header, &[vec![U32(3), I16(1), I16(2)]]);
    assert_eq!(
        error_of(&bytes),
        "m.ply: byte 94: expected a list length that fits in the file for property `names` \
         of `material` 0: 3 items need at least 6 bytes, found 4 left"
    );
}

#[test]
fn only_regular_files_are_loaded() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path()).unwrap_err().to_string();
    assert!(e.ends_with(": cannot read: not a regular file"), "{e}");
    let e = load(&dir.path().join("missing.ply"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.ply: cannot read: "), "{e}");
    let path = dir.path().join("quad.ply");
    std::fs::write(
        &path,
        file("binary_little_endian", QUAD_HEADER, &quad_rows()),
    )
    .unwrap();
    assert_eq!(load(&path).unwrap().triangles.len(), 2);
}

/// Position, normal, colour, texture coordinates.
type RandomVertex = ([f32; 3], [f32; 3], [u8; 3], [f32; 2]);

/// A random mesh: finite positions, normals, uchar colours, texture coordinates, and
/// polygons of 3 to 6 vertices.
#[derive(Debug, Clone)]
struct RandomMesh {
    vertices: Vec<RandomVertex>,
    polygons: Vec<Vec<u32>>,
}

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<f32>().prop_filter("finite", |x| x.is_finite()),
        -1000.0f32..1000.0,
    ]
}

fn random_mesh() -> impl Strategy<Value = RandomMesh> {
    let vertex = (
        [finite(), finite(), finite()],
        [finite(), finite(), finite()],
        any::<[u8; 3]>(),
        [finite(), finite()],
    );
    prop::collection::vec(vertex, 1..20).prop_flat_map(|vertices| {
        let n = vertices.len() as u32;
        let polygon = prop::collection::vec(0..n, 3..7);
        (Just(vertices), prop::collection::vec(polygon, 0..10))
            .prop_map(|(vertices, polygons)| RandomMesh { vertices, polygons })
    })
}

fn seeded(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x504c59),
        failure_persistence: None,
        ..Config::default()
    }
}

/// A header line from the PLY vocabulary with random arguments.
fn header_line() -> impl Strategy<Value = String> {
    let word = prop_oneof![
        "element|property|list|format|comment|end_header|vertex|face|x|y|z|red|u|vertex_indices",
        "char|uchar|short|ushort|int|uint|float|double|int8|uint32|float64",
        "ascii|binary_little_endian|binary_big_endian|1\\.0",
        "[0-9]{1,10}|-1|4294967296",
        "\\PC{0,4}",
    ];
    prop::collection::vec(word, 0..6).prop_map(|w| w.join(" "))
}

proptest! {
    #![proptest_config(seeded(256))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = parse_bytes(&bytes);
        let mut with_magic = b"ply\n".to_vec();
        with_magic.extend(&bytes);
        let _ = parse_bytes(&with_magic);
    }

    /// Random headers over random bodies: any mesh that parses names only its vertices,
    /// which are finite.
    #[test]
    fn random_headers_never_panic(
        encoding in 0..3usize,
        lines in prop::collection::vec(header_line(), 0..12),
        body in prop::collection::vec(any::<u8>(), 0..200),
    ) {
        let mut bytes = format!("ply\nformat {} 1.0\n{}\nend_header\n", ENCODINGS[encoding], lines.join("\n")).into_bytes();
        bytes.extend(&body);
        if let Ok(mesh) = parse_bytes(&bytes) {
            let n = mesh.positions.len();
            prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
            prop_assert!(mesh.positions.iter().all(|p| p.is_finite()));
        }
    }

    #[test]
    fn a_random_mesh_reads_back_identical_in_every_encoding(mesh in random_mesh()) {
        let header = format!(
            "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
             property double nx\nproperty double ny\nproperty double nz\n\
             property uint8 red\nproperty uint8 green\nproperty uint8 blue\n\
             property float s\nproperty float t\n\
             element face {}\nproperty list uchar uint vertex_indices\n",
            mesh.vertices.len(), mesh.polygons.len()
        );
        let mut rows: Vec<Vec<V>> = Vec::new();
        for (p, n, c, uv) in &mesh.vertices {
            let mut row: Vec<V> = p.iter().map(|&x| V::F32(x)).collect();
            row.extend(n.iter().map(|&x| V::F64(f64::from(x))));
            row.extend(c.iter().map(|&x| V::U8(x)));
            row.extend(uv.iter().map(|&x| V::F32(x)));
            rows.push(row);
        }
        for polygon in &mesh.polygons {
            let mut row = vec![V::U8(polygon.len() as u8)];
            row.extend(polygon.iter().map(|&i| V::U32(i)));
            rows.push(row);
        }
        let expected = PlyMesh {
            positions: mesh.vertices.iter().map(|v| Vec3::from_array(v.0)).collect(),
            normals: mesh.vertices.iter().map(|v| Vec3::from_array(v.1)).collect(),
            colors: mesh.vertices.iter().map(|v| Vec3::from_array(v.2.map(|c| (f64::from(c) / 255.0) as f32))).collect(),
            texcoords: mesh.vertices.iter().map(|v| v.3).collect(),
            triangles: mesh.polygons.iter().flat_map(|p| (1..p.len() - 1).map(move |k| [p[0], p[k], p[k + 1]])).collect(),
            warnings: Vec::new(),
        };
        for encoding in ENCODINGS {
            let read = parse_bytes(&file(encoding, &header, &rows)).unwrap();
            prop_assert_eq!(&read, &expected, "{}", encoding);
        }
    }
}
