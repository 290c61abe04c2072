#!/usr/bin/env python3
"""Prism's path tracer against Blender 3.4's Cycles on Khronos glTF sample models whose
materials use OpenPBR-relevant extensions: are the images the same, and how fast?

Models (Khronos glTF-Sample-Assets / glTF-Sample-Models, CC-BY 4.0 and others, see each
model's LICENSE.md): ClearCoatTest (KHR_materials_clearcoat), SheenChair
(KHR_materials_sheen), TransmissionRoughnessTest (rough KHR_materials_transmission,
_ior, _volume), SpecularTest (KHR_materials_specular), AttenuationTest
(KHR_materials_volume attenuation). They were obtained with the project's `fetch`
tool from the snapshot github:DRx3D/glTF-Sample-Assets-OLD (commit 02d4868, a bare git
dir), extracting only what is needed:

    D=<fetched git dir>; K=target/khronos; mkdir -p $K
    for m in ClearCoatTest TransmissionRoughnessTest SpecularTest AttenuationTest; do
      git -C $D show HEAD:Models/$m/glTF-Binary/$m.glb > $K/$m.glb; done
    mkdir -p $K/SheenChair   # its .glb is over 4 MiB: take the glTF folder
    for f in $(git -C $D ls-tree --name-only HEAD Models/SheenChair/glTF/); do
      git -C $D show HEAD:$f > $K/SheenChair/$(basename $f); done

(any copy of the sample models works: a model is looked for as K/Name.glb,
K/Name/Name.gltf, K/Name/glTF-Binary/Name.glb, K/Name/glTF/Name.gltf or the same under
K/Models/). The folder is --models or $PRISM_KHRONOS (default target/khronos); with no
model there the script says how to get them and exits 3 (skipped).

Blender: Debian's `apt-get install blender python3-numpy` (3.4.1; the glTF importer
needs numpy, which the blender package does not pull in), run headless as
`blender -b --factory-startup --python benches/cycles_materials_blender.py -- ...`; that
helper imports the model with Blender's own glTF importer, reports what the importer
made of each extension (the Principled BSDF's inputs and the added nodes), applies the
fix-ups its docstring lists (Cycles 3.4's Disney clearcoat fed 4x, the importer's volume
absorption converted to glTF's Beer law, Multiscatter GGX; --no-fixups to see the raw
import), and renders with Cycles: CPU, the given samples, adaptive sampling, denoising
and clamping off, 64 bounces of every kind, caustics on, Filter Glossy 0, a box pixel
filter one pixel wide, linear 32-bit EXR. Prism: `render M OUT.exr --integrator path
--spp N --aa 1 --width W --height H --seed S --exr-precision float --quiet
--environment env.hdr --look-from ... --look-at ... --up 0,1,0 --fov HFOV` (unlimited
depth, Russian roulette; --aa 1 = each pixel the mean of samples spread over its area,
as Cycles' one-pixel box).

Environment, written by the script as target/cycles/env.hdr (512 x 256 RGBE): a blue
gradient sky, a darker brown ground, a warm bright soft sun (peak ~40) up and to the
camera's right and a weaker blue patch low on the left. Orientation (verified by
`orient`, see below): Prism's equirect has its top along +y and its centre column along
-z (glTF coordinates), u growing towards +x. The glTF importer maps glTF (x, y, z) to
Blender (x, -z, y), and Blender's world equirect has its centre column along Blender +X
with u growing towards Blender -Y. So Blender's lookup vector must be Prism's turned by
-90 degrees about Blender's Z (a Mapping node, Point, rotation Z = -90 degrees, fed by
the Generated world coordinates): glTF -z = Blender +Y -> +X (centre), glTF +x = Blender
+X -> -Y (u = 0.75 in both). `orient` renders a mirror sphere (a glTF made here) in
both renderers with Blender's rotation at -90, 0, 90 and 180 degrees and with the
image mirrored, and reports the relative RMSE of each: -90 is the only match (run of
2026-12-05, 96 x 96, 16 spp: 0.014-0.043 for -90 degrees, the 16-spp noise, against
0.77-1.45 for 0, 90 and 180 degrees and 0.77-1.19 for -90 mirrored).

Subcommands:

  compare [--models DIR] [--prism BIN] [--spp 512] [--size 256] [--out target/cycles]
          [--only Name,...] [--no-fixups]
      For each model: one camera from the model's bounds (a three-quarter view, the
      horizontal field of view 40 degrees), given to Prism by flags and built in Blender
      (sensor fit horizontal, converted coordinates). Each renderer renders twice with
      half the samples and two seeds; the image is their mean and the difference of the
      halves measures each renderer's noise. Prints the extensions the model uses and
      what Blender's importer made of each (mapped / mapped, fixed up / approximate /
      not imported); a row with an approximate or missing extension is "not
      comparable": its figures are shown but do not count. Then, in linear radiance:
        - the whole image's mean per channel, Prism and Cycles, and Prism/Cycles - 1;
        - over 16 x 16-pixel blocks of the mean of R, G, B: the mean of
          |P - C| / max(C, 0.05 x the image's mean) over blocks, and the worst block
          (its position and values).
      Tolerances (chosen before looking at the results, from noise and from what the
      models are known to do differently; not tuned to pass):
        whole image, per channel   |rel| <= 5 %  + 3 sigma of the measured noise
        blocks, mean |rel|         <= 10 % + 2 x the blocks' mean relative noise
        worst block                |rel| <= 30 % + 4 sigma of its measured noise
      The model allowances (5, 10, 30 %) are for what Cycles 3.4's Principled BSDF does
      otherwise than OpenPBR: Disney's retro-reflective diffuse instead of Lambert, a
      specular layer added over the diffuse without taking its energy (OpenPBR scales the
      base by 1 - E), a clearcoat that does not darken the base, Multiscatter GGX's
      random walk against Prism's energy compensation, Schlick-interpolated Fresnel.
      Writes target/cycles/<Name>.png: Prism | Cycles | |difference| x 4 (all scaled by
      one exposure, clipped, sRGB), and <Name>.json with the figures. Exit status 1 when a
      comparable row is out of tolerance, 3 when there is no model or no Blender.

  speed [--prism BIN] [--spp 64] [--size 256] [--runs 3]
      Whole processes: Prism's CLI against `blender -b scene.blend -f 1` (Cycles, the
      same settings as compare, both with 2 threads) at equal samples per pixel, on a
      scene made here (speed.glb: a coated red sphere, a sheen sphere and a rough glass
      sphere on a grey floor, under the same environment). The .blend is prepared once
      (import excluded from the timing); Blender's start-up, loading and scene sync is
      measured as a 1-sample render of the same file and reported and subtracted, and
      Prism's likewise. Runs interleaved after one warm-up each; minimum and median;
      Cycles / Prism ratios.

  orient [--prism BIN]
      The environment-orientation check described above.

Run of 2026-12-05 (Prism at db5a7f3, Blender 3.4.1, 256 x 256, 512 spp; exit 1):

  model                      mean rel R/G/B        blocks |rel|  worst block  verdict
  ClearCoatTest              +0.2% +1.1% -0.5%     23.8%         +1901 %      out
  SheenChair                 -25.7% -11.2% -7.0%   11.5%         -48 %        not comparable
  TransmissionRoughnessTest  -0.4% -1.3% -4.1%     6.3%          -48 %        out (8 blocks)
  SpecularTest               -3.0% -3.3% -4.1%     7.5%          +173 %       not comparable
  AttenuationTest            -1.9% -2.5% -3.6%     3.5%          -41 %        out (1 block)

Run again after Prism's fixes (3ee0b83: an opaque surface's back shaded as its
front, the coat along the unbent normal under a base normal map):

  ClearCoatTest              -2.1% -1.1% -2.4%     7.2%          -62 %        out (worst block only)

What the failing blocks are:
  - ClearCoatTest, first run, the Partial-coating "coating only" tile (x,y 208,64):
    through its cut-out stripes Cycles saw the inside of the tile's back faces (dark),
    Prism the sky: Prism shaded every non-thin-walled OpenPBR surface hit from its back
    as the inside of a transmissive solid, whatever its transmission weight (an opaque
    red quad seen from behind rendered (0.55, 0.51, 0.50) where Cycles gives (0.28,
    0.05, 0.07)). Fixed in Prism; the blocks' mean |rel| fell from 23.8% to 7.2%. What
    remains is the coated column: Cycles' Disney coat (fed 4x) adds to the base where
    OpenPBR's coat takes its reflection from it and darkens it.
  - TransmissionRoughnessTest, the roughest high-index cells (diamond, sapphire): Prism
    0.23, Cycles with Multiscatter GGX 0.43, with plain GGX (--no-fixups) 0.06; how
    rough glass of index 2.4 gives back its lost energy is where the models differ.
  - AttenuationTest, the "Sample Color" row: those are single quads with transmission
    and no volume (glTF's thin-walled case), which Prism reads as the face of a solid:
    light seen through them is darker than in Cycles (a glass quad of IOR 1.5 over a
    grey floor: Prism 0.25, Cycles 0.37; at IOR 1.001 0.36 and 0.38).

`speed` the same day (256 x 256, 64 spp, 2 threads, 3 runs; a shared machine, whose
load halved the times between two runs while the ratios held): whole process Prism
1.63 / 1.66 s (min / median), Cycles 3.82 / 3.88 s: Cycles/Prism 2.34x, 2.33x; 1-spp
runs (start-up and load) Prism 0.07 s, Blender 0.61 s; rendering alone 2.06x. The run
before: Prism 3.40 / 3.48 s, Cycles 7.28 / 7.83 s, 2.14x / 2.25x, rendering alone 2.10x.

Needs Python 3.9+, numpy and Pillow; EXR files are read by a small reader here
(scan-line, uncompressed/ZIPS/ZIP, half or float), so nothing else is installed.
"""

