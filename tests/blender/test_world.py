"""The world's environment texture seen by the camera: Prism's picture of it is
Cycles', orientation and mapping rotation included."""

import math
import os
import tempfile
import unittest

import bpy
import numpy as np

import support


def _environment_image(path):
    """A smooth equirectangular image telling every direction apart: red grows with u,
    green with v, blue peaks at one spot."""
    h, w = 64, 128
    v, u = np.mgrid[0:h, 0:w]
    u = (u + 0.5) / w
    v = (v + 0.5) / h
    blob = np.exp(-(((u - 0.3) / 0.08) ** 2 + ((v - 0.35) / 0.1) ** 2))
    image = np.stack([0.2 + u, 0.2 + v, 0.2 + 2 * blob], axis=-1).astype(np.float32)
    support.prism().write_image(image, path, exr_precision="float")


def _scene(path, rotation):
    scene = support.empty_scene(96, 64)
    world = scene.world
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    background.inputs["Strength"].default_value = 1.0
    texture = nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(path)
    coords = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0, 0, rotation)
    links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], background.inputs["Color"])
    # A wide camera looking down a little, turned away from every axis.
    support.camera(scene, location=(0, 0, 0), rotation=(math.radians(70), 0, math.radians(25)),
                   lens=12)
    return scene


class Environment(unittest.TestCase):
    def test_the_environment_is_seen_as_cycles_sees_it(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "sky.exr")
            _environment_image(path)
            errors = {}
            for rotation in (0.0, math.radians(40)):
                scene = _scene(path, rotation)
                cycles = support.render_linear(scene, "CYCLES", 16)[..., :3]
                prism = support.render_linear(scene, "PRISM", 16)[..., :3]
                errors[rotation] = float(np.abs(prism - cycles).mean() / cycles.mean())
                print(f"  rotation {math.degrees(rotation):.0f}: mean error {errors[rotation]:.4f}")
                self.assertLess(errors[rotation], 0.02)
            # The comparison tells orientations apart: a turn of 40 degrees is seen.
            scene = _scene(path, 0.0)
            unturned = support.render_linear(scene, "PRISM", 16)[..., :3]
            turned = support.render_linear(_scene(path, math.radians(40)), "CYCLES", 16)[..., :3]
            self.assertGreater(float(np.abs(unturned - turned).mean() / turned.mean()), 0.1)
