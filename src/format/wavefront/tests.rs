use super::*;
use crate::scene::{Background, LightKind};

/// Writes `files` (name, contents) into a fresh folder and loads `scene.obj` from it.
fn load_files(files: &[(&str, &[u8])]) -> (tempfile::TempDir, SceneFile) {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let file = load(&dir.path().join("scene.obj")).unwrap();
    (dir, file)
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                    vn 0 0 1\n";

#[test]
fn illum_models_map_to_the_whitted_terms() {
    let mtl = "newmtl matte\nKd 0.5 0.25 1\nillum 1\n\
               newmtl plastic\nKd 0.1 0.2 0.3\nKs 0.4 0.4 0.4\nNs 50\n\
               newmtl mirror\nKd 0 0 0\nKs 0.9 0.8 0.7\nillum 3\n\
               newmtl glass\nKd 0 0 0\nKs 0 0 0\nNi 1.5\nTf 1 0.9 0.8\nillum 7\n\
               newmtl flat\nKd 1 1 1\nillum 0\n\
               newmtl lamp\nKd 0 0 0\nKe 10 9 8\n\
               newmtl veil\nKd 1 1 1\nd 0.25\n";
    let mut obj = String::from("mtllib s.mtl\n");
    obj += QUAD;
    for name in [
        "matte", "plastic", "mirror", "glass", "flat", "lamp", "veil",
    ] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let (_dir, file) = load_files(&[("scene.obj", obj.as_bytes()), ("s.mtl", mtl.as_bytes())]);
    let s = &file.scene;
    assert_eq!(
        s.materials.len(),
        7,
        "no default material: every face has one"
    );
    let surface = |i: usize| &s.surfaces[i];
    assert_eq!(surface(0).albedo, Albedo::Color(Vec3::new(0.5, 0.25, 1.0)));
    assert_eq!(surface(0).specular, Vec3::ZERO);
    assert_eq!(surface(1).specular, Vec3::splat(0.4));
    assert_eq!(surface(1).shininess, 50.0);
    assert_eq!(surface(1).reflection, Vec3::ZERO);
    assert_eq!(surface(2).reflection, Vec3::new(0.9, 0.8, 0.7));
    assert!(!surface(2).fresnel);
    let glass = surface(3);
    assert!(glass.fresnel);
    assert_eq!(glass.ior, 1.5);
    assert_eq!(glass.transmission, Vec3::new(1.0, 0.9, 0.8));
    assert_eq!(
        glass.reflection,
        Vec3::ONE,
        "Ks 0 with Fresnel reflects white"
    );
    assert!(!surface(4).lit);
    assert_eq!(surface(5).emission, Vec3::new(10.0, 9.0, 8.0));
    assert_eq!(surface(6).transmission, Vec3::splat(0.75));
    assert_eq!(surface(6).diffuse, 0.25);
    // The emissive face is an area light of area 1/2.
    assert_eq!(s.lights.len(), 1);
    let LightKind::Mesh { shapes, area, .. } = &s.lights[0].kind else {
        panic!("{:?}", s.lights[0]);
    };
    assert_eq!(
        (shapes.as_slice(), *area),
        (&[crate::scene::ShapeId::world(5)][..], 0.5)
    );
    assert_eq!(s.background, Background::Black);
}

#[test]
fn normals_texture_coordinates_and_colours_reach_the_mesh() {
    let obj = format!("{QUAD}v 2 0 0 1 0 0\nf 1/1/1 2/2/1 3/3/1\nf 1 3 4\n");
    let (_dir, file) = load_files(&[("scene.obj", obj.as_bytes())]);
    let s = &file.scene;
    assert_eq!(s.shapes.len(), 2);
    assert_eq!(s.meshes.len(), 1);
    let (mesh, i) = s.mesh_of(0).unwrap();
    assert_eq!(i, 0);
    assert_eq!(mesh.texcoord(0, [0.0, 1.0, 0.0]), Some([1.0, 0.0]));
    assert_eq!(mesh.normal(0, [0.2, 0.3, 0.5]), Some(Vec3::Z));
    // The face without normals keeps its own flat normal; its corners are white.
    assert_eq!(mesh.normal(1, [0.2, 0.3, 0.5]), Some(Vec3::Z));
    assert_eq!(mesh.color(1, [1.0, 0.0, 0.0]), Some(Vec3::ONE));
    assert_eq!((file.counts.vertices, file.counts.texcoords), (5, 4));
    // A face with no material wears the default.
    assert_eq!(s.materials.len(), 1);
}

#[test]
fn texture_maps_load_with_their_options_and_missing_ones_warn() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::from_raw(2, 1, vec![255, 0, 0, 0, 0, 255])
        .unwrap()
        .save(dir.path().join("red blue.png"))
        .unwrap();
    let mtl = "newmtl a\nKd 1 1 1\nmap_Kd -s 2 3 -o 0.5 0 -clamp on red blue.png\n\
               map_Ks red blue.png\nmap_Ka red blue.png\nmap_Ke red blue.png\n\
               newmtl b\nKd 0.5 0.5 0.5\nmap_Kd missing.png\n";
    std::fs::write(dir.path().join("s.mtl"), mtl).unwrap();
    let obj = format!("mtllib s.mtl\n{QUAD}usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1 3 4\n");
    std::fs::write(dir.path().join("scene.obj"), obj).unwrap();
    let file = load(&dir.path().join("scene.obj")).unwrap();
    let s = &file.scene;
    assert_eq!(s.images.len(), 2);
    let Albedo::Image { slot, .. } = &s.surfaces[0].albedo else {
        panic!("{:?}", s.surfaces[0].albedo);
    };
    assert_eq!(slot.scale, [2.0, 3.0]);
    // The other colour maps share the image (no -clamp: a second entry).
    let ks = s.surfaces[0].specular_map.unwrap();
    assert_eq!(s.surfaces[0].ambient_map, Some(ks));
    assert_eq!(s.surfaces[0].emission_map, Some(ks));
    assert_eq!((ks.scale, ks.clamp), ([1.0, 1.0], false));
    assert_eq!(slot.offset, [0.5, 0.0]);
    assert!(slot.clamp);
    // The left texel is red, decoded from sRGB (255 -> 1).
    assert_eq!(s.images[0].texel(0, 0).x, 1.0);
    assert_eq!(s.surfaces[1].albedo, Albedo::Color(Vec3::splat(0.5)));
    assert!(
        file.warnings
            .iter()
            .any(|w| w.contains("s.mtl:9:") && w.contains("missing.png")),
        "{:?}",
        file.warnings
    );
}

