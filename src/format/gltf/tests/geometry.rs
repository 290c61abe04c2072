//! Cameras, the node tree, and glTF scenes beside the scene files that say the same.

use super::*;

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
    let first = job::prepare(&path, &JobOptions::default()).unwrap();
    assert_eq!((first.camera.width, first.camera.height), (960, 480));
    let half = first.camera.retina_scale * first.camera.height as f32;
    assert!((half - 0.25f32.tan()).abs() < 1e-6, "{half}");
    let by_name = JobOptions {
        camera_name: Some("top".into()),
        ..JobOptions::default()
    };
    let top = job::prepare(&path, &by_name).unwrap();
    assert_eq!(
        top.camera.projection,
        crate::scene::Projection::Orthographic
    );
    assert_eq!(top.camera.eye, Vec3::new(0.0, 0.0, 1.0));
    let by_index = JobOptions {
        camera_index: Some(1),
        ..JobOptions::default()
    };
    assert_eq!(job::prepare(&path, &by_index).unwrap().camera, top.camera);
    let missing = JobOptions {
        camera_index: Some(2),
        ..JobOptions::default()
    };
    let e = job::prepare(&path, &missing).err().unwrap().to_string();
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
    // The mesh placed twice is one object placed by two instances.
    assert_eq!(file.scene.shapes.len(), 0);
    assert_eq!(file.scene.objects.len(), 1);
    assert_eq!(file.scene.instances.len(), 2);
    assert_eq!(file.scene.flattened().shapes.len(), 2);
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

/// `EXT_mesh_gpu_instancing`: each instance's translation, rotation and scale place the
/// node's mesh before the node's own transform; mismatched attribute counts are an
/// error naming the node.
#[test]
fn gpu_instances_place_the_mesh_by_their_own_transform_then_the_nodes() {
    let mut b = Builder::default();
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    b.mesh(&tri, None, 4, None);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let translation = b.floats(&[0.0, 0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, -4.0], "VEC3");
    let rotation = b.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h, 0.0, 0.0, 0.0, 1.0],
        "VEC4",
    );
    let scale = b.floats(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0], "VEC3");
    let short = b.floats(&[1.0, 1.0, 1.0], "VEC3");
    let node = |scale_accessor: usize| {
        json!({"translation": [0.0, 10.0, 0.0], "mesh": 0,
            "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {
                "TRANSLATION": translation, "ROTATION": rotation, "SCALE": scale_accessor}}}})
    };
    let doc = b.finish(json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "extensionsRequired": ["EXT_mesh_gpu_instancing"],
        "nodes": [node(scale), node(short)],
        "scenes": [{"nodes": [0]}, {"nodes": [1]}],
    }));
    let (_dir, path) = write(&doc);
    let file = crate::format::load(&path).unwrap();
    assert!(file.warnings.is_empty(), "{:?}", file.warnings);
    assert_eq!(file.scene.instances.len(), 3);
    let flat = file.scene.flattened();
    assert_eq!(flat.shapes.len(), 3);
    let node = glam::Mat4::from_translation(glam::Vec3::new(0.0, 10.0, 0.0));
    let instances = [
        glam::Mat4::IDENTITY,
        glam::Mat4::from_scale_rotation_translation(
            glam::Vec3::splat(2.0),
            glam::Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            glam::Vec3::new(5.0, 0.0, 0.0),
        ),
        glam::Mat4::from_translation(glam::Vec3::new(0.0, 0.0, -4.0)),
    ];
    for (k, instance) in instances.iter().enumerate() {
        let crate::scene::Shape::Triangle(t) = flat.shapes.get(k) else {
            panic!("shape {k} is not a triangle");
        };
        for (corner, v) in t.v.iter().zip(tri.chunks(3)) {
            let want: Vec3 = (node * *instance)
                .transform_point3(glam::Vec3::new(v[0], v[1], v[2]))
                .into();
            assert!(
                (*corner - want).abs().max_element() < 1e-5,
                "instance {k}: {corner} vs {want}"
            );
        }
    }
    // Scene 1's node gives SCALE one element for three placements.
    let mut doc = doc;
    doc["scene"] = json!(1);
    let (_dir, path) = write(&doc);
    let e = crate::format::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("nodes[1]") && e.contains("different counts"),
        "{e}"
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
         [[material]]\nname = \"grey\"\ncolor = [0.5, 0.5, 0.5]\n\
         [[material]]\nname = \"red\"\ncolor = [0.8, 0.2, 0.1]\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"grey\"\nvertices = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3]]\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"grey\"\nvertices = [[-3, 0, -3], [3, 0, 3], [3, 0, -3]]\n\
         [[object]]\ntype = \"triangle\"\nmaterial = \"red\"\nvertices = [{t}]\n\
         [[light]]\ntype = \"point\"\nposition = [1, 3, 1]\ncolor = [1.0, 0.9, 0.8]\nintensity = 20\n\
         falloff = \"inverse_square\"\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nintensity = 1.5\n",
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
    assert!(s.surfaces[0].openpbr.is_some());
}

