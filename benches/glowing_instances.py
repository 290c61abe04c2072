#!/usr/bin/env python3
"""Glowing instances: N lamps (an icosphere of 1,280 triangles, glowing) placed on a
grid over a ground by one scene file's `type = "instance"`, each a mesh light, rendered
by the path model; whole processes, timed and measured.

    benches/glowing_instances.py [--instances 400] [--spp 4] [PRISM ...]

Each PRISM binary given (default target/release/prism) reads and renders the same
scene: a Prism that copies glowing meshes at each placement and one that instances them
can be set side by side. Prints each one's `prism info` time and memory, its render's
wall time and peak memory, and whether the images match bit for bit.
"""

import argparse
import math
import re
import sys
import tempfile
from pathlib import Path

from process import Failed, measured

ROOT = Path(__file__).resolve().parent.parent


def icosphere(levels):
    """Vertices and faces of a unit icosphere subdivided `levels` times."""
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9),
             (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2),
             (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
             (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                p = [(x + y) / 2 for x, y in zip(verts[a], verts[b])]
                n = math.sqrt(sum(x * x for x in p))
                verts.append(tuple(x / n for x in p))
                middle[key] = len(verts) - 1
            return middle[key]

        out = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = out
    return verts, faces


def scene(n, lamp):
    side = math.ceil(math.sqrt(n))
    lines = [
        "[camera]",
        f"from = [0, {side * 0.6:.2f}, {side * 1.4:.2f}]",
        "at = [0, 0, 0]",
        "fov = 50",
        "",
        "[render]",
        "width = 480",
        "height = 270",
        "",
        "[[object]]",
        'type = "plane"',
        "point = [0, -0.2, 0]",
        "",
        "[[object]]",
        'type = "instance"',
        f'file = "{lamp}"',
        "material = { emission = [3, 2.6, 2] }",
        "transforms = [",
    ]
    for k in range(n):
        i, j = divmod(k, side)
        x, z = (i - side / 2) * 1.0, (j - side / 2) * 1.0
        s = 0.15 + 0.1 * ((k * 7919) % 13) / 13
        lines.append(f"  [[{s}, 0, 0, {x}], [0, {s}, 0, {s}], [0, 0, {s}, {z}], [0, 0, 0, 1]],")
    lines.append("]")
    return "\n".join(lines) + "\n"


def write_lamps(folder, n):
    """The lamp (an icosphere of 1,280 triangles) and the scene of `n` of them, written
    into `folder`: the scene's path and the lamp's triangle count."""
    verts, faces = icosphere(3)
    lamp = folder / "lamp.obj"
    lamp.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in verts)
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces))
    path = folder / "lamps.toml"
    path.write_text(scene(n, lamp))
    return path, len(faces)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--instances", type=int, default=400)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("prism", nargs="*", default=[str(ROOT / "target/release/prism")])
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        path, triangles = write_lamps(tmp, args.instances)
        print(f"{args.instances} lamps of {triangles} glowing triangles, 480 x 270, "
              f"{args.spp} spp, path model")
        print(f"{'prism':<28} {'info s':>7} {'info MB':>8} {'render s':>9} {'peak MB':>8}"
              f"  {'instances':>9} {'lights':>7}")
        images = []
        for k, prism in enumerate(args.prism):
            info_s, info_mb, info = measured([prism, "info", path])
            placed = re.search(r"instances\s+(\d+)", info)
            lights = re.search(r"lights\s+(\d+)", info)
            image = tmp / f"{k}.exr"
            render_s, render_mb, _ = measured([prism, "render", path, image, "--spp",
                                              str(args.spp), "--integrator", "path"])
            images.append(image.read_bytes())
            print(f"{prism[-28:]:<28} {info_s:>7.2f} {info_mb:>8.0f} {render_s:>9.2f} "
                  f"{render_mb:>8.0f}  {placed.group(1) if placed else 0:>9} "
                  f"{lights.group(1) if lights else '?':>7}")
        if len(images) > 1:
            same = all(i == images[0] for i in images[1:])
            print("images", "identical" if same else "differ")


if __name__ == "__main__":
    try:
        main()
    except Failed as e:
        sys.exit(str(e))