#[test]
fn a_texture_that_is_there_but_unusable_is_an_error_with_the_mtl_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("broken.png"),
        b"\x89PNG\r\n\x1a\nnot really",
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("folder.png")).unwrap();
    // The line that names the texture (its map_Kd), not the material's newmtl.
    for (name, line) in [("broken.png", 2), ("folder.png", 2)] {
        let mtl = format!("newmtl a\nmap_Kd {name}\n");
        std::fs::write(dir.path().join("s.mtl"), mtl).unwrap();
        let obj = format!("mtllib s.mtl\n{QUAD}usemtl a\nf 1 2 3\n");
        std::fs::write(dir.path().join("scene.obj"), obj).unwrap();
        let e = load(&dir.path().join("scene.obj")).unwrap_err().to_string();
        assert!(
            e.contains(&format!("s.mtl:{line}: cannot read texture")),
            "{e}"
        );
        assert!(e.contains(name), "{e}");
    }
}

#[test]
fn groups_become_scene_groups() {
    let obj = format!("{QUAD}o table\nf 1 2 3\ng legs top\nf 1 3 4\no table\nf 2 3 4\n");
    let (_dir, file) = load_files(&[("scene.obj", obj.as_bytes())]);
    let names: Vec<_> = file.scene.groups.iter().map(|g| g.name.as_str()).collect();
    assert!(names.contains(&"table"), "{names:?}");
    let table = file.scene.group("table").unwrap();
    assert!(table.shapes.contains(&0));
}

