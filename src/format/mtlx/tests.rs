use super::*;
use proptest::prelude::*;

/// Parses `text` as `/nonexistent-prism/m.mtlx` into a fresh library; no texture
/// path can resolve there, so only texture-free lines succeed.
fn parse_str(text: &str) -> Result<MaterialLibrary> {
    let mut library = MaterialLibrary::new();
    parse(text, Path::new("/nonexistent-prism/m.mtlx"), &mut library)?;
    Ok(library)
}

fn err(text: &str) -> String {
    parse_str(text).unwrap_err().to_string()
}

#[test]
fn reads_every_field_of_a_seed_line() {
    let text = "#newmtl mtl name, color, ambient coef, diffuse reflectivity, ... \n\
                #       shininess, refractiveIndex, reflection weight, refraction weight, \n\
                #       texture file, texture scale ratio\n\
                newmtl ball 221 125 22  10 1 15 8.5 1.33 0.5 0 0\n\
                \n\
                newmtl glass 34 103 16 0.0001 0.1 0.01 4.9 1.3 0.2 1 1\r\n";
    let library = parse_str(text).unwrap();
    assert_eq!(
        library.materials()[0],
        Material {
            name: "ball".into(),
            color: Vec3::new(221.0, 125.0, 22.0) / 255.0,
            ambient: 10.0,
            diffuse: 1.0,
            specular: 15.0,
            shininess: 8.5,
            ior: 1.33,
            reflect: 0.5,
            refract: 0.0,
            transparent: false,
            texture: None,
        }
    );
    let glass = &library.materials()[1];
    assert_eq!(
        (glass.refract, glass.transparent, glass.ior),
        (1.0, true, 1.3)
    );
    assert_eq!(library.find("glass"), Some(1));
    assert_eq!(library.find("nope"), None);
}

#[test]
fn ior_zero_is_read_as_one_on_a_material_that_does_not_refract() {
    let library = parse_str("newmtl lightsource 255 255 255 0 0 0 0 0 0 0 0\n").unwrap();
    assert_eq!(library.materials()[0].ior, 1.0);
    assert_eq!(library.materials()[0].color, Vec3::ONE);
    assert_eq!(
        err("newmtl g 0 0 0 1 1 1 1 0 0 1 1\n"),
        "/nonexistent-prism/m.mtlx:1: expected the refractive index > 0, found `0`"
    );
}

#[test]
fn scale_field_gives_the_fill_mode() {
    let at = At {
        path: Path::new("m.mtlx"),
        line: 1,
    };
    let fill = |token| fill_mode(at, token);
    assert_eq!(fill(None).unwrap(), FillMode::Tile { scale: 1.0 });
    assert_eq!(fill(Some("0")).unwrap(), FillMode::Stretch);
    assert_eq!(fill(Some("0.25")).unwrap(), FillMode::Tile { scale: 0.25 });
    assert_eq!(fill(Some("stretch")).unwrap(), FillMode::Stretch);
    assert_eq!(fill(Some("fit")).unwrap(), FillMode::Fit);
    assert_eq!(fill(Some("crop")).unwrap(), FillMode::Crop);
    assert_eq!(fill(Some("tile")).unwrap(), FillMode::Tile { scale: 1.0 });
    assert_eq!(
        fill(Some("-1")).unwrap_err().to_string(),
        "m.mtlx:1: expected the texture scale (a number >= 0, or stretch, fit, crop or \
         tile) >= 0, found `-1`"
    );
    assert!(fill(Some("Fit")).is_err());
    assert!(fill(Some("1e-50")).is_err());
    assert!(fill(Some("nan")).is_err());
}

