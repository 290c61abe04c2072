"""Writing arrays in every format, development of float arrays, and notebook display."""

import sys
import types

import numpy as np
import pytest

import prism
from conftest import read_ppm

MAGIC = {
    "png": b"\x89PNG", "bmp": b"BM", "jpg": b"\xff\xd8", "ppm": b"P6",
    "exr": b"\x76\x2f\x31\x01", "hdr": b"#?RADIANCE",
}


@pytest.mark.parametrize("ext", ["png", "bmp", "jpg", "ppm", "tga", "exr", "hdr"])
@pytest.mark.parametrize("dtype", [np.float32, np.uint8])
def test_every_format_is_written(tmp_path, ext, dtype):
    image = (np.arange(4 * 5 * 3).reshape(4, 5, 3) * 4).astype(dtype)
    if dtype == np.float32:
        image /= 255.0
    path = tmp_path / f"out.{ext}"
    prism.write_image(image, path)
    data = path.read_bytes()
    assert data.startswith(MAGIC.get(ext, b"")) and len(data) > 18
    assert not list(tmp_path.glob(".prism-*"))  # no temporary file left


def test_uint8_is_written_as_is(tmp_path):
    image = np.random.default_rng(1).integers(0, 256, (7, 9, 3), dtype=np.uint8)
    prism.write_image(image, tmp_path / "a.ppm", exposure=3.0, tonemap="aces")
    assert np.array_equal(read_ppm(tmp_path / "a.ppm"), image)


def test_float_arrays_are_developed(tmp_path):
    image = np.full((1, 2, 3), 0.25, dtype=np.float64)
    prism.write_image(image, tmp_path / "c.ppm", exposure=1.0, transfer="classic")
    assert read_ppm(tmp_path / "c.ppm").tolist() == [[[128] * 3] * 2]  # 0.5 * 255 rounds up
    prism.write_image(image, tmp_path / "s.ppm")  # sRGB: 1.055 * 0.25^(1/2.4) - 0.055
    assert read_ppm(tmp_path / "s.ppm")[0, 0, 0] == 137
    prism.write_image(image * 4, tmp_path / "r.ppm", tonemap="reinhard", transfer="classic")
    assert read_ppm(tmp_path / "r.ppm")[0, 0, 0] == 128  # 1 / (1 + 1)
    prism.write_image(image, tmp_path / "deep.png", png_bits=16)
    assert (tmp_path / "deep.png").read_bytes()[24] == 16  # IHDR bit depth


def test_bad_arrays_and_paths_raise(tmp_path):
    with pytest.raises(ValueError, match="H x W x 3"):
        prism.write_image(np.zeros((4, 4)), tmp_path / "a.png")
    with pytest.raises(prism.FileError, match="unknown image extension"):
        prism.write_image(np.zeros((2, 2, 3)), tmp_path / "a.webp")
    with pytest.raises(ValueError, match="tone map"):
        prism.write_image(np.zeros((2, 2, 3)), tmp_path / "a.png", tonemap="filmic")


def test_show_displays_a_png_in_ipython(monkeypatch):
    shown = []
    display = types.ModuleType("IPython.display")
    display.Image = lambda data, format: ("image", data, format)
    display.display = shown.append
    monkeypatch.setitem(sys.modules, "IPython", types.ModuleType("IPython"))
    monkeypatch.setitem(sys.modules, "IPython.display", display)
    assert prism.show(np.ones((3, 4, 3), dtype=np.float32)) is None
    assert shown[0][0] == "image" and shown[0][1].startswith(b"\x89PNG") and shown[0][2] == "png"


def test_show_without_ipython_returns_the_png(monkeypatch):
    monkeypatch.setitem(sys.modules, "IPython", None)
    png = prism.show(np.zeros((3, 4, 3), dtype=np.uint8))
    assert png.startswith(b"\x89PNG")
