#!/usr/bin/env python3
"""Prism's path-traced integrator against Mitsuba 3 on the Cornell box: does it converge
to the same image, and how fast?

The scene is Morgan McGuire's CornellBox-Original (OBJ + MTL: diffuse `Kd`, the ceiling
light's `Ke`), which Prism renders from scenes/cornell-box/cornell-box.toml. Mitsuba
gets the same scene built in Python: one mesh per `usemtl` group (polygons split into
fans, vertex order kept so the one-sided light faces down as in Prism), a `diffuse`
BSDF of reflectance `Kd` (linear RGB as written) wrapped in `twosided` (Prism shades
both sides of a diffuse surface; Mitsuba's BSDFs are black from behind), an `area`
emitter of radiance `Ke` (one-sided, like Prism's), the TOML's look-at camera and
horizontal field of view, a 512 x 512 `hdrfilm` with a `box` filter, the `independent`
sampler and the `path` integrator with unlimited depth (Russian roulette as Mitsuba
does by default).

Subcommands:

  reference [--spp 4096] [--variant V]
      Render Mitsuba's reference (default llvm_ad_rgb if LLVM works here, else
      scalar_rgb) and keep it as target/mitsuba/cornell-ref-<variant>-<spp>.exr (linear
      RGB float, with a .json beside it and a .png preview); prints the time it took.

  compare [--prism BIN] [--spps 4,16,64,256] [--json FILE]
      Render Prism (`--integrator path`) and Mitsuba at each spp (other seeds than the
      reference's) and compare both with the reference in linear radiance:
        - per 32 x 32-pixel block and channel, the difference of the block means as a
          z-score against its standard error, estimated from the per-pixel variance of
          (image - reference) inside the block, i.e. the image's noise plus the
          reference's; the share of blocks with |z| > 3 (0.27 % by chance alone for
          normal noise; path-tracing noise is skewed, so at low spp somewhat more fall
          below -3 even between agreeing renderers) and the largest |z|;
        - the whole image's mean relative difference per channel, with its z-score;
        - the RMSE at each spp and the slope of log RMSE against log spp: about -0.5 for
          an unbiased estimator of the same image (error ~ 1/sqrt(spp)); a bias flattens
          it at high spp. The reference's own noise is a floor too: keep the largest spp
          well below the reference's (1/16 of it adds ~3 % to the RMSE).
      Mitsuba against its own reference shows what agreement within noise looks like,
      beside Prism's figures.

  speed [--spp 64] [--runs 3] [--threads 2]
      Whole-process wall time (start to exit: loading, JIT compilation, rendering,
      writing the EXR) of Prism's path integrator and of Mitsuba llvm_ad_rgb and
      scalar_rgb (each a `render` subprocess of this script) at 512 x 512, runs
      interleaved after one warm-up run each (shown as `first`; Dr.Jit keeps compiled
      kernels on disk in ~/.drjit, so only a first-ever llvm run pays the whole
      compilation), minimum and median; ratios Mitsuba time / Prism time against the
      targets (>= 1.5x llvm_ad_rgb, the speed issue's bar; >= 3x scalar_rgb). Then
      time to equal error: the
      spp at which Prism's RMSE (fitted as c * spp^k from renders at --fit-spps,
      the reference's own noise taken out) equals Mitsuba llvm_ad_rgb's at --spp,
      Prism timed there, against Mitsuba's time (target >= 1x). Needs a reference for
      that part (run `reference`).
      Timings on a shared machine are noisy: the minimum is the run disturbed least.

  render --variant V --spp N --seed S --out FILE.exr
      One Mitsuba render, as `speed` times it.

The Prism command line (the output is written to a temporary folder):
  target/release/prism render scenes/cornell-box/cornell-box.toml OUT.exr
      --integrator path --spp N --aa 1 --filter area --width 512 --height 512
      --seed K --exr-precision float --quiet [--threads T]
(`area` is what Prism calls its box filter; with --aa 1 it has nothing to resample.
Float EXR rather than the default half, so that no rounding enters the statistics.)
For the block means to agree at the edges of the light and of the boxes, Prism must
spread each pixel's samples over the pixel's area as Mitsuba's box filter does; rays
through pixel centres only leave a bias there that no spp removes.

Exit status: 0 when every part ran; 1 with a one-line reason otherwise (no Prism binary,
no path integrator in it yet, no OBJ...), after printing the Mitsuba figures that could
be made.

Needs Python 3.11+, and Mitsuba 3 and numpy, which the script installs into its own
virtual environment target/mitsuba-venv under the repository on first use and then
re-runs itself inside it (by hand: python3 -m venv target/mitsuba-venv &&
target/mitsuba-venv/bin/pip install mitsuba==3.9.1 numpy). The llvm_ad_rgb variant
needs an LLVM shared library (Debian: apt-get install libllvm19); the script finds it
with a glob and sets DRJIT_LIBLLVM_PATH, or uses yours if set. Without it, only
scalar_rgb runs. The OBJ is read from ../shared/models/cornell-box/ beside the
repository unless --obj names another; the camera from the scene file (--scene).
"""

import argparse
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / "target" / "mitsuba-venv"
CACHE = ROOT / "target" / "mitsuba"
DEFAULT_SCENE = ROOT / "scenes" / "cornell-box" / "cornell-box.toml"
DEFAULT_OBJ = ROOT.parent / "shared" / "models" / "cornell-box" / "CornellBox-Original.obj"
DEFAULT_PRISM = ROOT / "target" / "release" / "prism"

