use super::*;

fn write(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.mtlx");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

const GOLD: &str = r#"<?xml version="1.0"?>
<materialx version="1.39" colorspace="acescg">
  <surfacematerial name="Gold" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="gold_shader" />
  </surfacematerial>
  <open_pbr_surface name="gold_shader" type="surfaceshader">
    <input name="base_color" type="color3" value="0.929, 0.788, 0.374" />
    <input name="base_metalness" type="float" value="1.0" />
    <input name="specular_roughness" type="float" value="0.02" />
    <input name="geometry_thin_walled" type="boolean" value="true" />
  </open_pbr_surface>
</materialx>
"#;

#[test]
fn an_open_pbr_surface_is_read_with_its_colours_out_of_acescg() {
    let (_dir, path) = write(GOLD);
    let m = load(&path, None).unwrap();
    assert_eq!(m.material.name, "Gold");
    let p = m.surface.openpbr.as_ref().unwrap();
    assert_eq!(
        (p.base_metalness.value, p.specular_roughness.value),
        (1.0, 0.02)
    );
    assert!(p.geometry_thin_walled);
    assert_eq!(p.coat_ior, OpenPbr::default().coat_ior);
    let Albedo::Color(c) = m.surface.albedo else {
        panic!()
    };
    // ACEScg (0.929, 0.788, 0.374) in linear Rec. 709.
    let want = from_acescg(Vec3::new(0.929, 0.788, 0.374));
    assert_eq!(c, want);
    assert!(
        (want.x - 1.06288).abs() < 1e-4 && (want.z - 0.30728).abs() < 1e-4,
        "{want}"
    );
    // White stays white: the matrix's rows sum to one.
    assert!((from_acescg(Vec3::ONE) - Vec3::ONE).abs().max_element() < 1e-5);
}

#[test]
fn a_materialx_document_is_told_from_a_2014_material_file_by_its_first_character() {
    assert!(is_materialx(GOLD.as_bytes()));
    assert!(is_materialx(b"\xef\xbb\xbf  \n<materialx/>"));
    assert!(!is_materialx(b"newmtl red 255 0 0 1 1 0 1 1 0 0 0\n"));
    assert!(!is_materialx(b"# a comment\n"));
}

#[test]
fn an_image_input_reads_its_file_and_mistakes_name_the_line() {
    let (dir, path) = write(
        r#"<materialx version="1.39">
  <image name="albedo" type="color3">
    <input name="file" type="filename" value="a.png" colorspace="srgb_texture" />
  </image>
  <open_pbr_surface name="s" type="surfaceshader">
    <input name="base_color" type="color3" nodename="albedo" />
    <input name="coat_weight" type="float" value="0.5" />
  </open_pbr_surface>
</materialx>"#,
    );
    image::RgbImage::from_pixel(1, 1, image::Rgb([255, 128, 0]))
        .save(dir.path().join("a.png"))
        .unwrap();
    let m = load(&path, None).unwrap();
    assert_eq!(m.images.len(), 1);
    assert!(matches!(m.surface.albedo, Albedo::Image { .. }));
    assert_eq!(m.surface.openpbr.as_ref().unwrap().coat_weight.value, 0.5);
    let (_d, bad) = write(
        "<materialx>\n<open_pbr_surface name=\"s\">\n<input name=\"coat_weight\" type=\"float\" value=\"lots\"/>\n</open_pbr_surface>\n</materialx>",
    );
    let e = load(&bad, None).unwrap_err().to_string();
    assert!(
        e.contains("m.mtlx:3:1") && e.contains("coat_weight: expected a number"),
        "{e}"
    );
    let (_d, none) = write("<materialx></materialx>");
    assert!(
        load(&none, None)
            .unwrap_err()
            .to_string()
            .contains("no <open_pbr_surface>")
    );
    let (_d, gold) = write(GOLD);
    assert!(
        load(&gold, Some("Silver"))
            .unwrap_err()
            .to_string()
            .contains("no material \"Silver\"")
    );
}

/// Every example material of the specification loads, without a warning.
#[test]
fn every_example_of_the_specification_loads() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/reference/openpbr-spec/examples");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!(
            "skipped: {} is absent (it sits beside the repository in CI)",
            dir.display()
        );
        return;
    };
    let mut n = 0;
    for entry in entries {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "mtlx") {
            let m = load(&path, None).unwrap_or_else(|e| panic!("{e}"));
            assert!(m.warnings.is_empty(), "{:?}", m.warnings);
            assert!(m.surface.openpbr.is_some());
            n += 1;
        }
    }
    assert!(n >= 83, "{n} examples");
}
