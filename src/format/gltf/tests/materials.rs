//! Metallic-roughness, glass and textures on the whitted model.

use super::*;

#[test]
fn texture_transform_places_texels_where_offset_rotation_and_scale_say() {
    // A 4 x 4 image whose texel (col, row) holds (col, row) / 255 in red and green.
    let texels = (0..4u8)
        .flat_map(|row| (0..4u8).map(move |col| [col, row, 0, 255]))
        .collect();
    let image = crate::scene::ImageTexture {
        name: "grid".into(),
        width: 4,
        height: 4,
        texels: crate::scene::Texels::Rgba8 {
            texels,
            srgb: false,
        },
    };
    // The extension's example: the lower left quadrant, turned a quarter clockwise.
    let mut slot = crate::scene::TextureSlot::new(0);
    material::transform(
        &mut slot,
        [0.0, 1.0],
        std::f32::consts::FRAC_PI_2,
        [0.5, 0.5],
    );
    // glTF uv (u, v) is looked up at Prism's (u, 1 - v). The texel centres in glTF
    // terms: the transform sends uv to (v / 2, 1 - u / 2): uv (1/4, 1/4) reads glTF
    // (1/8, 7/8), texel (0, 3); uv (3/4, 1/4) reads (1/8, 5/8), texel (0, 2).
    for ((u, v), (col, row)) in [
        ((0.25, 0.25), (0, 3)),
        ((0.75, 0.25), (0, 2)),
        ((0.25, 0.75), (1, 3)),
    ] {
        let c = image.sample_slot(&slot, [u, 1.0 - v]);
        let got = ((c.x * 255.0).round() as u8, (c.y * 255.0).round() as u8);
        assert_eq!(got, (col, row), "uv ({u}, {v})");
    }
    // Scale and offset alone: uv (1/4, 1/4) * 2 + (1/4, 0) = (3/4, 1/2): between rows
    // 1 and 2 at column 2 + 1/2 -> a blend, so test a centre: uv (1/8, 1/8) -> (1/2, 1/4).
    let mut slot = crate::scene::TextureSlot::new(0);
    material::transform(&mut slot, [0.25, 0.0], 0.0, [2.0, 2.0]);
    assert!(slot.matrix.is_none());
    let c = image.sample_slot(&slot, [0.0625, 1.0 - 0.0625]);
    assert_eq!(((c.x * 255.0).round(), (c.y * 255.0).round()), (1.0, 0.0));
}

#[test]
fn materials_map_onto_openpbr_as_documented() {
    let mut b = Builder::default();
    b.mesh(&wall(1.0, 0.0), None, 4, Some(0));
    let doc = b.finish(json!({
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1.0], "metallicFactor": 0.25,
              "roughnessFactor": 0.5}, "emissiveFactor": [1.0, 0.5, 0.0],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 1.0, 1.0, 1.0]},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.33},
                "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": 2.0,
                    "attenuationColor": [0.5, 0.25, 1.0]}}},
            {"alphaMode": "MASK", "alphaCutoff": 0.3,
             "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.2]}}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }));
    let (_dir, path) = write(&doc);
    let file = crate::format::load(&path).unwrap();
    let s = &file.scene.surfaces;
    assert_eq!(s.len(), 3, "the three materials, the default unused");
    let p = s[0].openpbr.as_ref().expect("an OpenPBR material");
    assert_eq!(
        (p.base_metalness.value, p.specular_roughness.value),
        (0.25, 0.5)
    );
    assert_eq!((p.specular_ior.value, p.specular_weight.value), (1.5, 1.0));
    assert_eq!(
        s[0].albedo,
        crate::scene::Albedo::Color(Vec3::new(0.8, 0.6, 0.4))
    );
    assert_eq!(s[0].emission, Vec3::new(4.0, 2.0, 0.0));
    // The emitter is an area light.
    assert_eq!(file.scene.lights.len(), 1);
    assert_eq!(file.scene.lights[0].kind_name(), "mesh");
    // Glass: transmission, its index, a volume whose colour is left after
    // attenuationDistance (and Beer's absorption from it).
    let glass = &s[1];
    let g = glass.openpbr.as_ref().unwrap();
    assert_eq!(g.transmission_weight.value, 1.0);
    assert_eq!((g.specular_ior.value, glass.ior), (1.33, 1.33));
    assert!(!g.geometry_thin_walled);
    assert_eq!(g.transmission_color.value, Vec3::new(0.5, 0.25, 1.0));
    assert_eq!(g.transmission_depth.value, 2.0);
    let beer = Vec3::new(0.5f32.ln(), 0.25f32.ln(), 0.0) / -2.0;
    assert!(
        (glass.absorption - beer).abs().max_element() < 1e-7,
        "{:?}",
        glass.absorption
    );
    // The classic reading keeps the base colour (in display values), not white.
    let classic = &file.scene.materials[0];
    let srgb = crate::scene::material::linear_to_srgb(Vec3::new(0.8, 0.6, 0.4));
    assert!(
        (classic.color - srgb).abs().max_element() < 1e-6,
        "{:?}",
        classic.color
    );
    assert_eq!(file.scene.materials[1].refract, 1.0);
    // A constant alpha below the cutoff cuts the whole surface out.
    let slot = s[2].alpha_map.expect("a cut-out");
    assert_eq!(file.scene.images[slot.image as usize].texel(0, 0).w, 0.0);
}

