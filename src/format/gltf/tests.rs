//! glTF scenes written here, small enough that geometry and optics give the answer.

use super::*;
use crate::film::Image;
use crate::render::Renderer;
use crate::still::{self, StillOptions};
use base64::Engine as _;
use serde_json::{Value, json};
use std::f32::consts::PI;
use std::path::PathBuf;

/// A glTF file being written: its JSON and one buffer.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
}

impl Builder {
    fn floats(&mut self, data: &[f32], kind: &str) -> usize {
        let n = match kind {
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 1,
        };
        let offset = self.bin.len();
        for v in data {
            self.bin.extend(v.to_le_bytes());
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 4}));
        let mut acc = json!({"bufferView": self.views.len() - 1, "componentType": 5126,
            "count": data.len() / n, "type": kind});
        if kind == "VEC3" {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for p in data.chunks(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    fn indices(&mut self, data: &[u16]) -> usize {
        let offset = self.bin.len();
        for v in data {
            self.bin.extend(v.to_le_bytes());
        }
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 2}));
        self.accessors.push(
            json!({"bufferView": self.views.len() - 1, "componentType": 5123,
            "count": data.len(), "type": "SCALAR"}),
        );
        self.accessors.len() - 1
    }

    /// A mesh of `positions` (and `indices`, with `mode`) wearing `material`.
    fn mesh(
        &mut self,
        positions: &[f32],
        indices: Option<&[u16]>,
        mode: u32,
        material: Option<usize>,
    ) -> usize {
        let p = self.floats(positions, "VEC3");
        let mut prim = json!({"attributes": {"POSITION": p}, "mode": mode});
        if let Some(i) = indices {
            prim["indices"] = json!(self.indices(i));
        }
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        self.meshes.push(json!({"primitives": [prim]}));
        self.meshes.len() - 1
    }

    /// The document with `rest` (nodes, scenes, materials ...) merged in.
    fn finish(self, rest: Value) -> Value {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": self.bin.len(), "uri": uri}],
            "bufferViews": self.views,
            "accessors": self.accessors,
            "meshes": self.meshes,
        });
        for (k, v) in rest.as_object().unwrap() {
            doc[k] = v.clone();
        }
        doc
    }
}

/// A square of half side `h` in the plane y = 0 (two triangles facing +y).
fn floor(h: f32) -> Vec<f32> {
    vec![
        -h, 0.0, -h, -h, 0.0, h, h, 0.0, h, -h, 0.0, -h, h, 0.0, h, h, 0.0, -h,
    ]
}

/// A square of half side `h` in the plane z = `z`, facing +z.
fn wall(h: f32, z: f32) -> Vec<f32> {
    vec![-h, -h, z, h, -h, z, h, h, z, -h, -h, z, h, h, z, -h, h, z]
}

fn write(doc: &Value) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    (dir, path)
}

fn render(path: &Path, options: &StillOptions) -> Image {
    let s = still::prepare(path, options).unwrap();
    Renderer::new(&s.scene, &s.camera, s.settings)
        .unwrap()
        .render(&|_| {})
        .unwrap()
        .0
}

fn sized(w: u32, h: u32) -> StillOptions {
    StillOptions {
        width: Some(w),
        height: Some(h),
        aa: Some(1),
        ..StillOptions::default()
    }
}

/// The rotation (x, y, z, w) that turns a node's -z (where cameras look) to -y.
const LOOK_DOWN: [f32; 4] = [
    -std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
];

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

/// A white unlit square of half side 1 at z = -2 before a camera at the origin.
fn square_before(camera: Value) -> Value {
    let mut b = Builder::default();
    b.mesh(&wall(1.0, -2.0), None, 4, Some(0));
    b.finish(json!({
        "extensionsUsed": ["KHR_materials_unlit"],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
            "extensions": {"KHR_materials_unlit": {}}}],
        "cameras": [camera],
        "nodes": [{"mesh": 0}, {"camera": 0, "name": "view"}],
        "scenes": [{"nodes": [0, 1]}],
    }))
}

/// Which pixels of a 64 x 64 render see the square.
fn coverage(doc: &Value) -> (Vec<bool>, Image) {
    let (_dir, path) = write(doc);
    let image = render(&path, &sized(64, 64));
    // The square is (0.2, 0.4, 0.6); the background the default lighting's grey.
    (image.pixels.iter().map(|p| p[2] > 0.5).collect(), image)
}

