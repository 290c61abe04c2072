"""Peak memory of a scene of instances built from Python (`prism.scene_from_dict`
with an N x 4 x 4 array of transforms), against the same mesh placed once:

    python benches/instances_memory.py        # from the environment prism is built in

Each count runs in a process of its own, so each peak is its own.
"""

import resource
import subprocess
import sys

CHILD = r"""
import resource, sys
import numpy as np, prism
n = int(sys.argv[1])
k = 51  # a 50 x 50 grid: 5,000 triangles
u, v = np.meshgrid(np.linspace(0, 1, k), np.linspace(0, 1, k))
verts = np.stack([u.ravel(), v.ravel(), np.zeros(k * k)], axis=1)
idx = np.arange(k * k).reshape(k, k)
a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
t = np.tile(np.eye(4), (n, 1, 1))
t[:, 0, 3] = np.arange(n) * 2.0
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
scene = prism.scene_from_dict({"object": [{"type": "instance", "vertices": verts,
                                           "faces": faces, "transforms": t}]})
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
info = scene.info()
print(info["instances"], info["unique_triangles"], (after - before) * 1024)
"""


def peak(n):
    out = subprocess.run([sys.executable, "-c", CHILD, str(n)], capture_output=True,
                         text=True, check=True).stdout.split()
    return int(out[0]), int(out[1]), int(out[2])


def main():
    one = peak(1)
    many = peak(100_000)
    grown = many[2] - one[2]
    print(f"{one[1]:,}-triangle mesh placed once: the scene's build raised the peak by "
          f"{one[2] / 2**20:.1f} MB")
    print(f"placed {many[0]:,} times: {many[2] / 2**20:.1f} MB, "
          f"{grown / (many[0] - 1):.0f} bytes a placement more")


if __name__ == "__main__":
    main()