#[test]
fn a_mirror_metal_reflects_its_colour_and_an_unlit_file_gets_default_lights() {
    // A smooth metal wall facing the camera, under no light, with a unlit white
    // square behind the camera: the camera sees the square in the metal at the metal's
    // colour times Schlick's F at normal incidence (F0 = the colour).
    let mut b = Builder::default();
    b.mesh(&wall(10.0, -2.0), None, 4, Some(0));
    let mut back = wall(10.0, 2.0);
    // Facing -z, toward the metal.
    back.swap(3, 6);
    back.swap(4, 7);
    back.swap(5, 8);
    b.mesh(&back, None, 4, Some(1));
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_materials_unlit"],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.5, 0.2, 1.0], "metallicFactor": 1.0,
                "roughnessFactor": 0.0}},
            {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0]},
             "extensions": {"KHR_materials_unlit": {}}}],
        "cameras": [{"type": "orthographic", "orthographic": {"xmag": 0.01, "ymag": 0.01, "znear": 0.1, "zfar": 9.0}}],
        "nodes": [{"mesh": 0}, {"mesh": 1}, {"camera": 0}],
        "scenes": [{"nodes": [0, 1, 2]}],
    }));
    let (_dir, path) = write(&doc);
    let s = job::prepare(&path, &sized(1, 1)).unwrap();
    // The emitter-free, light-free file got the key and fill.
    assert_eq!(s.scene.lights.len(), 2);
    let mut scene = s.scene.clone();
    scene.lights.clear();
    let image = Renderer::new(&scene, &s.camera, s.settings.clone())
        .unwrap()
        .render(&())
        .unwrap()
        .0;
    let got = Vec3::from_array(image.pixels[0]);
    assert!(
        (got - Vec3::new(0.9, 0.5, 0.2)).abs().max_element() < 1e-6,
        "{got}"
    );
}

