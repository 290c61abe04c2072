//! Each object type and transform, with exact positions: spheres, quads, triangles, boxes, disks, cylinders, planes and mesh files.

use super::*;
use crate::math::{cross, normalize};
use crate::scene::{Albedo, LightKind, Shape, ShapeId};

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
        let n = normalize(cross(r.v[1] - r.v[0], r.v[3] - r.v[0]));
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
    assert_close(mesh.normals[0], normalize(v(0.5, 1.0, 0.0)));
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
            assert_close(normal, normalize(radial));
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
    let n = normalize(cross(r.v[1] - r.v[0], r.v[3] - r.v[0]));
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
        "DIR/scene.toml:3:8: expected a mesh file .obj, .ply, .gltf, .glb or .objx, found DIR/scene.toml"
    );
}

#[test]
fn a_mesh_file_with_z_up_is_turned_to_y_up() {
    let dir = Folder::new();
    // A triangle standing up along +z, as Blender keeps it.
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n");
    let f = dir
        .load("[[object]]\ntype = \"mesh\"\nfile = \"tri.obj\"\nup_axis = \"z\"\nsmooth = true\n");
    let Shape::Triangle(t) = f.scene.shapes.get(0) else {
        panic!()
    };
    assert_eq!(t.v, [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]);
    assert_eq!(f.scene.meshes.len(), 1, "smooth normals");
    let e = dir.error("[[object]]\ntype = \"mesh\"\nfile = \"tri.obj\"\nup_axis = \"x\"\n");
    assert!(
        e.contains("expected up_axis \"y\" or \"z\", found \"x\""),
        "{e}"
    );
}

/// `type = "instance"` places a named mesh object again, by its own transform or by
/// each of its `transforms` (applied before it): one object in memory, placed like the
/// same mesh written as objects of its own, and rendered as the flattened twin.
#[test]
fn instances_place_a_named_mesh_by_their_transforms() {
    let dir = Folder::new();
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let f = dir.load(
        "[[object]]\nname = \"tri\"\ntype = \"mesh\"\nfile = \"tri.obj\"\n\
         material = { color = [0, 1, 0] }\n\
         [[object]]\ntype = \"instance\"\nof = \"tri\"\ntranslate = [0, 0, -2]\n\
         [[object]]\ntype = \"instance\"\nof = \"tri\"\ntranslate = [10, 0, 0]\n\
         transforms = [[[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[-1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]\n",
    );
    let scene = &f.scene;
    assert_eq!(scene.shapes.len(), 1, "the mesh object itself");
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.instances.len(), 3);
    let green = scene.material_of[0];
    assert_eq!(scene.objects[0].material_of, [green]);
    let flat = scene.flattened();
    let corners = |i: usize| {
        let Shape::Triangle(t) = flat.shapes.get(i) else {
            panic!()
        };
        t.v
    };
    assert_eq!(
        corners(1),
        [v(0.0, 0.0, -2.0), v(1.0, 0.0, -2.0), v(0.0, 1.0, -2.0)]
    );
    assert_eq!(
        corners(2),
        [v(10.0, 0.0, 0.0), v(12.0, 0.0, 0.0), v(10.0, 1.0, 0.0)]
    );
    // The mirror keeps the face turned the way it was: its winding is reversed.
    assert_eq!(
        corners(3),
        [v(15.0, 0.0, 0.0), v(15.0, 1.0, 0.0), v(14.0, 0.0, 0.0)]
    );
    let e = dir.error("[[object]]\ntype = \"instance\"\nof = \"tree\"\n");
    assert_eq!(
        e,
        "DIR/scene.toml:3:6: expected the name of a mesh object given before this instance, \
         found \"tree\""
    );
    let e = dir.error(
        "[[object]]\nname = \"tri\"\ntype = \"mesh\"\nfile = \"tri.obj\"\n\
         [[object]]\ntype = \"instance\"\nof = \"tri\"\n\
         transforms = [[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]]\n",
    );
    assert!(
        e.contains("DIR/scene.toml:8:14: expected the last row of transform 0"),
        "{e}"
    );
    let e = dir.error("[[object]]\ntype = \"instance\"\n");
    assert!(e.contains("an instance needs `of` or `file`"), "{e}");
    // Transforms are matrices: 3 x 3 is too few, a number is none, and a name only
    // names arrays handed over in memory (Python's).
    let tri = "[[object]]\nname = \"tri\"\ntype = \"mesh\"\nfile = \"tri.obj\"\n\
               [[object]]\ntype = \"instance\"\nof = \"tri\"\n";
    for (transforms, says) in [
        (
            "[[[1, 0, 0], [0, 1, 0], [0, 0, 1]]]",
            "invalid length 3, expected an array of length 4",
        ),
        ("5", "expected a list of 4 x 4 matrices"),
        (
            "\"trees\"",
            "found the name \"trees\", which no array handed over holds",
        ),
    ] {
        let e = dir.error(&format!("{tri}transforms = {transforms}\n"));
        assert!(e.contains(says), "{transforms}: {e}");
    }
}