# Pinned so that a cached reference and a fresh one come from the same renderer.
MITSUBA_REQUIREMENTS = ["mitsuba==3.9.1", "numpy"]
LLVM_VARIANT = "llvm_ad_rgb"
SCALAR_VARIANT = "scalar_rgb"
SIZE = 512
BLOCK = 32
Z_LIMIT = 3.0
# Two-sided chance that a standard normal exceeds Z_LIMIT: the share of blocks expected
# past it when the two renderers agree.
CHANCE_PAST_LIMIT = math.erfc(Z_LIMIT / math.sqrt(2.0))
# `area` is what Prism calls its box filter.
PRISM_FILTER = "area"
# Seeds: the reference's passes, Mitsuba's comparison renders and Prism's renders each
# draw from their own range, far apart, so that no two images share random streams
# whichever way a variant derives its per-block or per-lane streams from the seed.
REFERENCE_SEED = 1 << 28
COMPARE_SEED = 1 << 24
SEED_STRIDE = 1 << 16
SERIES_SEED_STRIDE = 1 << 22
# Samples per pixel of one render call when an image is made in passes, so that
# progress shows between them (Mitsuba's memory does not grow with spp: ~150 MB here).
PASS_SPP = 256

LLVM_GLOBS = [
    "/usr/lib/x86_64-linux-gnu/libLLVM-*.so*",
    "/usr/lib/x86_64-linux-gnu/libLLVM.so.*",
    "/usr/lib/aarch64-linux-gnu/libLLVM-*.so*",
    "/usr/lib/aarch64-linux-gnu/libLLVM.so.*",
    "/usr/lib/llvm-*/lib/libLLVM*.so*",
    "/usr/local/lib/libLLVM*.so*",
]

# The speed issue's bar at equal samples (its goal is 2x); an earlier issue's was 1x.
TARGET_EQUAL_SPP = 1.5
TARGET_EQUAL_ERROR = 1.0
TARGET_SCALAR = 3.0


def progress(message):
    """A line that rewrites itself on a terminal; nothing in a log file."""
    if sys.stderr.isatty():
        print(f"\r{message}   ", end="", file=sys.stderr, flush=True)


def end_progress():
    if sys.stderr.isatty():
        print(file=sys.stderr)


class Stop(Exception):
    """A reason to stop that the user can act on; printed without a traceback."""


class PrismUnavailable(Stop):
    """Prism's side cannot run (no binary, or no path integrator in it yet)."""


# --------------------------------------------------------------------------------------
# The virtual environment and LLVM: stdlib only, before Mitsuba is imported.


def running_in_venv():
    return Path(sys.prefix).resolve() == VENV.resolve()


def venv_python():
    return VENV / "bin" / "python"


def venv_has_mitsuba():
    return any(VENV.glob("lib/python3*/site-packages/mitsuba/__init__.py"))


def create_venv():
    print(f"setting up {VENV.relative_to(ROOT)} with {' '.join(MITSUBA_REQUIREMENTS)} "
          "(first run only) ...", file=sys.stderr)
    try:
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
        subprocess.run([str(venv_python()), "-m", "pip", "install", "--quiet",
                        *MITSUBA_REQUIREMENTS], check=True)
    except (OSError, subprocess.CalledProcessError) as e:
        raise Stop(f"could not set up {VENV}: {e}\n  by hand: {sys.executable} -m venv "
                   f"{VENV} && {venv_python()} -m pip install "
                   f"{' '.join(MITSUBA_REQUIREMENTS)}") from e


def enter_venv():
    """Re-runs this script with the venv's Python (creating the venv first), since
    Mitsuba and numpy live there and not in the Python that started it."""
    if running_in_venv():
        return
    if not venv_has_mitsuba():
        create_venv()
    python = str(venv_python())
    os.execv(python, [python, str(Path(__file__).resolve()), *sys.argv[1:]])


def llvm_major(path):
    """LLVM's major version from a library path (libLLVM-19.so, libLLVM.so.19.1,
    /usr/lib/llvm-19/lib/libLLVM.so.1), or 0."""
    name = Path(path).name
    m = re.match(r"libLLVM(?:-|\.so\.)(\d+)", name)
    if m is None:
        m = re.search(r"/llvm-(\d+)/", str(path))
    return int(m.group(1)) if m else 0


def find_libllvm():
    """The newest LLVM shared library on the machine, or None. Dr.Jit loads LLVM at run
    time and looks in few places, so the path is handed to it (DRJIT_LIBLLVM_PATH)."""
    given = os.environ.get("DRJIT_LIBLLVM_PATH")
    if given and Path(given).exists():
        return given
    found = {p for pattern in LLVM_GLOBS for p in glob.glob(pattern)}
    found = [p for p in found if llvm_major(p) > 0]
    if not found:
        return None
    return max(found, key=lambda p: (llvm_major(p), -len(p)))


def point_drjit_at_llvm():
    path = find_libllvm()
    if path:
        os.environ["DRJIT_LIBLLVM_PATH"] = path
    return path


# --------------------------------------------------------------------------------------
# The scene: the TOML's camera, the OBJ split by material.


@dataclass
class Camera:
    eye: tuple
    target: tuple
    up: tuple
    fov: float


@dataclass
class Group:
    """The triangles of one `usemtl` material, with its own vertex list."""

    material: str
    vertices: list
    triangles: list


@dataclass
class Material:
    kd: tuple
    ke: tuple

    def emits(self):
        return any(c > 0.0 for c in self.ke)


def read_camera(scene):
    if not scene.is_file():
        raise Stop(f"no scene file at {scene}")
    with open(scene, "rb") as f:
        camera = tomllib.load(f).get("camera", {})
    try:
        return Camera(tuple(camera["from"]), tuple(camera["at"]),
                      tuple(camera.get("up", (0.0, 1.0, 0.0))), float(camera["fov"]))
    except KeyError as e:
        raise Stop(f"{scene}: [camera] has no {e}") from e


def strip_comment(line):
    return line.split("#", 1)[0].split()


