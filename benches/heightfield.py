#!/usr/bin/env python3
"""Writes the 2 000 000-triangle height field of docs/performance.md ("Millions of
triangles", "Loading OBJ in parallel"): a 1000x1000 grid of quads over the unit square,
1001x1001 vertices, about 60 MB of OBJ. The output is the same on every run.

Usage: benches/heightfield.py [OUT] [--cells N]    (default target/heightfield.obj)
"""

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main():
    args = sys.argv[1:]
    cells = 1000
    if "--cells" in args:
        at = args.index("--cells")
        cells = int(args[at + 1])
        del args[at : at + 2]
    out = Path(args[0]) if args else ROOT / "target" / "heightfield.obj"
    out.parent.mkdir(parents=True, exist_ok=True)
    n = cells + 1
    with open(out, "w", newline="\n") as f:
        f.write(f"# height field: {cells}x{cells} quads, {2 * cells * cells} triangles\n")
        f.write("o heightfield\n")
        for j in range(n):
            y = j / cells
            rows = []
            for i in range(n):
                x = i / cells
                z = 0.05 * math.sin(7.0 * x) * math.cos(5.0 * y) + 0.01 * math.sin(40.0 * x * y)
                rows.append(f"v {x:.6f} {y:.6f} {z:.6f}\n")
            f.write("".join(rows))
        for j in range(cells):
            rows = []
            for i in range(cells):
                a = j * n + i + 1
                rows.append(f"f {a} {a + 1} {a + n + 1} {a + n}\n")
            f.write("".join(rows))
    print(f"{out}: {out.stat().st_size} bytes, {2 * cells * cells} triangles")


if __name__ == "__main__":
    main()