import argparse
import json
import math
import os
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parent.parent
HELPER = Path(__file__).resolve().parent / "cycles_materials_blender.py"
DEFAULT_MODELS = os.environ.get("PRISM_KHRONOS", str(ROOT / "target" / "khronos"))
DEFAULT_OUT = ROOT / "target" / "cycles"
ENV_ROTATION = -90.0  # degrees about Blender's Z: verified by `orient`
FOV = 40.0
BLOCK = 16

# name, camera: (azimuth from +z towards +x, elevation, distance factor)
MODELS = [
    ("ClearCoatTest", (20.0, 12.0, 0.75)),
    ("SheenChair", (35.0, 20.0, 0.8)),
    ("TransmissionRoughnessTest", (20.0, 12.0, 0.75)),
    ("SpecularTest", (20.0, 12.0, 0.75)),
    ("AttenuationTest", (20.0, 12.0, 0.75)),
]

TOL_MEAN = 0.05
TOL_BLOCKS = 0.10
TOL_WORST = 0.30

HOW_TO_GET = """The Khronos sample models are not in {folder}.
Get them from the Khronos glTF sample repositories (glTF-Sample-Assets or the older
glTF-Sample-Models, folder Models/<Name>/), e.g. with this project's fetch tool on
github:DRx3D/glTF-Sample-Assets-OLD and `git show HEAD:Models/<Name>/glTF-Binary/<Name>.glb`
(see this script's docstring), for: {names}.
Put them in {folder} (or pass --models DIR / set PRISM_KHRONOS)."""