def read_mtl(path):
    materials = {}
    current = None
    for line in path.read_text().splitlines():
        words = strip_comment(line)
        if not words:
            continue
        if words[0] == "newmtl":
            current = materials.setdefault(words[1], Material((0.8, 0.8, 0.8), (0.0, 0.0, 0.0)))
        elif words[0] in ("Kd", "Ke") and current is not None:
            rgb = tuple(float(x) for x in words[1:4])
            rgb = rgb if len(rgb) == 3 else (rgb[0],) * 3
            setattr(current, words[0].lower(), rgb)
    return materials


def obj_index(token, count):
    """0-based vertex index of a face token (`7`, `7/2/3`, `-4//1`): OBJ counts from 1,
    and negative indices count back from the last vertex read."""
    i = int(token.split("/")[0])
    return i - 1 if i > 0 else count + i


def read_obj(path):
    """(groups by material, MTL file names). Polygons become fans (v0, vi, vi+1) in the
    file's vertex order, so each triangle's normal (counter-clockwise front) is the
    polygon's."""
    vertices = []
    faces = {}
    mtllibs = []
    material = None
    for line in path.read_text().splitlines():
        words = strip_comment(line)
        if not words:
            continue
        if words[0] == "v":
            vertices.append(tuple(float(x) for x in words[1:4]))
        elif words[0] == "f":
            corners = [obj_index(t, len(vertices)) for t in words[1:]]
            fan = faces.setdefault(material, [])
            fan.extend((corners[0], corners[i], corners[i + 1])
                       for i in range(1, len(corners) - 1))
        elif words[0] == "usemtl":
            material = words[1]
        elif words[0] == "mtllib":
            mtllibs.extend(words[1:])
    groups = []
    for name, triangles in faces.items():
        used = sorted({i for t in triangles for i in t})
        local = {i: n for n, i in enumerate(used)}
        groups.append(Group(name, [vertices[i] for i in used],
                            [tuple(local[i] for i in t) for t in triangles]))
    return groups, mtllibs


def load_model(obj):
    if not obj.is_file():
        raise Stop(f"no Cornell box OBJ at {obj}: the models folder is expected at "
                   f"{DEFAULT_OBJ.parent} (beside the repository); pass --obj PATH to "
                   "use another copy")
    groups, mtllibs = read_obj(obj)
    materials = {}
    for name in mtllibs:
        mtl = obj.parent / name
        if not mtl.is_file():
            raise Stop(f"{obj} names {name}, which is not at {mtl}")
        materials.update(read_mtl(mtl))
    missing = [g.material for g in groups if g.material not in materials]
    if missing:
        raise Stop(f"{obj}: faces with no material defined in its MTL: {missing}")
    return groups, materials


def write_group_obj(group, path):
    """Triangles only, vertex order as read: Mitsuba's OBJ reader then has nothing to
    triangulate or reorder."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in group.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in group.triangles]
    path.write_text("\n".join(lines) + "\n")


# --------------------------------------------------------------------------------------
# Mitsuba (imported inside the venv only).


def import_mitsuba(variant):
    import drjit as dr
    import mitsuba as mi

    try:
        mi.set_variant(variant)
    except (ImportError, AttributeError, RuntimeError) as e:
        raise Stop(f"Mitsuba variant {variant} is not available: {e}") from e
    return mi, dr


def llvm_status():
    """(works, message): whether llvm_ad_rgb runs here, tried in a child process, since
    a missing or unusable LLVM can abort the process that loads it."""
    path = os.environ.get("DRJIT_LIBLLVM_PATH")
    if not path:
        return False, "no LLVM library found (Debian: apt-get install libllvm19)"
    probe = ("import drjit as dr, mitsuba as mi\n"
             f"mi.set_variant('{LLVM_VARIANT}')\n"
             "x = dr.arange(mi.Float, 8)\n"
             "print(dr.sum(x * 2))\n")
    try:
        done = subprocess.run([sys.executable, "-c", probe], capture_output=True,
                              text=True, timeout=300)
    except subprocess.TimeoutExpired:
        return False, f"{LLVM_VARIANT} did not answer within 300 s"
    if done.returncode != 0 or "56" not in done.stdout:
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["(no output)"]
        return False, f"{LLVM_VARIANT} fails with {path}: {tail[0]}"
    return True, f"{LLVM_VARIANT} with {path}"


def default_variant():
    works, message = llvm_status()
    if works:
        return LLVM_VARIANT
    print(f"note: {message}; using {SCALAR_VARIANT}", file=sys.stderr)
    return SCALAR_VARIANT


def scene_dict(mi, groups, materials, folder, camera):
    """Mitsuba's description of the scene, its meshes written into `folder`."""
    scene = {
        "type": "scene",
        # max_depth -1: no depth limit; Russian roulette (from depth 5) ends paths.
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": {
            "type": "perspective",
            "fov": camera.fov,
            "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=list(camera.eye), target=list(camera.target), up=list(camera.up)),
            "sampler": {"type": "independent", "sample_count": 1},
            "film": {
                "type": "hdrfilm",
                "width": SIZE,
                "height": SIZE,
                "pixel_format": "rgb",
                "component_format": "float32",
                "rfilter": {"type": "box"},
            },
        },
    }
    for n, group in enumerate(groups):
        path = Path(folder) / f"{n:02d}-{group.material}.obj"
        write_group_obj(group, path)
        material = materials[group.material]
        diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(material.kd)}}
        # Two-sided for every surface, the light's too: Prism reflects off both sides
        # of a diffuse surface. Emission stays one-sided, as in Prism.
        shape = {"type": "obj", "filename": str(path), "face_normals": True,
                 "bsdf": {"type": "twosided", "bsdf": diffuse}}
        if material.emits():
            shape["emitter"] = {"type": "area",
                                "radiance": {"type": "rgb", "value": list(material.ke)}}
        scene[f"{n:02d}-{group.material}"] = shape
    return scene


