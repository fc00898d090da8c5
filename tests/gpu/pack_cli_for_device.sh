#!/usr/bin/env bash
# Packs the framepass command line and the Debian shared libraries it needs (everything ldd
# resolves except glibc, libstdc++ and the loader, which a GPU machine has) for a machine that has
# none of them, in parts small enough to carry one at a time (docs/gpu.md, "The command line on
# a GPU machine"): .gpu-cli/ (ignored by git) then holds framepass and libs.tar.xz.part-aa, -ab, …
#   tests/gpu/pack_cli_for_device.sh [BUILD_DIR] [PART_SIZE]      (default build, 30M)
# On the GPU machine, once every part has arrived in one folder (say /tmp/fp), unpack them:
#   cat /tmp/fp/libs.tar.xz.part-* | tar -xJ -C /tmp/fp
#   LD_LIBRARY_PATH=/tmp/fp FRAMEPASS_CONFIG_DIR=$PWD/configs .gpu-cli/framepass run … --device cuda
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
part=${2:-30M}
bin=$build/cli/framepass
[ -x "$bin" ] || { echo "no $bin: build it first (make, or cmake --build $build --target framepass)" >&2; exit 2; }
exclude=$(git rev-parse --git-path info/exclude)
mkdir -p "$(dirname "$exclude")"
grep -qx '/.gpu-cli/' "$exclude" 2>/dev/null || echo '/.gpu-cli/' >> "$exclude"
rm -rf .gpu-cli && mkdir -p .gpu-cli/lib
cp "$bin" .gpu-cli/
ldd "$bin" | awk '/=> \// {print $3}' | while read -r lib; do
    case "$(basename "$lib")" in
        libc.so*|libm.so*|libstdc++.so*|libgcc_s.so*|ld-linux*) ;;
        *) cp -L "$lib" .gpu-cli/lib/ ;;
    esac
done
missing=$(ldd "$bin" | grep -c 'not found' || true)
[ "$missing" = 0 ] || { echo "ldd finds no library for $missing of framepass's needs" >&2; exit 2; }
tar -cJf - -C .gpu-cli/lib . | split -b "$part" - .gpu-cli/libs.tar.xz.part-
rm -rf .gpu-cli/lib
ls -la .gpu-cli
