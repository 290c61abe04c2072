#!/usr/bin/env python3
"""Casts Prism's rays with Embree and compares: throughput and hit agreement.

Usage: embree.py DUMP_DIR [--seconds S]

DUMP_DIR holds what `prism::bench::write_ray_dump` writes: triangles.f32, rays.f32 and
hits.bin. Embree (through the `embreex` package, Embree 4) casts every ray one at a time
(rtcIntersect1) on one thread, repeated until S seconds have passed. Prints one JSON
object: Embree's million rays per second, and how many rays Embree and Prism answer
differently (hit or miss, or a different triangle at a different distance).

Exit code 3 when embreex or numpy is missing, so callers can skip with a reason.
"""

import json
import sys
import time

try:
    import numpy as np
    from embreex import mesh_construction, rtcore_scene
except ImportError as e:  # pragma: no cover - depends on the machine
    print(f"embreex is not installed: {e}", file=sys.stderr)
    sys.exit(3)


def main() -> None:
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    folder = args[0]
    seconds = float(args[args.index("--seconds") + 1]) if "--seconds" in args else 1.0

    triangles = np.fromfile(f"{folder}/triangles.f32", dtype="<f4").reshape(-1, 3, 3)
    rays = np.fromfile(f"{folder}/rays.f32", dtype="<f4").reshape(-1, 6)
    prism = np.fromfile(f"{folder}/hits.bin", dtype=[("prim", "<i4"), ("t", "<f4")])
    origins = np.ascontiguousarray(rays[:, :3])
    directions = np.ascontiguousarray(rays[:, 3:])

    start = time.perf_counter()
    scene = rtcore_scene.EmbreeScene()
    mesh_construction.TriangleMesh(scene, triangles)
    # Embree builds lazily on the first query: time the build with one ray.
    scene.run(origins[:1], directions[:1])
    build_s = time.perf_counter() - start

    passes, start = 0, time.perf_counter()
    while True:
        hit = scene.run(origins, directions, output=1)
        passes += 1
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            break
    mrays = passes * len(rays) / elapsed / 1e6

    prim = hit["primID"]
    t = hit["tfar"]
    embree_hit = prim >= 0
    prism_hit = prism["prim"] >= 0
    hit_or_miss = embree_hit != prism_hit
    both = embree_hit & prism_hit
    other_prim = both & (prim != prism["prim"])
    rel = np.abs(t - prism["t"]) / np.maximum(np.abs(t), 1e-30)
    far = both & (rel > 1e-4)
    disagree = hit_or_miss | (other_prim & far)
    print(
        json.dumps(
            {
                "embree_version": "4 (embreex)",
                "rays": int(len(rays)),
                "triangles": int(len(triangles)),
                "embree_build_s": build_s,
                "embree_mrays": mrays,
                "hit_fraction": float(embree_hit.mean()),
                "hit_or_miss_differs": int(hit_or_miss.sum()),
                "other_triangle": int(other_prim.sum()),
                "distance_differs": int(far.sum()),
                "disagree": int(disagree.sum()),
                "disagree_fraction": float(disagree.mean()),
            }
        )
    )


if __name__ == "__main__":
    main()