class MitsubaScene:
    """The Cornell box loaded into one Mitsuba variant, ready to render."""

    def __init__(self, variant, obj, scene_file, threads=None):
        self.mi, self.dr = import_mitsuba(variant)
        self.variant = variant
        if threads:
            self.dr.set_thread_count(threads)
        groups, materials = load_model(obj)
        camera = read_camera(scene_file)
        # Mitsuba reads the meshes while loading; the folder can go afterwards.
        with tempfile.TemporaryDirectory(prefix="mitsuba-cornell-") as folder:
            self.scene = self.mi.load_dict(scene_dict(self.mi, groups, materials, folder, camera))

    def render(self, spp, seed, pass_spp=None):
        """Linear RGB, float64, height x width x 3. With `pass_spp`, renders of at most
        that many samples each (seeds apart), averaged with their sample counts as
        weights: the estimate of one render of `spp` samples (each pixel's value is the
        mean of its own samples under the box filter)."""
        import numpy as np

        if not pass_spp or pass_spp >= spp:
            return self._render_once(spp, seed).astype(np.float64)
        passes = [pass_spp] * (spp // pass_spp) + ([spp % pass_spp] if spp % pass_spp else [])
        total = 0.0
        for i, n in enumerate(passes):
            total = total + n * self._render_once(n, seed + i * SEED_STRIDE).astype(np.float64)
            progress(f"  pass {i + 1}/{len(passes)}")
        end_progress()
        return total / spp

    def _render_once(self, spp, seed):
        import numpy as np

        image = self.mi.render(self.scene, spp=spp, seed=seed)
        return np.array(image, dtype=np.float32)[..., :3]


def write_exr(mi, image, path):
    import numpy as np

    path.parent.mkdir(parents=True, exist_ok=True)
    mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32)).write(str(path))


def write_png_preview(mi, image, path):
    import numpy as np

    bitmap = mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32))
    srgb = bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True)
    srgb.write(str(path))


def read_exr(mi, path):
    """Linear RGB, float64, height x width x 3, from any EXR (half or float, with or
    without alpha; a one-channel image is repeated over the three)."""
    import numpy as np

    bitmap = mi.Bitmap(str(path)).convert(component_format=mi.Struct.Type.Float32)
    image = np.array(bitmap, dtype=np.float64)
    if image.ndim == 2:
        image = image[..., None]
    if image.shape[2] < 3:
        image = np.repeat(image[..., :1], 3, axis=2)
    return image[..., :3]


# --------------------------------------------------------------------------------------
# The reference.


def reference_path(variant, spp, obj):
    """The cache file; another OBJ than the default's gets its name added, so that it
    does not replace the default's reference."""
    other = "" if obj.resolve() == DEFAULT_OBJ.resolve() else f"-{obj.stem}"
    return CACHE / f"cornell-ref-{variant}-{spp}{other}.exr"


def reference_info_path(exr):
    return exr.with_suffix(".json")


def make_reference(variant, spp, obj, scene_file):
    """Renders, writes and returns the reference's path."""
    import mitsuba as mi

    exr = reference_path(variant, spp, obj)
    start = time.perf_counter()
    scene = MitsubaScene(variant, obj, scene_file)
    print(f"rendering the reference: Mitsuba {mi.__version__} {variant}, {spp} spp, "
          f"{SIZE}x{SIZE}", file=sys.stderr)
    image = scene.render(spp, REFERENCE_SEED, PASS_SPP)
    seconds = time.perf_counter() - start
    write_exr(scene.mi, image, exr)
    write_png_preview(scene.mi, image, exr.with_suffix(".png"))
    info = {"variant": variant, "spp": spp, "seconds": round(seconds, 2),
            "mitsuba": mi.__version__, "obj": str(obj.resolve()),
            "seed": REFERENCE_SEED, "pass_spp": PASS_SPP,
            "libllvm": os.environ.get("DRJIT_LIBLLVM_PATH")}
    reference_info_path(exr).write_text(json.dumps(info, indent=2) + "\n")
    print(f"reference: {exr.relative_to(ROOT)} ({variant}, {spp} spp) in {seconds:.1f} s")
    return exr


def cached_reference(obj, variant=None, spp=None):
    """The cached reference with the most samples (of this variant and spp, if given)
    rendered from this OBJ, or None."""
    best = None
    for exr in CACHE.glob("cornell-ref-*.exr"):
        info_path = reference_info_path(exr)
        if not info_path.is_file():
            continue
        info = json.loads(info_path.read_text())
        if info.get("obj") != str(obj.resolve()):
            continue
        if (variant and info["variant"] != variant) or (spp and info["spp"] != spp):
            continue
        if best is None or info["spp"] > best[1]["spp"]:
            best = (exr, info)
    return best


def reference_for(args, render_if_missing):
    """(path, info) of the reference `compare` and `speed` measure against."""
    found = cached_reference(args.obj, args.variant, args.reference_spp)
    if found:
        return found
    if not render_if_missing:
        return None
    variant = args.variant or default_variant()
    spp = args.reference_spp or 4096
    exr = make_reference(variant, spp, args.obj, args.scene)
    return exr, json.loads(reference_info_path(exr).read_text())


# --------------------------------------------------------------------------------------
# Statistics.


def blocks_of(image, block):
    """(rows, columns, channels, pixels) view of image x image blocks; a margin that
    does not fill a block is left out."""
    h, w, c = image.shape
    rows, cols = h // block, w // block
    x = image[: rows * block, : cols * block].reshape(rows, block, cols, block, c)
    return x.transpose(0, 2, 4, 1, 3).reshape(rows, cols, c, block * block)