#[test]
fn a_square_projects_to_the_pixels_through_perspective_and_orthographic_cameras() {
    // yfov 90 degrees: at distance 2 the screen spans [-2, 2]; the square, the middle
    // half: pixels 16 to 47 both ways. Orthographic of half width 2: the same.
    let perspective = json!({"type": "perspective",
        "perspective": {"yfov": PI / 2.0, "aspectRatio": 1.0, "znear": 0.1}});
    let orthographic = json!({"type": "orthographic",
        "orthographic": {"xmag": 2.0, "ymag": 2.0, "znear": 0.1, "zfar": 10.0}});
    for camera in [perspective, orthographic] {
        let (seen, image) = coverage(&square_before(camera.clone()));
        for y in 0..64 {
            for x in 0..64 {
                let inside = (16..48).contains(&x) && (16..48).contains(&y);
                assert_eq!(seen[y * 64 + x], inside, "{camera}: pixel ({x}, {y})");
            }
        }
        // Unlit: the base colour itself, linear.
        assert_eq!(image.pixels[32 * 64 + 32], [0.2, 0.4, 0.6]);
    }
}

#[test]
fn a_cameras_aspect_ratio_sets_the_output_and_names_pick_cameras() {
    let mut doc = square_before(json!({"type": "perspective",
        "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}));
    doc["cameras"]
        .as_array_mut()
        .unwrap()
        .push(json!({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 9.0}}));
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"camera": 1, "name": "top", "translation": [0.0, 0.0, 1.0]}));
    doc["scenes"][0]["nodes"] = json!([0, 1, 2]);
    let (_dir, path) = write(&doc);
    let first = still::prepare(&path, &StillOptions::default()).unwrap();
    assert_eq!((first.camera.width, first.camera.height), (960, 480));
    let half = first.camera.retina_scale * first.camera.height as f32;
    assert!((half - 0.25f32.tan()).abs() < 1e-6, "{half}");
    let by_name = StillOptions {
        camera_name: Some("top".into()),
        ..StillOptions::default()
    };
    let top = still::prepare(&path, &by_name).unwrap();
    assert_eq!(
        top.camera.projection,
        crate::scene::Projection::Orthographic
    );
    assert_eq!(top.camera.eye, Vec3::new(0.0, 0.0, 1.0));
    let by_index = StillOptions {
        camera_index: Some(1),
        ..StillOptions::default()
    };
    assert_eq!(still::prepare(&path, &by_index).unwrap().camera, top.camera);
    let missing = StillOptions {
        camera_index: Some(2),
        ..StillOptions::default()
    };
    let e = still::prepare(&path, &missing).err().unwrap().to_string();
    assert!(
        e.contains("no camera has index 2: the scene's cameras are 0: `view`, 1: `top`"),
        "{e}"
    );
}