#[test]
fn light_through_a_volume_slab_is_absorbed_by_beer() {
    // A slab 2 thick (faces at z = 0 and z = -2) of index 1, so nothing bends or
    // reflects, before a white unlit wall: the camera sees the wall through it,
    // times attenuationColor^(2 / attenuationDistance).
    let mut b = Builder::default();
    b.mesh(&wall(2.0, 0.0), None, 4, Some(0));
    b.mesh(&back_wall(2.0, -2.0), None, 4, Some(0));
    b.mesh(&wall(5.0, -5.0), None, 4, Some(1));
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
            "KHR_materials_unlit"],
        "materials": [
            {"pbrMetallicRoughness": {"metallicFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.0},
                "KHR_materials_volume": {"thicknessFactor": 2.0, "attenuationDistance": 1.0,
                    "attenuationColor": [0.5, 0.25, 1.0]}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0]},
             "extensions": {"KHR_materials_unlit": {}}}],
        "cameras": [{"type": "orthographic", "orthographic": {"xmag": 0.01, "ymag": 0.01, "znear": 0.1, "zfar": 50.0}}],
        "nodes": [{"mesh": 0}, {"mesh": 1}, {"mesh": 2}, {"camera": 0, "translation": [0.0, 0.0, 3.0]}],
        "scenes": [{"nodes": [0, 1, 2, 3]}],
    }));
    let (_dir, path) = write(&doc);
    let got = Vec3::from_array(render(&path, &sized(1, 1)).pixels[0]);
    let expected = Vec3::new(0.25, 0.0625, 1.0);
    assert!(
        (got - expected).abs().max_element() < 1e-5,
        "{got} vs {expected}"
    );
}

#[test]
fn the_khr_material_extensions_map_onto_openpbr() {
    let mut b = Builder::default();
    b.mesh(&wall(1.0, 0.0), None, 4, Some(0));
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_sheen",
            "KHR_materials_iridescence", "KHR_materials_anisotropy", "KHR_materials_dispersion",
            "KHR_materials_diffuse_transmission", "KHR_materials_transmission",
            "KHR_materials_specular"],
        "materials": [
            {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": {
                "KHR_materials_clearcoat": {"clearcoatFactor": 0.7, "clearcoatRoughnessFactor": 0.2},
                "KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.25, 1.0], "sheenRoughnessFactor": 0.6},
                "KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 1.8,
                    "iridescenceThicknessMaximum": 500.0},
                "KHR_materials_anisotropy": {"anisotropyStrength": 0.5,
                    "anisotropyRotation": std::f32::consts::FRAC_PI_2},
                "KHR_materials_dispersion": {"dispersion": 0.5},
                "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.25},
                "KHR_materials_specular": {"specularFactor": 0.5,
                    "specularColorFactor": [1.0, 0.5, 0.5]}}},
            {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.0001}}}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }));
    let (dir, path) = write(&doc);
    let file = crate::format::load(&path).unwrap();
    assert!(
        file.warnings.iter().all(|w| !w.contains("ignores")),
        "{:?}",
        file.warnings
    );
    let p = file.scene.surfaces[0].openpbr.as_ref().unwrap();
    assert_eq!(
        (
            p.coat_weight.value,
            p.coat_roughness.value,
            p.coat_ior.value
        ),
        (0.7, 0.2, 1.5)
    );
    assert_eq!(p.fuzz_weight.value, 1.0);
    assert_eq!(p.fuzz_color.value, Vec3::new(0.5, 0.25, 1.0));
    assert_eq!(p.fuzz_roughness.value, 0.6);
    assert_eq!(
        (p.thin_film_weight.value, p.thin_film_ior.value),
        (1.0, 1.8)
    );
    assert_eq!(p.thin_film_thickness.value, 0.5);
    assert_eq!(p.specular_roughness_anisotropy.value, 0.5);
    assert!((p.tangent_rotation - 0.25).abs() < 1e-7);
    assert_eq!(p.transmission_dispersion_abbe_number.value, 40.0);
    assert_eq!(p.subsurface_weight.value, 0.25);
    assert_eq!(p.specular_weight.value, 0.5);
    assert_eq!(p.specular_color.value, Vec3::new(1.0, 0.5, 0.5));
    // A trace of transmission is a trace of thin glass, not a darker surface.
    let t = file.scene.surfaces[1].openpbr.as_ref().unwrap();
    assert_eq!(t.transmission_weight.value, 0.0001);
    assert!(!t.geometry_thin_walled, "a solid, as Blender reads it");
    // A value out of range names the material and the property.
    let (_bad_dir, bad) = {
        let mut doc = doc.clone();
        doc["materials"] =
            json!([{"extensions": {"KHR_materials_sheen": {"sheenRoughnessFactor": 2.0}}}]);
        write(&doc)
    };
    let e = crate::format::load(&bad).unwrap_err().to_string();
    assert!(
        e.contains("materials[0]") && e.contains("sheenRoughnessFactor"),
        "{e}"
    );
    drop(dir);
}