def compare_images(test, reference, block=BLOCK):
    """Figures of `test` against `reference`, both linear RGB.

    Per block, the difference image's sample variance is the test's per-pixel noise
    plus the reference's, without the picture's own structure (edges, gradients), which
    would inflate a variance taken from the test image alone."""
    import numpy as np

    diff = test - reference
    blocks = blocks_of(diff, block)
    n = blocks.shape[-1]
    mean = blocks.mean(axis=-1)
    var = blocks.var(axis=-1, ddof=1)
    se = np.sqrt(var / n)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(se > 0, mean / se, np.where(mean == 0, 0.0, np.inf))
    above = int(np.count_nonzero(z > Z_LIMIT))
    below = int(np.count_nonzero(z < -Z_LIMIT))
    past = above + below

    pixels = diff.shape[0] * diff.shape[1]
    ref_mean = reference.reshape(-1, 3).mean(axis=0)
    diff_mean = diff.reshape(-1, 3).mean(axis=0)
    # Standard error of the whole image's mean: the blocks' noise added up.
    diff_se = np.sqrt((var * n).sum(axis=(0, 1))) / pixels
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = diff_mean / ref_mean
        rel_z = np.where(diff_se > 0, diff_mean / diff_se, 0.0)
    return {
        "rmse": float(np.sqrt(np.mean(diff ** 2))),
        "blocks": int(z.size),
        "blocks_past_3": past,
        "share_past_3": past / z.size,
        "blocks_above_3": above,
        "blocks_below_minus_3": below,
        "max_abs_z": float(np.max(np.abs(z))),
        "worst_block": [int(i) for i in np.unravel_index(np.argmax(np.abs(z)), z.shape)],
        "mean_rel_diff": [float(x) for x in rel],
        "mean_rel_diff_z": [float(x) for x in rel_z],
    }


def loglog_slope(spps, rmses):
    import numpy as np

    if len(spps) < 2:
        return float("nan")
    return float(np.polyfit(np.log(spps), np.log(rmses), 1)[0])


def reference_noise_mse(mses_by_spp, reference_spp):
    """The reference's own noise as a mean squared error, from Mitsuba's MSE against
    it at other spps: each is V / spp + V / reference_spp (its noise plus the
    reference's, V the per-sample variance), so V is estimated and V / reference_spp
    returned. Every renderer's MSE against the reference carries this floor."""
    estimates = [mse / (1.0 / spp + 1.0 / reference_spp) for spp, mse in mses_by_spp.items()]
    return statistics.mean(estimates) / reference_spp


def without_floor(rmse, floor_mse):
    """RMSE with the reference's noise taken out (never below a tenth of the raw)."""
    return math.sqrt(max(rmse * rmse - floor_mse, 0.01 * rmse * rmse))


def prism_command(prism, scene, out, spp, seed, threads=None):
    command = [str(prism), "render", str(scene), str(out),
               "--integrator", "path", "--spp", str(spp), "--aa", "1",
               "--filter", PRISM_FILTER, "--width", str(SIZE), "--height", str(SIZE),
               "--seed", str(seed), "--exr-precision", "float", "--quiet"]
    if threads:
        command += ["--threads", str(threads)]
    return command


def check_prism_binary(prism):
    if not Path(prism).is_file():
        raise PrismUnavailable(f"no prism binary at {prism}: build it with "
                               "cargo build --release, or pass --prism PATH")


def prism_failure(command, stderr):
    """The error for a failed Prism run: a plain sentence when it is the path
    integrator that is missing."""
    if "--integrator" in stderr and "'path'" in stderr:
        return PrismUnavailable("prism does not know --integrator path yet: build it "
                                "with cargo build --release (or pass --prism PATH)")
    return PrismUnavailable(f"prism failed: {' '.join(command)}\n  {stderr.strip()}")


def run_prism(prism, scene, out, spp, seed, threads=None):
    command = prism_command(prism, scene, out, spp, seed, threads)
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise prism_failure(command, done.stderr)


# --------------------------------------------------------------------------------------
# Whole-process timing.


@dataclass
class Timing:
    wall: float
    cpu: float
    max_rss_mib: float


def timed(command):
    """Wall and CPU seconds and peak memory of one whole process; raises
    CalledProcessError (with its standard error) if it fails."""
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, command, stderr=stderr.decode())
    return Timing(wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024)


def mitsuba_render_command(variant, spp, seed, out, args):
    return [sys.executable, str(Path(__file__).resolve()), "render", "--variant", variant,
            "--spp", str(spp), "--seed", str(seed), "--out", str(out),
            "--obj", str(args.obj), "--scene", str(args.scene), "--threads", str(args.threads)]


# --------------------------------------------------------------------------------------
# Subcommands.


def cmd_render(args):
    """One Mitsuba render written as EXR: what `speed` times as a whole process."""
    scene = MitsubaScene(args.variant, args.obj, args.scene, args.threads)
    image = scene.render(args.spp, args.seed)
    write_exr(scene.mi, image, Path(args.out))


def cmd_reference(args):
    variant = args.variant or default_variant()
    exr = make_reference(variant, args.spp, args.obj, args.scene)
    print(f"preview: {exr.with_suffix('.png').relative_to(ROOT)}")


def format_row(label, spp, figures):
    rel = " ".join(f"{100 * r:+7.3f}%" for r in figures["mean_rel_diff"])
    rel_z = " ".join(f"{z:+5.1f}" for z in figures["mean_rel_diff_z"])
    past = (f"{figures['blocks_past_3']} ({figures['blocks_above_3']}+"
            f"{figures['blocks_below_minus_3']}-)")
    row, col, channel = figures["worst_block"]
    worst = f"{row},{col} {'RGB'[channel]}"
    return (f"{label:<9} {spp:>6} {figures['rmse']:>9.5f} {past:>11} "
            f"{100 * figures['share_past_3']:>6.2f}% {figures['max_abs_z']:>7.2f} {worst:>8}   "
            f"{rel}   ({rel_z})")


