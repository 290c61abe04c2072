#!/usr/bin/env python3
"""Many lights: the glowing-lamps scene (N lamps of 1,280 glowing triangles each, one
mesh light a lamp, placed by one scene file) rendered by the path model under each
`--light-sampling` way, timed as whole processes and held to a reference for error.

    benches/many_lights.py [--instances 400] [--spp 4] [--reference-spp 256]
                           [--ways one,tree] [--size 240x135] [PRISM]

The reference is the tree's own at --reference-spp with another seed (its noise is
--reference-spp / --spp times smaller than a render's; a bias would show as the other
ways' error not falling with spp, and is what the unit tests hold against a shadow ray
toward every light). For each way: wall time, relative RMSE against the reference
(root mean squared error over the reference's mean), and the work to equal error,
time x MSE, as a ratio to the first way's: below 1 is less work for the same noise.

Needs numpy (for reading the float EXRs).
"""

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from cycles_materials import read_exr
from glowing_instances import write_lamps
from process import Failed, measured

ROOT = Path(__file__).resolve().parent.parent


def render(prism, path, out, spp, way, size, seed):
    w, h = size
    seconds, _, _ = measured([prism, "render", path, out, "--integrator", "path",
                              "--spp", str(spp), "--light-sampling", way,
                              "--width", str(w), "--height", str(h), "--seed", str(seed),
                              "--exr-precision", "float", "--quiet"])
    return seconds, read_exr(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--instances", type=int, default=400)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--reference-spp", type=int, default=256)
    ap.add_argument("--ways", default="one,tree")
    ap.add_argument("--size", default="240x135")
    ap.add_argument("prism", nargs="?", default=str(ROOT / "target/release/prism"))
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        path, triangles = write_lamps(tmp, args.instances)
        ref_s, ref = render(args.prism, path, tmp / "ref.exr", args.reference_spp, "tree",
                            size, 99)
        mean = float(ref.mean())
        print(f"{args.instances} lamps ({args.instances} lights of {triangles} glowing "
              f"triangles), {size[0]} x {size[1]}, path model; reference: tree at "
              f"{args.reference_spp} spp ({ref_s:.1f} s), mean radiance {mean:.4f}")
        print(f"{'way':<6} {'spp':>5} {'wall s':>8} {'rel. RMSE':>10} {'time x MSE':>11}"
              f" {'vs first':>9}")
        first = None
        for way in args.ways.split(","):
            seconds, img = render(args.prism, path, tmp / f"{way}.exr", args.spp, way,
                                  size, 1)
            mse = float(((img - ref) ** 2).mean())
            work = seconds * mse
            first = first or work
            print(f"{way:<6} {args.spp:>5} {seconds:>8.2f} {mse ** 0.5 / mean:>10.4f} "
                  f"{work / mean ** 2:>11.3g} {work / first:>9.3f}")


if __name__ == "__main__":
    try:
        main()
    except Failed as e:
        sys.exit(str(e))
