#!/usr/bin/env bash
# Runs every fuzz target (or those named) for SECONDS each, one process at a time, and
# prints each one's executions and coverage. Needs the nightly toolchain and
# cargo-fuzz; without them it says so and exits 0, so CI can call it unconditionally.
#
#   fuzz/run.sh SECONDS [TARGET...]
#
# The working corpus grows in fuzz/corpus/TARGET (untracked), seeded from
# fuzz/seeds/TARGET; crashes land in fuzz/artifacts/TARGET; logs in fuzz/logs/.
# Exits 1 if any target found a crash, a hang or an over-allocation.
set -uo pipefail
cd "$(dirname "$0")"

if [[ $# -lt 1 || ! $1 =~ ^[0-9]+$ ]]; then
    echo "usage: fuzz/run.sh SECONDS [TARGET...]" >&2
    exit 2
fi
seconds=$1
shift
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
    targets=(objx mtlx cmr obj obj_full mtl ply gltf scene_toml anim_toml render_objx render_toml texture)
fi

if ! rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    echo "fuzz: skipped, the nightly toolchain is not installed (rustup toolchain install nightly)"
    exit 0
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    echo "fuzz: skipped, cargo-fuzz is not installed (cargo install cargo-fuzz)"
    exit 0
fi

# Debug assertions on, so integer overflow is a crash rather than a silent wrap.
flags=(--debug-assertions)
cargo +nightly fuzz build "${flags[@]}" || exit 1

mkdir -p logs
failed=()
printf '%-12s %12s %8s %8s  %s\n' target executions cov ft result
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t"
    # One process per target; -timeout finds hangs, -malloc_limit_mb over-allocations.
    cargo +nightly fuzz run "${flags[@]}" "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$seconds" -dict="dict/$t.dict" -max_len=4096 \
        -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 -print_final_stats=1 \
        >"logs/$t.log" 2>&1
    status=$?
    runs=$(grep -oE '^stat::number_of_executed_units: *[0-9]+' "logs/$t.log" | grep -oE '[0-9]+$' | tail -1)
    last=$(grep -E '^#[0-9]+' "logs/$t.log" | tail -1)
    cov=$(grep -oE 'cov: [0-9]+' <<<"$last" | grep -oE '[0-9]+')
    ft=$(grep -oE 'ft: [0-9]+' <<<"$last" | grep -oE '[0-9]+')
    result=ok
    if [[ $status -ne 0 ]]; then
        result="FOUND (see fuzz/logs/$t.log, fuzz/artifacts/$t)"
        failed+=("$t")
    fi
    printf '%-12s %12s %8s %8s  %s\n' "$t" "${runs:-?}" "${cov:-?}" "${ft:-?}" "$result"
done
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "fuzz: findings in ${failed[*]}" >&2
    exit 1
fi