/// An instance of a `file` holds the mesh without placing it anywhere else; a later
/// instance may place it again by the first one's name.
#[test]
fn an_instance_of_a_file_holds_the_mesh_once_for_every_placement() {
    let dir = Folder::new();
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let f = dir.load(
        "[[object]]\nname = \"trees\"\ntype = \"instance\"\nfile = \"tri.obj\"\n\
         material = { color = [0, 1, 0] }\n\
         transforms = [[[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[1, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]\n\
         [[object]]\ntype = \"instance\"\nof = \"trees\"\ntranslate = [0, 5, 0]\n",
    );
    let scene = &f.scene;
    assert_eq!(scene.shapes.len(), 0);
    assert_eq!((scene.objects.len(), scene.instances.len()), (1, 3));
    let m = scene.objects[0].material_of[0] as usize;
    assert_eq!(scene.surfaces[m].albedo, Albedo::Color(Vec3::Y));
    let bounds = scene.bounds();
    assert_eq!(
        (bounds.min, bounds.max),
        (v(0.0, 0.0, 0.0), v(3.0, 6.0, 0.0))
    );
}

/// A plane is sized by the instances too: a wide forest still stands on it.
#[test]
fn a_plane_is_sized_by_the_instances_too() {
    let dir = Folder::new();
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let f = dir.load(
        "[[object]]\ntype = \"plane\"\n\
         [[object]]\ntype = \"instance\"\nfile = \"tri.obj\"\n\
         transforms = [[[1, 0, 0, -1000], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[1, 0, 0, 1000], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]\n",
    );
    // A hundred times the scene's diagonal (2001) on a side.
    let plane = f.scene.shapes.get(0).bounds();
    assert!(plane.max.x > 2001.0 * 50.0, "{plane:?}");
}

/// Each instance of a glowing mesh is a light of its own, over its placed triangles,
/// as a copy of it was: the object's own glow (`emission` on it), or the glowing
/// materials of its file.
#[test]
fn instances_of_a_glowing_mesh_are_lights() {
    let dir = Folder::new();
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    dir.write(
        "lamp.mtl",
        "newmtl glow\nKe 2 2 2\nnewmtl matte\nKd 0.5 0.5 0.5\n",
    );
    dir.write(
        "lamp.obj",
        "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         usemtl glow\nf 1 2 3\nusemtl matte\nf 2 4 3\n",
    );
    let f = dir.load(
        "[[object]]\nname = \"tri\"\ntype = \"mesh\"\nfile = \"tri.obj\"\n\
         material = { emission = [4, 4, 4] }\n\
         [[object]]\ntype = \"instance\"\nof = \"tri\"\ntranslate = [0, 0, -2]\n\
         scale = [2, 2, 2]\n\
         [[object]]\ntype = \"instance\"\nfile = \"lamp.obj\"\n\
         transforms = [[[1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[3, 0, 0, 9], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]\n",
    );
    let s = &f.scene;
    // The named mesh is the scene's own triangle; three instances place the rest.
    assert_eq!((s.shapes.len(), s.instances.len()), (1, 3));
    let lights: Vec<(Vec<ShapeId>, f32)> = s
        .lights
        .iter()
        .map(|l| match &l.kind {
            LightKind::Mesh { shapes, area, .. } => (shapes.clone(), *area),
            other => panic!("{other:?}"),
        })
        .collect();
    let placed = |instance| ShapeId { instance, shape: 0 };
    assert_eq!(
        lights,
        [
            (vec![ShapeId::world(0)], 0.5),
            (vec![placed(0)], 2.0),
            (vec![placed(1)], 0.5),
            (vec![placed(2)], 1.5),
        ]
    );
    // An emission light sits at the middle of its placed triangles; a file's light
    // where the placement puts its own.
    assert_eq!(s.lights[1].position, Vec3::new(1.0, 1.0, -2.0));
    assert_eq!(s.lights[3].position, Vec3::new(9.0, 0.0, 0.0));
}

