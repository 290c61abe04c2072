"""Builds the bundled Blender scene and exports it as glTF: a camera, a point light
and a sun, a glass sphere, a gold sphere and a red box on a grey floor.

    blender -b --factory-startup --python scenes/blender/make-scene.py

writes scenes/blender/blender-export.glb (Blender 3.4's own glTF exporter).
"""

import math
import os

import bpy

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender-export.glb")

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def material(name, color, metallic=0.0, roughness=0.5, transmission=0.0, ior=1.45):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Transmission"].default_value = transmission
    bsdf.inputs["IOR"].default_value = ior
    return m


def wear(obj, m):
    obj.data.materials.append(m)
    for p in obj.data.polygons:
        p.use_smooth = obj.name != "Box" and obj.name != "Floor"


bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
floor = bpy.context.active_object
floor.name = "Floor"
wear(floor, material("Floor", (0.5, 0.5, 0.5), roughness=0.9))

bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.7, location=(-1.0, 0.3, 0.7))
glass = bpy.context.active_object
glass.name = "Glass"
wear(glass, material("Glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5))

bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.6, location=(0.9, 0.9, 0.6))
gold = bpy.context.active_object
gold.name = "Gold"
wear(gold, material("Gold", (1.0, 0.766, 0.336), metallic=1.0, roughness=0.2))

bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.6, -1.0, 0.4), rotation=(0, 0, math.radians(30)))
box = bpy.context.active_object
box.name = "Box"
wear(box, material("Red", (0.8, 0.1, 0.08), roughness=0.6))

bpy.ops.object.camera_add(location=(0.0, -6.5, 3.2))
camera = bpy.context.active_object
camera.name = "Camera"
camera.data.lens = 40
camera.rotation_euler = (math.radians(66), 0, 0)
scene.camera = camera
scene.render.resolution_x = 640
scene.render.resolution_y = 400

bpy.ops.object.light_add(type="POINT", location=(2.5, -2.0, 3.5))
lamp = bpy.context.active_object
lamp.name = "Lamp"
lamp.data.energy = 800.0
lamp.data.shadow_soft_size = 0.0

bpy.ops.object.light_add(type="SUN", location=(0, 0, 5), rotation=(math.radians(40), math.radians(15), 0))
sun = bpy.context.active_object
sun.name = "Sun"
sun.data.energy = 2.0

bpy.ops.export_scene.gltf(
    filepath=OUT,
    export_format="GLB",
    export_cameras=True,
    export_lights=True,
    export_apply=True,
    export_yup=True,
)
print("wrote", OUT)