#[test]
fn errors_name_the_line_and_what_was_expected() {
    let cases: &[(&str, &str)] = &[
        (
            "newmtl a 256 0 0 1 1 1 1 1 0 0 0",
            "expected the red component from 0 to 255, found `256`",
        ),
        (
            "newmtl a 0 -1 0 1 1 1 1 1 0 0 0",
            "the green component from 0 to 255",
        ),
        (
            "newmtl a 0 0 x 1 1 1 1 1 0 0 0",
            "expected a number for the blue component, found `x`",
        ),
        (
            "newmtl a 0 0 0 -1 1 1 1 1 0 0 0",
            "expected the ambient coefficient ka >= 0, found `-1`",
        ),
        (
            "newmtl a 0 0 0 1 -1 1 1 1 0 0 0",
            "the diffuse coefficient kd >= 0",
        ),
        (
            "newmtl a 0 0 0 1 1 -1 1 1 0 0 0",
            "the specular coefficient ks >= 0",
        ),
        ("newmtl a 0 0 0 1 1 1 -1 1 0 0 0", "the shininess >= 0"),
        (
            "newmtl a 0 0 0 1 1 1 1 -1 0 0 0",
            "the refractive index >= 0",
        ),
        (
            "newmtl a 0 0 0 1 1 1 1 1 -1 0 0",
            "the reflection weight >= 0",
        ),
        (
            "newmtl a 0 0 0 1 1 1 1 1 0 -1 0",
            "the refraction weight >= 0",
        ),
        (
            "newmtl a 0 0 0 1 1 1 1 1 0 0 2",
            "expected 0 or 1 for the transparent flag, found `2`",
        ),
        ("newmtl a 0 0 0 1 1 1 1 1 0 0 1.0", "found `1.0`"),
        (
            "newmtl a 0 0 0 1 1 1 1 1 0 0",
            "12 to 14 values after newmtl, found 11",
        ),
        ("newmtl a 0 0 0 1 1 1 1 1 0 0 0 t.png 1 extra", "found 15"),
        ("newmtl", "found 0"),
        ("Ka 1 1 1", "unknown keyword `Ka`: expected newmtl"),
        (
            "newmtl a 0 0 0 1 1 1 1 1 0 0 0 t.png 1",
            "cannot load texture /nonexistent-prism/t.png: ",
        ),
    ];
    for &(line, words) in cases {
        // A good line first, so the bad one is not the first material read.
        let e = err(&format!(
            "# header\nnewmtl ok 0 0 0 1 1 1 1 1 0 0 0\n\n{line}\n"
        ));
        let expected_start = "/nonexistent-prism/m.mtlx:4: ";
        assert!(
            e.starts_with(expected_start) && e.contains(words),
            "{line:?} gave {e}"
        );
    }
}

#[test]
fn duplicate_names_are_an_error() {
    assert_eq!(
        err("newmtl a 0 0 0 1 1 1 1 1 0 0 0\nnewmtl a 0 0 0 1 1 1 1 1 0 0 0 tex.png\n"),
        "/nonexistent-prism/m.mtlx:2: material `a` is already defined at \
         /nonexistent-prism/m.mtlx:1"
    );
}

/// Writes `n` PNG images of different sizes and contents into `dir`: `t0.png`..
fn write_images(dir: &Path, n: u32) {
    for i in 0..n {
        let (w, h) = (3 + 5 * i, 2 + 3 * i);
        let image = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb([
                (x * 37 + i) as u8,
                (y * 91 + 7 * i) as u8,
                (x ^ y ^ i) as u8,
            ])
        });
        image.save(dir.join(format!("t{i}.png"))).unwrap();
    }
}

/// Parses `text` as `m.mtlx` in `dir` on a pool of `threads` threads.
fn parse_on(threads: usize, dir: &Path, text: &str) -> Result<MaterialLibrary> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let mut library = MaterialLibrary::new();
            parse(text, &dir.join("m.mtlx"), &mut library)?;
            Ok(library)
        })
}

#[test]
fn images_decoded_together_give_each_line_its_own_texels() {
    let dir = tempfile::tempdir().unwrap();
    write_images(dir.path(), 6);
    // Six images, one of them twice with another fill mode, one line without.
    let mut text = String::new();
    for i in 0..6 {
        text += &format!("newmtl m{i} 0 0 0 1 1 1 1 1 0 0 0 t{i}.png 0.5\n");
    }
    text += "newmtl plain 9 9 9 1 1 1 1 1 0 0 0\n";
    text += "newmtl again 0 0 0 1 1 1 1 1 0 0 0 t2.png fit\n";
    text += "newmtl same 0 0 0 1 1 1 1 1 0 0 0 t4.png 0.5\n";
    let one = parse_on(1, dir.path(), &text).unwrap();
    for threads in [2, 4] {
        let many = parse_on(threads, dir.path(), &text).unwrap();
        assert_eq!(many.materials(), one.materials(), "{threads} threads");
        assert_eq!(many.textures(), one.textures(), "{threads} threads");
    }
    // What each line names, decoded alone.
    let textures = one.textures();
    assert_eq!(textures.len(), 7);
    for i in 0..6u32 {
        let m = &one.materials()[i as usize];
        let t = &textures[m.texture.unwrap() as usize];
        let image = image::open(dir.path().join(format!("t{i}.png")))
            .unwrap()
            .into_rgb8();
        assert_eq!((t.width, t.height), image.dimensions());
        let texels: Vec<[u8; 3]> = image.pixels().map(|p| p.0).collect();
        assert_eq!(t.texels, texels, "t{i}.png");
        assert_eq!(t.fill, FillMode::Tile { scale: 0.5 });
    }
    let again = &textures[one.materials()[7].texture.unwrap() as usize];
    assert_eq!(again.fill, FillMode::Fit);
    assert_eq!(again.texels, textures[2].texels);
    assert_eq!(one.materials()[8].texture, one.materials()[4].texture);
    assert_eq!(one.materials()[6].texture, None);
}

