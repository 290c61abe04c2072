#!/usr/bin/env bash
# Adds the shared models and seed scenes (../shared beside the repo)
# to the untracked working corpora in fuzz/corpus/, which libFuzzer then
# minimises as it goes. The tracked seeds in fuzz/seeds/ stay small.
set -euo pipefail
cd "$(dirname "$0")"
shared=../../shared
add() { # TARGET FILE...: copies the files of at most 64 KiB
    local target=$1
    shift
    mkdir -p "corpus/$target"
    for f in "$@"; do
        if [[ -f $f && $(stat -c %s "$f") -le 65536 ]]; then
            cp "$f" "corpus/$target/$(basename "$(dirname "$f")")-$(basename "$f")"
        fi
    done
}
shopt -s nullglob globstar
add obj "$shared"/models/**/*.obj
add objx "$shared"/seed-scenes/**/*.objx
add render_objx "$shared"/seed-scenes/**/*.objx
add mtlx "$shared"/seed-scenes/**/*.mtlx
add cmr "$shared"/seed-scenes/**/*.cmr
add ply "$shared"/models/**/*.ply
for t in corpus/*; do
    echo "$t: $(ls "$t" | wc -l) files"
done
