#!/usr/bin/env bash
# Prism's BVH against native Embree 3 on the same triangles, rays and threads.
#
#   benches/embree3.sh [MESH CAMERA] [--seconds S] [--rounds R] [--threads "1 2"] [--accel A] [--json]
#   benches/embree3.sh dragon [...]    # target/models/stanford-dragon, benches/dragon.cmr
#
# --accel picks Prism's intersector (`bvh`, the default, or `bvh-copied`, whose leaves
# hold copies of their triangles as Embree's do).
#
# Default: the Stanford bunny beside the repository with benches/bunny.cmr. Writes a
# dump with `prism bench --dump`, compiles benches/embree3/harness.cpp against
# Debian's libembree-dev (Embree 3.13, which picks the widest ISA the CPU has; set
# EMBREE_CONFIG=isa=avx2 to hold it to AVX2), then runs `prism bench --json` and the
# harness R times for each thread count, interleaved so that noise on a shared machine
# hits both, and prints the medians side by side. The ratio is the median of each
# round's ratio, Prism's run against the Embree run right after it. With --json the
# medians come out as one JSON object on stdout instead of the table, everything else
# on stderr (benches/scaling.py reads it).
#
# libembree-dev is installed here with apt when missing: it is a dependency of this
# benchmark only. Prism does not link Embree and CI does not need it. Exit code 3 when
# Embree, g++ or python3 cannot be had, so callers can skip with a reason.
set -euo pipefail
cd "$(dirname "$0")/.."

mesh=../shared/models/stanford-bunny/stanford-bunny.obj
camera=benches/bunny.cmr
seconds=1
rounds=5
threads="1 2"
accel=bvh
json=0
positional=()
while (($#)); do
    case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --accel) accel=$2; shift 2 ;;
    --json) json=1; shift ;;
    -h | --help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) positional+=("$1"); shift ;;
    esac
