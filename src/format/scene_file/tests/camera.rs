//! The camera's look-at, lens and render size; the ambient light and the background.

use super::*;
use crate::scene::Background;

#[test]
fn the_camera_looks_at_with_a_lens_and_the_render_size() {
    let f = scene(
        "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nfov = 90\naperture = 0.1\nlens_samples = 8\n\
         [render]\nwidth = 200\nheight = 100\naa = 2\nfilter = \"lanczos\"\nspp = 4\nmax_depth = 5\n\
         min_weight = 0.01\nseed = 7\nintegrator = \"classic\"\nexposure = -1\ntonemap = \"aces\"\n\
         denoise = true\nlight_sampling = \"one\"\n",
    );
    assert_eq!(f.settings.denoise, Some(true));
    assert_eq!(
        f.settings.light_sampling,
        Some(crate::options::LightSampling::One)
    );
    let c = f.camera.unwrap();
    assert_eq!((c.width, c.height, c.aa, c.spp), (200, 100, 2, 8));
    assert_eq!((c.focal_length, c.aperture), (4.0, 0.1));
    assert!((c.retina_scale * 200.0 - 1.0).abs() < 1e-6);
    // `spp` is the camera's key too; `lens_samples` (above) its older name.
    let named = scene("[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\naperture = 0.1\nspp = 8\n");
    assert_eq!(named.camera.unwrap().spp, 8);
    let s = f.settings;
    assert_eq!(
        (s.width, s.height, s.aa, s.spp, s.max_depth, s.seed),
        (Some(200), Some(100), Some(2), Some(4), Some(5), Some(7))
    );
    assert_eq!(s.filter, Some(crate::film::resample::Filter::Lanczos));
    assert_eq!(s.integrator, Some(crate::render::IntegratorKind::Classic));
    assert_eq!(
        (s.min_weight, s.exposure, s.tonemap),
        (Some(0.01), Some(-1.0), Some(crate::options::ToneMap::Aces))
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
fn an_orthographic_camera_sees_view_width_across() {
    let c = scene(
        "[camera]\nprojection = \"orthographic\"\nview_width = 4\nfrom = [0, 0, 5]\nat = [0, 0, 0]\n\
         [render]\nwidth = 200\nheight = 100\n",
    )
    .camera
    .unwrap();
    assert_eq!(c.projection, crate::scene::Projection::Orthographic);
    assert_eq!(c.retina_scale * 200.0, 2.0);
    let dir = Folder::new();
    for (text, expected) in [
        (
            "projection = \"orthographic\"\n",
            "an orthographic camera needs `view_width`",
        ),
        (
            "projection = \"orthographic\"\nview_width = 2\nfov = 30\n",
            "an orthographic camera has no field of view or lens",
        ),
        (
            "view_width = 2\n",
            "`view_width` is for projection = \"orthographic\"",
        ),
        (
            "projection = \"fisheye\"\n",
            "expected projection \"perspective\" or \"orthographic\"",
        ),
        (
            "projection = \"orthographic\"\nview_width = -1\n",
            "expected view_width > 0",
        ),
    ] {
        let e = dir.error(&format!(
            "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\n{text}"
        ));
        assert!(e.contains(expected), "{e}");
    }
}

#[test]
fn a_lens_shift_is_in_units_of_the_fitted_side() {
    let shift = |axis: &str| {
        scene(&format!(
            "[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nfov_axis = \"{axis}\"\n\
             shift = [0.25, -0.5]\n[render]\nwidth = 200\nheight = 100\n"
        ))
        .camera
        .unwrap()
        .shift
    };
    assert_eq!(shift("horizontal"), [0.25, -0.5]);
    // A vertical fit's side is the height, half the width here.
    assert_eq!(shift("vertical"), [0.125, -0.25]);
    let e = Folder::new().error("[camera]\nfrom = [0, 0, 5]\nat = [0, 0, 0]\nshift = [20, 0]\n");
    assert!(e.contains("expected a shift within [-10, 10]"), "{e}");
    let e = Folder::new().error(
        "[camera]\nprojection = \"orthographic\"\nview_width = 2\nfrom = [0, 0, 5]\n\
         at = [0, 0, 0]\nshift = [0.1, 0]\n",
    );
    assert!(e.contains("no field of view or lens"), "{e}");
}
