use super::*;

fn parse_str(text: &str) -> Result<MtlLibrary> {
    parse(text.as_bytes(), Path::new("lib/m.mtl"))
}

fn error_of(text: &str) -> String {
    parse_str(text).unwrap_err().to_string()
}

#[test]
fn texture_option_numbers_beyond_f32_are_errors() {
    // Found by fuzzing: an optional second scale of 1e99 was taken as infinity.
    let e = error_of("newmtl a\nmap_Kd -s 2 1e99 -o 0 tex.png\n");
    assert!(e.starts_with("lib/m.mtl:2:13: "), "{e}");
    let lib = parse_str("newmtl a\nmap_Kd -s 2 3 tex.png\n").unwrap();
    assert_eq!(
        lib.materials[0].map_kd.as_ref().unwrap().scale,
        [2.0, 3.0, 1.0]
    );
}

#[test]
fn colours_scalars_and_illumination_are_read() {
    let lib = parse_str(
        "# header\n  newmtl  red wall \nKa 0.1 0.2 0.3\nKd .5\nKs 1 1 1 # shiny\n\
         Ke 17 12 4\nKt 0.1 0.2 0.3\nNs 10\nNi 1.5\nd 0.75\nTr 0.5\nillum 2\n\
         newmtl glass\nTf 1 0.5 0.25\nTr 0.25\nillum 7\n",
    )
    .unwrap();
    assert_eq!(lib.materials.len(), 2);
    let red = &lib.materials[0];
    assert_eq!(red.name, "red wall");
    assert_eq!(red.ka, Some(Vec3::new(0.1, 0.2, 0.3)));
    assert_eq!(red.kd, Some(Vec3::splat(0.5)));
    assert_eq!(red.ks, Some(Vec3::ONE));
    assert_eq!(red.ke, Some(Vec3::new(17.0, 12.0, 4.0)));
    assert_eq!(red.tf, Some(Vec3::new(0.1, 0.2, 0.3)));
    assert_eq!(
        (red.ns, red.ni, red.d, red.illum),
        (Some(10.0), Some(1.5), Some(0.75), Some(2))
    );
    assert_eq!((red.path.as_path(), red.line), (Path::new("lib/m.mtl"), 2));
    let glass = &lib.materials[1];
    assert_eq!((glass.d, glass.illum), (Some(0.75), Some(7)));
    assert_eq!(glass.tf, Some(Vec3::new(1.0, 0.5, 0.25)));
    assert_eq!(lib.warnings.len(), 1);
    assert_eq!(
        lib.warnings[0].to_string(),
        "lib/m.mtl:11: material `red wall` gives both d and Tr: d is used"
    );
}

#[test]
fn d_wins_over_tr_in_either_order() {
    let lib = parse_str("newmtl a\nTr 0.5\nd 0.75\nnewmtl b\nd 0.75\nTr 0.5\n").unwrap();
    assert!(lib.materials.iter().all(|m| m.d == Some(0.75)));
    assert_eq!(lib.warnings.len(), 2);
}

#[test]
fn texture_options_are_applied_or_kept_and_names_keep_their_spaces() {
    let lib = parse_str(
        "newmtl t\nmap_Kd -o 0.1 diffuse 01.jpg  \nmap_Ks -s 0.1 0.2 specular.jpg\n\
         map_Ka -clamp on -mm 0.1 0.3 -t 1 2 3 ambient.png\n\
         map_bump -bm 3 -imfchan r -colorspace linear tex\\bump.png\n\
         map_d -type sphere -texres 512 -boost 2 -blendu off -blendv on -cc off a.png\n\
         norm n.png\nrefl -type cube_top top.png\nrefl -type cube_bottom bottom.png\n\
         map_Ke -bm 2 glow.png -bm 1.5\n",
    )
    .unwrap();
    let m = &lib.materials[0];
    let kd = m.map_kd.as_ref().unwrap();
    assert_eq!(kd.name, "diffuse 01.jpg");
    assert_eq!(kd.path, Path::new("lib/diffuse 01.jpg"));
    assert_eq!((kd.offset, kd.scale), ([0.1, 0.0, 0.0], [1.0; 3]));
    let ks = m.map_ks.as_ref().unwrap();
    assert_eq!(
        (ks.name.as_str(), ks.scale),
        ("specular.jpg", [0.1, 0.2, 1.0])
    );
    let ka = m.map_ka.as_ref().unwrap();
    assert!(ka.clamp);
    assert_eq!(ka.other_options, ["-mm 0.1 0.3", "-t 1 2 3"]);
    let bump = m.bump.as_ref().unwrap();
    assert_eq!(bump.bump_multiplier, 3.0);
    assert_eq!(bump.colorspace.as_deref(), Some("linear"));
    assert_eq!(bump.other_options, ["-imfchan r"]);
    assert_eq!(
        (bump.name.as_str(), bump.path.as_path()),
        ("tex\\bump.png", Path::new("lib/tex/bump.png"))
    );
    let d = m.map_d.as_ref().unwrap();
    assert_eq!(
        d.other_options,
        [
            "-type sphere",
            "-texres 512",
            "-boost 2",
            "-blendu off",
            "-blendv on",
            "-cc off"
        ]
    );
    assert_eq!(m.norm.as_ref().unwrap().name, "n.png");
    assert_eq!(m.refl.as_ref().unwrap().name, "top.png");
    let ke = m.map_ke.as_ref().unwrap();
    assert_eq!(
        (ke.name.as_str(), ke.bump_multiplier),
        ("glow.png -bm 1.5", 2.0)
    );
    assert_eq!(lib.warnings.len(), 1);
    assert!(
        lib.warnings[0].message.contains("holds the option `-bm`"),
        "{:?}",
        lib.warnings
    );
}