/// A placement that flattens the mesh onto a plane (a scale of 0 along one axis, which
/// Blender allows) cannot be an instance, whose rays go back through its inverse: the
/// triangles are copied into the scene, their normals taken by the cofactor matrix, and
/// lit where they glow. One that leaves a line or a point places nothing.
#[test]
fn a_placement_that_flattens_the_mesh_copies_it_into_the_scene() {
    let dir = Folder::new();
    // A face toward +z and one toward +x, each with its vertex normal.
    dir.write(
        "two.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nvn 1 0 0\n\
         f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n",
    );
    let f = dir.load(
        "[[object]]\ntype = \"instance\"\nfile = \"two.obj\"\n\
         material = { emission = [1, 1, 1] }\n\
         transforms = [[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n\
                       [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 3], [0, 0, 0, 1]],\n\
                       [[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]]\n",
    );
    let s = &f.scene;
    assert_eq!((s.instances.len(), s.shapes.len()), (1, 2));
    let corners = |i: usize| {
        let Shape::Triangle(t) = s.shapes.get(i) else {
            panic!()
        };
        t.v
    };
    // Squashed onto z = 3 and stretched twice along x: the face toward +z keeps its
    // area (twice over), the one toward +x has none.
    assert_eq!(
        corners(0),
        [v(0.0, 0.0, 3.0), v(2.0, 0.0, 3.0), v(0.0, 1.0, 3.0)]
    );
    assert_eq!(
        corners(1),
        [v(0.0, 0.0, 3.0), v(0.0, 1.0, 3.0), v(0.0, 0.0, 3.0)]
    );
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.meshes[0].first_shape, 0);
    assert_eq!(s.meshes[0].normals, [v(0.0, 0.0, 2.0), v(0.0, 0.0, 0.0)]);
    // The instance glows over its two triangles; the flat copies over the one with area.
    let lights: Vec<(Vec<ShapeId>, f32)> = s
        .lights
        .iter()
        .map(|l| match &l.kind {
            LightKind::Mesh { shapes, area, .. } => (shapes.clone(), *area),
            other => panic!("{other:?}"),
        })
        .collect();
    let placed = |shape| ShapeId { instance: 0, shape };
    assert_eq!(
        lights,
        [
            (vec![placed(0), placed(1)], 1.0),
            (vec![ShapeId::world(0)], 1.0),
        ]
    );
    // Copies that would leave the range of floats are an error naming the mesh.
    dir.write("far.obj", "v 0 0 0\nv 1e10 0 0\nv 0 1 0\nf 1 2 3\n");
    let e = dir.error(
        "[[object]]\nname = \"far\"\ntype = \"instance\"\nfile = \"far.obj\"\n\
         transforms = [[[1e30, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]]\n",
    );
    assert!(e.contains("takes a vertex past the range of floats"), "{e}");
}

