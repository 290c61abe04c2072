//! Each object type, transform, material term, light and setting with exact values;
//! includes; every class of error with its `file:line:column`; the showcase rendered.

use super::*;
use crate::math::Vec3;
use crate::scene::{Albedo, Background, Falloff, Highlight, LightKind, Shape, Texels};
use std::path::PathBuf;

/// A scene file in a fresh folder, so relative paths have somewhere to point.
struct Folder {
    dir: tempfile::TempDir,
}

impl Folder {
    fn new() -> Folder {
        Folder {
            dir: tempfile::tempdir().unwrap(),
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }

    fn load(&self, text: &str) -> SceneFile {
        let p = self.write("scene.toml", text);
        load(&p).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The error text with the folder replaced by `DIR`.
    fn error(&self, text: &str) -> String {
        let p = self.write("scene.toml", text);
        let e = load(&p).expect_err("expected an error").to_string();
        e.replace(&self.dir.path().display().to_string(), "DIR")
    }
}

fn scene(text: &str) -> SceneFile {
    Folder::new().load(text)
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!(close(a, b), "{a} != {b}");
}

#[test]
fn a_sphere_is_scaled_then_translated() {
    let f = scene(
        "[[object]]\ntype = \"sphere\"\ncenter = [1, 0, 0]\nradius = 0.5\nscale = 2\n\
         rotate = [0, 0, 1, 90]\ntranslate = [10, 0, 0]\n",
    );
    let Shape::Sphere(s) = f.scene.shapes.get(0) else {
        panic!("{:?}", f.scene.shapes)
    };
    // (1,0,0) * 2 = (2,0,0), turned 90 degrees about z = (0,2,0), moved to (10,2,0).
    assert_close(s.center, v(10.0, 2.0, 0.0));
    assert_eq!(s.radius, 1.0);
    assert_eq!(f.dialect, SceneDialect::PrismScene);
}

#[test]
fn a_quad_turned_about_y_keeps_its_corners_in_order() {
    let f = scene(
        "[[object]]\ntype = \"quad\"\ncorner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [0, 2, 0]\n\
         rotate = [0, 1, 0, 90]\ntranslate = [0, 0, 5]\n",
    );
    let Shape::Rectangle(r) = f.scene.shapes.get(0) else {
        panic!()
    };
    // x turns to -z about +y.
    for (got, want) in r.v.iter().zip([
        v(0.0, 0.0, 5.0),
        v(0.0, 0.0, 4.0),
        v(0.0, 2.0, 4.0),
        v(0.0, 2.0, 5.0),
    ]) {
        assert_close(*got, want);
    }
}

#[test]
fn several_rotations_apply_in_order() {
    let f = scene(
        "[[object]]\ntype = \"triangle\"\nvertices = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n\
         rotate = [[0, 0, 1, 90], [1, 0, 0, 90]]\n",
    );
    let Shape::Triangle(t) = f.scene.shapes.get(0) else {
        panic!()
    };
    // x -> y (about z) -> z (about x); y -> -x -> -x; z -> z -> -y.
    assert_close(t.v[0], v(0.0, 0.0, 1.0));
    assert_close(t.v[1], v(-1.0, 0.0, 0.0));
    assert_close(t.v[2], v(0.0, -1.0, 0.0));
}

#[test]
fn a_matrix_is_row_major_and_a_mirror_keeps_the_winding() {
    let f = scene(
        "[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         matrix = [[-1, 0, 0, 3], [0, 1, 0, 4], [0, 0, 1, 5], [0, 0, 0, 1]]\n",
    );
    let Shape::Triangle(t) = f.scene.shapes.get(0) else {
        panic!()
    };
    // Mirrored in x and moved by (3, 4, 5); vertices 1 and 2 swap so the normal
    // stays +z as authored.
    assert_eq!(t.v, [v(3.0, 4.0, 5.0), v(3.0, 5.0, 5.0), v(2.0, 4.0, 5.0)]);
    assert_close(t.normal(), Vec3::Z);
}

#[test]
fn a_box_is_six_rectangles_facing_out() {
    let f = scene("[[object]]\ntype = \"box\"\nmin = [-1, -2, -3]\nmax = [1, 2, 3]\n");
    assert_eq!(f.scene.shapes.len(), 6);
    let mut normals = Vec::new();
    for s in f.scene.shapes.iter() {
        let Shape::Rectangle(r) = s else { panic!() };
        let n = (r.v[1] - r.v[0]).cross(r.v[3] - r.v[0]).normalize();
        let centre = (r.v[0] + r.v[2]) * 0.5;
        assert!(n.dot(centre) > 0.0, "{r:?} faces in");
        normals.push(n);
    }
    assert_eq!(
        normals,
        [-Vec3::Z, Vec3::Z, -Vec3::X, Vec3::X, -Vec3::Y, Vec3::Y]
    );
    let b = f.scene.bounds();
    assert_eq!((b.min, b.max), (v(-1.0, -2.0, -3.0), v(1.0, 2.0, 3.0)));
}

#[test]
fn a_disk_is_a_fan_whose_normal_transforms_by_the_inverse_transpose() {
    let f = scene(
        "[[object]]\ntype = \"disk\"\ncenter = [0, 0, 0]\nnormal = [1, 1, 0]\nradius = 1\n\
         scale = [2, 1, 1]\n",
    );
    assert_eq!(f.scene.shapes.len(), SEGMENTS as usize);
    let mesh = &f.scene.meshes[0];
    assert_eq!((mesh.first_shape, mesh.len), (0, SEGMENTS));
    mesh.check().unwrap();
    // (1, 1, 0) under diag(2, 1, 1): inverse transpose diag(1/2, 1, 1) gives (1/2, 1, 0).
    assert_close(mesh.normals[0], v(0.5, 1.0, 0.0).normalize());
    // The geometric normals agree with the smooth one.
    for s in f.scene.shapes.iter() {
        let Shape::Triangle(t) = s else { panic!() };
        assert!(close(t.normal(), mesh.normals[0]), "{}", t.normal());
    }
}

#[test]
fn a_cylinder_has_radial_side_normals_and_two_caps() {
    let f = scene(
        "[[object]]\ntype = \"cylinder\"\nbase = [0, 0, 0]\naxis = [0, 0, 1]\nheight = 2\n\
         radius = 0.5\ntranslate = [1, 0, 0]\n",
    );
    let n = SEGMENTS as usize;
    assert_eq!(f.scene.shapes.len(), 4 * n);
    let mesh = &f.scene.meshes[0];
    mesh.check().unwrap();
    for (i, s) in f.scene.shapes.iter().take(2 * n).enumerate() {
        let Shape::Triangle(t) = s else { panic!() };
        for (k, p) in t.v.iter().enumerate() {
            assert!((0.0..=2.0 + 1e-6).contains(&p.z));
            let radial = v(p.x - 1.0, p.y, 0.0);
            assert!((radial.length() - 0.5).abs() < 1e-5);
            let normal = mesh.normals[mesh.normal_indices[i][k] as usize];
            assert_close(normal, radial.normalize());
        }
    }
    // Caps face down and up.
    let cap_normal = |i: usize| match f.scene.shapes.get(i) {
        Shape::Triangle(t) => t.normal(),
        _ => panic!(),
    };
    assert_close(cap_normal(2 * n), -Vec3::Z);
    assert_close(cap_normal(3 * n), Vec3::Z);
    let open =
        scene("[[object]]\ntype = \"cylinder\"\ntop = [0, 1, 0]\nradius = 1\ncapped = false\n");
    assert_eq!(open.scene.shapes.len(), 2 * n);
}

#[test]
fn a_plane_is_a_square_a_hundred_times_the_rest_of_the_scene() {
    let f = scene(
        "[camera]\nfrom = [0, 0, 3]\nat = [0, 0, 0]\n\
         [[object]]\ntype = \"plane\"\npoint = [0, -1, 0]\nnormal = [0, 1, 0]\n\
         [[object]]\ntype = \"sphere\"\nradius = 1\n",
    );
    let Shape::Rectangle(r) = f.scene.shapes.get(0) else {
        panic!()
    };
    // Sphere bounds [-1, 1]^3 grown by the eye (0, 0, 3): extent (2, 2, 4).
    let half = 0.5 * PLANE_SCALE * 24f32.sqrt();
    for p in r.v {
        assert!((p.y + 1.0).abs() < 1e-3);
        assert!(((p.x.abs().max(p.z.abs())) - half).abs() < 1e-2, "{p}");
    }
    let n = (r.v[1] - r.v[0]).cross(r.v[3] - r.v[0]).normalize();
    assert_close(n, Vec3::Y);
}

#[test]
fn a_mesh_file_is_merged_and_placed() {
    let dir = Folder::new();
    dir.write("meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let f = dir.load(
        "[[object]]\nname = \"tri\"\ntype = \"mesh\"\nfile = \"meshes/tri.obj\"\n\
         translate = [0, 0, -2]\nmaterial = { color = [0, 1, 0] }\n",
    );
    let Shape::Triangle(t) = f.scene.shapes.get(0) else {
        panic!()
    };
    assert_eq!(
        t.v,
        [v(0.0, 0.0, -2.0), v(1.0, 0.0, -2.0), v(0.0, 1.0, -2.0)]
    );
    let m = f.scene.material_of[0] as usize;
    assert_eq!(f.scene.surfaces[m].albedo, Albedo::Color(Vec3::Y));
    assert_eq!(f.scene.materials[m].name, "tri");
    assert_eq!(f.scene.group("tri").unwrap().shapes, [0]);
    let e = dir.error("[[object]]\ntype = \"mesh\"\nfile = \"scene.toml\"\n");
    assert_eq!(
        e,
        "DIR/scene.toml:3:8: expected a mesh file .obj, .ply or .objx, found DIR/scene.toml"
    );
}

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
    crate::film::write_image_with(
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

#[test]
fn lights_of_every_type() {
    let f = scene(
        "[[light]]\ntype = \"point\"\nposition = [1, 2, 3]\ncolor = [1, 0.5, 0]\nintensity = 2\n\
         falloff = \"inverse_square\"\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -2, 0]\n\
         [[light]]\ntype = \"spot\"\nposition = [0, 5, 0]\nat = [0, 0, 0]\nangle = 60\n\
         falloff_angle = 30\n\
         [[light]]\ntype = \"quad\"\ncorner = [0, 4, 0]\nedge1 = [2, 0, 0]\nedge2 = [0, 0, 2]\n\
         samples = 9\n\
         [[light]]\ntype = \"disk\"\ncenter = [0, 3, 0]\nradius = 0.5\n\
         [[light]]\nname = \"bulb\"\ntype = \"sphere\"\ncenter = [1, 1, 1]\nradius = 0.25\n",
    );
    let l = &f.scene.lights;
    assert_eq!(l.len(), 6);
    assert_eq!(
        (
            l[0].position,
            l[0].color,
            l[0].intensity,
            l[0].falloff,
            &l[0].kind
        ),
        (
            v(1.0, 2.0, 3.0),
            v(1.0, 0.5, 0.0),
            2.0,
            Falloff::InverseSquare,
            &LightKind::Point
        )
    );
    assert_eq!(
        l[1].kind,
        LightKind::Directional {
            direction: -Vec3::Y
        }
    );
    let LightKind::Spot {
        direction,
        cos_inner,
        cos_outer,
    } = l[2].kind
    else {
        panic!()
    };
    assert_eq!(direction, -Vec3::Y);
    assert!((cos_outer - 0.5).abs() < 1e-6 && (cos_inner - 0.75f32.sqrt()).abs() < 1e-6);
    assert_eq!(l[3].position, v(1.0, 4.0, 1.0));
    assert_eq!(
        l[3].kind,
        LightKind::Quad {
            u: v(2.0, 0.0, 0.0),
            v: v(0.0, 0.0, 2.0)
        }
    );
    assert_eq!(l[3].samples, 9);
    assert_eq!(
        l[4].kind,
        LightKind::Disk {
            normal: -Vec3::Y,
            radius: 0.5
        }
    );
    assert_eq!(l[4].samples, DEFAULT_AREA_SAMPLES);
    assert_eq!(l[5].kind, LightKind::Sphere { radius: 0.25 });
    assert_eq!(f.scene.group("bulb").unwrap().lights, [5]);
}

#[test]
fn glowing_objects_are_area_lights_in_their_group() {
    let f = scene(
        "[[material]]\nname = \"lamp\"\nemission = [4, 4, 3]\n\
         [[object]]\nname = \"panel\"\ntype = \"quad\"\ncorner = [0, 2, 0]\nedge1 = [0, 0, 1]\n\
         edge2 = [3, 0, 0]\nmaterial = \"lamp\"\nsamples = 4\n\
         [[object]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0, 1, 0]\nradius = 0.5\n\
         material = \"lamp\"\n",
    );
    // The quad became two triangles, sampled by area (1.5 each).
    assert_eq!(f.scene.shapes.len(), 3);
    let LightKind::Mesh { shapes, cdf, area } = &f.scene.lights[0].kind else {
        panic!()
    };
    assert_eq!(
        (shapes.as_slice(), cdf.as_slice(), *area),
        (&[0u32, 1][..], &[0.5, 1.0][..], 3.0)
    );
    assert_eq!(f.scene.lights[0].samples, 4);
    assert_eq!(f.scene.lights[1].kind, LightKind::Sphere { radius: 0.5 });
    assert_eq!(f.scene.lights[1].color, v(4.0, 4.0, 3.0));
    let panel = f.scene.group("panel").unwrap();
    assert_eq!(
        (panel.shapes.as_slice(), panel.lights.as_slice()),
        (&[0, 1][..], &[0][..])
    );
    assert_eq!(f.scene.group("ball").unwrap().lights, [1]);
}

#[test]
fn the_camera_looks_at_with_a_lens_and_the_render_size() {
    let f = scene(
        "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nfov = 90\naperture = 0.1\nlens_samples = 8\n\
         [render]\nwidth = 200\nheight = 100\naa = 2\nfilter = \"lanczos\"\nspp = 4\nmax_depth = 5\n\
         min_weight = 0.01\nseed = 7\nintegrator = \"classic\"\nexposure = -1\ntonemap = \"aces\"\n",
    );
    let c = f.camera.unwrap();
    assert_eq!(
        (c.width, c.height, c.aa, c.rays_per_pixel),
        (200, 100, 2, 8)
    );
    assert_eq!((c.focal_length, c.aperture), (4.0, 0.1));
    assert!((c.retina_scale * 200.0 - 1.0).abs() < 1e-6);
    let s = f.settings;
    assert_eq!(
        (s.width, s.height, s.aa, s.spp, s.max_depth, s.seed),
        (Some(200), Some(100), Some(2), Some(4), Some(5), Some(7))
    );
    assert_eq!(s.filter, Some(crate::film::resample::Filter::Lanczos));
    assert_eq!(s.integrator, Some(crate::render::IntegratorKind::Classic));
    assert_eq!(
        (s.min_weight, s.exposure, s.tonemap.as_deref()),
        (Some(0.01), Some(-1.0), Some("aces"))
    );
    // Vertical 90 degrees at 2:1 is a horizontal half-width of 2; focus on an object.
    let g = scene(
        "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nfov = 90\nfov_axis = \"vertical\"\n\
         aperture = 0.5\nfocus_on = \"ball\"\n[render]\nwidth = 200\nheight = 100\n\
         [[object]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\n",
    );
    let c = g.camera.unwrap();
    assert!(
        (c.retina_scale * 200.0 - 2.0).abs() < 1e-5,
        "{}",
        c.retina_scale
    );
    assert!((c.focal_length - 7.0).abs() < 1e-6);
    // Without [render] the camera is 640 x 360.
    let h = scene("[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\n")
        .camera
        .unwrap();
    assert_eq!((h.width, h.height), DEFAULT_SIZE);
}

#[test]
fn ambient_and_background() {
    let f = scene("[ambient]\ncolor = [0.1, 0.2, 0.3]\nintensity = 2\n[background]\ncolor = 0.5\n");
    assert_close(f.scene.ambient, v(0.2, 0.4, 0.6));
    assert_eq!(f.scene.background, Background::Color(Vec3::splat(0.5)));
    let dir = Folder::new();
    image::RgbImage::new(4, 2)
        .save(dir.path("sky.png"))
        .unwrap();
    let g = dir.load("[background]\nimage = \"sky.png\"\nup = [0, 0, 1]\nintensity = 3\n");
    assert_eq!(
        g.scene.background,
        // -z made perpendicular to up = +z is nothing, so the centre looks along +x.
        Background::Environment {
            image: 0,
            up: Vec3::Z,
            forward: Vec3::X,
            intensity: 3.0
        }
    );
}

#[test]
fn includes_resolve_against_the_including_file() {
    let dir = Folder::new();
    dir.write(
        "lib/materials.toml",
        "include = [\"more/colours.toml\"]\n[[material]]\nname = \"red\"\ncolor = [1, 0, 0]\n",
    );
    dir.write(
        "lib/more/colours.toml",
        "[[material]]\nname = \"blue\"\ncolor = [0, 0, 1]\n",
    );
    let f = dir.load(
        "include = [\"lib/materials.toml\"]\n[[object]]\ntype = \"sphere\"\nradius = 1\n\
         material = \"blue\"\n",
    );
    let names: Vec<_> = f.scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["blue", "red"]);
    assert_eq!(f.scene.material_of, [0]);
}

#[test]
fn include_cycles_and_depth_are_errors_at_the_include_line() {
    let dir = Folder::new();
    dir.write("a.toml", "\ninclude = [\"b.toml\"]\n");
    dir.write("b.toml", "include = [\"a.toml\"]\n");
    assert_eq!(
        dir.error("include = [\"a.toml\"]\n"),
        "DIR/b.toml:1:12: include cycle: DIR/a.toml is already being read (it includes itself, \
         directly or not)"
    );
    let deep = Folder::new();
    for i in 0..20 {
        deep.write(
            &format!("f{i}.toml"),
            &format!("include = [\"f{}.toml\"]\n", i + 1),
        );
    }
    deep.write("f20.toml", "");
    assert_eq!(
        deep.error("include = [\"f0.toml\"]\n"),
        "DIR/f15.toml:1:12: includes nest more than 16 files deep"
    );
    assert_eq!(
        dir.error("include = [\"nowhere.toml\"]\n")
            .split(": No such")
            .next()
            .unwrap(),
        "DIR/scene.toml:1:12: cannot open DIR/nowhere.toml"
    );
    dir.write("cam.toml", "[camera]\nfrom = [0, 0, 1]\nat = [0, 0, 0]\n");
    assert_eq!(
        dir.error("include = [\"cam.toml\"]\n"),
        "DIR/cam.toml:1:1: [camera] belongs in the main scene file: an included file holds \
         materials, lights and objects"
    );
}

#[test]
fn every_error_names_file_line_and_column() {
    let cases = [
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\ncolour = 3\n",
            "DIR/scene.toml:4:1: unknown field `colour`",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = \"big\"\n",
            "DIR/scene.toml:3:10: invalid type: string \"big\", expected f64",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = inf\n",
            "DIR/scene.toml:3:10: expected a finite number of magnitude at most 1e30, found inf",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\nscale = [1, 2, 1]\n",
            "DIR/scene.toml:4:9: a sphere cannot be scaled differently along different axes",
        ),
        (
            "[[object]]\ntype = \"quad\"\nradius = 1\n",
            "DIR/scene.toml:3:10: `radius` does not apply to a quad, which takes `corner`, `edge1`, `edge2`",
        ),
        (
            "[[object]]\ntype = \"cone\"\n",
            "DIR/scene.toml:2:8: unknown object type \"cone\": expected mesh, sphere, plane",
        ),
        (
            "[[object]]\ntype = \"sphere\"\n",
            "DIR/scene.toml:2:8: a sphere needs `radius`",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"gold\"\n",
            "DIR/scene.toml:4:12: unknown material \"gold\": expected one of the [[material]] names (there are none)",
        ),
        (
            "[[material]]\nname = \"a\"\n[[material]]\nname = \"a\"\n",
            "DIR/scene.toml:4:8: material \"a\" is defined twice (first at DIR/scene.toml:2:8)",
        ),
        (
            "[[material]]\nname = \"a\"\ncolor = [1, -1, 0]\n",
            "DIR/scene.toml:3:9: expected colour channels >= 0, found [1, -1, 0]",
        ),
        (
            "[[material]]\nname = \"a\"\ncolor = \"#12345\"\n",
            "DIR/scene.toml:3:9: expected a colour \"#rrggbb\", found \"#12345\"",
        ),
        (
            "[[material]]\nname = \"a\"\ntexture = \"nowhere.png\"\n",
            "DIR/scene.toml:3:11: cannot open DIR/nowhere.png",
        ),
        (
            "[[object]]\nname = \"x\"\ntype = \"sphere\"\nradius = 1\n[[light]]\nname = \"x\"\ntype = \"point\"\nposition = [0, 0, 0]\n",
            "DIR/scene.toml:6:8: the name \"x\" is already taken",
        ),
        (
            "[[light]]\ntype = \"point\"\n",
            "DIR/scene.toml:2:8: a point light needs `position`",
        ),
        (
            "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\nfalloff = \"linear\"\n",
            "DIR/scene.toml:4:11: expected falloff \"none\" or \"inverse_square\", found \"linear\"",
        ),
        (
            "[render]\nwidth = 0\n",
            "DIR/scene.toml:2:9: expected width between 1 and 65536, found 0",
        ),
        (
            "[render]\ntonemap = \"filmic\"\n",
            "DIR/scene.toml:2:11: unknown tonemap \"filmic\": expected clamp, reinhard or aces",
        ),
        (
            "[render]\nfilter = \"box\"\n",
            "DIR/scene.toml:2:10: unknown filter `box`",
        ),
        (
            "[camera]\nfrom = [0, 0, 0]\nat = [0, 0, 0]\n",
            "DIR/scene.toml:3:6: expected `at` away from `from`",
        ),
        (
            "[camera]\ncmr = \"c.cmr\"\nfov = 40\n",
            "DIR/scene.toml:3:7: a camera given by `cmr` takes no other key",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nscale = 0\n",
            "DIR/scene.toml:5:9: the transform flattens the object",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nrotate = [0, 1, 0]\n",
            "DIR/scene.toml:5:10: expected rotate = [ax, ay, az, degrees], found 3 numbers",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]\n",
            "DIR/scene.toml:5:10: expected the last row of the matrix to be [0, 0, 0, 1]",
        ),
        (
            "[[track]]\ntarget = \"object:ghost\"\nmotion = \"translate\"\n",
            "DIR/scene.toml:2:10: unknown target \"object:ghost\": the named objects are: there are none",
        ),
        (
            "[[track]]\ntarget = \"camera\"\nmotion = \"spin\"\n",
            "DIR/scene.toml:3:10: unknown motion \"spin\"",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\n[[object]\n",
            "DIR/scene.toml:4:10: unclosed array table, expected `]`",
        ),
    ];
    let dir = Folder::new();
    for (text, expected) in cases {
        let e = dir.error(text);
        assert!(
            e.starts_with(expected),
            "for\n{text}\nexpected\n{expected}\nfound\n{e}"
        );
    }
}

#[test]
fn tracks_may_name_objects_lights_materials_and_the_camera() {
    let f = scene(
        "[[material]]\nname = \"m\"\n[[object]]\nname = \"o\"\ntype = \"sphere\"\nradius = 1\n\
         material = \"m\"\n[[light]]\nname = \"l\"\ntype = \"point\"\nposition = [0, 2, 0]\n\
         [[track]]\ntarget = \"object:o\"\nmotion = \"translate\"\nkeys = [[0, [0, 0, 0]], [1, [0, 1, 0]]]\n\
         [[track]]\ntarget = \"light:l\"\nmotion = \"orbit\"\naxis = [0, 1, 0]\nkeys = [[0, 0], [1, 90]]\n\
         [[track]]\ntarget = \"material:m\"\nmotion = \"rotate\"\naxis = [0, 1, 0]\nkeys = [[0, 0]]\n\
         [[track]]\ntarget = \"camera\"\nmotion = \"look_at\"\nat = \"group:o\"\n",
    );
    assert_eq!(f.scene.group("o").unwrap().shapes, [0]);
    assert_eq!(f.scene.group("l").unwrap().lights, [0]);
}

#[test]
fn the_showcase_renders_a_mirror_glass_and_checker() {
    use crate::render::{IntegratorKind, RenderSettings, Renderer};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/showcase/showcase.toml");
    let f = crate::format::load(&path).unwrap();
    let camera = f.camera.clone().unwrap().with_resolution(64, 36);
    let settings = RenderSettings {
        aa: Some(1),
        integrator: IntegratorKind::Whitted,
        ..RenderSettings::default()
    };
    let renderer = Renderer::new(&f.scene, &camera, settings).unwrap();
    let (image, _) = renderer.render(&|_| {}).unwrap();
    let frame = camera.frame();
    // The pixel a world point projects to (the screen at distance 1, pixels 2 s wide).
    let pixel = |p: Vec3| {
        let d = p - camera.eye;
        let (x, y) = (
            d.dot(frame.right) / d.dot(frame.forward),
            d.dot(frame.down) / d.dot(frame.forward),
        );
        let s2 = 2.0 * camera.retina_scale;
        let (px, py) = ((x / s2 + 32.0) as u32, (y / s2 + 18.0) as u32);
        Vec3::from_array(image.pixels[(py * 64 + px) as usize])
    };
    let sky = Vec3::new(0.45, 0.65, 1.0);
    // Where the mirror's normal tilts up by half (toward (0, 0.5, 1)), it sends the view
    // up and back over the camera to the sky: the pixel is 0.9 of the sky (the mirror
    // has no colour of its own, and its tight highlights point elsewhere).
    let mirror = pixel(Vec3::new(-1.2, 1.0, 0.0) + Vec3::new(0.0, 0.5, 1.0).normalize());
    assert!(close_rel(mirror, sky * 0.9, 0.05), "mirror {mirror}");
    // The glass is bright: it shows the lit floor and sky through it, never black.
    let glass = pixel(Vec3::new(1.3, 1.0, 1.6));
    assert!(glass.min_element() > 0.05, "glass {glass}");
    // Floor cells (the checker's unit cubes) alternate light and dark.
    let light_cell = pixel(Vec3::new(0.5, 0.0, 2.5));
    let dark_cell = pixel(Vec3::new(-0.5, 0.0, 2.5));
    let (a, b) = (light_cell.element_sum(), dark_cell.element_sum());
    assert!(
        a > 4.0 * b || b > 4.0 * a,
        "floor {light_cell} vs {dark_cell}"
    );
}

fn close_rel(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol * b.max_element()
}
