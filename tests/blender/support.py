"""What the Blender tests share: a fresh scene, the add-on registered once, renders
read back as linear arrays."""

import os
import tempfile

import bpy
import numpy as np

import prism_blender
from prism_blender import runtime

_registered = []


def addon():
    """The add-on, registered once for the whole run."""
    if not _registered:
        prism_blender.register()
        _registered.append(True)
    return prism_blender


def prism():
    module = runtime.load()
    if module is None:
        raise RuntimeError(f"the prism package did not load: {runtime.error()}")
    return module


def release_prism():
    """The prism package, refusing a debug build: a benchmark of one would understate
    Prism (the test suite's `maturin develop` build renders about a fifth slower)."""
    module = prism()
    build = getattr(module._prism, "BUILD", "unknown")
    if build != "release":
        raise SystemExit(
            f"prism at {os.path.dirname(module.__file__)} is not a release build "
            f"({build}); benchmark a release one: VIRTUAL_ENV=target/py-venv "
            "target/py-venv/bin/maturin develop --release --manifest-path "
            "python/Cargo.toml (or set PRISM_PYTHON_PATH to an unpacked wheel of "
            "`python3 blender/package.py`)")
    return module


def empty_scene(width=64, height=64):
    """An empty scene (no world light) of `width` x `height` pixels, linear output."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene


def render_linear(scene, engine, samples=64):
    """Renders `scene` with `engine` (F12, through Blender) and reads the file back: an
    H x W x 4 float32 array of linear values, top row first."""
    scene.render.engine = engine
    if engine == "CYCLES":
        scene.cycles.samples = samples
        scene.cycles.use_adaptive_sampling = False
        scene.cycles.use_denoising = False
        scene.cycles.device = "CPU"
        scene.cycles.seed = 1
        # Every kind of bounce limited as Prism limits a path: by its length alone.
        bounces = scene.prism.max_bounces
        for kind in ("max", "diffuse", "glossy", "transmission", "volume", "transparent_max"):
            setattr(scene.cycles, f"{kind}_bounces", bounces)
    else:
        scene.prism.samples = samples
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "frame.exr")
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        if not os.path.isfile(path):
            raise AssertionError(f"{engine} wrote no image")
        return read_image(path)


def lambert_floor(scene, size=40.0, color=(0.8, 0.8, 0.8)):
    """A square floor at z = 0 wearing a Diffuse BSDF of `color`."""
    bpy.ops.mesh.primitive_plane_add(size=size)
    floor = bpy.context.active_object
    material = bpy.data.materials.new("Floor")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*color, 1.0)
    material.node_tree.links.new(diffuse.outputs[0], nodes["Material Output"].inputs["Surface"])
    floor.data.materials.append(material)
    return floor


def camera(scene, location=(0, 0, 6), rotation=(0, 0, 0), lens=50.0, ortho=None):
    data = bpy.data.cameras.new("Camera")
    data.lens = lens
    if ortho is not None:
        data.type = "ORTHO"
        data.ortho_scale = ortho
    obj = bpy.data.objects.new("Camera", data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def light(scene, kind, location=(0, 0, 3), rotation=(0, 0, 0), **settings):
    data = bpy.data.lights.new(kind.title(), kind)
    for key, value in settings.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(kind.title(), data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    return obj


def depsgraph():
    bpy.context.view_layer.update()
    return bpy.context.evaluated_depsgraph_get()


#: Blender's Principled BSDF v2 (4.0) renamed the inputs v1 had.
V2 = bpy.app.version >= (4, 0, 0)
SPECULAR = "Specular IOR Level" if V2 else "Specular"
TRANSMISSION = "Transmission Weight" if V2 else "Transmission"


def export_scene(scene, width, height, **settings):
    """The add-on's export of `scene` as F12 makes it, with `settings` over its
    `[render]` keys."""
    from prism_blender import export, properties

    graph = depsgraph()
    camera = scene.camera.evaluated_get(graph)
    job = dict(properties.job_settings(scene), **settings)
    return export.export(graph, width, height, camera_object=camera, settings=job)


def read_image(path):
    """An image file as Blender reads it: H x W x 4 float32, top row first."""
    image = bpy.data.images.load(path)
    try:
        w, h = image.size
        pixels = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(h, w, 4)[::-1]
