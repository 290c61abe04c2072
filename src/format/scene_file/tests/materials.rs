//! Material terms, hex colours and checkers, image textures, the image size limit and HDR environment maps.

use super::*;
use crate::scene::{Albedo, Highlight, Texels};

#[test]
fn material_terms_fill_the_surface_and_the_classic_material() {
    let f = scene(
        "[[material]]\nname = \"gold\"\ncolor = [0.8, 0.6, 0.2]\nambient = 0.5\ndiffuse = 0.7\n\
         specular = [1, 0.9, 0.5]\nshininess = 80\nhighlight = \"blinn\"\nnormalized = true\n\
         reflection = 0.25\nabsorption = [0.1, 0.2, 0.3]\nemission = 0\nlit = true\n\
         [[material]]\nname = \"glass\"\ncolor = \"#ffffff\"\ntransmission = 0.9\nior = 1.5\n\
         fresnel = true\n",
    );
    let gold = &f.scene.surfaces[0];
    assert_eq!(gold.albedo, Albedo::Color(v(0.8, 0.6, 0.2)));
    assert_close(gold.ambient, v(0.4, 0.3, 0.1));
    assert_eq!(gold.diffuse, 0.7);
    assert_eq!(gold.specular, v(1.0, 0.9, 0.5));
    assert_eq!(
        (gold.shininess, gold.highlight),
        (80.0, Highlight::BlinnPhong)
    );
    assert!(gold.normalized && gold.lit && !gold.fresnel);
    assert_eq!(gold.reflection, Vec3::splat(0.25));
    assert_eq!(gold.absorption, v(0.1, 0.2, 0.3));
    let classic = &f.scene.materials[0];
    assert_eq!(classic.name, "gold");
    assert_eq!(
        (
            classic.ambient,
            classic.diffuse,
            classic.specular,
            classic.reflect
        ),
        (0.5, 0.7, 1.0, 0.25)
    );
    // Linear 0.2 is sRGB 0.4845.
    assert!((classic.color.z - 0.4845).abs() < 1e-3, "{}", classic.color);
    let glass = &f.scene.surfaces[1];
    assert_eq!(glass.albedo, Albedo::Color(Vec3::ONE));
    // Fresnel without a reflection colour reflects white.
    assert_eq!(glass.reflection, Vec3::ONE);
    assert_eq!((glass.transmission, glass.ior), (Vec3::splat(0.9), 1.5));
    assert!(f.scene.materials[1].transparent);
}

#[test]
fn hex_colours_are_srgb_and_checkers_are_solid() {
    let f = scene(
        "[[material]]\nname = \"c\"\ntexture = { checker = [\"#bcbcbc\", [0, 0, 1]], scale = 0.5 }\n",
    );
    let Albedo::Checker { a, b, scale } = f.scene.surfaces[0].albedo else {
        panic!("{:?}", f.scene.surfaces[0].albedo)
    };
    // sRGB 188/255 decodes to linear 0.50289.
    assert!((a.x - 0.502_886).abs() < 1e-5, "{a}");
    assert_eq!((b, scale), (Vec3::Z, 0.5));
}

#[test]
fn an_image_texture_is_read_once_as_srgb_rgba() {
    let dir = Folder::new();
    let mut png = image::RgbImage::new(2, 1);
    png.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    png.put_pixel(1, 0, image::Rgb([0, 0, 255]));
    png.save(dir.path("tex/rb.png")).unwrap_or_else(|_| {
        std::fs::create_dir_all(dir.path("tex")).unwrap();
        png.save(dir.path("tex/rb.png")).unwrap()
    });
    let f = dir.load(
        "[[material]]\nname = \"a\"\ntexture = \"tex/rb.png\"\ncolor = [0.5, 0.5, 0.5]\n\
         [[material]]\nname = \"b\"\ntexture = \"tex/./rb.png\"\nnormal_map = \"tex/rb.png\"\n",
    );
    // One sRGB image for both colour maps, a linear copy for the normal map.
    assert_eq!(f.scene.images.len(), 2);
    let Texels::Rgba8 { texels, srgb } = &f.scene.images[0].texels else {
        panic!()
    };
    assert_eq!(
        (texels.as_slice(), *srgb),
        (&[[255, 0, 0, 255], [0, 0, 255, 255]][..], true)
    );
    let Albedo::Image { slot, tint } = f.scene.surfaces[0].albedo else {
        panic!()
    };
    assert_eq!((slot.image, tint), (0, Vec3::splat(0.5)));
    assert_eq!(f.scene.surfaces[1].normal_map.unwrap().image, 1);
}

#[test]
fn images_larger_than_the_limit_are_refused_from_their_header() {
    let dir = Folder::new();
    // A PPM header promising 10^8 pixels, and not one of them.
    dir.write("huge.ppm", "P6\n10000 10000\n255\n");
    let e = dir.error("[[material]]\nname = \"a\"\ntexture = \"huge.ppm\"\n");
    assert_eq!(
        e,
        format!(
            "DIR/scene.toml:3:11: cannot load image DIR/huge.ppm: the image is 10000x10000 \
             (100000000 pixels); textures may have at most {MAX_IMAGE_PIXELS} pixels"
        )
    );
}

#[test]
fn hdr_environment_maps_are_read_as_linear_radiance() {
    let dir = Folder::new();
    // A 2 x 1 Radiance image: a bright texel (8 in red) and a dim one.
    let image = prism_film_image(vec![[8.0, 0.5, 0.25], [0.125, 0.0, 1.0]]);
    crate::film::write_image(
        &image,
        &dir.path("sky.hdr"),
        &crate::film::OutputOptions::default(),
    )
    .unwrap();
    let f = dir.load("[background]\nimage = \"sky.hdr\"\n");
    let crate::scene::Background::Environment { image, .. } = f.scene.background else {
        panic!("{:?}", f.scene.background);
    };
    let t = &f.scene.images[image as usize];
    assert_eq!((t.width, t.height), (2, 1));
    assert_eq!(t.texel(0, 0).x, 8.0);
    assert_eq!(t.texel(1, 0).z, 1.0);
}

fn prism_film_image(pixels: Vec<[f32; 3]>) -> crate::film::Image {
    crate::film::Image::new(pixels.len() as u32, 1, pixels)
}
