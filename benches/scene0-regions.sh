#!/usr/bin/env sh
# Renders twelve 64x36 windows of the 2014 scene0 at its full 3840x2160 resolution with
# the camera file's own heaviest setting (anti-aliasing 4, 128 lens rays): a 4x3 grid,
# 0.33 % of the frame's pixels from every part of the picture. Time it whole, for two
# Prism binaries in turn, to measure "a fraction of the frame":
#
#   farm-bench -n 5 --vs 'benches/scene0-regions.sh OLD_PRISM' -- benches/scene0-regions.sh target/release/prism
#
# The full frame takes about 8.29e6 / 27648 = 300 times one run of this script.
# SCENE0 names the scene's folder (default: the seed scenes beside the repository,
# which a clone of Prism alone does not have; exit 3 when it is absent).
set -eu
prism=${1:?usage: benches/scene0-regions.sh PRISM_BINARY}
here=$(cd "$(dirname "$0")/.." && pwd)
scene=${SCENE0:-$here/../shared/seed-scenes/Ray-Tracing/scene0}
[ -f "$scene/scene.objx" ] || { echo "scene0 is absent: $scene" >&2; exit 3; }
case $prism in /*) ;; *) prism=$PWD/$prism ;; esac
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cd "$scene"
for y in 342 1062 1782; do
    for x in 448 1408 2368 3328; do
        "$prism" render scene.objx scene.cmr "$out/window.png" --region "$x,$y,64,36" -q
    done
done