#[test]
fn unused_keys_are_counted_with_one_warning_per_kind() {
    let lib = parse_str(
        "Kd 1 1 1\nnewmtl pbr\nmap_anisor 0.2\nsharpness 0.3\nmap_anisor 0.4\nmap_aniso r.tex\ndisp d.png\n\
         Kd spectral a.rfl 1\nfoo bar\nbaz\n",
    )
    .unwrap();
    let skipped: Vec<_> = lib.skipped.iter().map(|(k, &n)| (k.as_str(), n)).collect();
    assert_eq!(
        skipped,
        [
            ("disp", 1),
            ("map_aniso", 1),
            ("map_anisor", 2),
            ("sharpness", 1),
            ("unknown", 2)
        ]
    );
    let messages: Vec<_> = lib.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        messages,
        [
            "lib/m.mtl:1: `Kd` comes before any newmtl: it is ignored, and so is what \
             follows until the first newmtl",
            "lib/m.mtl:8: Kd `spectral` is not supported: the colour is left unset",
            "lib/m.mtl:9: unknown material statement `foo` skipped",
            "lib/m.mtl:7: 1 `disp` statements skipped: Prism does not use them",
            "lib/m.mtl:6: 1 `map_aniso` statements skipped: Prism does not use them",
            "lib/m.mtl:3: 2 `map_anisor` statements skipped: Prism does not use them",
            "lib/m.mtl:4: 1 `sharpness` statements skipped: Prism does not use them",
            "lib/m.mtl:9: 2 unknown material statements skipped",
        ]
    );
    assert_eq!(lib.materials[0].kd, None);
}

#[test]
fn the_pbr_extension_is_read_with_its_maps() {
    // tinyobjloader's pbr-mat-ext.mtl, as its test reads it.
    let lib = parse_str(
        "newmtl pbr\nKd 1 1 1\nKe 0.1 0.1 0.1\nPr 0.2\nPm 0.3\nPs 0.4\nPc 0.5\nPcr 0.6\n\
         aniso 0.7\nanisor 0.8\nmap_Pr roughness.tex\nmap_Pm -s 2 2 metallic.tex\n\
         map_Ps sheen.tex\nmap_Pc coat.tex\nmap_Pcr coat roughness.tex\n",
    )
    .unwrap();
    let p = &lib.materials[0].pbr;
    assert!(p.is_given());
    assert_eq!(
        (p.roughness, p.metallic, p.sheen, p.clearcoat),
        (Some(0.2), Some(0.3), Some(0.4), Some(0.5))
    );
    assert_eq!(
        (p.clearcoat_roughness, p.anisotropy),
        (Some(0.6), Some(0.7))
    );
    let name = |m: &Option<TextureMap>| m.as_ref().unwrap().name.clone();
    assert_eq!(name(&p.map_roughness), "roughness.tex");
    assert_eq!(name(&p.map_metallic), "metallic.tex");
    assert_eq!(p.map_metallic.as_ref().unwrap().scale, [2.0, 2.0, 1.0]);
    assert_eq!(name(&p.map_sheen), "sheen.tex");
    assert_eq!(name(&p.map_clearcoat), "coat.tex");
    assert_eq!(name(&p.map_clearcoat_roughness), "coat roughness.tex");
    assert_eq!(p.anisotropy_rotation, Some(0.8));
    assert!(lib.skipped.is_empty(), "{:?}", lib.skipped);
    assert!(!MtlPbr::default().is_given());
    // A malformed value is an error at its column, as for any key.
    let e = parse_str("newmtl a\nPm x\n").unwrap_err().to_string();
    assert!(e.contains(":2:4") && e.contains("the metalness"), "{e}");
}

#[test]
fn malformed_values_are_errors_at_their_column() {
    let cases = [
        (
            "newmtl a\nKd 1 x 1\n",
            "m.mtl:2:6: expected a number for the green of Kd, found `x`",
        ),
        (
            "newmtl a\nKd 1 1\n",
            "m.mtl:2:7: expected r g b after Kd, the blue is missing",
        ),
        (
            "newmtl a\nNs nan\n",
            "m.mtl:2:4: expected a finite number for the shininess, found `nan`",
        ),
        (
            "newmtl a\nNi\n",
            "m.mtl:2:3: expected the index of refraction after Ni, found the end of the line",
        ),
        (
            "newmtl a\nd 1 2\n",
            "m.mtl:2:5: expected the end of the line after d's values, found `2`",
        ),
        (
            "newmtl a\nillum 2.5\n",
            "m.mtl:2:7: expected an illumination model (0 to 10) after illum, found `2.5`",
        ),
        (
            "newmtl a\nmap_Kd -bm x.png\n",
            "m.mtl:2:12: expected a number for map_Kd's -bm, found `x.png`",
        ),
        (
            "newmtl a\nmap_Kd -clamp yes a.png\n",
            "m.mtl:2:15: expected on or off for map_Kd's -clamp, found `yes`",
        ),
        (
            "newmtl a\nKa 1e39\n",
            "m.mtl:2:4: expected a finite number of magnitude at most",
        ),
    ];
    for (text, expected) in cases {
        let message = error_of(text);
        assert!(
            message.starts_with(&format!("lib/{expected}")),
            "{message:?} for {text:?}"
        );
    }
}
