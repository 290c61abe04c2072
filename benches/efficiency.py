#!/usr/bin/env python3
"""Whole-process parallel efficiency of `prism render`: wall time on one thread (T1) and
on two (T2), loading, texture decoding, rendering and writing the image all counted.

Prints the medians of T1 and T2, the efficiency T1 / (2 T2), the serial fraction s that
Amdahl's law gives from them (T2 / T1 = s + (1 - s) / 2, so s = 2 T2 / T1 - 1) and the
speed-up s predicts for 16 and 64 cores, 1 / (s + (1 - s) / N). Runs alternate one
thread, two threads, one, two...; the figures are given from the medians and from the
minimums (the runs another job on the machine disturbed least), and the efficiency
also as the median over the pairs.

Usage: benches/efficiency.py [--runs N] [--prism BINARY] [--scene DIR] [-- RENDER OPTIONS]

Default: 7 pairs after one warm-up, target/release/prism, the 2014 scene1 beside the
repository (../shared/seed-scenes/Ray-Tracing/scene1) at `--width 960 --aa 2
--dof-rays 1`. The image goes to a temporary folder.
"""

import statistics
import sys
import tempfile
from pathlib import Path

from process import Failed, timed

ROOT = Path(__file__).resolve().parent.parent


def run(command):
    """Wall and CPU seconds of one whole process; exits if it fails."""
    try:
        return timed(command)
    except Failed as e:
        sys.exit(str(e))


def speedup(s, cores):
    return 1.0 / (s + (1.0 - s) / cores)


def main():
    args = sys.argv[1:]
    runs = 7
    prism = ROOT / "target/release/prism"
    scene = ROOT.parent / "shared/seed-scenes/Ray-Tracing/scene1"
    options = ["--width", "960", "--aa", "2", "--dof-rays", "1"]
    while args:
        arg = args.pop(0)
        if arg == "--runs":
            runs = int(args.pop(0))
        elif arg == "--prism":
            prism = Path(args.pop(0))
        elif arg == "--scene":
            scene = Path(args.pop(0))
        elif arg == "--":
            options = args
            args = []
        else:
            sys.exit(__doc__)
    objx = next(scene.glob("*.objx"))
    cameras = sorted(scene.glob("*.cmr"))
    with tempfile.TemporaryDirectory() as out:
        def command(threads):
            return [prism, "render", objx, *cameras[:1], Path(out) / "out.png",
                    *options, "--quiet", "--threads", str(threads)]

        run(command(1))
        run(command(2))
        t1, t2, cpu1, cpu2 = [], [], [], []
        for _ in range(runs):
            wall, cpu = run(command(1))
            t1.append(wall)
            cpu1.append(cpu)
            wall, cpu = run(command(2))
            t2.append(wall)
            cpu2.append(cpu)
    print(f"scene: {objx} {' '.join(map(str, cameras[:1]))} {' '.join(options)}")
    print(f"pairs: {runs}")
    print(f"T1 (1 thread):  median {statistics.median(t1):.3f} s  (min {min(t1):.3f},"
          f" max {max(t1):.3f}), CPU {statistics.median(cpu1):.3f} s")
    print(f"T2 (2 threads): median {statistics.median(t2):.3f} s  (min {min(t2):.3f},"
          f" max {max(t2):.3f}), CPU {statistics.median(cpu2):.3f} s")
    # Another job on the machine only ever adds time: the minimums are the runs it
    # disturbed least, the medians what a user would see on the day.
    for name, a, b in (("medians", statistics.median(t1), statistics.median(t2)),
                       ("minimums", min(t1), min(t2))):
        s = max(0.0, 2 * b / a - 1)
        print(f"{name}: efficiency T1/(2 T2) {a / (2 * b):.3f}, serial fraction"
              f" s = 2 T2/T1 - 1 = {s:.4f}, predicted speed-up"
              f" {speedup(s, 16):.1f} on 16 cores, {speedup(s, 64):.1f} on 64")
    pairs = statistics.median(a / (2 * b) for a, b in zip(t1, t2))
    print(f"efficiency, median over the pairs: {pairs:.3f}")

if __name__ == "__main__":
    main()
