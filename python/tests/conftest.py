"""Shared fixtures: the repository's scenes, the command-line binary to compare with,
and a small animation (few frames, small size) written for each test."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


@pytest.fixture(scope="session")
def prism_bin() -> Path:
    """The `prism` binary: $PRISM_BIN (set by `cargo test --test python`), else the
    debug build."""
    path = Path(os.environ.get("PRISM_BIN", REPO / "target" / "debug" / "prism"))
    if not path.is_file():
        pytest.skip(f"no prism binary at {path}: run `cargo build` (or `cargo test`)")
    return path


def run_cli(prism_bin: Path, *args) -> None:
    subprocess.run([str(prism_bin), *map(str, args), "--quiet"], check=True)


def read_ppm(path: Path) -> np.ndarray:
    """A binary PPM (P6, maxval 255), as Prism writes it."""
    data = path.read_bytes()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    assert fields[0] == b"P6" and fields[3] == b"255"
    w, h = int(fields[1]), int(fields[2])
    return np.frombuffer(data[pos + 1:], dtype=np.uint8).reshape(h, w, 3)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


@pytest.fixture
def small_animation(tmp_path: Path) -> Path:
    """The turntable, 6 frames at 64x36: its tracks and files, fewer and smaller frames
    (the scene and camera named by absolute paths)."""
    folder = tmp_path / "anim"
    folder.mkdir()
    source = SCENES / "turntable"
    text = (source / "turntable.toml").read_text()
    for name in ("turntable.objx", "turntable.cmr"):
        text = text.replace(f'"{name}"', f'"{source / name}"')
    text = text.replace("frames = 48", "frames = 6").replace("width = 320", "width = 64")
    text = text.replace("height = 180", "height = 36")
    path = folder / "small.toml"
    path.write_text(text)
    return path
