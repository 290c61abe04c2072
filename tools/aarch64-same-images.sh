#!/usr/bin/env bash
# Prism on aarch64 writes the same image bytes as on x86-64: builds the command for
# aarch64-unknown-linux-gnu (without H.264, whose C++ would need a cross C++ compiler),
# runs it under qemu-aarch64 on every bundled scene and the POV-Ray scene at a small
# size, and compares each PNG with the native build's, byte for byte.
#
#   tools/aarch64-same-images.sh            # exit 0 when every image is the same
#   tools/aarch64-same-images.sh --tests    # also run the library's tests under qemu
#                                           # (about 20 minutes on two cores)
#
# Needs the aarch64 standard library (rustup target add aarch64-unknown-linux-gnu), a
# cross linker and qemu-user (apt-get install gcc-aarch64-linux-gnu
# libc6-dev-arm64-cross qemu-user); installs them when it can, exit 3 when it cannot.
set -euo pipefail
cd "$(dirname "$0")/.."

target=aarch64-unknown-linux-gnu
skip() {
    echo "aarch64-same-images.sh: $*" >&2
    exit 3
}
rustup target list --installed | grep -qx $target ||
    rustup target add $target >/dev/null || skip "the $target standard library did not install"
if ! command -v aarch64-linux-gnu-gcc >/dev/null || ! command -v qemu-aarch64 >/dev/null; then
    command -v apt-get >/dev/null || skip "no aarch64-linux-gnu-gcc or qemu-aarch64, and no apt-get"
    apt-get update -qq >/dev/null || true
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user >/dev/null ||
        skip "gcc-aarch64-linux-gnu and qemu-user did not install"
fi

export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc
export CC_aarch64_unknown_linux_gnu=aarch64-linux-gnu-gcc
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L /usr/aarch64-linux-gnu"
cargo build --release --bin prism --quiet
cargo build --release --bin prism --no-default-features --target $target --quiet
out_dir=$(cd "${CARGO_TARGET_DIR:-target}" && pwd)
native=$out_dir/release/prism
arm=(qemu-aarch64 -L /usr/aarch64-linux-gnu "$out_dir/$target/release/prism")

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failed=0
compare() {
    local name=$1
    shift
    "$native" render "$@" "$out/x86-64.png" --quiet
    "${arm[@]}" render "$@" "$out/aarch64.png" --quiet
    if cmp -s "$out/x86-64.png" "$out/aarch64.png"; then
        echo "same     $name"
    else
        echo "DIFFERS  $name"
        failed=1
    fi
}
compare povray-whitted benches/povray/whitted.toml --width 160
compare example scenes/example/example.objx scenes/example/example.cmr --width 120
# The dragon's 871k triangles take minutes under emulation; the turntable and the orbit
# are animations.
for name in showcase cornell-box spot bunny; do
    scene=scenes/$name/$name.toml
    if grep -q '^[^#]*\.\./shared' "$scene" && [[ ! -d ../shared ]]; then
        echo "skipped  $name (its model is in ../shared)"
        continue
    fi
    compare "$name" "$scene" --width 120
done
# The 2014 scenes beside the repository, textures, lens and anti-aliasing included.
for name in scene0 scene1; do
    dir=../shared/seed-scenes/Ray-Tracing/$name
    [[ -d $dir ]] || continue
    pushd "$dir" >/dev/null
    compare "$name" scene.objx scene.cmr --width 80 --aa 2 --dof-rays 4
    popd >/dev/null
done

if [[ ${1:-} == --tests ]]; then
    # Every f32 from 0 to 1 through the 8-bit cut-offs is a billion values: hours
    # under emulation, and the cut-off test on chosen values covers the same code.
    cargo test --lib --no-default-features --target $target -- --test-threads "$(nproc)" \
        --skip cut_offs_match_the_formula_for_every_f32_up_to_1
fi
exit $failed
