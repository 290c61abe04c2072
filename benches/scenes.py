#!/usr/bin/env python3
"""Whole-process render times of the bundled scenes, for one Prism binary or two side by
side: each scene's frame as its file sets it (size, anti-aliasing, depth), from reading
the scene to the image on disk.

With `--vs BINARY` the two binaries run in turn on each scene (new, old, new, old...),
and the table gives each one's median wall and CPU seconds and the new / old ratios
taken pair by pair (medians of the pairs' ratios: a slow spell on the machine hits both
sides of a pair). It also says whether the two wrote the same image byte for byte,
which every speed change that keeps the arithmetic must.

Usage: benches/scenes.py [--runs N] [--prism BINARY] [--vs BINARY] [SCENE ...]

Default: 5 runs (pairs) after one warm-up, target/release/prism, the bundled still
scenes (the Blender export among them) and `benches/povray/whitted.toml`. A scene that does not render (the dragon reads
a mesh beside the repository) is skipped with its error. Images go to a temporary
folder.
"""

import filecmp
import statistics
import sys
import tempfile
from pathlib import Path

from process import Failed, timed

ROOT = Path(__file__).resolve().parent.parent
STILLS = [
    "scenes/blender/blender-export.glb",
    "scenes/bunny/bunny.toml",
    "scenes/cornell-box/cornell-box.toml",
    "scenes/dragon/dragon.toml",
    "scenes/showcase/showcase.toml",
    "scenes/spot/spot.toml",
    "benches/povray/whitted.toml",
]


def run(command):
    """Wall and CPU seconds of one whole process, or None if it failed (its error is
    printed)."""
    try:
        return timed(command)
    except Failed as e:
        print(f"  {e}")
        return None


def main():
    args = sys.argv[1:]
    runs = 5
    prism = ROOT / "target/release/prism"
    baseline = None
    scenes = []
    while args:
        arg = args.pop(0)
        if arg == "--runs":
            runs = int(args.pop(0))
        elif arg == "--prism":
            prism = Path(args.pop(0))
        elif arg == "--vs":
            baseline = Path(args.pop(0))
        elif arg in ("-h", "--help"):
            print(__doc__)
            return
        else:
            scenes.append(Path(arg))
    if not scenes:
        scenes = [ROOT / s for s in STILLS]
    binaries = [prism] + ([baseline] if baseline else [])
    for b in binaries:
        if not b.exists():
            sys.exit(f"{b}: no such binary (cargo build --release)")

    if baseline:
        print(f"{prism} against {baseline}, {runs} pairs a scene (medians)\n")
        print("| scene | new wall s | old wall s | new / old wall | new / old CPU | same image |")
        print("|---|---:|---:|---:|---:|---|")
    else:
        print(f"{prism}, {runs} runs a scene (medians)\n")
        print("| scene | wall s | CPU s |")
        print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            name = scene.relative_to(ROOT) if scene.is_relative_to(ROOT) else scene
            outputs = [Path(tmp) / f"{i}.png" for i in range(len(binaries))]
            rows = []
            for i in range(runs + 1):
                row = []
                for b, out in zip(binaries, outputs):
                    r = run([b, "render", scene, out, "--quiet"])
                    if r is None:
                        break
                    row.append(r)
                if len(row) < len(binaries):
                    print(f"| {name} | skipped: it does not render |")
                    break
                # The first round warms the page cache and the clocks; it is not counted.
                if i > 0:
                    rows.append(row)
            else:
                wall = [statistics.median(r[k][0] for r in rows) for k in range(len(binaries))]
                cpu = [statistics.median(r[k][1] for r in rows) for k in range(len(binaries))]
                if baseline:
                    ratio_wall = statistics.median(r[0][0] / r[1][0] for r in rows)
                    ratio_cpu = statistics.median(r[0][1] / r[1][1] for r in rows)
                    same = filecmp.cmp(outputs[0], outputs[1], shallow=False)
                    print(
                        f"| {name} | {wall[0]:.3f} | {wall[1]:.3f} | **{ratio_wall:.3f}** "
                        f"| {ratio_cpu:.3f} | {'yes' if same else 'NO'} |"
                    )
                else:
                    print(f"| {name} | {wall[0]:.3f} | {cpu[0]:.3f} |")


if __name__ == "__main__":
    main()
