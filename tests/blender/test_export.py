"""The converter from Blender data to a Prism scene, value by value: meshes (split
normals, UVs, material slots), instances (collection instances, geometry nodes),
cameras, lights and materials."""

import math
import os
import tempfile
import time
import unittest

import bpy
import numpy as np

import support
from prism_blender import export, materials
from prism_blender.meshes import mesh_parts


def _evaluated_parts(obj):
    graph = support.depsgraph()
    evaluated = obj.evaluated_get(graph)
    mesh = evaluated.to_mesh()
    try:
        return mesh_parts(mesh)
    finally:
        evaluated.to_mesh_clear()


def _warnings():
    out = []
    return out, out.append


class Meshes(unittest.TestCase):
    def setUp(self):
        support.empty_scene()

    def test_a_flat_cube_with_uvs_has_a_vertex_per_corner_and_no_normals(self):
        bpy.ops.mesh.primitive_cube_add(size=2)
        (part,) = _evaluated_parts(bpy.context.active_object)
        self.assertEqual(part.triangles, 12)
        self.assertEqual(part.vertices.shape, (24, 3))
        self.assertIsNone(part.normals)
        self.assertEqual(part.uvs.shape, (24, 2))
        self.assertEqual(sorted(set(np.abs(part.vertices).ravel().tolist())), [1.0])
        self.assertLess(int(part.faces.max()), 24)

    def test_a_mesh_without_uvs_or_smooth_faces_keeps_its_own_vertices(self):
        bpy.ops.mesh.primitive_cube_add(size=2)
        cube = bpy.context.active_object
        cube.data.uv_layers.remove(cube.data.uv_layers[0])
        cube.data.update()  # Blender 5 does not tag the mesh for this removal itself
        (part,) = _evaluated_parts(cube)
        self.assertEqual((part.vertices.shape, part.uvs, part.normals), ((8, 3), None, None))

    def test_a_smooth_sphere_has_normals_along_its_radius(self):
        bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, segments=32, ring_count=16)
        bpy.ops.object.shade_smooth()
        (part,) = _evaluated_parts(bpy.context.active_object)
        radial = part.vertices / np.linalg.norm(part.vertices, axis=1, keepdims=True)
        # Blender weighs faces by their corner angles: near the poles the mean tilts.
        self.assertLess(float(np.abs(part.normals - radial).max()), 1e-2)

    def test_auto_smooth_keeps_sharp_edges_sharp(self):
        bpy.ops.mesh.primitive_cube_add(size=2)
        cube = bpy.context.active_object
        bpy.ops.object.shade_smooth()
        if hasattr(cube.data, "use_auto_smooth"):  # 3.x to 4.0
            cube.data.use_auto_smooth = True
            cube.data.auto_smooth_angle = math.radians(30)
        else:  # 4.1+: the modifier
            bpy.ops.object.shade_smooth_by_angle(angle=math.radians(30))
        (part,) = _evaluated_parts(cube)
        # Every corner's normal is its face's: an axis.
        self.assertTrue(np.allclose(np.abs(part.normals).max(axis=1), 1.0, atol=1e-5))
        self.assertTrue(np.allclose(np.sort(np.abs(part.normals), axis=1)[:, :2], 0, atol=1e-5))

    def test_each_material_slot_is_a_part_of_its_own(self):
        bpy.ops.mesh.primitive_cube_add(size=2)
        cube = bpy.context.active_object
        for name in ("A", "B"):
            cube.data.materials.append(bpy.data.materials.new(name))
        cube.data.polygons[0].material_index = 1
        parts = _evaluated_parts(cube)
        self.assertEqual([(p.slot, p.triangles) for p in parts], [(0, 10), (1, 2)])
        b = parts[1]
        self.assertEqual(len(b.vertices), 4)  # compacted to the corners its face uses
        self.assertTrue(np.all(b.faces < 4))


def _collection_with_cube():
    source = bpy.data.collections.new("Source")
    bpy.context.scene.collection.children.link(source)
    bpy.ops.mesh.primitive_cube_add(size=0.5)
    cube = bpy.context.active_object
    for c in cube.users_collection:
        c.objects.unlink(cube)
    source.objects.link(cube)
    bpy.context.view_layer.layer_collection.children["Source"].exclude = True
    return source, cube