#[test]
fn a_node_hierarchys_bounds_are_its_matrices_product_and_instances_count() {
    let mut b = Builder::default();
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    b.mesh(&tri, None, 4, None);
    // Parent: translate (1, 2, 3), rotate 90 degrees about z, scale 2. Child: a matrix
    // translating by (0, 0, 5) and scaling x by 3; it and the parent place the mesh.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let doc = b.finish(json!({
        "nodes": [
            {"translation": [1.0, 2.0, 3.0], "rotation": [0.0, 0.0, h, h], "scale": [2.0, 2.0, 2.0],
             "children": [1], "mesh": 0},
            {"matrix": [3.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 5.0, 1.0],
             "mesh": 0}],
        "scenes": [{"nodes": [0]}],
    }));
    let (_dir, path) = write(&doc);
    let file = crate::format::load(&path).unwrap();
    assert_eq!(file.dialect, SceneDialect::Gltf);
    assert_eq!(file.scene.shapes.len(), 2);
    let parent = glam::Mat4::from_scale_rotation_translation(
        Vec3::splat(2.0).into(),
        glam::Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
        glam::Vec3::new(1.0, 2.0, 3.0),
    );
    let child = parent
        * glam::Mat4::from_translation(glam::Vec3::new(0.0, 0.0, 5.0))
        * glam::Mat4::from_scale(glam::Vec3::new(3.0, 1.0, 1.0));
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    for m in [parent, child] {
        for v in tri.chunks(3) {
            let p: Vec3 = m.transform_point3(glam::Vec3::new(v[0], v[1], v[2])).into();
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let bounds = file.scene.bounds();
    assert!(
        (bounds.min - lo).abs().max_element() < 1e-5,
        "{bounds:?} vs {lo}"
    );
    assert!(
        (bounds.max - hi).abs().max_element() < 1e-5,
        "{bounds:?} vs {hi}"
    );
}

#[test]
fn a_mirroring_node_keeps_faces_outward_and_strips_and_fans_triangulate() {
    let mut b = Builder::default();
    b.mesh(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        None,
        4,
        None,
    );
    // A strip and a fan of the four corners of a unit square: two triangles each.
    let quad = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
    b.mesh(&quad, None, 5, None);
    b.mesh(&quad, Some(&[0, 1, 3, 2]), 6, None);
    let doc = b.finish(json!({
        "nodes": [{"mesh": 0, "scale": [-1.0, 1.0, 1.0]}, {"mesh": 1}, {"mesh": 2}],
        "scenes": [{"nodes": [0, 1, 2]}],
    }));
    let (_dir, path) = write(&doc);
    let scene = crate::format::load(&path).unwrap().scene;
    assert_eq!(scene.shapes.len(), 5);
    for i in 0..5 {
        let crate::scene::Shape::Triangle(t) = scene.shapes.get(i) else {
            panic!()
        };
        assert!(t.normal().z > 0.99, "triangle {i}: {:?}", t.normal());
    }
}

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
fn materials_map_onto_the_whitted_model_as_documented() {
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
    let mr = s[0].metallic_roughness.unwrap();
    assert_eq!((mr.metallic, mr.roughness), (0.25, 0.5));
    assert!((mr.f0.x - 0.04).abs() < 1e-7);
    assert!((s[0].diffuse - 1.0 / PI).abs() < 1e-7);
    assert_eq!(s[0].emission, Vec3::new(4.0, 2.0, 0.0));
    // The emitter is an area light.
    assert_eq!(file.scene.lights.len(), 1);
    assert_eq!(file.scene.lights[0].kind_name(), "mesh");
    // Glass: Fresnel, ior, Beer from the colour left after attenuationDistance.
    let glass = &s[1];
    assert!(glass.fresnel && glass.metallic_roughness.is_none());
    assert_eq!(
        (glass.ior, glass.transmission),
        (1.33, Vec3::new(0.9, 1.0, 1.0))
    );
    assert_eq!(glass.diffuse, 0.0);
    let beer = Vec3::new(0.5f32.ln(), 0.25f32.ln(), 0.0) / -2.0;
    assert!(
        (glass.absorption - beer).abs().max_element() < 1e-7,
        "{:?}",
        glass.absorption
    );
    // A constant alpha below the cutoff cuts the whole surface out.
    let slot = s[2].alpha_map.expect("a cut-out");
    assert_eq!(file.scene.images[slot.image as usize].texel(0, 0).w, 0.0);
    // Roughness to exponent: a = r^2, 2 / a^2 - 2.
    assert_eq!(
        crate::scene::MetallicRoughness::exponent(0.5),
        2.0 / 0.0625 - 2.0
    );
    assert_eq!(crate::scene::MetallicRoughness::exponent(1.0), 0.0);
    assert_eq!(crate::scene::MetallicRoughness::exponent(0.0), 1e4);
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
    let s = still::prepare(&path, &sized(1, 1)).unwrap();
    // The emitter-free, light-free file got the key and fill.
    assert_eq!(s.scene.lights.len(), 2);
    let mut scene = s.scene.clone();
    scene.lights.clear();
    let image = Renderer::new(&scene, &s.camera, s.settings.clone())
        .unwrap()
        .render(&|_| {})
        .unwrap()
        .0;
    let got = Vec3::from_array(image.pixels[0]);
    assert!(
        (got - Vec3::new(0.9, 0.5, 0.2)).abs().max_element() < 1e-6,
        "{got}"
    );
}

#[test]
fn bad_files_are_errors_naming_the_json_path() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let base = |f: &dyn Fn(&mut Value)| {
        let mut b = Builder::default();
        b.mesh(&tri, Some(&[0, 1, 2]), 4, None);
        let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
        f(&mut doc);
        doc
    };
    let cases: Vec<(Value, &str)> = vec![
        (
            base(&|d| {
                d["accessors"][1]["count"] = json!(4);
            }),
            "meshes[0].primitives[0].indices: 4 elements of 2 bytes from byte 0 need more than",
        ),
        (
            base(&|d| {
                d["bufferViews"][0]["byteLength"] = json!(400);
            }),
            "past the end of buffer 0",
        ),
        (
            base(&|d| {
                d["buffers"][0]["byteLength"] = json!(4000);
            }),
            "buffers[0]: byteLength is 4000 but the data holds",
        ),
        (
            base(&|d| {
                d["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
            }),
            "scenes[0] lists nodes[0] as a root, but it is a child of nodes[1]",
        ),
        (
            base(&|d| {
                d["nodes"] = json!([{"mesh": 0, "children": [2]}, {"children": [2]}, {}]);
                d["scenes"] = json!([{"nodes": [0, 1]}]);
            }),
            "nodes[2] has two parents",
        ),
        (
            base(&|d| {
                d["buffers"][0]["uri"] = json!("http://example.com/b.bin");
            }),
            "buffers[0]: the URI `http://example.com/b.bin` is not a file",
        ),
        (
            base(&|d| {
                d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(9);
            }),
            "meshes[0].primitives[0].attributes",
        ),
    ];
    for (doc, expected) in cases {
        let (_dir, path) = write(&doc);
        let e = crate::format::load(&path).expect_err(expected).to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(e.contains(expected), "{e}\nexpected: {expected}");
    }
    // An index past the vertices, and a NaN position.
    let mut b = Builder::default();
    b.mesh(&tri, Some(&[0, 1, 7]), 4, None);
    let doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).err().unwrap().to_string();
    assert!(
        e.contains("meshes[0].primitives[0].indices: index 7 is past the primitive's 3 vertices"),
        "{e}"
    );
    let mut b = Builder::default();
    b.mesh(
        &[0.0, f32::NAN, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        None,
        4,
        None,
    );
    let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    doc["accessors"][0].as_object_mut().unwrap().remove("min");
    doc["accessors"][0].as_object_mut().unwrap().remove("max");
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).err().unwrap().to_string();
    assert!(
        e.contains("attributes.POSITION: vertex 0 is not finite"),
        "{e}"
    );
}