done
if ((${#positional[@]} == 1)) && [[ ${positional[0]} == dragon ]]; then
    mesh=target/models/stanford-dragon/dragon_vrip.ply
    camera=benches/dragon.cmr
    [[ -f $mesh ]] || benches/fetch-dragon.sh
elif ((${#positional[@]} == 2)); then
    mesh=${positional[0]}
    camera=${positional[1]}
elif ((${#positional[@]} != 0)); then
    echo "usage: $0 [MESH CAMERA | dragon] [--seconds S] [--rounds R] [--threads \"1 2\"] [--accel A] [--json]" >&2
    exit 2
fi
[[ -f $mesh ]] || { echo "$mesh is absent" >&2; exit 1; }
# The table (or the JSON) goes to descriptor 3; with --json all else goes to stderr.
exec 3>&1
((json)) && exec 1>&2

skip() {
    echo "embree3.sh: $*" >&2
    exit 3
}
apt_install() {
    command -v apt-get >/dev/null || return 1
    [[ $(id -u) == 0 ]] || return 1
    echo "embree3.sh: installing $* with apt-get" >&2
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null; }
}
if [[ ! -f /usr/include/embree3/rtcore.h ]]; then
    apt_install libembree-dev ||
        skip "libembree-dev (Embree 3) is not installed and cannot be installed here (needs apt-get as root)"
fi
if ! command -v g++ >/dev/null; then
    apt_install g++ || skip "g++ is not installed and cannot be installed here"
fi
command -v python3 >/dev/null || skip "python3 is needed for the table"

out=target/embree3
mkdir -p "$out"
harness=$out/harness
if [[ ! -x $harness || benches/embree3/harness.cpp -nt $harness ]]; then
    g++ -O3 -std=c++17 -pthread -o "$harness" benches/embree3/harness.cpp -lembree3
fi
cargo build --release --quiet --bin prism
prism=target/release/prism

name=$(basename "${mesh%.*}")
dump=$out/dump-$name
"$prism" bench "$mesh" "$camera" --dump "$dump" --accel "$accel"
config=${EMBREE_CONFIG:-}
# Embree runs the widest ISA both this CPU and its build support.
"$harness" --probe --config "$config" |
    sed -n 's/^ *Targets *: *\(.*[^ ]\) *(supported)$/Embree targets here: \1 (it runs the widest)/p'

results=$out/results-$name.jsonl
: >"$results"
for round in $(seq "$rounds"); do
    for t in $threads; do
        p=$("$prism" bench "$mesh" "$camera" --json --no-frame --seconds "$seconds" --threads "$t" --accel "$accel")
        e=$("$harness" "$dump" --threads "$t" --seconds "$seconds" --config "$config")
        printf '{"round":%d,"tool":"prism","data":%s}\n' "$round" "$p" >>"$results"
        printf '{"round":%d,"tool":"embree","data":%s}\n' "$round" "$e" >>"$results"
        echo "round $round, $t thread(s): done" >&2
    done
done

python3 - "$results" "$rounds" "$json" "$mesh" "$camera" "$seconds" "$config" <<'EOF' >&3
import json, statistics, sys

rows = [json.loads(line) for line in open(sys.argv[1])]
rounds = sys.argv[2]
def figures(tool, threads, key):
    return [
        r["data"][key] for r in rows if r["tool"] == tool and r["data"]["threads"] == threads
    ]

embree = next(r["data"] for r in rows if r["tool"] == "embree")
prism = next(r["data"] for r in rows if r["tool"] == "prism")
threads = sorted({r["data"]["threads"] for r in rows})
if sys.argv[3] == "1":
    def medians(tool, t):
        data = [r["data"] for r in rows if r["tool"] == tool and r["data"]["threads"] == t]
        return {
            k: statistics.median(d[k] for d in data)
            for k, v in data[0].items()
            if isinstance(v, (int, float)) and not isinstance(v, bool) and k != "threads"
        }
    def ratios(t):
        pairs = [
            ("primary_mrays", "intersect1_mrays"),
            ("primary_packet_mrays", "intersect16_mrays"),
            ("shadow_mrays", "occluded1_mrays"),
            ("shadow_packet_mrays", "occluded1_mrays"),
            ("build_s", "build_s"),
        ]
        return {
            f"{p}/{e}": statistics.median(a / b for a, b in zip(figures("prism", t, p), figures("embree", t, e)))
            for p, e in pairs
        }
    keep = ["embree_version", "config", "tasking", "packets", "triangles", "rays", "shadow_rays"]
    summary = {
        "mesh": sys.argv[4], "camera": sys.argv[5], "seconds": float(sys.argv[6]),
        "rounds": int(rounds), "embree_config": sys.argv[7], "results": sys.argv[1],
        "width": prism["width"], "height": prism["height"], "hit_fraction": prism["hit_fraction"],
        "prism_simd": prism["simd"], "prism_accel": prism["accel"],
        "prism_bytes_per_triangle": prism["bytes"] / max(prism["primitives"], 1),
        "prism_accel_bytes_per_triangle": prism["accel_bytes"] / max(prism["primitives"], 1),
        "embree_scene_bytes_per_triangle": embree["scene_bytes"] / max(embree["triangles"], 1),
        **{k: embree[k] for k in keep},
        "agreement": {k: embree[k] for k in ["hit_or_miss_differs", "other_triangle", "distance_differs", "disagree", "intersect16_differs_from_intersect1", "occluded_differs"]},
        "medians": [
            {"threads": t, "prism": medians("prism", t), "embree": medians("embree", t), "ratios": ratios(t)}
            for t in threads
        ],
    }
    print(json.dumps(summary))
    sys.exit(0)
print(
    f"\n{embree['triangles']} triangles, {embree['rays']} primary rays "
    f"({prism['width']}x{prism['height']}), {embree['shadow_rays']} shadow rays; "
    f"Prism's {prism['accel']} ({prism['bytes'] / max(prism['primitives'], 1):.1f} bytes a triangle); "
    f"Embree {embree['embree_version']} ({embree['tasking']} tasking); "
    f"medians of {rounds} interleaved rounds, the ratio the median of each round's\n"
)
print("| figure | threads | Prism | Embree 3 | Prism / Embree |")
print("|---|---:|---:|---:|---:|")
lines = [
    ("primary, closest hit, Mrays/s: rtcIntersect1", "primary_mrays", "intersect1_mrays", 1),
    ("primary, Prism packets of 16 vs rtcIntersect16, 4x4 tiles, Mrays/s", "primary_packet_mrays", "intersect16_mrays", 1),
    ("shadow, any hit, Mrays/s: rtcOccluded1", "shadow_mrays", "occluded1_mrays", 1),
    ("shadow, Prism packets of a tile's hits vs rtcOccluded1, Mrays/s", "shadow_packet_mrays", "occluded1_mrays", 1),
    ("build, ms (time: above 1 is slower)", "build_s", "build_s", 1000),
]
for label, pkey, ekey, scale in lines:
    for t in threads:
        p, e = figures("prism", t, pkey), figures("embree", t, ekey)
        ratio = statistics.median(a / b for a, b in zip(p, e))
        p, e = statistics.median(p) * scale, statistics.median(e) * scale
        print(f"| {label} | {t} | {p:.2f} | {e:.2f} | {ratio:.2f} |")
a = embree
n = max(a["triangles"], 1)
print(
    f"\nMemory, bytes a triangle: Prism's {prism['accel']} {prism['accel_bytes'] / n:.1f} beside its "
    f"mesh's {(prism['bytes'] - prism['accel_bytes']) / n:.1f} (positions, index triples, materials); "
    f"Embree's scene {a['scene_bytes'] / n:.1f} (its memory monitor: BVH and leaves) beside "
    f"the application's vertex and index buffers, which it shares."
)
print(
    f"\nAgreement with Prism (rtcIntersect1): {a['hit_or_miss_differs']} hit/miss, "
    f"{a['other_triangle']} other triangle, {a['distance_differs']} distance > 1e-4, "
    f"{a['disagree']} disagree; rtcIntersect16 differs from rtcIntersect1 on "
    f"{a['intersect16_differs_from_intersect1']}; shadow rays blocked differ on "
    f"{a['occluded_differs']} of {a['shadow_rays']}."
)
EOF
echo "raw figures: $results"
