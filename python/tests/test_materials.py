"""OpenPBR materials from Python: ``type = "openpbr"`` in ``scene_from_dict``, and
``render``'s ``material=`` (a MaterialX document) and ``environment=`` (an image)."""

import numpy as np

import prism
from conftest import same_bits

GOLD = {
    "name": "gold",
    "type": "openpbr",
    "base_metalness": 1.0,
    "base_color": [1.0, 0.78, 0.34],
    "specular_roughness": 0.3,
}

GOLD_TOML = """
[[material]]
name = "gold"
type = "openpbr"
base_metalness = 1.0
base_color = [1.0, 0.78, 0.34]
specular_roughness = 0.3

[[object]]
type = "sphere"
radius = 1.0
material = "gold"
"""

RED_MTLX = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="red" type="surfaceshader">
    <input name="base_color" type="color3" value="0.9, 0.05, 0.05" />
  </open_pbr_surface>
</materialx>
"""

PATH = dict(integrator="path", spp=4, width=24, height=24, seed=2)


def ball(material=None):
    obj = {"type": "sphere", "radius": 1.0}
    if material:
        obj["material"] = material["name"]
    return prism.scene_from_dict(
        {"material": [material] if material else [], "object": [obj]}
    )


def test_an_openpbr_dict_is_the_scene_file_it_spells(tmp_path):
    path = tmp_path / "gold.toml"
    path.write_text(GOLD_TOML)
    from_dict = prism.render(ball(GOLD), **PATH)
    from_file = prism.render(prism.load_scene(path), **PATH)
    assert same_bits(from_dict, from_file)
    # Gold in the default studio: red over blue where the ball is.
    centre = from_dict[8:16, 8:16].reshape(-1, 3).mean(axis=0)
    assert centre[0] > 1.5 * centre[2], centre


def test_material_dresses_every_shape_in_a_materialx_document(tmp_path):
    mtlx = tmp_path / "red.mtlx"
    mtlx.write_text(RED_MTLX)
    plain = prism.render(ball(), **PATH)[8:16, 8:16].reshape(-1, 3).mean(axis=0)
    red = prism.render(ball(), material=str(mtlx), **PATH)[8:16, 8:16].reshape(-1, 3).mean(axis=0)
    assert abs(plain[0] - plain[1]) < 0.02 * plain[0], plain  # the default is grey
    assert red[0] > 4 * red[1], red


def test_environment_strength_scales_the_light_exactly(tmp_path):
    # A 2 x 1 sRGB image, written as a binary PPM: a dim warm and a dim cool half.
    env = tmp_path / "env.ppm"
    env.write_bytes(b"P6\n2 1\n255\n" + bytes([90, 70, 50, 40, 60, 90]))
    one = prism.render(ball(), environment=str(env), **PATH)
    two = prism.render(ball(), environment=str(env), environment_strength=2.0, **PATH)
    assert one.max() > 0.01
    # A power of two scales every sample's radiance without rounding.
    assert same_bits(two, 2.0 * one)
    turned = prism.render(ball(), environment=str(env), environment_rotate=90.0, **PATH)
    assert not same_bits(turned, one)
