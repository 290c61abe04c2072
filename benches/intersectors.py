#!/usr/bin/env python3
"""Prints a markdown table of `prism bench` for each intersector on the report's two
scenes and the Stanford bunny (all from ../shared, beside the repository).

Usage: benches/intersectors.py [PRISM_BINARY] [--threads N] [--seconds S]

Brute force on the bunny is measured at 160x90: its rate per ray does not depend on
the image size, and at 1280x720 one pass would take minutes.
"""

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"


def bench(binary, scene, camera, accel, extra):
    out = subprocess.run(
        [binary, "bench", str(scene), str(camera), "--json", "--no-frame", "--accel", accel, *extra],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out)


def main():
    args = sys.argv[1:]
    binary = args[0] if args and not args[0].startswith("--") else str(ROOT / "target/release/prism")
    extra = []
    for flag in ("--threads", "--seconds"):
        if flag in args:
            extra += [flag, args[args.index(flag) + 1]]
    seeds = SHARED / "seed-scenes/Ray-Tracing"
    bunny = SHARED / "models/stanford-bunny/stanford-bunny.obj"
    cases = [
        ("scene0", seeds / "scene0/scene.objx", seeds / "scene0/scene.cmr", ["--width", "960"]),
        ("scene1", seeds / "scene1/scene.objx", seeds / "scene1/scene.cmr", ["--width", "960"]),
        ("bunny", bunny, ROOT / "benches/bunny.cmr", []),
    ]
    print("| scene | primitives | intersector | build ms | bytes/prim | primary Mrays/s | shadow Mrays/s | hit % |")
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    for name, scene, camera, size in cases:
        if not scene.is_file():
            print(f"skipped {name}: {scene} is absent", file=sys.stderr)
            continue
        for accel in ("bvh", "bvh-copied", "octree", "list"):
            this_size = ["--width", "160"] if (name == "bunny" and accel == "list") else size
            r = bench(binary, scene, camera, accel, extra + this_size)
            note = f" ({r['width']}x{r['height']})" if this_size != size else ""
            print(
                f"| {name} | {r['primitives']} | {accel}{note} | {1000 * r['build_s']:.2f} | "
                f"{r['bytes'] / max(r['primitives'], 1):.0f} | {r['primary_mrays']:.3g} | "
                f"{r['shadow_mrays']:.3g} | {100 * r['hit_fraction']:.1f} |"
            )


if __name__ == "__main__":
    main()