#[test]
fn the_first_bad_line_is_the_error_whenever_its_image_is_decoded() {
    let dir = tempfile::tempdir().unwrap();
    write_images(dir.path(), 3);
    std::fs::write(
        dir.path().join("bad.png"),
        b"\x89PNG\r\n\x1a\n not an image",
    )
    .unwrap();
    let good = |i: u32| format!("newmtl g{i} 0 0 0 1 1 1 1 1 0 0 0 t{i}.png\n");
    let bad_image = "newmtl b 0 0 0 1 1 1 1 1 0 0 0 bad.png\n";
    let bad_line = "newmtl x 0 0 0 1 1 1 1 1 0 0 7\n";
    for threads in [1, 2] {
        // The image that does not decode comes first: it is the error, not the line
        // read after it.
        let text = good(0) + bad_image + &good(1) + bad_line + &good(2);
        let e = parse_on(threads, dir.path(), &text)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("m.mtlx:2: cannot load texture") && e.contains("bad.png"),
            "{e}"
        );
        // The bad line comes first: the image after it is never the error.
        let text = good(0) + bad_line + bad_image + &good(1);
        let e = parse_on(threads, dir.path(), &text)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("m.mtlx:2: expected 0 or 1"), "{e}");
        // An image that does not decode on the last line.
        let text = good(0) + &good(1) + bad_image;
        let e = parse_on(threads, dir.path(), &text)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("m.mtlx:3: cannot load texture"), "{e}");
    }
}

#[test]
fn a_second_file_numbers_its_textures_after_the_first() {
    let dir = tempfile::tempdir().unwrap();
    write_images(dir.path(), 3);
    let mut library = MaterialLibrary::new();
    let first = "newmtl a 0 0 0 1 1 1 1 1 0 0 0 t0.png\nnewmtl b 0 0 0 1 1 1 1 1 0 0 0 t1.png\n";
    parse(first, &dir.path().join("a.mtlx"), &mut library).unwrap();
    let second =
        "newmtl c 0 0 0 1 1 1 1 1 0 0 0 t2.png\nnewmtl d 0 0 0 1 1 1 1 1 0 0 0 t0.png fit\n";
    parse(second, &dir.path().join("b.mtlx"), &mut library).unwrap();
    let texture = |name: &str| {
        let m = &library.materials()[library.find(name).unwrap() as usize];
        &library.textures()[m.texture.unwrap() as usize]
    };
    assert_eq!(library.textures().len(), 4);
    assert_eq!(texture("c").width, 13);
    assert_eq!(texture("d").texels, texture("a").texels);
    assert_eq!(texture("d").fill, FillMode::Fit);
}

/// A material line with random fields, mostly well formed.
fn material_line() -> impl Strategy<Value = String> {
    let field = prop_oneof![
        4 => "[0-9]{1,3}(\\.[0-9]{0,2})?",
        1 => "-[0-9]|nan|inf|1e39|1e-50|0|1|fit|crop|stretch|tile|x.png|\\.|/|\\.\\.",
        1 => "\\PC{0,4}",
    ];
    let head = prop_oneof![4 => Just("newmtl".to_string()), 1 => "\\PC{0,6}"];
    (head, "[a-c]", prop::collection::vec(field, 0..16))
        .prop_map(|(h, name, fields)| format!("{h} {name} {}", fields.join(" ")))
}

proptest! {
    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
        let _ = parse_str(&text);
    }

    #[test]
    fn arbitrary_material_lines_never_panic(lines in prop::collection::vec(material_line(), 0..12)) {
        let _ = parse_str(&lines.join("\n"));
    }
}
