//! Animation tracks naming objects, lights, materials and the camera; the showcase scene rendered.

use super::*;
use crate::math::normalize;

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
    let (image, _) = renderer.render(&()).unwrap();
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
    let mirror = pixel(Vec3::new(-1.2, 1.0, 0.0) + normalize(Vec3::new(0.0, 0.5, 1.0)));
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