/// The path model's radiance of a glTF floor with a trace of transmission is that of
/// the same floor without it (it was 0.35 times as bright when transmission turned
/// the base's Lambert term into the whitted reading's).
#[test]
fn a_trace_of_transmission_leaves_a_floor_as_bright() {
    let floor = |extensions: serde_json::Value| {
        let mut b = Builder::default();
        b.mesh(&floor(1.0), None, 4, Some(0));
        let doc = b.finish(json!({
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10.0}]}},
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                "metallicFactor": 0.0, "roughnessFactor": 1.0}, "extensions": extensions}],
            "cameras": [{"type": "orthographic", "orthographic": {"xmag": 0.01, "ymag": 0.01, "znear": 0.1, "zfar": 9.0}}],
            "nodes": [{"mesh": 0}, {"translation": [0.0, 2.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                {"camera": 0, "translation": [0.0, 3.0, 0.0], "rotation": [-0.70710677, 0.0, 0.0, 0.70710677]}],
            "scenes": [{"nodes": [0, 1, 2]}],
        }));
        let (_dir, path) = write(&doc);
        let mut o = sized(1, 1);
        o.render.integrator = Some(crate::options::IntegratorKind::Path);
        o.render.spp = Some(64);
        Vec3::from_array(render(&path, &o).pixels[0])
    };
    let opaque = floor(json!({}));
    let trace = floor(json!({"KHR_materials_transmission": {"transmissionFactor": 0.0001}}));
    assert!(opaque.x > 0.1, "{opaque}");
    assert!(
        ((trace - opaque) / opaque).abs().max_element() < 0.01,
        "{trace} {opaque}"
    );
}

/// A scene file that places a glTF mesh rebases every image its materials read,
/// OpenPBR textures included (a coat's map read the scene file's own image before).
#[test]
fn a_placed_gltf_meshs_openpbr_textures_follow_its_images() {
    let mut b = Builder::default();
    b.mesh(&wall(1.0, 0.0), None, 4, Some(0));
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_materials_clearcoat"],
        "images": [{"uri": "g.png"}],
        "textures": [{"source": 0}],
        "materials": [{"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
            "clearcoatTexture": {"index": 0}}}}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }));
    let (dir, _) = write(&doc);
    image::RgbImage::from_pixel(1, 1, image::Rgb([0, 255, 0]))
        .save(dir.path().join("g.png"))
        .unwrap();
    image::RgbImage::from_pixel(1, 1, image::Rgb([255, 0, 0]))
        .save(dir.path().join("r.png"))
        .unwrap();
    let toml = dir.path().join("outer.toml");
    std::fs::write(
        &toml,
        "[[material]]\nname = \"red\"\ntexture = \"r.png\"\n\
         [[object]]\ntype = \"sphere\"\ncenter = [5, 0, 0]\nradius = 1\nmaterial = \"red\"\n\
         [[object]]\ntype = \"mesh\"\nfile = \"scene.gltf\"\n",
    )
    .unwrap();
    let f = crate::format::load(&toml).unwrap();
    let coat = f
        .scene
        .surfaces
        .iter()
        .find_map(|s| s.openpbr.as_ref())
        .unwrap();
    let (slot, _) = coat.coat_weight.texture.unwrap();
    let texel = f.scene.images[slot.image as usize].sample_slot(&slot, [0.5, 0.5]);
    assert_eq!(
        (texel.x, texel.y),
        (0.0, 1.0),
        "the coat reads the green image"
    );
}
