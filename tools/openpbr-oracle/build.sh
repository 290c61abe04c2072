#!/bin/sh
# Builds the OpenPBR test oracle (Adobe's reference BSDF behind a stdin/stdout protocol).
# Usage: tools/openpbr-oracle/build.sh [output-path]   (default: <repo>/target/openpbr-oracle)
# Exit status 3 with a one-line reason on stderr when a prerequisite is missing, so a test
# can skip. Environment: OPENPBR_BSDF_DIR (Adobe's sources), CXX (default g++).
set -eu

here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
out=${1:-"$repo/target/openpbr-oracle"}
# ../shared beside the repository, as CI lays it out.
bsdf_dir=${OPENPBR_BSDF_DIR:-"$repo/../shared/reference/openpbr-bsdf"}
cxx=${CXX:-g++}

if ! command -v "$cxx" >/dev/null 2>&1; then
    echo "openpbr-oracle: $cxx not found (install g++)" >&2
    exit 3
fi
if [ ! -f /usr/include/glm/glm.hpp ]; then
    echo "openpbr-oracle: GLM not found at /usr/include/glm/glm.hpp (apt-get install libglm-dev)" >&2
    exit 3
fi
if [ ! -f "$bsdf_dir/openpbr.h" ]; then
    echo "openpbr-oracle: Adobe's OpenPBR BSDF not found at $bsdf_dir (set OPENPBR_BSDF_DIR)" >&2
    exit 3
fi

mkdir -p "$(dirname "$out")"
exec "$cxx" -O2 -std=c++17 -I"$bsdf_dir" "$here/oracle.cpp" -o "$out"
