#!/usr/bin/env python3
"""How quickly `prism preview` answers, on the bundled scenes: from starting the
command to its first image (the coarsest pass) and to the final one (prism render's
image), and from a camera message (as a drag sends) to the first image of the new view
and to its final one. Each figure is the median of several runs.

Usage: benches/preview.py [--runs N] [--prism BINARY] [SCENE ...]

Default: 5 runs, target/release/prism, the bundled still scenes that read (a scene
whose mesh lies outside the repository is skipped with its error).
"""

import json
import statistics
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = [
    "scenes/example/example.objx scenes/example/example.cmr",
    "scenes/showcase/showcase.toml",
    "scenes/cornell-box/cornell-box.toml",
    "scenes/spot/spot.toml",
    "scenes/blender/blender-export.glb",
    "scenes/bunny/bunny.toml",
]


def get(url):
    with urllib.request.urlopen(url, timeout=60) as r:
        return json.load(r)


def until(url, version, test):
    """Long-polls the status until `test` holds; returns it and the time it arrived."""
    while True:
        s = get(f"{url}status?after={version}")
        version = s["version"]
        if test(s):
            return s, time.perf_counter()


def one_run(prism, scene):
    start = time.perf_counter()
    p = subprocess.Popen([prism, "preview", *scene.split(), "--port", "0"],
                         cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = p.stdout.readline().strip()
        if not line.startswith("http"):
            raise RuntimeError(p.stderr.read().strip() or "no address printed")
        url = line
        s, first = until(url, -1, lambda s: s["frame"] is not None)
        s, final = until(url, -1, lambda s: s["frame"] and s["frame"]["final"])
        cam = s["camera"]
        # A drag's first step: the eye turned a little around the point looked at.
        moved = dict(cam, **{"from": [c + 0.05 * abs(c) + 0.01 for c in cam["from"]]})
        sent = time.perf_counter()
        req = urllib.request.Request(f"{url}camera", data=json.dumps(moved).encode(),
                                     method="POST")
        urllib.request.urlopen(req, timeout=60).read()
        g = s["frame"]["generation"]
        _, moved_first = until(url, s["version"],
                               lambda s: s["frame"] and s["frame"]["generation"] > g)
        _, moved_final = until(url, -1, lambda s: s["frame"]["generation"] > g
                               and s["frame"]["final"])
        return (first - start, final - start, moved_first - sent, moved_final - sent,
                s["frame"]["width"], s["frame"]["height"])
    finally:
        p.terminate()
        p.wait(timeout=10)


def main(argv):
    runs, prism, scenes = 5, str(ROOT / "target/release/prism"), []
    it = iter(argv)
    for a in it:
        if a == "--runs":
            runs = int(next(it))
        elif a == "--prism":
            prism = next(it)
        else:
            scenes.append(a)
    print("| scene | size | first image | final image | drag → first new image | "
          "drag → final |")
    print("|---|---|---|---|---|---|")
    for scene in scenes or SCENES:
        try:
            got = [one_run(prism, scene) for _ in range(runs)]
        except (RuntimeError, OSError) as e:
            print(f"| {scene.split()[0]} | skipped: {str(e).splitlines()[-1][:80]} |||||")
            continue
        med = [statistics.median(g[i] for g in got) for i in range(4)]
        w, h = got[0][4], got[0][5]
        print(f"| {scene.split()[0]} | {w}×{h} | {med[0]*1000:.0f} ms | {med[1]*1000:.0f} ms "
              f"| {med[2]*1000:.0f} ms | {med[3]*1000:.0f} ms |")


if __name__ == "__main__":
    main(sys.argv[1:])