/// A quad in the plane z = 0 scaled to nothing along z is the same quad: it renders as
/// the quad placed as a mesh of the scene, bit for bit.
#[test]
fn a_quad_flattened_along_its_normal_renders_as_itself() {
    use crate::render::{IntegratorKind, RenderSettings, Renderer};
    let dir = Folder::new();
    dir.write(
        "quad.obj",
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n",
    );
    let light = "[[light]]\ntype = \"point\"\nposition = [0.5, 0.5, 3]\n";
    let plain = dir.load(&format!(
        "[[object]]\ntype = \"mesh\"\nfile = \"quad.obj\"\n{light}"
    ));
    let flattened = dir.load(&format!(
        "[[object]]\ntype = \"instance\"\nfile = \"quad.obj\"\n\
         transforms = [[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]]\n{light}"
    ));
    assert_eq!(flattened.scene.instances.len(), 0);
    let camera = crate::scene::Camera::look_at(v(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 16, 16);
    let render = |f: &SceneFile| {
        let settings = RenderSettings {
            integrator: IntegratorKind::Whitted,
            ..RenderSettings::default()
        };
        let renderer = Renderer::new(&f.scene, &camera, settings).unwrap();
        renderer.render(&()).unwrap().0.pixels
    };
    let (a, b) = (render(&plain), render(&flattened));
    assert!(a[8 * 16 + 8][0] > 0.0, "the quad is lit");
    assert_eq!(a, b);
}

/// A mesh file that carries lights of other kinds (a glTF point light) is copied at
/// each placement; placements whose copies would pass the scene's bound on triangles
/// are an error before the first copy is made, not a fill of memory.
#[test]
fn copies_of_a_lit_mesh_are_bounded_before_they_are_made() {
    use crate::format::scene_file::from_value::from_value;
    let dir = Folder::new();
    let triangles = 16_385usize;
    let corners: Vec<u8> = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]]
        .iter()
        .cycle()
        .take(3 * triangles)
        .flat_map(|c| c.iter().flat_map(|x| x.to_le_bytes()))
        .collect();
    std::fs::write(dir.path("lamp.bin"), &corners).unwrap();
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "lamp.bin", "byteLength": corners.len()}],
        "bufferViews": [{"buffer": 0, "byteLength": corners.len()}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3 * triangles,
                       "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point"}]}},
        "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0,
    });
    dir.write("lamp.gltf", &gltf.to_string());
    let moved = |k: usize| {
        let mut m = [[0.0; 4]; 4];
        (0..4).for_each(|i| m[i][i] = 1.0);
        m[0][3] = k as f64;
        m
    };
    let value = serde_json::json!({
        "object": [{"type": "instance", "file": "lamp.gltf", "transforms": "t"}],
    });
    let load = |count: usize| {
        let transforms = (0..count).map(moved).collect();
        let named = std::collections::HashMap::from([("t".to_string(), transforms)]);
        from_value(&value, dir.dir.path(), &Default::default(), named)
    };
    // Two placements: two copies, each with its point light.
    let f = load(2).unwrap();
    assert_eq!(
        (f.scene.shapes.len(), f.scene.lights.len()),
        (2 * triangles, 2)
    );
    // 16 385 copies of 16 385 triangles pass 2^28.
    let e = load(triangles).unwrap_err().to_string();
    assert!(
        e.contains("found 16385 placements of a mesh that carries lights of its own"),
        "{e}"
    );
}

/// Placements handed over by name (Python's arrays) may serve several instance objects,
/// glowing ones lit each; a name no array holds is an error naming it.
#[test]
fn named_transforms_place_every_instance_that_names_them() {
    use crate::format::scene_file::from_value::{ArrayMesh, from_value};
    let tri = ArrayMesh {
        vertices: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        faces: vec![[0, 1, 2]],
        normals: None,
        uvs: None,
        colors: None,
    };
    let meshes = std::collections::HashMap::from([("tri".to_string(), tri)]);
    let moved = |x: f64| {
        [
            [1.0, 0.0, 0.0, x],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    };
    let transforms =
        || std::collections::HashMap::from([("t".to_string(), vec![moved(2.0), moved(4.0)])]);
    let value = serde_json::json!({
        "object": [
            {"type": "instance", "file": "tri", "transforms": "t",
             "material": {"emission": [1, 1, 1]}},
            {"type": "instance", "file": "tri", "transforms": "t", "translate": [0, 0, 3]},
        ],
    });
    let dir = Folder::new();
    let f = from_value(&value, dir.dir.path(), &meshes, transforms()).unwrap();
    assert_eq!(f.scene.instances.len(), 4);
    assert_eq!(
        f.scene.instances[3].to_world().translation,
        Vec3::new(4.0, 0.0, 3.0)
    );
    // The glowing pair is two lights; the others wear the default material.
    assert_eq!(f.scene.lights.len(), 2);
    let value = serde_json::json!({
        "object": [{"type": "instance", "file": "tri", "transforms": "u"}],
    });
    let e = from_value(&value, dir.dir.path(), &meshes, transforms()).unwrap_err();
    assert!(e.to_string().contains("found the name \"u\""), "{e}");
}