class Instances(unittest.TestCase):
    def setUp(self):
        self.scene = support.empty_scene()
        support.camera(self.scene, location=(0, -30, 10), rotation=(1.2, 0, 0))

    def test_collection_instances_hold_the_mesh_once(self):
        source, cube = _collection_with_cube()
        for i in range(50):
            empty = bpy.data.objects.new(f"I{i}", None)
            empty.instance_type = "COLLECTION"
            empty.instance_collection = source
            empty.location = (i % 10, i // 10, 0)
            empty.scale = (1, 1, -1) if i % 7 == 0 else (1, 1, 1)  # mirrors too
            self.scene.collection.objects.link(empty)
        made = support.export_scene(self.scene, 64, 64)
        self.assertEqual((made.meshes, made.placements, made.triangles), (1, 50, 600))
        prism = support.prism()
        info = prism.scene_from_dict(made.scene).info()
        self.assertEqual((info["instances"], info["unique_triangles"]), (50, 12))

    def test_a_hundred_thousand_geometry_node_instances_cost_one_mesh(self):
        bpy.ops.mesh.primitive_ico_sphere_add(radius=0.1, subdivisions=3)
        source = bpy.context.active_object
        source.hide_render = source.hide_viewport = True
        tris = 20 * 4 ** 2
        holder = bpy.data.objects.new("Scatter", bpy.data.meshes.new("Scatter"))
        self.scene.collection.objects.link(holder)
        tree = bpy.data.node_groups.new("Scatter", "GeometryNodeTree")
        if hasattr(tree, "interface"):  # 4.0+
            tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        else:
            tree.outputs.new("NodeSocketGeometry", "Geometry")
        nodes, links = tree.nodes, tree.links
        grid = nodes.new("GeometryNodeMeshGrid")
        grid.inputs["Vertices X"].default_value = 400
        grid.inputs["Vertices Y"].default_value = 250
        grid.inputs["Size X"].default_value = 40
        grid.inputs["Size Y"].default_value = 25
        info = nodes.new("GeometryNodeObjectInfo")
        info.inputs["Object"].default_value = source
        scatter = nodes.new("GeometryNodeInstanceOnPoints")
        out = nodes.new("NodeGroupOutput")
        links.new(grid.outputs["Mesh"], scatter.inputs["Points"])
        links.new(info.outputs["Geometry"], scatter.inputs["Instance"])
        links.new(scatter.outputs["Instances"], out.inputs[0])
        holder.modifiers.new("Scatter", "NODES").node_group = tree
        started = time.perf_counter()
        made = support.export_scene(self.scene, 64, 64)
        took = time.perf_counter() - started
        print(f"  10^5 instances exported in {took:.2f} s")
        self.assertEqual((made.meshes, made.placements), (1, 100_000))
        self.assertEqual(made.triangles, 100_000 * tris)
        info = support.prism().scene_from_dict(made.scene).info()
        self.assertEqual((info["instances"], info["unique_triangles"]), (100_000, tris))


class Cameras(unittest.TestCase):
    def setUp(self):
        self.scene = support.empty_scene()

    def camera(self, width, height, **settings):
        cam = support.camera(self.scene, location=(1, 2, 3), rotation=(math.radians(90), 0, 0))
        for key, value in settings.items():
            target = cam.data.dof if key in ("use_dof", "focus_distance", "aperture_fstop",
                                             "focus_object") else cam.data
            setattr(target, key, value)
        self.scene.render.resolution_x, self.scene.render.resolution_y = width, height
        return support.export_scene(self.scene, width, height).scene["camera"]

    def test_a_perspective_camera_keeps_its_field_of_view_and_frame(self):
        c = self.camera(160, 120, lens=50, sensor_width=36)
        self.assertAlmostEqual(c["fov"], 2 * math.degrees(math.atan(18 / 50)), places=5)
        self.assertEqual(c["fov_axis"], "horizontal")
        np.testing.assert_allclose(c["from"], [1, 2, 3], atol=1e-6)
        # Rotated 90 degrees about X, a Blender camera looks along +Y with +Z up.
        np.testing.assert_allclose(np.subtract(c["at"], c["from"]), [0, 1, 0], atol=1e-6)
        np.testing.assert_allclose(c["up"], [0, 0, 1], atol=1e-6)

    def test_sensor_fit_picks_the_side_the_sensor_spans(self):
        tall = self.camera(90, 160, lens=35, sensor_width=36)
        self.assertEqual(tall["fov_axis"], "vertical")
        self.assertAlmostEqual(tall["fov"], 2 * math.degrees(math.atan(18 / 35)), places=5)
        fixed = self.camera(160, 90, lens=35, sensor_fit="VERTICAL", sensor_height=24)
        self.assertEqual(fixed["fov_axis"], "vertical")
        self.assertAlmostEqual(fixed["fov"], 2 * math.degrees(math.atan(12 / 35)), places=5)

    def test_an_orthographic_camera_spans_its_scale(self):
        c = self.camera(200, 100, type="ORTHO", ortho_scale=8)
        self.assertEqual((c["projection"], c["view_width"]), ("orthographic", 8))
        c = self.camera(100, 200, type="ORTHO", ortho_scale=8)
        self.assertAlmostEqual(c["view_width"], 4)

    def test_depth_of_field_from_the_f_stop_and_the_focus_object(self):
        target = bpy.data.objects.new("Target", None)
        target.location = (3, 9, 3)  # 7 along the view axis (+Y), off to the side
        self.scene.collection.objects.link(target)
        c = self.camera(64, 64, lens=50, use_dof=True, aperture_fstop=2.0, focus_object=target)
        self.assertAlmostEqual(c["aperture"], 0.050 / (2 * 2.0), places=7)
        self.assertAlmostEqual(c["focus_distance"], 7.0, places=5)

    def test_the_lens_shift_is_carried_in_units_of_the_fitted_side(self):
        c = self.camera(160, 90, shift_x=0.25, shift_y=-0.125)
        self.assertEqual(c["shift"], [0.25, -0.125])


class Lights(unittest.TestCase):
    def setUp(self):
        self.scene = support.empty_scene()
        support.camera(self.scene)

    def exported(self, kind, **settings):
        support.light(self.scene, kind, (1, 2, 3), **settings)
        (light,) = support.export_scene(self.scene, 16, 16).scene["light"]
        return light

    def test_a_point_light_has_the_intensity_of_its_power(self):
        light = self.exported("POINT", energy=100, shadow_soft_size=0, color=(1, 0.5, 0.25))
        self.assertEqual((light["type"], light["falloff"]), ("point", "inverse_square"))
        self.assertAlmostEqual(light["intensity"], 100 / (4 * math.pi), places=5)
        np.testing.assert_allclose(light["color"], [1, 0.5, 0.25])

    def test_a_point_light_with_a_radius_is_a_sphere_of_that_intensity(self):
        light = self.exported("POINT", energy=100, shadow_soft_size=0.5)
        self.assertEqual((light["type"], light["radius"]), ("sphere", 0.5))
        self.assertFalse(light["camera_visible"])  # Blender's lights are hidden from it
        self.assertAlmostEqual(light["intensity"] * math.pi * 0.25, 100 / (4 * math.pi), places=5)

    def test_an_area_light_has_the_radiance_of_its_power_over_four_areas(self):
        light = self.exported("AREA", energy=64, shape="RECTANGLE", size=2, size_y=0.5)
        self.assertEqual(light["type"], "quad")
        # Blender 4.0 corrected Cycles' power of an area light from 4 L A to pi L A.
        per_area = math.pi if bpy.app.version >= (4, 0, 0) else 4.0
        self.assertAlmostEqual(light["intensity"], 64 / (per_area * 1.0), places=5)
        normal = np.cross(light["edge1"], light["edge2"])
        np.testing.assert_allclose(normal / np.linalg.norm(normal), [0, 0, -1], atol=1e-6)

    def test_a_spot_light_keeps_its_cone_and_blend(self):
        light = self.exported("SPOT", energy=10, spot_size=math.radians(60), spot_blend=0.5,
                              shadow_soft_size=0)
        # Before Blender 4.0 Cycles' spots fade with the cosine from the axis too.
        edge = "smooth" if bpy.app.version >= (4, 0, 0) else "smooth_cosine"
        self.assertEqual((light["type"], light["edge"]), ("spot", edge))
        self.assertAlmostEqual(light["angle"], 30, places=5)
        cos_outer = math.cos(math.radians(30))
        inner = math.degrees(math.acos(cos_outer + (1 - cos_outer) * 0.5))
        self.assertAlmostEqual(light["inner_angle"], inner, places=5)

    def test_a_sun_is_its_irradiance_along_its_direction(self):
        light = self.exported("SUN", energy=3.5)
        self.assertEqual((light["type"], light["intensity"]), ("directional", 3.5))
        np.testing.assert_allclose(light["direction"], [0, 0, -1], atol=1e-6)


def _principled_material(**inputs):
    material = bpy.data.materials.new("Test")
    material.use_nodes = True
    node = material.node_tree.nodes["Principled BSDF"]
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    return material, node


class Materials(unittest.TestCase):
    def setUp(self):
        support.empty_scene()
        self.images = materials.Images()

    def tearDown(self):
        self.images.close()

    def convert(self, material):
        warnings, warn = _warnings()
        return materials.material_dict(material, self.images, warn), warnings

    def test_principled_metal(self):
        m, _ = _principled_material(**{"Base Color": (0.9, 0.6, 0.2, 1), "Metallic": 1.0,
                                       "Roughness": 0.25})
        out, warnings = self.convert(m)
        self.assertEqual(warnings, [])
        self.assertEqual((out["type"], out["base_metalness"]), ("openpbr", 1.0))
        self.assertAlmostEqual(out["specular_roughness"], 0.25)
        np.testing.assert_allclose(out["base_color"], [0.9, 0.6, 0.2], atol=1e-6)

    def test_principled_specular_is_the_ior_of_its_reflectance(self):
        out, _ = self.convert(_principled_material(**{support.SPECULAR: 0.5, "IOR": 1.5})[0])
        self.assertAlmostEqual(out["specular_ior"], 1.5, places=5)  # F0 = 0.08 * 0.5 = 0.04
        self.assertAlmostEqual(materials._mean_fresnel(1.5), 0.0918, places=3)  # Fresnel's mean
        # v1 lifts the base by what its specular takes (v1's energy gain); v2 conserves.
        lift = 1.0 if support.V2 else 1 / (1 - materials._mean_fresnel(1.5))
        np.testing.assert_allclose(out["base_color"], np.array([0.8, 0.8, 0.8]) * lift, rtol=1e-5)
        out, _ = self.convert(_principled_material(**{support.TRANSMISSION: 1.0, "IOR": 1.33})[0])
        self.assertAlmostEqual(out["specular_ior"], 1.33, places=5)
        self.assertEqual(out["transmission_weight"], 1.0)

    def test_a_smooth_diffuse_bsdf_is_a_plain_lambertian(self):
        material = bpy.data.materials.new("Matte")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        nodes.remove(nodes["Principled BSDF"])
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (0.25, 0.5, 0.75, 1)
        material.node_tree.links.new(diffuse.outputs[0],
                                     nodes["Material Output"].inputs["Surface"])
        out, _ = self.convert(material)
        self.assertEqual(out, {"color": [0.25, 0.5, 0.75]})
        diffuse.inputs["Roughness"].default_value = 0.5  # Oren-Nayar: OpenPBR's EON
        out, _ = self.convert(material)
        self.assertEqual((out["type"], out["base_diffuse_roughness"]), ("openpbr", 0.5))

    def test_image_textures_and_their_channels(self):
        m, node = _principled_material()
        tree = m.node_tree
        image = bpy.data.images.new("Grid", 8, 8)
        image.generated_type = "COLOR_GRID"
        tex = tree.nodes.new("ShaderNodeTexImage")
        tex.image = image
        tree.links.new(tex.outputs["Color"], node.inputs["Base Color"])
        data = bpy.data.images.new("Data", 4, 4)
        data.colorspace_settings.name = "Non-Color"
        data_tex = tree.nodes.new("ShaderNodeTexImage")
        data_tex.image = data
        split = tree.nodes.new("ShaderNodeSeparateRGB" if bpy.app.version < (3, 3, 0)
                               else "ShaderNodeSeparateColor")
        tree.links.new(data_tex.outputs["Color"], split.inputs[0])
        tree.links.new(split.outputs[1], node.inputs["Roughness"])
        normal_map = tree.nodes.new("ShaderNodeNormalMap")
        tree.links.new(data_tex.outputs["Color"], normal_map.inputs["Color"])
        tree.links.new(normal_map.outputs["Normal"], node.inputs["Normal"])
        out, warnings = self.convert(m)
        self.assertEqual(warnings, [])
        grid = out["base_color"]["texture"]
        self.assertTrue(os.path.isfile(grid) and grid.endswith(".png"))
        self.assertEqual(out["specular_roughness"]["channel"], "g")
        self.assertEqual(out["geometry_normal"], out["specular_roughness"]["texture"])
        # The textured material renders.
        prism = support.prism()
        scene = {"object": [{"type": "sphere", "radius": 1, "material": "m"}],
                 "material": [dict(out, name="m")], "light": [{"type": "directional",
                                                              "direction": [0, -1, 0]}]}
        prism.render(prism.scene_from_dict(scene), width=8, height=8)

    def test_a_transparent_mix_is_a_cut_out_and_unknown_nodes_are_named(self):
        m, node = _principled_material()
        tree = m.node_tree
        output = tree.nodes["Material Output"]
        mix = tree.nodes.new("ShaderNodeMixShader")
        mix.inputs[0].default_value = 0.25
        transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
        tree.links.new(node.outputs[0], mix.inputs[1])
        tree.links.new(transparent.outputs[0], mix.inputs[2])
        tree.links.new(mix.outputs[0], output.inputs["Surface"])
        out, _ = self.convert(m)
        self.assertAlmostEqual(out["geometry_opacity"], 0.75)
        toon = tree.nodes.new("ShaderNodeBsdfToon")
        toon.name = "Cartoon"
        tree.links.new(toon.outputs[0], output.inputs["Surface"])
        out, warnings = self.convert(m)
        self.assertEqual(out, materials.default_material())
        self.assertEqual(len(warnings), 1)
        self.assertIn("Cartoon", warnings[0])
        self.assertIn("ShaderNodeBsdfToon", warnings[0])