#[test]
fn the_cornell_box_has_its_ceiling_light_as_an_area_light() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/models/cornell-box/CornellBox-Original.obj");
    if !path.exists() {
        crate::util::skipped(format_args!("{} is absent", path.display()));
        return;
    }
    let file = load(&path).unwrap();
    let s = &file.scene;
    assert_eq!(s.lights.len(), 1);
    let LightKind::Mesh { shapes, area, .. } = &s.lights[0].kind else {
        panic!("{:?}", s.lights[0]);
    };
    assert_eq!(shapes.len(), 2);
    // The light is 0.47 x 0.38 in the file.
    assert!((area - 0.47 * 0.38).abs() < 1e-3, "{area}");
}

#[test]
fn the_pbr_extension_reads_onto_openpbr() {
    let mtl = "newmtl brushed\nKd 0.9 0.8 0.7\nKs 0.5 0.5 0.5\nPm 1\nPr 0.3\naniso 0.6\nanisor 1.25\n\
               newmtl car\nKd 0.5 0 0\nPr 0.5\nPc 1\nPcr 0.1\nPs 0.25\nNi 1\n\
               newmtl shiny\nKd 1 1 1\nNs 250\nPm 0\nNi 1.33\n\
               newmtl glass\nKd 1 1 1\nPr 0.2\nNi 1.5\nTf 1 0.9 0.8\nillum 7\n\
               newmtl mapped\nKd 1 1 1\nmap_Pr rough.png\nPm 0.5\nmap_Pm -s 2 2 rough.png\n";
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(1, 1, image::Rgba([64, 0, 0, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let mut obj = String::from("mtllib s.mtl\n");
    obj += QUAD;
    for name in ["brushed", "car", "shiny", "glass", "mapped"] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let (_dir, file) = load_files(&[
        ("scene.obj", obj.as_bytes()),
        ("s.mtl", mtl.as_bytes()),
        ("rough.png", &png),
    ]);
    assert!(file.warnings.is_empty(), "{:?}", file.warnings);
    let s = &file.scene;
    let pbr = |i: usize| {
        s.surfaces[i]
            .openpbr
            .as_deref()
            .expect("an OpenPBR material")
    };
    let brushed = pbr(0);
    assert_eq!(
        s.surfaces[0].albedo,
        Albedo::Color(Vec3::new(0.9, 0.8, 0.7))
    );
    assert_eq!(brushed.base_metalness.value, 1.0);
    assert_eq!(brushed.specular_roughness.value, 0.3);
    assert_eq!(brushed.specular_roughness_anisotropy.value, 0.6);
    assert_eq!(brushed.tangent_rotation, 0.25);
    // Ks is the Phong readers' and leaves OpenPBR's specular as it is.
    assert_eq!(brushed.specular_weight.value, 1.0);
    assert_eq!(s.surfaces[0].specular, Vec3::ZERO);
    let car = pbr(1);
    assert_eq!(
        (car.coat_weight.value, car.coat_roughness.value),
        (1.0, 0.1)
    );
    assert_eq!(car.fuzz_weight.value, 0.25);
    assert_eq!(
        car.specular_ior.value, 1.5,
        "Ni 1 is an exporter's placeholder"
    );
    // Without Pr, Ns as Blender reads it: 1 - sqrt(Ns / 1000).
    let shiny = pbr(2);
    assert_eq!(shiny.specular_roughness.value, 0.5);
    assert_eq!(shiny.specular_ior.value, 1.33);
    assert_eq!(s.surfaces[2].ior, 1.33);
    let glass = pbr(3);
    assert_eq!(glass.transmission_weight.value, 1.0);
    assert_eq!(glass.transmission_color.value, Vec3::new(1.0, 0.9, 0.8));
    assert!(s.surfaces[3].resolved().is_transmissive());
    assert!(
        s.materials[3].transparent,
        "the classic reading refracts too"
    );
    // A map multiplies its key's value, 1 where there is none, by its red channel.
    let mapped = pbr(4);
    let (slot, channel) = mapped.specular_roughness.texture.expect("map_Pr");
    assert_eq!(
        (mapped.specular_roughness.value, channel),
        (1.0, Channel::R)
    );
    let texel = s.images[slot.image as usize].texel(0, 0);
    assert!(
        (texel.x - 64.0 / 255.0).abs() < 1e-6,
        "read linear: {texel}"
    );
    let (slot, _) = mapped.base_metalness.texture.expect("map_Pm");
    assert_eq!((mapped.base_metalness.value, slot.scale), (0.5, [2.0, 2.0]));
}
