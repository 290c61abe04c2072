"""A Blender scene with glass, metal, a dielectric and three kinds of light, rendered
by Cycles and by Prism in the same Blender at equal samples and bounces; prints the
F12 times and their ratio, and writes both images side by side:

    blender -b --factory-startup --python benches/blender_showcase.py -- \\
        [--size 800x600] [--samples 64] [--light-sampling auto|all|one|tree] \\
        [--out showcase.png] [--blend scene.blend]

Cycles runs on the CPU, denoising and adaptive sampling off; both use every core.
Prism must be a release build (PRISM_PYTHON_PATH, default python/): the script says how
to make one when it finds the test suite's debug build.
"""

import argparse
import math
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


def principled(name, **inputs):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    node = material.node_tree.nodes["Principled BSDF"]
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    return material


def build(width, height):
    scene = support.empty_scene(width, height)
    scene.view_settings.view_transform = "Filmic" if bpy.app.version < (4, 0, 0) else "AgX"
    world = scene.world.node_tree.nodes["Background"]
    world.inputs["Color"].default_value = (0.35, 0.45, 0.6, 1)
    world.inputs["Strength"].default_value = 0.4
    floor = support.lambert_floor(scene, size=30, color=(0.6, 0.6, 0.6))
    floor.location.z = 0
    things = [
        ("Glass", bpy.ops.mesh.primitive_uv_sphere_add, (-1.6, 0, 0.8),
         {support.TRANSMISSION: 1.0, "Roughness": 0.0, "IOR": 1.5,
          "Base Color": (0.95, 0.97, 1.0, 1)}),
        ("Gold", bpy.ops.mesh.primitive_uv_sphere_add, (0.3, 0.8, 0.8),
         {"Metallic": 1.0, "Roughness": 0.25, "Base Color": (1.0, 0.75, 0.35, 1)}),
        ("Plastic", bpy.ops.mesh.primitive_cube_add, (1.9, -0.6, 0.6),
         {"Roughness": 0.4, "Base Color": (0.7, 0.08, 0.05, 1)}),
    ]
    for name, add, where, inputs in things:
        if name == "Plastic":
            add(size=1.2, location=where, rotation=(0, 0, 0.5))
        else:
            add(radius=0.8, location=where, segments=64, ring_count=32)
            bpy.ops.object.shade_smooth()
        bpy.context.active_object.data.materials.append(principled(name, **inputs))
    support.light(scene, "AREA", (0, -2.5, 4), rotation=(math.radians(30), 0, 0), energy=400,
                  shape="RECTANGLE", size=3, size_y=1.5)
    support.light(scene, "SUN", rotation=(math.radians(50), 0, math.radians(-40)), energy=1.5,
                  angle=0)
    support.light(scene, "POINT", (2.5, 2.5, 2.5), energy=300, shadow_soft_size=0.2)
    support.camera(scene, location=(0, -8, 3.2), rotation=(math.radians(73), 0, 0), lens=35)
    return scene


def timed_render(scene, engine, samples):
    started = time.perf_counter()
    image = support.render_linear(scene, engine, samples)
    return time.perf_counter() - started, image


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--samples", type=int, default=64)
    parser.add_argument("--light-sampling", default="auto", choices=("auto", "all", "one", "tree"))
    parser.add_argument("--out")
    parser.add_argument("--blend")
    args = parser.parse_args(argv)
    support.release_prism()
    width, height = map(int, args.size.split("x"))
    scene = build(width, height)
    scene.prism.max_bounces = 12
    scene.prism.light_sampling = args.light_sampling
    if args.blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.blend))
    times, images = {}, {}
    for engine in ("CYCLES", "PRISM"):
        times[engine], images[engine] = timed_render(scene, engine, args.samples)
        print(f"{engine}: {times[engine]:.2f} s for {width}x{height} at {args.samples} spp")
    cycles, prism = images["CYCLES"][..., :3], images["PRISM"][..., :3]
    print(f"Cycles takes {times['CYCLES'] / times['PRISM']:.2f}x Prism's time; "
          f"mean radiance Prism / Cycles {prism.mean() / cycles.mean():.4f}")
    if args.out:
        both = np.concatenate([cycles, prism], axis=1)
        support.prism().write_image(np.ascontiguousarray(both), args.out, tonemap="aces")
        print(f"wrote {args.out} (Cycles left, Prism right)")


main()