#[test]
fn an_unknown_extension_is_an_error_listing_the_formats_and_dialect() {
    let e = crate::format::load(Path::new("/nonexistent/model.fbx"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("cannot tell the scene format from the extension `.fbx`"),
        "{e}"
    );
    assert!(
        e.contains(".gltf, .glb") && e.contains("--dialect obj|gltf|ply|toml|objx"),
        "{e}"
    );
}

/// A floor and a tilted triangle over it, under a point light and a sun, seen by an
/// orthographic camera: as glTF, and as the Prism scene file that says the same.
#[test]
fn the_same_scene_as_gltf_and_as_a_scene_file_renders_bit_for_bit_the_same() {
    let mut b = Builder::default();
    b.mesh(&floor(3.0), None, 4, Some(0));
    let tri = [-1.0, 0.5, 0.0, 1.0, 0.5, 0.2, 0.0, 1.5, -0.5];
    b.mesh(&tri, None, 4, Some(1));
    let lambert = |c: [f32; 3]| {
        json!({"pbrMetallicRoughness": {"baseColorFactor": [c[0], c[1], c[2], 1.0],
            "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}})
    };
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 20.0, "color": [1.0, 0.9, 0.8]},
            {"type": "directional", "intensity": 1.5}]}},
        "materials": [lambert([0.5, 0.5, 0.5]), lambert([0.8, 0.2, 0.1])],
        "cameras": [{"type": "orthographic",
            "orthographic": {"xmag": 2.5, "ymag": 2.5, "znear": 0.1, "zfar": 50.0}}],
        "nodes": [
            {"mesh": 0}, {"mesh": 1},
            {"translation": [1.0, 3.0, 1.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"rotation": LOOK_DOWN, "extensions": {"KHR_lights_punctual": {"light": 1}}},
            // Straight down, the image's up along -z: exact columns, as the file's
            // look-at below gives them.
            {"matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 5.0, 0.0, 1.0],
             "camera": 0}],
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
    }));
    let (dir, gltf) = write(&doc);
    let f = |v: f32| format!("{v:?}");
    let tri_toml: Vec<String> = tri
        .chunks(3)
        .map(|p| format!("[{}, {}, {}]", f(p[0]), f(p[1]), f(p[2])))
        .collect();
    let toml = format!(
        "[camera]\nprojection = \"orthographic\"\nview_width = 5.0\nfrom = [0, 5, 0]\nat = [0, 0, 0]\nup = [0, 0, -1]\n\
         [[material]]\nname = \"grey\"\ncolor = [0.5, 0.5, 0.5]\ndiffuse = {pi}\n\
         [[material]]\nname = \"red\"\ncolor = [0.8, 0.2, 0.1]\ndiffuse = {pi}\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"grey\"\nvertices = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3]]\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"grey\"\nvertices = [[-3, 0, -3], [3, 0, 3], [3, 0, -3]]\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"red\"\nvertices = [{t}]\n\
         [[light]]\ntype = \"point\"\nposition = [1, 3, 1]\ncolor = [1.0, 0.9, 0.8]\nintensity = 20\n\
         falloff = \"inverse_square\"\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nintensity = 1.5\n",
        pi = 1.0 / std::f64::consts::PI,
        t = tri_toml.join(", ")
    );
    let toml_path = dir.path().join("scene.toml");
    std::fs::write(&toml_path, toml).unwrap();
    let options = sized(48, 48);
    let a = render(&gltf, &options);
    let b = render(&toml_path, &options);
    let lit = a.pixels.iter().filter(|p| p[0] > 0.0).count();
    assert!(lit > 48 * 40, "the floor fills the view: {lit}");
    let bits = |i: &Image| -> Vec<u32> { i.pixels.iter().flatten().map(|c| c.to_bits()).collect() };
    assert_eq!(bits(&a), bits(&b));
}

