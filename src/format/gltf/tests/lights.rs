//! KHR_lights_punctual lights on a Lambert floor, against their closed forms.

use super::*;

/// A grey Lambert floor (specular off, fully rough) under `light` at height 2, seen
/// straight down by an orthographic camera of half width `mag` centred above `x`.
fn lit_floor(light: Value, x: f32, mag: f32) -> Value {
    let mut b = Builder::default();
    b.mesh(&floor(50.0), None, 4, Some(0));
    b.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [light]}},
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
            "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}],
        "cameras": [{"type": "orthographic",
            "orthographic": {"xmag": mag, "ymag": mag, "znear": 0.01, "zfar": 100.0}}],
        "nodes": [
            {"mesh": 0},
            {"translation": [0.0, 2.0, 0.0], "rotation": LOOK_DOWN,
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [x, 5.0, 0.0], "rotation": LOOK_DOWN, "camera": 0}],
        "scenes": [{"nodes": [0, 1, 2]}],
        "scene": 0,
    }))
}

#[test]
fn a_lambert_floor_under_a_point_light_has_the_closed_form_radiance() {
    let (_dir, path) = write(&lit_floor(
        json!({"type": "point", "intensity": 10.0, "color": [1.0, 1.0, 1.0]}),
        0.0,
        1e-3,
    ));
    let image = render(&path, &sized(1, 1));
    let expected = 0.5 / PI * 10.0 / 4.0;
    for c in image.pixels[0] {
        assert!((c - expected).abs() <= 1e-6 * expected, "{c} vs {expected}");
    }
}

#[test]
fn a_spot_light_fades_between_its_cones_by_the_squared_ramp() {
    let (inner, outer) = (0.2f32, 0.4f32);
    let spot = json!({"type": "spot", "intensity": 10.0,
        "spot": {"innerConeAngle": inner, "outerConeAngle": outer}});
    for theta in [0.1f32, 0.3, 0.45] {
        let x = 2.0 * theta.tan();
        let (_dir, path) = write(&lit_floor(spot.clone(), x, 1e-4));
        let got = render(&path, &sized(1, 1)).pixels[0][0];
        let t = ((theta.cos() - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        let d2 = 4.0 + x * x;
        let expected = 0.5 / PI * 10.0 / d2 * theta.cos() * t * t;
        assert!(
            (got - expected).abs() <= 1e-4 * 0.4,
            "theta {theta}: {got} vs {expected}"
        );
    }
}

#[test]
fn a_light_past_its_range_lights_nothing_and_a_sun_gives_lux() {
    let ranged = json!({"type": "point", "intensity": 10.0, "range": 1.5});
    let (_dir, path) = write(&lit_floor(ranged, 0.0, 1e-3));
    assert_eq!(render(&path, &sized(1, 1)).pixels[0], [0.0; 3]);
    // A sun of 3 lux straight down: radiance 0.5 / pi * 3.
    let sun = json!({"type": "directional", "intensity": 3.0});
    let (_dir, path) = write(&lit_floor(sun, 0.0, 1e-3));
    let got = render(&path, &sized(1, 1)).pixels[0][0];
    assert!((got - 1.5 / PI).abs() < 1e-6, "{got}");
}
