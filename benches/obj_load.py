#!/usr/bin/env python3
"""Times `prism info FILE` as a whole process, on one thread and on two
(RAYON_NUM_THREADS), and prints MB/s of OBJ text beside the file size: the median of
the rounds, less the median time of `prism info` on a one-triangle OBJ (start-up).

Usage: benches/obj_load.py [--rounds N] [--prism BINARY]... FILE...

Give --prism twice to compare two builds: each round runs every binary and thread
count in turn on every file, so a busy machine's swings fall on all of them alike.
Default binary: target/release/prism.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run(binary, path, threads):
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    start = time.perf_counter()
    subprocess.run([binary, "info", str(path)], check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    args = sys.argv[1:]
    rounds = 7
    binaries = []
    files = []
    while args:
        arg = args.pop(0)
        if arg == "--rounds":
            rounds = int(args.pop(0))
        elif arg == "--prism":
            binaries.append(args.pop(0))
        else:
            files.append(Path(arg))
    binaries = binaries or [str(ROOT / "target/release/prism")]
    if not files:
        sys.exit(__doc__)
    with tempfile.TemporaryDirectory() as tmp:
        tiny = Path(tmp) / "tiny.obj"
        tiny.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        cases = [(b, f, t) for f in [tiny, *files] for b in binaries for t in (1, 2)]
        times = {case: [] for case in cases}
        for _ in range(rounds):
            for case in cases:
                times[case].append(run(*case))
    median = {case: statistics.median(t) for case, t in times.items()}
    print(f"start-up: {' '.join(f'{median[(b, tiny, 1)] * 1e3:.1f} ms' for b in binaries)}")
    label = len(binaries) > 1
    print(f"| file | MB |{' build |' if label else ''} threads | ms | MB/s |")
    print(f"|---|---:|{'---|' if label else ''}---:|---:|---:|")
    for f in files:
        mb = f.stat().st_size / 1e6
        for b in binaries:
            for t in (1, 2):
                seconds = median[(b, f, t)] - median[(b, tiny, t)]
                column = f" {b} |" if label else ""
                print(f"| {f.name} | {mb:.1f} |{column} {t} | {seconds * 1e3:.0f} | {mb / seconds:.0f} |")


if __name__ == "__main__":
    main()