/// A mesh placed by several nodes is held once and placed by instances; where it
/// emits, its placed triangles are one light per emissive material, as copies were.
#[test]
fn a_mesh_placed_twice_is_instanced_and_lights_where_it_emits() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    for emits in [false, true] {
        let mut b = Builder::default();
        b.mesh(&tri, None, 4, Some(0));
        let glow = if emits { [1.0, 1.0, 1.0] } else { [0.0; 3] };
        let doc = b.finish(json!({
            "materials": [{"emissiveFactor": glow}],
            "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0.0, 0.0, 2.0], "scale": [2.0, 1.0, 1.0]}],
            "scenes": [{"nodes": [0, 1]}],
        }));
        let (_dir, path) = write(&doc);
        let scene = crate::format::load(&path).unwrap().scene;
        assert_eq!(scene.instances.len(), 2, "emits {emits}");
        assert_eq!((scene.shapes.len(), scene.placed_triangles()), (0, 2));
        assert_eq!(scene.lights.len(), emits as usize);
        if emits {
            let crate::scene::LightKind::Mesh { shapes, cdf, area } = &scene.lights[0].kind else {
                panic!("{:?}", scene.lights[0])
            };
            let placed = |instance| crate::scene::ShapeId { instance, shape: 0 };
            assert_eq!(shapes, &[placed(0), placed(1)]);
            // The second is scaled twice as wide: 0.5 and 1.0 square units.
            assert_eq!((cdf.as_slice(), *area), (&[1.0 / 3.0, 1.0][..], 1.5));
        }
    }
}

/// A node that flattens a mesh placed twice onto a plane (a scale of 0 along one axis)
/// places world copies of its triangles, normals turned by the cofactor matrix, where
/// an instance's inverse would not exist; a scale of 0 along two axes places nothing.
#[test]
fn a_flattening_node_copies_its_mesh_into_the_scene() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut b = Builder::default();
    b.mesh(&tri, None, 4, None);
    let doc = b.finish(json!({
        "nodes": [
            {"mesh": 0},
            {"mesh": 0, "translation": [0.0, 0.0, 2.0], "scale": [3.0, 1.0, 0.0]},
            {"mesh": 0, "scale": [0.0, 1.0, 0.0]},
        ],
        "scenes": [{"nodes": [0, 1, 2]}],
    }));
    let (_dir, path) = write(&doc);
    let scene = crate::format::load(&path).unwrap().scene;
    assert_eq!((scene.instances.len(), scene.shapes.len()), (1, 1));
    let crate::scene::Shape::Triangle(t) = scene.shapes.get(0) else {
        panic!("{:?}", scene.shapes)
    };
    let v = |x, y, z| Vec3::new(x, y, z);
    assert_eq!(t.v, [v(0.0, 0.0, 2.0), v(3.0, 0.0, 2.0), v(0.0, 1.0, 2.0)]);
}

/// A mesh without a material, placed twice: its instances wear Prism's matte default,
/// which is added though no triangle of the scene's own wears it.
#[test]
fn instances_of_a_mesh_without_a_material_wear_the_default() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut b = Builder::default();
    b.mesh(&tri, None, 4, None);
    let doc = b.finish(json!({
        "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0.0, 0.0, 2.0]}],
        "scenes": [{"nodes": [0, 1]}],
    }));
    let (_dir, path) = write(&doc);
    let scene = crate::format::load(&path).unwrap().scene;
    assert_eq!((scene.shapes.len(), scene.instances.len()), (0, 2));
    let m = scene.objects[0].material_of[0] as usize;
    assert!(m < scene.surfaces.len() && m < scene.materials.len());
    assert_eq!(scene.surfaces[m].openpbr, None);
}

/// A glTF file whose nodes reuse a mesh, read as a mesh object of a scene file: its
/// instances become the object's own triangles, glowing ones with their light.
#[test]
fn a_scene_file_mesh_from_a_gltf_of_instances_keeps_them() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut b = Builder::default();
    b.mesh(&tri, None, 4, Some(0));
    let doc = b.finish(json!({
        "materials": [{"emissiveFactor": [1.0, 1.0, 1.0]}],
        "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0.0, 0.0, 2.0]}],
        "scenes": [{"nodes": [0, 1]}],
    }));
    let (dir, _) = write(&doc);
    let toml = dir.path().join("scene.toml");
    std::fs::write(
        &toml,
        "[[object]]\ntype = \"mesh\"\nfile = \"scene.gltf\"\ntranslate = [0, 1, 0]\n",
    )
    .unwrap();
    let scene = crate::format::load(&toml).unwrap().scene;
    assert_eq!((scene.shapes.len(), scene.instances.len()), (2, 0));
    assert_eq!(scene.shapes.get(1).bounds().min, Vec3::new(0.0, 1.0, 2.0));
    let crate::scene::LightKind::Mesh { shapes, area, .. } = &scene.lights[0].kind else {
        panic!("{:?}", scene.lights)
    };
    assert_eq!(shapes, &[0, 1].map(crate::scene::ShapeId::world));
    assert_eq!(*area, 1.0);
}
