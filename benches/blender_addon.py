"""Timings of the Blender add-on (issue targets: export of a 1 M-triangle mesh under
2 s; 10^5 instances of one mesh cost memory for one; a 1080p pass handed to Blender
under 0.2 s):

    blender -b --factory-startup --python benches/blender_addon.py

Prints one line a figure. PRISM_PYTHON_PATH defaults to python/, which must hold a
release build (the script says how to make one).
"""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(REPO, "blender"))
sys.path.insert(0, os.path.join(REPO, "tests", "blender"))
os.environ.setdefault("PRISM_PYTHON_PATH", os.path.join(REPO, "python"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import support  # noqa: E402
from prism_blender import engine, export  # noqa: E402


def best_of(n, fn):
    times = []
    for _ in range(n):
        started = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - started)
    return min(times), out


def mesh_export():
    scene = support.empty_scene(64, 64)
    support.camera(scene, location=(0, 0, 10))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=10)
    grid = bpy.context.active_object
    graph = support.depsgraph()
    for smooth in (False, True):
        if smooth:
            bpy.ops.object.shade_smooth()
            graph = support.depsgraph()
        took, made = best_of(3, lambda: export.export(graph, 64, 64, camera_object=scene.camera))
        prism = support.prism()
        built, _ = best_of(1, lambda: prism.scene_from_dict(made.scene))
        print(f"export of a {made.triangles:,}-triangle mesh ({'smooth, UVs' if smooth else 'flat, UVs'}):"
              f" {took:.3f} s; Prism scene from it: {built:.3f} s")
    del grid


def instances():
    scene = support.empty_scene(64, 64)
    support.camera(scene, location=(0, -60, 30), rotation=(1.1, 0, 0))
    import test_export

    case = test_export.Instances()
    case.scene = scene
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.1, subdivisions=5)
    source = bpy.context.active_object
    source.hide_render = source.hide_viewport = True
    holder = bpy.data.objects.new("Scatter", bpy.data.meshes.new("Scatter"))
    scene.collection.objects.link(holder)
    tree = bpy.data.node_groups.new("Scatter", "GeometryNodeTree")
    if hasattr(tree, "interface"):
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    grid = tree.nodes.new("GeometryNodeMeshGrid")
    grid.inputs["Vertices X"].default_value = 400
    grid.inputs["Vertices Y"].default_value = 250
    grid.inputs["Size X"].default_value = 40
    grid.inputs["Size Y"].default_value = 25
    info = tree.nodes.new("GeometryNodeObjectInfo")
    info.inputs["Object"].default_value = source
    scatter = tree.nodes.new("GeometryNodeInstanceOnPoints")
    out = tree.nodes.new("NodeGroupOutput")
    tree.links.new(grid.outputs["Mesh"], scatter.inputs["Points"])
    tree.links.new(info.outputs["Geometry"], scatter.inputs["Instance"])
    tree.links.new(scatter.outputs["Instances"], out.inputs[0])
    holder.modifiers.new("Scatter", "NODES").node_group = tree
    graph = support.depsgraph()
    took, made = best_of(1, lambda: export.export(graph, 64, 64, camera_object=scene.camera))
    prism = support.prism()
    built, prism_scene = best_of(1, lambda: prism.scene_from_dict(made.scene))
    info = prism_scene.info()
    print(f"10^5 geometry-nodes instances of a {info['unique_triangles']:,}-triangle mesh "
          f"({info['triangles']:,} placed): export {took:.2f} s, Prism scene {built:.2f} s "
          "(memory: benches/instances_memory.py)")
    started = time.perf_counter()
    prism.render(prism_scene, width=320, height=180, integrator="path", spp=1)
    print(f"  rendered 320x180 at 1 spp in {time.perf_counter() - started:.2f} s")


def result_writes():
    scene = support.empty_scene(1920, 1080)
    bpy.ops.wm.read_factory_settings(use_empty=False)
    support.addon()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 1920, 1080
    scene.render.resolution_percentage = 100
    scene.render.engine = "PRISM"
    scene.prism.samples = 4
    timings = []
    show_passes = engine.show_passes

    def timed_show_passes(passes, show, should_stop):
        def timed(samples, image):
            started = time.perf_counter()
            show(samples, image)
            timings.append(time.perf_counter() - started)
        return show_passes(passes, timed, should_stop)

    engine.show_passes = timed_show_passes
    try:
        bpy.ops.render.render()
    finally:
        engine.show_passes = show_passes
    print(f"a 1080p pass handed to Blender (RGBA rows, rect, update_result): "
          f"{min(timings) * 1000:.0f} ms best, {max(timings) * 1000:.0f} ms worst of {len(timings)}")


support.release_prism()
instances()
mesh_export()
result_writes()