# ---------------------------------------------------------------- files

def read_exr(path):
    """RGB float32 array (H, W, 3) of a scan-line OpenEXR file (NONE, ZIPS or ZIP)."""
    data = Path(path).read_bytes()
    if struct.unpack("<I", data[:4])[0] != 20000630:
        raise ValueError(f"{path}: not an OpenEXR file")
    pos = 8
    header = {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        kind = data[end + 1:end2].decode()
        size = struct.unpack("<I", data[end2 + 1:end2 + 5])[0]
        header[name] = (kind, data[end2 + 5:end2 + 5 + size])
        pos = end2 + 5 + size
    pos += 1
    channels = []
    raw = header["channels"][1]
    p = 0
    while raw[p] != 0:
        end = raw.index(b"\0", p)
        name = raw[p:end].decode()
        ptype = struct.unpack("<i", raw[end + 1:end + 5])[0]
        channels.append((name, ptype))
        p = end + 17
    compression = header["compression"][1][0]
    x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    lines = {0: 1, 2: 1, 3: 16}.get(compression)
    if lines is None:
        raise ValueError(f"{path}: EXR compression {compression} not supported here")
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack(f"<{chunks}Q", data[pos:pos + 8 * chunks])
    sizes = {1: 2, 2: 4}
    dtypes = {1: np.float16, 2: np.float32}
    out = {name: np.zeros((height, width), np.float32) for name, _ in channels}
    for off in offsets:
        y, n = struct.unpack("<ii", data[off:off + 8])
        block = data[off + 8:off + 8 + n]
        rows = min(lines, y1 + 1 - y)
        raw_size = rows * width * sum(sizes[t] for _, t in channels)
        if compression in (2, 3) and n < raw_size:  # else the chunk is stored as it is
            d = np.frombuffer(zlib.decompress(block), np.uint8).astype(np.int64)
            d[1:] -= 128  # undo the predictor: t[i] = t[i-1] + d[i] - 128
            t = (np.cumsum(d) & 0xFF).astype(np.uint8)
            half = (len(t) + 1) // 2
            b = np.empty_like(t)
            b[0::2] = t[:half]
            b[1::2] = t[half:]
            block = b.tobytes()
        p = 0
        for r in range(rows):
            for name, ptype in channels:
                nbytes = width * sizes[ptype]
                out[name][y - y0 + r] = np.frombuffer(block[p:p + nbytes], dtypes[ptype])
                p += nbytes
    return np.dstack([out["R"], out["G"], out["B"]]).astype(np.float32)


def write_hdr(path, img):
    """Radiance RGBE, flat (uncompressed) scan lines, top row first."""
    h, w, _ = img.shape
    v = np.maximum(img.astype(np.float64), 0.0)
    m = v.max(axis=2)
    e = np.zeros_like(m, dtype=np.int32)
    mant = np.zeros_like(m)
    nz = m > 1e-32
    mant[nz], e[nz] = np.frexp(m[nz])
    scale = np.where(nz, mant * 256.0 / np.where(nz, m, 1.0), 0.0)
    rgbe = np.zeros((h, w, 4), np.uint8)
    rgbe[..., :3] = np.clip(v * scale[..., None], 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(nz, e + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {h} +X {w}\n".encode())
        f.write(rgbe.tobytes())


def environment(width=512, height=256):
    """The bench's sky, in Prism's equirect convention (glTF coordinates)."""
    v = 1.0 - (np.arange(height) + 0.5) / height  # 1 at the top
    u = (np.arange(width) + 0.5) / width
    lat = (v - 0.5) * math.pi
    phi = (u - 0.5) * 2 * math.pi
    lat, phi = np.meshgrid(lat, phi, indexing="ij")
    # forward -z, right +x, up +y
    d = np.stack([np.cos(lat) * np.sin(phi), np.sin(lat), -np.cos(lat) * np.cos(phi)], -1)
    y = d[..., 1]
    t = np.sqrt(np.clip(y, 0, 1))[..., None]
    sky = (1 - t) * np.array([0.95, 0.97, 1.0]) + t * np.array([0.22, 0.4, 0.85])
    ground = np.array([0.16, 0.12, 0.08]) * (0.6 + 0.4 * (1 + np.clip(y, -1, 0)))[..., None]
    img = np.where((y >= 0)[..., None], sky, ground)

    def patch(direction, colour, peak, width_rad):
        s = np.array(direction, float)
        s /= np.linalg.norm(s)
        ang = np.arccos(np.clip(d @ s, -1, 1))
        return np.exp(-(ang / width_rad) ** 2)[..., None] * np.array(colour) * peak

    img = img + patch((0.55, 0.6, 0.6), (1.0, 0.85, 0.6), 40.0, 0.09)
    img = img + patch((-0.9, 0.15, -0.1), (0.3, 0.6, 1.0), 6.0, 0.22)
    return img.astype(np.float32)


def tonemap(img, exposure):
    x = np.clip(img * exposure, 0, 1)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (x * 255 + 0.5).astype(np.uint8)


def side_by_side(prism, cycles, path):
    exposure = 0.8 / max(float(np.percentile(cycles.mean(axis=2), 95)), 1e-6)
    diff = np.abs(prism - cycles) * 4
    gap = np.full((prism.shape[0], 4, 3), 255, np.uint8)
    row = np.hstack([tonemap(prism, exposure), gap, tonemap(cycles, exposure), gap,
                     tonemap(diff, exposure)])
    Image.fromarray(row).save(path)


# ---------------------------------------------------------------- glTF

def gltf_json(path):
    data = Path(path).read_bytes()
    if data[:4] == b"glTF":
        n = struct.unpack("<I", data[12:16])[0]
        return json.loads(data[20:20 + n])
    return json.loads(data)


def node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], float).reshape(4, 4).T
    t = np.eye(4)
    t[:3, 3] = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.eye(4)
    r[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    s = np.diag(list(node.get("scale", [1, 1, 1])) + [1])
    return t @ r @ s


def bounds(path):
    g = gltf_json(path)
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    scene = g.get("scenes", [{}])[g.get("scene", 0)]
    stack = [(i, np.eye(4)) for i in scene.get("nodes", range(len(g["nodes"])))]
    while stack:
        i, parent = stack.pop()
        node = g["nodes"][i]
        m = parent @ node_matrix(node)
        if "mesh" in node:
            for prim in g["meshes"][node["mesh"]]["primitives"]:
                acc = g["accessors"][prim["attributes"]["POSITION"]]
                a, b = np.array(acc["min"], float), np.array(acc["max"], float)
                for k in range(8):
                    c = np.array([(a, b)[(k >> j) & 1][j] for j in range(3)] + [1.0])
                    p = (m @ c)[:3]
                    lo, hi = np.minimum(lo, p), np.maximum(hi, p)
        stack.extend((c, m) for c in node.get("children", []))
    return lo, hi


def camera_for(path, azimuth, elevation, factor, fov=FOV):
    lo, hi = bounds(path)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2
    az, el = math.radians(azimuth), math.radians(elevation)
    direction = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
    dist = factor * radius / math.sin(math.radians(fov) / 2)
    eye = centre + dist * direction
    return eye, centre, fov


def fmt3(v):
    return ",".join(f"{x:.6g}" for x in v)


def find_model(folder, name):
    folder = Path(folder)
    for base in (folder, folder / "Models"):
        for p in (base / f"{name}.glb", base / f"{name}.gltf", base / name / f"{name}.glb",
                  base / name / f"{name}.gltf", base / name / "glTF-Binary" / f"{name}.glb",
                  base / name / "glTF" / f"{name}.gltf"):
            if p.is_file():
                return p
    return None


class GlbWriter:
    """A small glTF binary: meshes of positions, normals and indices, PBR materials."""

    def __init__(self):
        self.bin = bytearray()
        self.g = {"asset": {"version": "2.0", "generator": "prism benches/cycles_materials.py"},
                  "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                  "materials": [], "accessors": [], "bufferViews": [], "buffers": [],
                  "extensionsUsed": []}

    def _view(self, arr, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        off = len(self.bin)
        self.bin += arr.tobytes()
        self.g["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": arr.nbytes,
                                      "target": target})
        return len(self.g["bufferViews"]) - 1

    def _accessor(self, arr, kind, target):
        view = self._view(arr, target)
        acc = {"bufferView": view, "count": len(arr),
               "componentType": 5126 if arr.dtype == np.float32 else 5125, "type": kind}
        if kind == "VEC3":
            acc["min"] = arr.min(axis=0).tolist()
            acc["max"] = arr.max(axis=0).tolist()
        self.g["accessors"].append(acc)
        return len(self.g["accessors"]) - 1

    def material(self, mat):
        for ext in mat.get("extensions", {}):
            if ext not in self.g["extensionsUsed"]:
                self.g["extensionsUsed"].append(ext)
        self.g["materials"].append(mat)
        return len(self.g["materials"]) - 1

    def mesh(self, pos, nrm, idx, material, translation=(0, 0, 0)):
        prim = {"attributes": {"POSITION": self._accessor(pos.astype(np.float32), "VEC3", 34962),
                               "NORMAL": self._accessor(nrm.astype(np.float32), "VEC3", 34962)},
                "indices": self._accessor(idx.astype(np.uint32).ravel(), "SCALAR", 34963),
                "material": material}
        self.g["meshes"].append({"primitives": [prim]})
        self.g["nodes"].append({"mesh": len(self.g["meshes"]) - 1, "translation": list(translation)})
        self.g["scenes"][0]["nodes"].append(len(self.g["nodes"]) - 1)

    def write(self, path):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.g["buffers"] = [{"byteLength": len(self.bin)}]
        if not self.g["extensionsUsed"]:
            del self.g["extensionsUsed"]
        js = json.dumps(self.g).encode()
        js += b" " * (-len(js) % 4)
        total = 12 + 8 + len(js) + 8 + len(self.bin)
        with open(path, "wb") as f:
            f.write(struct.pack("<4sII", b"glTF", 2, total))
            f.write(struct.pack("<I4s", len(js), b"JSON") + js)
            f.write(struct.pack("<I4s", len(self.bin), b"BIN\0") + bytes(self.bin))


def uv_sphere(radius, rings=48, segments=96):
    th = np.linspace(0, math.pi, rings + 1)
    ph = np.linspace(0, 2 * math.pi, segments + 1)
    th, ph = np.meshgrid(th, ph, indexing="ij")
    n = np.stack([np.sin(th) * np.sin(ph), np.cos(th), np.sin(th) * np.cos(ph)], -1).reshape(-1, 3)
    idx = []
    w = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * w + j, i * w + j + 1, (i + 1) * w + j, (i + 1) * w + j + 1
            if i > 0:
                idx.append((a, c, b))
            if i < rings - 1:
                idx.append((b, c, d))
    return n * radius, n, np.array(idx)


def plane(half):
    pos = np.array([[-half, 0, -half], [half, 0, -half], [half, 0, half], [-half, 0, half]], float)
    nrm = np.tile([0.0, 1.0, 0.0], (4, 1))
    return pos, nrm, np.array([(0, 2, 1), (0, 3, 2)])


def mirror_sphere_glb(path):
    w = GlbWriter()
    m = w.material({"name": "mirror", "pbrMetallicRoughness": {
        "baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1.0, "roughnessFactor": 0.0}})
    w.mesh(*uv_sphere(1.0), m)
    w.write(path)


def speed_glb(path):
    w = GlbWriter()
    floor = w.material({"name": "floor", "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 0.8}})
    coat = w.material({"name": "coated", "pbrMetallicRoughness": {
        "baseColorFactor": [0.6, 0.05, 0.03, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                   "clearcoatRoughnessFactor": 0.05}}})
    sheen = w.material({"name": "sheen", "pbrMetallicRoughness": {
        "baseColorFactor": [0.1, 0.12, 0.35, 1], "metallicFactor": 0.0, "roughnessFactor": 0.8},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.8, 1.0],
                                               "sheenRoughnessFactor": 0.4}}})
    glass = w.material({"name": "rough glass", "pbrMetallicRoughness": {
        "baseColorFactor": [0.9, 0.95, 1.0, 1], "metallicFactor": 0.0, "roughnessFactor": 0.3},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                       "KHR_materials_volume": {"thicknessFactor": 1.0}}})
    w.mesh(*plane(6.0), floor)
    sphere = uv_sphere(0.9)
    w.mesh(*sphere, coat, (-2.0, 0.9, 0.0))
    w.mesh(*sphere, sheen, (0.0, 0.9, 0.0))
    w.mesh(*sphere, glass, (2.0, 0.9, 0.0))
    w.write(path)


# ---------------------------------------------------------------- renderers

def prism_command(prism, model, out, env, cam, size, spp, seed, threads=None):
    eye, at, fov = cam
    cmd = [str(prism), "render", str(model), str(out), "--integrator", "path",
           "--spp", str(spp), "--width", str(size), "--height", str(size), "--aa", "1",
           "--seed", str(seed), "--exr-precision", "float", "--quiet",
           "--environment", str(env), f"--look-from={fmt3(eye)}", f"--look-at={fmt3(at)}",
           "--up", "0,1,0", "--fov", f"{fov:g}"]
    if threads:
        cmd += ["--threads", str(threads)]
    return cmd


def blender_command(model, prefix, env, cam, size, spp, seeds, report=None, fixups=True,
                    rotations=None, save_blend=None, no_render=False, threads=None):
    eye, at, fov = cam
    cmd = [shutil.which("blender") or "blender", "-b", "--factory-startup", "--python",
           str(HELPER), "--", "--model", str(model), "--env", str(env),
           f"--look-from={fmt3(eye)}", f"--look-at={fmt3(at)}", f"--fov={fov:g}",
           "--width", str(size), "--height", str(size), "--spp", str(spp),
           "--seeds", ",".join(str(s) for s in seeds), "--out-prefix", str(prefix),
           "--env-rotations=" + ",".join(f"{r:g}" for r in (rotations or [ENV_ROTATION]))]
    if report:
        cmd += ["--report", str(report)]
    if not fixups:
        cmd += ["--no-fixups"]
    if save_blend:
        cmd += ["--save-blend", str(save_blend)]
    if no_render:
        cmd += ["--no-render"]
    if threads:
        cmd += ["--threads", str(threads)]
    return cmd


def child_env():
    """This environment without this Python's own folders on PATH: Blender embeds the
    system's libpython, which finds its standard library (and Debian's numpy) from the
    first python3 on PATH; under pyenv or a virtual environment that would be theirs."""
    env = dict(os.environ)
    env.pop("PYTHONHOME", None)
    env.pop("PYTHONPATH", None)
    mine = {os.path.realpath(p) for p in (sys.prefix, sys.base_prefix, sys.exec_prefix)}
    mine -= {"/usr", "/usr/local"}
    keep = [d for d in env.get("PATH", "").split(os.pathsep)
            if not any(os.path.realpath(d).startswith(m + os.sep) for m in mine)]
    env["PATH"] = os.pathsep.join(keep)
    return env


def run(cmd, what):
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       env=child_env())
    dt = time.perf_counter() - t
    if r.returncode != 0:
        tail = "\n".join((r.stdout + r.stderr).strip().splitlines()[-15:])
        raise RuntimeError(f"{what} failed ({r.returncode}):\n{' '.join(cmd)}\n{tail}")
    if "Traceback" in r.stderr or "Error:" in r.stdout and "Traceback" in r.stdout:
        tail = "\n".join((r.stdout + r.stderr).strip().splitlines()[-15:])
        raise RuntimeError(f"{what} raised:\n{tail}")
    return dt


def need_tools(args):
    if not shutil.which("blender"):
        print("skipped: no `blender` on PATH (Debian: apt-get install -y blender python3-numpy; 3.4)")
        sys.exit(3)
    if not Path(args.prism).is_file():
        print(f"no Prism binary at {args.prism} (cargo build --release, or --prism BIN)")
        sys.exit(1)


def prepare_out(out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    env = out / "env.hdr"
    write_hdr(env, environment())
    return out, env


# ---------------------------------------------------------------- figures

def block_means(img, block=BLOCK):
    h, w = img.shape[:2]
    h, w = h - h % block, w - w % block
    return img[:h, :w].reshape(h // block, block, w // block, block, -1).mean(axis=(1, 3))


def figures(p1, p2, c1, c2):
    prism, cycles = (p1 + p2) / 2, (c1 + c2) / 2
    mp, mc = prism.mean(axis=(0, 1)), cycles.mean(axis=(0, 1))
    # noise of a mean of two halves: (a - b)^2 / 4 estimates its variance
    var_mean = (((p1 - p2).mean(axis=(0, 1))) ** 2 + ((c1 - c2).mean(axis=(0, 1))) ** 2) / 4
    rel = mp / np.maximum(mc, 1e-12) - 1
    sig = np.sqrt(var_mean) / np.maximum(mc, 1e-12)
    lum = lambda a: a.mean(axis=2, keepdims=True)
    bp, bc = block_means(lum(prism))[..., 0], block_means(lum(cycles))[..., 0]
    bvar = ((block_means(lum(p1 - p2))[..., 0]) ** 2 + (block_means(lum(c1 - c2))[..., 0]) ** 2) / 4
    floor = 0.05 * float(lum(cycles).mean())
    denom = np.maximum(bc, floor)
    brel = (bp - bc) / denom
    bsig = np.sqrt(bvar) / denom
    mean_rel = float(np.abs(brel).mean())
    mean_sig = float(bsig.mean())
    excess = np.abs(brel) - (TOL_WORST + 4 * bsig)
    k = np.unravel_index(np.argmax(np.abs(brel)), brel.shape)
    ke = np.unravel_index(np.argmax(excess), brel.shape)
    return {
        "prism_mean": mp.tolist(), "cycles_mean": mc.tolist(), "rel": rel.tolist(),
        "rel_sigma": sig.tolist(),
        "mean_ok": bool(np.all(np.abs(rel) <= TOL_MEAN + 3 * sig)),
        "blocks_mean_rel": mean_rel, "blocks_mean_sigma": mean_sig,
        "blocks_ok": mean_rel <= TOL_BLOCKS + 2 * mean_sig,
        "worst": {"block_row": int(k[0]), "block_col": int(k[1]),
                  "pixel_xy": [int(k[1]) * BLOCK, int(k[0]) * BLOCK],
                  "prism": float(bp[k]), "cycles": float(bc[k]), "rel": float(brel[k]),
                  "sigma": float(bsig[k])},
        "worst_over": {"pixel_xy": [int(ke[1]) * BLOCK, int(ke[0]) * BLOCK],
                       "rel": float(brel[ke]), "sigma": float(bsig[ke]),
                       "excess": float(excess[ke])},
        "worst_ok": bool(np.all(excess <= 0)),
        "blocks_over": int((excess > 0).sum()), "blocks": int(excess.size),
    }


def summarise_import(report):
    """Per extension: the worst status over the model's materials, and a note."""
    rank = {"mapped": 0, "mapped, fixed up": 1, "unchecked": 1, "approximate": 2,
            "not imported": 3}
    out = {}
    for mat, info in report["materials"].items():
        for ext, e in info["extensions"].items():
            cur = out.get(ext)
            if cur is None or rank[e["status"]] > rank[cur["status"]]:
                out[ext] = {"status": e["status"], "note": e["note"], "material": mat}
    for ext in report.get("extensionsUsed", []):
        notes = {"KHR_texture_transform": "a Mapping node before the texture",
                 "KHR_materials_variants": "not shading: both use each primitive's default material"}
        out.setdefault(ext, {"status": "mapped" if ext in notes else "not imported",
                             "note": notes.get(ext, "no material carries it"), "material": ""})
    return out


def pct(x):
    return f"{100 * x:+.1f}%"


def cmd_compare(args):
    need_tools(args)
    names = [m for m in MODELS if not args.only or m[0] in args.only.split(",")]
    found = [(n, cam, find_model(args.models, n)) for n, cam in names]
    missing = [n for n, _, p in found if p is None]
    if missing:
        print(HOW_TO_GET.format(folder=args.models, names=", ".join(missing)))
    found = [f for f in found if f[2] is not None]
    if not found:
        print("skipped: no model")
        return 3
    out, env = prepare_out(args.out)
    work = Path(tempfile.mkdtemp(prefix="cycles-cmp-", dir=out))
    half = max(1, args.spp // 2)
    rows, bad = [], []
    print(f"Prism {args.prism} vs Blender's Cycles: {args.size}x{args.size}, {2 * half} spp "
          f"(2 seeds x {half}), environment {env}, fix-ups {'off' if args.no_fixups else 'on'}")
    for name, (az, el, factor), model in found:
        cam = camera_for(model, az, el, factor)
        print(f"\n== {name}  ({model})\n   camera: --look-from {fmt3(cam[0])} --look-at "
              f"{fmt3(cam[1])} --fov {cam[2]:g}")
        t_p = 0.0
        for seed in (1, 2):
            t_p += run(prism_command(args.prism, model, work / f"{name}-prism-{seed}.exr", env,
                                     cam, args.size, half, seed), "Prism")
        report_path = work / f"{name}-import.json"
        t_c = run(blender_command(model, work / f"{name}-cycles", env, cam, args.size, half,
                                  (1, 2), report=report_path, fixups=not args.no_fixups),
                  "Blender")
        report = json.loads(report_path.read_text())
        imp = summarise_import(report)
        comparable = all(v["status"] in ("mapped", "mapped, fixed up") for v in imp.values())
        for ext, v in sorted(imp.items()):
            print(f"   {ext:34s} {v['status']:17s} {v['note']}")
        for f in report.get("fixups", []):
            print(f"   fix-up: {f[:160]}")
        p1, p2 = (read_exr(work / f"{name}-prism-{s}.exr") for s in (1, 2))
        c1, c2 = (read_exr(work / f"{name}-cycles-{s}.exr") for s in (1, 2))
        fig = figures(p1, p2, c1, c2)
        side_by_side((p1 + p2) / 2, (c1 + c2) / 2, out / f"{name}.png")
        fig.update(name=name, comparable=comparable, imports=imp, camera=[list(map(float, cam[0])),
                   list(map(float, cam[1])), cam[2]], prism_seconds=t_p, blender_seconds=t_c,
                   fixups=report.get("fixups", []))
        (out / f"{name}.json").write_text(json.dumps(fig, indent=1))
        ok = fig["mean_ok"] and fig["blocks_ok"] and fig["worst_ok"]
        verdict = ("ok" if ok else "OUT OF TOLERANCE") if comparable else "not comparable"
        if comparable and not ok:
            bad.append(name)
        w = fig["worst"]
        print(f"   mean RGB  Prism {fmt3(fig['prism_mean'])}  Cycles {fmt3(fig['cycles_mean'])}")
        print(f"   rel  {' '.join(pct(r) for r in fig['rel'])} (noise 1 sigma "
              f"{' '.join(f'{100 * s:.2f}%' for s in fig['rel_sigma'])}; tol 5% + 3 sigma)")
        print(f"   blocks mean |rel| {100 * fig['blocks_mean_rel']:.1f}% (noise "
              f"{100 * fig['blocks_mean_sigma']:.1f}%; tol 10% + 2x noise); worst block at "
              f"x,y={w['pixel_xy'][0]},{w['pixel_xy'][1]}: Prism {w['prism']:.4g} Cycles "
              f"{w['cycles']:.4g} rel {pct(w['rel'])} (noise {100 * w['sigma']:.1f}%); "
              f"{fig['blocks_over']}/{fig['blocks']} blocks over 30% + 4 sigma")
        print(f"   time: Prism {t_p:.1f} s, Blender (import + 2 renders) {t_c:.1f} s  -> {verdict}")
        rows.append((name, fig, verdict))
    print("\nmodel                      mean rel R/G/B           blocks |rel|  worst block   verdict")
    for name, fig, verdict in rows:
        print(f"{name:26s} {' '.join(f'{pct(r):>7s}' for r in fig['rel'])}   "
              f"{100 * fig['blocks_mean_rel']:6.1f}%   {pct(fig['worst']['rel']):>9s}   {verdict}")
    print(f"tolerances: mean 5% + 3 sigma, blocks 10% + 2x noise, worst block 30% + 4 sigma; "
          f"images in {out}")
    shutil.rmtree(work, ignore_errors=True)
    if bad:
        print(f"out of tolerance: {', '.join(bad)}")
        return 1
    return 0


def cmd_orient(args):
    need_tools(args)
    out, env = prepare_out(args.out)
    work = Path(tempfile.mkdtemp(prefix="orient-", dir=out))
    model = work / "mirror-sphere.glb"
    mirror_sphere_glb(model)
    size = 96
    cams = {"front (from +z)": ((0, 0, 4.5), (0, 0, 0), 60.0),
            "side (from +x)": ((4.5, 0, 0), (0, 0, 0), 60.0),
            "above-front (from +y+z)": ((0, 3.2, 3.2), (0, 0, 0), 60.0)}
    rotations = [-90.0, 0.0, 90.0, 180.0]
    results = {}
    for label, cam in cams.items():
        tag = label.split()[0]
        run(prism_command(args.prism, model, work / f"{tag}-prism-1.exr", env, cam, size, 16, 1),
            "Prism")
        run(blender_command(model, work / f"{tag}-cycles", env, cam, size, 16, (1,),
                            rotations=rotations), "Blender")
        p = read_exr(work / f"{tag}-prism-1.exr")
        row = {}
        for r in rotations:
            c = read_exr(work / f"{tag}-cycles-rot{r:g}-1.exr")
            row[f"{r:g}"] = float(np.sqrt(((p - c) ** 2).mean()) / np.sqrt((c ** 2).mean()))
        c = read_exr(work / f"{tag}-cycles-rot{ENV_ROTATION:g}-1.exr")
        row["-90 mirrored"] = float(np.sqrt(((p[:, ::-1] - c) ** 2).mean()) / np.sqrt((c ** 2).mean()))
        results[label] = row
        side_by_side(p, c, out / f"orient-{tag}.png")
    print("relative RMSE, Prism against Cycles, per Blender world rotation about Z "
          "(Prism: its own convention, no rotation):")
    keys = list(next(iter(results.values())).keys())
    print(f"{'view':26s}" + "".join(f"{k:>14s}" for k in keys))
    for label, row in results.items():
        print(f"{label:26s}" + "".join(f"{row[k]:14.3f}" for k in keys))
    best = {label: min(row, key=row.get) for label, row in results.items()}
    ok = all(b == f"{ENV_ROTATION:g}" for b in best.values())
    print(f"best: {best}: {'verified' if ok else 'NOT the assumed'} mapping, "
          f"Blender rotation {ENV_ROTATION:g} degrees about Z")
    shutil.rmtree(work, ignore_errors=True)
    return 0 if ok else 1


def timed(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       env=child_env())
    dt = time.perf_counter() - t
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{r.stderr[-2000:]}")
    return dt


def cmd_speed(args):
    need_tools(args)
    out, env = prepare_out(args.out)
    work = Path(tempfile.mkdtemp(prefix="speed-", dir=out))
    model = work / "speed.glb"
    speed_glb(model)
    cam = ((1.2, 3.2, 7.5), (0.0, 0.8, 0.0), 50.0)
    size, spp, threads = args.size, args.spp, args.threads
    blends, prepare = {}, []
    for n in (spp, 1):
        blends[n] = work / f"speed-{n}.blend"
        prepare.append(run(blender_command(model, work / f"cycles-{n}-", env, cam, size, n, (1,),
                                           save_blend=blends[n], no_render=True,
                                           threads=threads), "Blender"))
    blender = shutil.which("blender")
    cmds = {
        "prism": prism_command(args.prism, model, work / "prism.exr", env, cam, size, spp, 1,
                               threads),
        "prism 1 spp": prism_command(args.prism, model, work / "prism1.exr", env, cam, size, 1,
                                     1, threads),
        "cycles": [blender, "-b", str(blends[spp]), "-f", "1"],
        "cycles 1 spp": [blender, "-b", str(blends[1]), "-f", "1"],
    }
    times = {k: [] for k in cmds}
    first = {k: timed(c) for k, c in cmds.items()}
    for _ in range(args.runs):
        for k, c in cmds.items():
            times[k].append(timed(c))
    print(f"speed: speed.glb (coat, sheen, rough glass spheres on a floor, environment), "
          f"{size}x{size}, {spp} spp, {threads} threads, {args.runs} runs after a warm-up")
    print(f"{'process':14s} {'first':>8s} {'min':>8s} {'median':>8s}")
    stats = {}
    for k in cmds:
        stats[k] = (min(times[k]), statistics.median(times[k]))
        print(f"{k:14s} {first[k]:8.2f} {stats[k][0]:8.2f} {stats[k][1]:8.2f}")
    ratio_min = stats["cycles"][0] / stats["prism"][0]
    ratio_med = stats["cycles"][1] / stats["prism"][1]
    net_c = stats["cycles"][1] - stats["cycles 1 spp"][1]
    net_p = stats["prism"][1] - stats["prism 1 spp"][1]
    print(f"Cycles/Prism whole process: {ratio_min:.2f}x (min), {ratio_med:.2f}x (median)")
    print(f"not timed above: Blender start-up + glTF import + set-up + saving the .blend "
          f"{min(prepare):.2f} s")
    print(f"start-up, load and 1 sample (median): Blender {stats['cycles 1 spp'][1]:.2f} s, "
          f"Prism {stats['prism 1 spp'][1]:.2f} s")
    print(f"rendering alone (median minus 1-spp median): Cycles {net_c:.2f} s, Prism "
          f"{net_p:.2f} s, Cycles/Prism {net_c / max(net_p, 1e-9):.2f}x")
    shutil.rmtree(work, ignore_errors=True)
    return 0


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)

    def common(s):
        s.add_argument("--prism", default=str(ROOT / "target" / "release" / "prism"))
        s.add_argument("--out", default=str(DEFAULT_OUT))
        return s

    c = common(sub.add_parser("compare", help="images of the Khronos models, Prism and Cycles"))
    c.add_argument("--models", default=DEFAULT_MODELS)
    c.add_argument("--spp", type=int, default=512)
    c.add_argument("--size", type=int, default=256)
    c.add_argument("--only", help="comma-separated model names")
    c.add_argument("--no-fixups", action="store_true",
                   help="render Blender's import as it is (see cycles_materials_blender.py)")
    c.set_defaults(func=cmd_compare)
    s = common(sub.add_parser("speed", help="whole-process times at equal spp"))
    s.add_argument("--spp", type=int, default=64)
    s.add_argument("--size", type=int, default=256)
    s.add_argument("--runs", type=int, default=3)
    s.add_argument("--threads", type=int, default=2)
    s.set_defaults(func=cmd_speed)
    o = common(sub.add_parser("orient", help="verify the environment orientation mapping"))
    o.set_defaults(func=cmd_orient)
    return p


def main():
    args = parser().parse_args()
    try:
        return args.func(args)
    except RuntimeError as e:
        print(e)
        return 1


if __name__ == "__main__":
    sys.exit(main())