#[test]
fn a_scene_file_places_a_gltf_mesh_with_its_materials_and_lights() {
    let mut b = Builder::default();
    b.mesh(&wall(1.0, 0.0), None, 4, Some(0));
    let doc = b.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 3.0}]}},
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1.0]},
            "emissiveFactor": [1.0, 1.0, 1.0]}],
        "nodes": [{"mesh": 0, "name": "panel"},
            {"translation": [0.0, 0.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "scenes": [{"nodes": [0, 1]}],
    }));
    let (dir, _) = write(&doc);
    let toml = dir.path().join("scene.toml");
    std::fs::write(
        &toml,
        "[[object]]\ntype = \"mesh\"\nfile = \"scene.gltf\"\ntranslate = [10, 0, 0]\nscale = 2\n",
    )
    .unwrap();
    let file = crate::format::load(&toml).unwrap();
    let s = &file.scene;
    assert_eq!(s.shapes.len(), 2);
    assert!(
        (s.bounds().min - Vec3::new(8.0, -2.0, 0.0))
            .abs()
            .max_element()
            < 1e-6
    );
    let kinds: Vec<_> = s.lights.iter().map(|l| l.kind_name()).collect();
    assert_eq!(kinds, ["point", "mesh"]);
    assert_eq!(s.lights[0].position, Vec3::new(10.0, 0.0, 4.0));
    // The emitter's area is the placed one: a 2 x 2 square scaled by 2.
    let crate::scene::LightKind::Mesh { area, .. } = s.lights[1].kind else {
        panic!()
    };
    assert_eq!(area, 16.0);
    assert!(s.surfaces[0].metallic_roughness.is_some());
}

/// Faces of `wall(h, z)` wound the other way: facing -z.
fn back_wall(h: f32, z: f32) -> Vec<f32> {
    let mut w = wall(h, z);
    for tri in w.chunks_mut(9) {
        let (a, b) = tri.split_at_mut(6);
        a[3..6].swap_with_slice(&mut b[0..3]);
    }
    w
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
fn a_large_accessor_named_by_many_primitives_is_refused_before_it_is_read_again() {
    // A sparse POSITION accessor of 2^24 vertices with no bytes behind it (200 MB once
    // decoded), named by 30 primitives: past the decoding budget at the 22nd, whose
    // counts are checked before it is read.
    let mut b = Builder::default();
    b.mesh(&[0.0; 9], Some(&[0, 1, 2]), 4, None);
    let mut doc = b.finish(json!({"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}));
    doc["accessors"][0] = json!({"componentType": 5126, "count": 1 << 24, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                   "values": {"bufferView": 0}}});
    let prim = doc["meshes"][0]["primitives"][0].clone();
    doc["meshes"][0]["primitives"] = json!(vec![prim; 30]);
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("would decode to more than 4294967296 bytes"),
        "{e}"
    );
}