def print_comparison(reference_info, results, spps, floor_mse):
    blocks = next(iter(next(iter(results.values())).values()))["blocks"]
    print()
    print(f"against Mitsuba's reference ({reference_info['variant']}, "
          f"{reference_info['spp']} spp), linear radiance, {BLOCK}x{BLOCK}-pixel blocks "
          f"x 3 channels; by chance alone |z| > {Z_LIMIT:g} in "
          f"{100 * CHANCE_PAST_LIMIT:.2f}% of blocks ({CHANCE_PAST_LIMIT * blocks:.1f} "
          f"of {blocks})")
    print("Noise in a path tracer is skewed (rare bright samples): at low spp a few more than")
    print("that fall past -3 even when the images agree, as Mitsuba's rows against its own")
    print("reference show. R, G and B of a block share their paths, so they tend to fail together.")
    print(f"{'renderer':<9} {'spp':>6} {'RMSE':>9} {'|z|>3 (+-)':>11} {'share':>7} {'max|z|':>7} "
          f"{'at block':>8}   "
          f"{'mean rel. diff R, G, B':<26}   (z of each)")
    for spp in spps:
        for label, by_spp in results.items():
            if spp in by_spp:
                print(format_row(label, spp, by_spp[spp]))
    print()
    print(f"the reference's own noise (estimated from Mitsuba's series): RMSE "
          f"{math.sqrt(floor_mse):.5f}, a floor under every RMSE above")
    slopes = {}
    if len(spps) < 2:
        print("slope of log RMSE against log spp: needs two spps or more")
        return slopes
    for label, by_spp in results.items():
        got = sorted(by_spp)
        rmses = [by_spp[s]["rmse"] for s in got]
        slope = loglog_slope(got, rmses)
        net = loglog_slope(got, [without_floor(r, floor_mse) for r in rmses])
        slopes[label] = {"raw": slope, "without_reference_noise": net}
        print(f"{label}: slope of log RMSE against log spp {slope:+.3f}, {net:+.3f} without "
              "the reference's noise (-0.5: unbiased, converging to the reference)")
    return slopes


def mitsuba_series(args, reference, variant, spps):
    """Mitsuba at each spp against its reference, with seeds of its own."""
    scene = MitsubaScene(variant, args.obj, args.scene)
    figures = {}
    for k, spp in enumerate(spps):
        print(f"Mitsuba {variant} at {spp} spp ...", file=sys.stderr)
        image = scene.render(spp, COMPARE_SEED + k * SERIES_SEED_STRIDE, PASS_SPP)
        figures[spp] = compare_images(image, reference)
    return figures


def prism_series(args, mi, reference, spps):
    check_prism_binary(args.prism)
    figures = {}
    with tempfile.TemporaryDirectory(prefix="prism-cornell-") as folder:
        for k, spp in enumerate(spps):
            print(f"Prism path at {spp} spp ...", file=sys.stderr)
            out = Path(folder) / f"prism-{spp}.exr"
            run_prism(args.prism, args.scene, out, spp, seed=1 + k)
            figures[spp] = compare_images(read_exr(mi, out), reference)
    return figures


def cmd_compare(args):
    import mitsuba as mi

    spps = parse_spps(args.spps)
    ref_path, ref_info = reference_for(args, render_if_missing=True)
    variant = args.variant or ref_info["variant"]
    import_mitsuba(variant)
    reference = read_exr(mi, ref_path)
    print(f"reference: {ref_path.relative_to(ROOT)}", file=sys.stderr)

    results = {}
    prism_error = None
    if not args.mitsuba_only:
        try:
            results["prism"] = prism_series(args, mi, reference, spps)
        except PrismUnavailable as e:
            prism_error = e
            print(f"prism: {e}", file=sys.stderr)
    results["mitsuba"] = mitsuba_series(args, reference, variant, spps)
    floor_mse = reference_noise_mse({s: f["rmse"] ** 2 for s, f in results["mitsuba"].items()},
                                    ref_info["spp"])
    slopes = print_comparison(ref_info, results, spps, floor_mse)

    if args.json:
        report = {"reference": {**ref_info, "path": str(ref_path)}, "block": BLOCK,
                  "z_limit": Z_LIMIT, "chance_past_limit": CHANCE_PAST_LIMIT,
                  "mitsuba_variant": variant, "prism_command": prism_command(
                      args.prism, args.scene, "OUT.exr", "N", "K"),
                  "prism_error": str(prism_error) if prism_error else None,
                  "results": {label: {str(s): f for s, f in by_spp.items()}
                              for label, by_spp in results.items()},
                  "reference_noise_rmse": math.sqrt(floor_mse), "rmse_slope": slopes}
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
        print(f"figures written to {args.json}")
    if prism_error:
        raise prism_error


def time_runs(commands, runs):
    """Per name: one warm-up run (first), then `runs` runs interleaved across the
    commands so that the machine's other load falls on all of them alike. A command
    that fails is dropped with its error."""
    timings = {name: [] for name in commands}
    errors = {}
    for round_ in range(runs + 1):
        for name, command in commands.items():
            if name in errors:
                continue
            try:
                timings[name].append(timed(command))
            except subprocess.CalledProcessError as e:
                errors[name] = e
            progress(f"  round {round_ + 1}/{runs + 1}: {name}")
    end_progress()
    return timings, errors


