#!/usr/bin/env bash
# Times Prism against POV-Ray 3.7 on the classic Whitted scene (benches/povray/whitted.pov
# and its translation whitted.toml): whole processes, parse to PNG on disk, 1280x720,
# without anti-aliasing and with 3x3 samples per pixel, on both cores, plus a one-thread
# pair for reference. The two commands alternate (POV-Ray, Prism, POV-Ray, ...) and each
# ratio is taken pair by pair, so a machine whose speed drifts during the run still gives
# a fair ratio; the medians are printed.
#
#   benches/povray.sh            # RUNS=5 pairs per row after one warm-up pair
#   RUNS=9 benches/povray.sh
#
# Installs POV-Ray with apt-get when it is missing (exit 3 when that cannot be done).
# Never run by the test suite: nothing in CI depends on POV-Ray.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
runs=${RUNS:-5}

if ! command -v povray >/dev/null 2>&1; then
    if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1; then
        echo "povray is missing, and installing it needs root and apt-get" >&2
        exit 3
    fi
    echo "installing povray ..." >&2
    if ! { apt-get update -qq &&
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq povray >/dev/null; }; then
        echo "povray is missing and apt-get could not install it" >&2
        exit 3
    fi
fi
if ! povray --version 2>&1 | grep -q 'POV-Ray 3\.7'; then
    echo "the povray on the PATH is not POV-Ray 3.7:" >&2
    povray --version 2>&1 | grep -m1 'POV-Ray' >&2 || true
    exit 3
fi

cargo build --release --quiet
prism=$root/target/release/prism
pov_scene=$root/benches/povray/whitted.pov
toml_scene=$root/benches/povray/whitted.toml

# POV-Ray's default I/O restrictions allow writing only below the working directory, so
# both programs run and write inside one scratch folder.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

# -D: no preview window; -GA: no text streams. File_Gamma=sRGB writes linear radiance
# through the sRGB curve, as Prism does.
pov_common=("+I$pov_scene" +Opov.png +FN +W1280 +H720 -D -GA File_Gamma=sRGB)
# Anti-aliasing 3: method 1 with threshold 0 supersamples every pixel on a regular 3x3
# grid (jitter off), as Prism's --aa 3 (whitted.pov explains the one extra centre ray).
pov_aa3=(+A0.0 +AM1 +R3 -J)

# One timed run: prints "wall cpu" in seconds (cpu = user + sys of the process).
timed() {
    local TIMEFORMAT='%R %U %S' t
    t=$({ time "$@" >/dev/null 2>&1; } 2>&1) || {
        echo "failed: $*" >&2
        exit 1
    }
    awk '{ printf "%s %.3f\n", $1, $2 + $3 }' <<<"$t"
}

median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# pair LABEL -- POVRAY_ARGS... -- PRISM_ARGS...
pair() {
    local label=$1 pov_args=() prism_args=() side=pov
    shift 2
    for a in "$@"; do
        if [ "$a" = -- ]; then side=prism; continue; fi
        if [ $side = pov ]; then pov_args+=("$a"); else prism_args+=("$a"); fi
    done
    local rows=$work/rows
    : >"$rows"
    for i in $(seq 0 "$runs"); do
        local a b
        a=$(timed povray "${pov_common[@]}" "${pov_args[@]}")
        b=$(timed "$prism" render "$toml_scene" prism.png --quiet "${prism_args[@]}")
        # The first pair warms the page cache and the CPU's clocks; it is not counted.
        [ "$i" = 0 ] || echo "$a $b" >>"$rows"
    done
    local pw pc mw mc rw rc
    pw=$(awk '{ print $1 }' "$rows" | median)
    pc=$(awk '{ print $2 }' "$rows" | median)
    mw=$(awk '{ print $3 }' "$rows" | median)
    mc=$(awk '{ print $4 }' "$rows" | median)
    rw=$(awk '{ print $1 / $3 }' "$rows" | median)
    rc=$(awk '{ print $2 / $4 }' "$rows" | median)
    printf '| %s | %.2f | %.2f | **%.1f** | %.2f | %.2f | %.1f |\n' \
        "$label" "$pw" "$mw" "$rw" "$pc" "$mc" "$rc"
}

echo "POV-Ray $(povray --version 2>&1 | grep -m1 -o '^POV-Ray 3\.7[0-9.]*[0-9]' | cut -d' ' -f2), Prism $(git -C "$root" rev-parse --short HEAD), $(nproc) cores, $runs pairs a row (medians)"
echo
echo "| 1280x720 | POV-Ray wall s | Prism wall s | POV-Ray / Prism wall | POV-Ray cpu s | Prism cpu s | POV-Ray / Prism cpu |"
echo "|---|---:|---:|---:|---:|---:|---:|"
pair "no AA, 2 threads" -- +WT2 -- --threads 2
pair "AA 3, 2 threads" -- +WT2 "${pov_aa3[@]}" -- --threads 2 --aa 3
pair "no AA, 1 thread" -- +WT1 -- --threads 1
