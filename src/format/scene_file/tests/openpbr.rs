//! `[[material]] type = "openpbr"`: the specification's names and defaults, textures
//! with their channel, and every kind of mistake with its place.

use super::*;
use crate::scene::openpbr::Channel;

const OBJECT: &str =
    "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n";

fn material(body: &str) -> String {
    format!("[[material]]\nname = \"m\"\ntype = \"openpbr\"\n{body}\n{OBJECT}")
}

#[test]
fn openpbr_materials_take_the_specifications_names_and_defaults() {
    let f = scene(&material(
        "base_color = [0.9, 0.6, 0.2]\nbase_metalness = 1\nspecular_roughness = 0.25\n\
         coat_weight = 0.5\ncoat_ior = 1.4\nfuzz_color = \"#ff0000\"\ngeometry_thin_walled = true\n\
         emission_luminance = 2\nemission_color = [1, 0.5, 0]\ntransmission_weight = 0.5\n\
         transmission_color = [0.5, 0.5, 1.0]\ntransmission_depth = 2",
    ));
    let s = &f.scene.surfaces[0];
    let p = s.openpbr.as_ref().unwrap();
    assert_eq!(s.albedo, crate::scene::Albedo::Color(v(0.9, 0.6, 0.2)));
    assert_eq!(p.base_metalness.value, 1.0);
    assert_eq!(p.specular_roughness.value, 0.25);
    assert_eq!((p.coat_weight.value, p.coat_ior.value), (0.5, 1.4));
    assert_eq!(p.fuzz_color.value, v(1.0, 0.0, 0.0));
    assert!(p.geometry_thin_walled);
    assert_eq!(s.emission, v(2.0, 1.0, 0.0));
    // Beer: the colour is what remains after the depth.
    assert_close(s.absorption, v(0.5f32.ln(), 0.5f32.ln(), 0.0) / -2.0);
    // Everything not given is the specification's default.
    let d = crate::scene::OpenPbr::default();
    assert_eq!(p.specular_ior, d.specular_ior);
    assert_eq!(p.coat_darkening, d.coat_darkening);
    assert_eq!(p.fuzz_roughness, d.fuzz_roughness);
    let plain = scene(&material(""));
    assert_eq!(plain.scene.surfaces[0].openpbr.as_deref(), Some(&d));
    assert_eq!(
        plain.scene.surfaces[0].albedo,
        crate::scene::Albedo::Color(crate::scene::openpbr::DEFAULT_BASE_COLOR)
    );
}

#[test]
fn a_parameter_reads_a_textures_channel_times_its_factor() {
    let dir = Folder::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([10, 20, 30, 40]))
        .save(dir.path("rough.png"))
        .unwrap();
    let f = dir.load(&material(
        "specular_roughness = { texture = \"rough.png\", channel = \"g\", factor = 0.5 }\n\
         base_color = { texture = \"rough.png\" }",
    ));
    let s = &f.scene.surfaces[0];
    let p = s.openpbr.as_ref().unwrap();
    let (slot, channel) = p.specular_roughness.texture.unwrap();
    assert_eq!((p.specular_roughness.value, channel), (0.5, Channel::G));
    // Scalars read data (linear), colours sRGB: two decodings of one file.
    let crate::scene::Albedo::Image { slot: colour, .. } = s.albedo else {
        panic!("{:?}", s.albedo)
    };
    assert_ne!(slot.image, colour.image);
    let texel = f.scene.images[slot.image as usize].sample_slot(&slot, [0.5, 0.5]);
    assert!((texel.y - 20.0 / 255.0).abs() < 1e-6, "{texel}");
}

#[test]
fn openpbr_mistakes_name_the_key_and_the_place() {
    let dir = Folder::new();
    let e = dir.error(&material("specular_roughness = 1.5"));
    assert!(
        e.contains("scene.toml:4") && e.contains("specular_roughness from 0 to 1, found 1.5"),
        "{e}"
    );
    let e = dir.error(&material("coat_ior = 0"));
    assert!(e.contains("coat_ior > 0"), "{e}");
    let e = dir.error(&material("shininess = 20"));
    assert!(e.contains("`shininess` is not an OpenPBR parameter"), "{e}");
    let e = dir.error(&material("base_weight = \"heavy\""));
    assert!(e.contains("base_weight as a number"), "{e}");
    let e = dir.error(&material(
        "base_weight = { texture = \"w.png\", chanel = \"r\" }",
    ));
    assert!(e.contains("unknown key `chanel`"), "{e}");
    let e = dir.error(&format!(
        "[[material]]\nname = \"m\"\nspecular_roughness = 0.2\n{OBJECT}"
    ));
    assert!(e.contains("give the material type = \"openpbr\""), "{e}");
    let e = dir.error(&format!(
        "[[material]]\nname = \"m\"\ntype = \"pbr\"\n{OBJECT}"
    ));
    assert!(e.contains("expected material type \"openpbr\""), "{e}");
}

/// Python's `scene_from_dict` takes the same material as data.
#[test]
fn a_scene_given_as_data_takes_openpbr_materials() {
    let value = serde_json::json!({
        "material": [{"name": "m", "type": "openpbr", "base_color": [0.2, 0.4, 0.6],
            "specular_roughness": 0.1, "coat_weight": 1.0}],
        "object": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
    });
    let dir = Folder::new();
    let f = crate::format::scene_file::from_value::from_value(
        &value,
        dir.dir.path(),
        &std::collections::HashMap::new(),
        std::collections::HashMap::new(),
    )
    .unwrap();
    let p = f.scene.surfaces[0].openpbr.as_ref().unwrap();
    assert_eq!(
        (p.specular_roughness.value, p.coat_weight.value),
        (0.1, 1.0)
    );
    assert_eq!(
        f.scene.surfaces[0].albedo,
        crate::scene::Albedo::Color(v(0.2, 0.4, 0.6))
    );
}

#[test]
fn a_material_may_be_a_materialx_documents() {
    let dir = Folder::new();
    dir.write(
        "paint.mtlx",
        r#"<materialx version="1.39" colorspace="lin_rec709">
  <surfacematerial name="Blue" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="blue" />
  </surfacematerial>
  <open_pbr_surface name="blue" type="surfaceshader">
    <input name="base_color" type="color3" value="0.1, 0.2, 0.8" />
    <input name="coat_weight" type="float" value="1" />
  </open_pbr_surface>
</materialx>"#,
    );
    let f = dir.load(&format!(
        "[[material]]\nname = \"m\"\nfile = \"paint.mtlx\"\n{OBJECT}"
    ));
    let s = &f.scene.surfaces[0];
    assert_eq!(s.albedo, crate::scene::Albedo::Color(v(0.1, 0.2, 0.8)));
    assert_eq!(s.openpbr.as_ref().unwrap().coat_weight.value, 1.0);
    assert_eq!(f.scene.materials[0].name, "m");
    let e = dir.error(&format!(
        "[[material]]\nname = \"m\"\nfile = \"paint.mtlx\"\ncoat_weight = 0.5\n{OBJECT}"
    ));
    assert!(
        e.contains("scene.toml:4") && e.contains("not with `file`"),
        "{e}"
    );
    dir.write("old.mtlx", "newmtl red 255 0 0 1 1 0 1 1 0 0 0\n");
    let e = dir.error(&format!(
        "[[material]]\nname = \"m\"\nfile = \"old.mtlx\"\n{OBJECT}"
    ));
    assert!(e.contains("expected a MaterialX document"), "{e}");
}