def summary(timings):
    walls = [t.wall for t in timings[1:]] or [timings[0].wall]
    return {"first": timings[0].wall, "min": min(walls), "median": statistics.median(walls),
            "cpu_median": statistics.median(t.cpu for t in timings[1:] or timings),
            "max_rss_mib": max(t.max_rss_mib for t in timings)}


def verdict(ratio, target):
    return "met" if ratio >= target else "not met"


def print_speed_table(args, figures, errors):
    print()
    print(f"whole-process wall time, {SIZE}x{SIZE}, {args.spp} spp, {args.threads} threads, "
          f"{args.runs} runs after a warm-up (shared machine: the minimum is the run "
          "disturbed least)")
    print("CPU: user + system seconds (median), steadier than wall time when other jobs run;")
    print("ratios: Mitsuba / Prism, of the minimum and median wall times and of CPU time")
    print(f"{'renderer':<22} {'first':>8} {'min':>8} {'median':>8} {'CPU':>8} {'peak MiB':>9}"
          f" {'ratio min, median, CPU':>24}  target (median)")
    prism = figures.get("prism")
    targets = {f"mitsuba {LLVM_VARIANT}": TARGET_EQUAL_SPP,
               f"mitsuba {SCALAR_VARIANT}": TARGET_SCALAR}
    for name, f in figures.items():
        ratio = ""
        target = ""
        if prism and name != "prism":
            r_min, r_med = f["min"] / prism["min"], f["median"] / prism["median"]
            r_cpu = f["cpu_median"] / prism["cpu_median"]
            f["ratio_min"], f["ratio_median"], f["ratio_cpu"] = r_min, r_med, r_cpu
            ratio = f"{r_min:.2f}x, {r_med:.2f}x, {r_cpu:.2f}x"
            target = f">= {targets[name]:g}x: {verdict(r_med, targets[name])}"
        elif name != "prism":
            target = f">= {targets[name]:g}x: (no Prism time)"
        print(f"{name:<22} {f['first']:>7.2f}s {f['min']:>7.2f}s {f['median']:>7.2f}s "
              f"{f['cpu_median']:>7.2f}s {f['max_rss_mib']:>9.0f} {ratio:>24}  {target}")
    for name, e in errors.items():
        print(f"{name}: failed: {(e.stderr or '').strip()[-500:]}")


def equal_error(args, mi, llvm_exr, llvm_time, folder):
    """Prism's time at the spp where its RMSE matches Mitsuba llvm's at --spp."""
    import numpy as np

    found = reference_for(args, render_if_missing=False)
    if not found:
        print("\ntime to equal error: no cached reference; run `reference` first")
        return None
    ref_path, ref_info = found
    reference = read_exr(mi, ref_path)
    llvm_rmse = compare_images(read_exr(mi, llvm_exr), reference)["rmse"]
    fit_spps = parse_spps(args.fit_spps)
    rmses = []
    for k, spp in enumerate(fit_spps):
        out = Path(folder) / f"fit-{spp}.exr"
        run_prism(args.prism, args.scene, out, spp, seed=100 + k, threads=args.threads)
        rmses.append(compare_images(read_exr(mi, out), reference)["rmse"])
    # Both RMSEs carry the reference's noise; matched without it, Prism's error is
    # fitted as c * spp^k, k measured rather than assumed: stratified (Sobol) samples
    # converge faster than 1 / sqrt(spp).
    floor_mse = reference_noise_mse({args.spp: llvm_rmse ** 2}, ref_info["spp"])
    own = [without_floor(r, floor_mse) for r in rmses]
    slope, log_c = np.polyfit(np.log(fit_spps), np.log(own), 1)
    c = float(np.exp(log_c))
    spp_equal = max(1, round((without_floor(llvm_rmse, floor_mse) / c) ** (1.0 / slope)))
    out = Path(folder) / "prism-equal.exr"
    command = prism_command(args.prism, args.scene, out, spp_equal, 200, args.threads)
    try:
        times = [timed(command) for _ in range(args.runs + 1)]
    except subprocess.CalledProcessError as e:
        raise prism_failure(command, e.stderr or "") from None
    prism_equal = summary(times)
    prism_rmse = compare_images(read_exr(mi, out), reference)["rmse"]
    ratio_min = llvm_time["min"] / prism_equal["min"]
    ratio_median = llvm_time["median"] / prism_equal["median"]
    print()
    print(f"time to equal error (reference {ref_info['variant']}, {ref_info['spp']} spp):")
    print(f"  Mitsuba {LLVM_VARIANT} at {args.spp} spp: RMSE {llvm_rmse:.5f}, "
          f"{llvm_time['min']:.2f} s min, {llvm_time['median']:.2f} s median")
    print(f"  Prism RMSE at {fit_spps} spp: {[round(r, 5) for r in rmses]}; "
          f"slope {loglog_slope(fit_spps, rmses):+.3f}; without the reference's noise "
          f"(RMSE {math.sqrt(floor_mse):.5f}) fitted as {c:.4f} * spp^{slope:.3f}")
    print(f"  Prism at {spp_equal} spp (equal error): RMSE {prism_rmse:.5f}, "
          f"{prism_equal['min']:.2f} s min, {prism_equal['median']:.2f} s median")
    print(f"  Mitsuba / Prism at equal error: {ratio_min:.2f}x (min), {ratio_median:.2f}x "
          f"(median); target >= {TARGET_EQUAL_ERROR:g}x: "
          f"{verdict(ratio_median, TARGET_EQUAL_ERROR)}")
    return {"mitsuba_llvm_rmse": llvm_rmse, "fit_spps": fit_spps, "prism_rmses": rmses,
            "reference_noise_rmse": math.sqrt(floor_mse), "fit_c": c, "prism_spp": spp_equal,
            "prism_rmse": prism_rmse,
            "prism_time": prism_equal, "ratio_min": ratio_min, "ratio_median": ratio_median}


def cmd_speed(args):
    import mitsuba as mi

    llvm_works, llvm_message = llvm_status()
    prism_error = None
    with tempfile.TemporaryDirectory(prefix="cornell-speed-") as folder:
        commands = {}
        try:
            check_prism_binary(args.prism)
            probe = Path(folder) / "probe.exr"
            # One tiny render first: a Prism without the path integrator fails here with
            # a plain message instead of inside the timing loop.
            run_prism(args.prism, args.scene, probe, 1, 0, args.threads)
            commands["prism"] = prism_command(args.prism, args.scene, Path(folder) / "prism.exr",
                                              args.spp, 1, args.threads)
        except PrismUnavailable as e:
            prism_error = e
            print(f"prism: {e}", file=sys.stderr)
        llvm_exr = Path(folder) / "llvm.exr"
        if llvm_works:
            commands[f"mitsuba {LLVM_VARIANT}"] = mitsuba_render_command(
                LLVM_VARIANT, args.spp, COMPARE_SEED, llvm_exr, args)
        else:
            print(f"skipping {LLVM_VARIANT}: {llvm_message}", file=sys.stderr)
        commands[f"mitsuba {SCALAR_VARIANT}"] = mitsuba_render_command(
            SCALAR_VARIANT, args.spp, COMPARE_SEED, Path(folder) / "scalar.exr", args)

        timings, errors = time_runs(commands, args.runs)
        figures = {name: summary(t) for name, t in timings.items() if t}
        print_speed_table(args, figures, errors)
        report = {"spp": args.spp, "size": SIZE, "threads": args.threads, "runs": args.runs,
                  "libllvm": os.environ.get("DRJIT_LIBLLVM_PATH"), "times": figures,
                  "prism_error": str(prism_error) if prism_error else None}
        llvm_name = f"mitsuba {LLVM_VARIANT}"
        if "prism" in figures and llvm_name in figures:
            import_mitsuba(SCALAR_VARIANT)
            report["equal_error"] = equal_error(args, mi, llvm_exr, figures[llvm_name], folder)
        else:
            print(f"\ntime to equal error: needs both Prism and Mitsuba {LLVM_VARIANT}")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
        print(f"figures written to {args.json}")
    if prism_error:
        raise prism_error


# --------------------------------------------------------------------------------------
# Command line.


def parse_spps(text):
    try:
        spps = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise Stop(f"not a list of sample counts: {text!r} (e.g. 4,16,64,256)") from None
    if not spps or min(spps) < 1:
        raise Stop(f"sample counts must be positive: {text!r}")
    return spps


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See the module docstring (head of this file) for details.")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--obj", type=Path, default=DEFAULT_OBJ,
                        help="the Cornell box OBJ for Mitsuba (default: %(default)s)")
    common.add_argument("--scene", type=Path, default=DEFAULT_SCENE,
                        help="Prism's scene file, also the camera's source (default: %(default)s)")
    sub = p.add_subparsers(dest="command", required=True)

    ref = sub.add_parser("reference", parents=[common], help="render Mitsuba's reference")
    ref.add_argument("--spp", type=int, default=4096)
    ref.add_argument("--variant",
                     help=f"{LLVM_VARIANT} (default if LLVM works) or {SCALAR_VARIANT}")

    cmp_ = sub.add_parser("compare", parents=[common],
                          help="Prism and Mitsuba against the reference")
    cmp_.add_argument("--prism", type=Path, default=DEFAULT_PRISM,
                      help="the prism binary (default: %(default)s)")
    cmp_.add_argument("--spps", default="4,16,64,256",
                      help="samples per pixel to compare at (default: %(default)s)")
    cmp_.add_argument("--variant", help="the reference's and Mitsuba's variant (default: "
                      "the cached reference's)")
    cmp_.add_argument("--reference-spp", type=int,
                      help="the reference's spp (default: the largest cached; 4096 if none)")
    cmp_.add_argument("--mitsuba-only", action="store_true", help="skip Prism")
    cmp_.add_argument("--json", help="write every figure to this file too")

    speed = sub.add_parser("speed", parents=[common], help="whole-process times, Prism and Mitsuba")
    speed.add_argument("--prism", type=Path, default=DEFAULT_PRISM,
                       help="the prism binary (default: %(default)s)")
    speed.add_argument("--spp", type=int, default=64, help="(default: %(default)s)")
    speed.add_argument("--runs", type=int, default=3,
                       help="timed runs of each, after a warm-up (default: %(default)s)")
    speed.add_argument("--threads", type=int, default=2,
                       help="threads of Prism and of Mitsuba (default: %(default)s)")
    speed.add_argument("--fit-spps", default="4,8,16,32",
                       help="Prism's spps for the c * spp^k fit of its RMSE (bracketing "
                            "the equal-error spp)")
    speed.add_argument("--variant", help="the reference's variant for the equal-error part")
    speed.add_argument("--reference-spp", type=int)
    speed.add_argument("--json", help="write every figure to this file too")

    render = sub.add_parser("render", parents=[common],
                            help="one Mitsuba render (what speed times)")
    render.add_argument("--variant", required=True)
    render.add_argument("--spp", type=int, required=True)
    render.add_argument("--seed", type=int, default=0)
    render.add_argument("--out", required=True)
    render.add_argument("--threads", type=int)
    return p


def main():
    args = parser().parse_args()
    try:
        enter_venv()
        point_drjit_at_llvm()
        {"reference": cmd_reference, "compare": cmd_compare, "speed": cmd_speed,
         "render": cmd_render}[args.command](args)
    except Stop as e:
        sys.exit(f"{Path(__file__).name}: {e}")


if __name__ == "__main__":
    main()
