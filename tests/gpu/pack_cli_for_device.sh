#!/usr/bin/env bash
# Packs what of framepass a build made for a GPU machine — the command line, the GPU check and the
# Python module built for that machine's Python (FP_OTHER_PYTHON_INCLUDE: docs/gpu.md), whichever
# are built — and the Debian shared libraries they need (everything ldd resolves except glibc,
# libstdc++ and the loader, which a GPU machine has), in parts small enough to carry one at a
# time (docs/gpu.md, "The command line on a GPU machine"): .gpu-cli/ (ignored by git) then holds
# framepass, framepass_gpu_check, python/framepass/ and libs.tar.xz.part-aa, -ab, …
#   tests/gpu/pack_cli_for_device.sh [BUILD_DIR] [PART_SIZE]      (default build, 30M)
# On the GPU machine, once every part has arrived in one folder (say /tmp/fp), unpack them:
#   cat /tmp/fp/libs.tar.xz.part-* | tar -xJ -C /tmp/fp
#   LD_LIBRARY_PATH=/tmp/fp FRAMEPASS_CONFIG_DIR=$PWD/configs .gpu-cli/framepass run … --device cuda
#   LD_LIBRARY_PATH=/tmp/fp PYTHONPATH=.gpu-cli/python python3 tests/gpu/cuda_outputs_check.py …
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
part=${2:-30M}
bins=()
for b in "$build/cli/framepass" "$build/tests/framepass_gpu_check"; do [ -x "$b" ] && bins+=("$b"); done
module=$(ls "$build"/python-other/framepass/_framepass*.so 2>/dev/null | head -1 || true)
[ -n "$module" ] && bins+=("$module")
[ ${#bins[@]} -gt 0 ] || { echo "nothing to pack in $build: build framepass first (make, or cmake --build $build --target framepass)" >&2; exit 2; }
exclude=$(git rev-parse --git-path info/exclude)
mkdir -p "$(dirname "$exclude")"
grep -qx '/.gpu-cli/' "$exclude" 2>/dev/null || echo '/.gpu-cli/' >> "$exclude"
rm -rf .gpu-cli && mkdir -p .gpu-cli/lib
for b in "${bins[@]}"; do
    case "$b" in
        *.so) mkdir -p .gpu-cli/python && cp -r "$(dirname "$b")" .gpu-cli/python/ ;;
        *) cp "$b" .gpu-cli/ ;;
    esac
    ldd "$b" | awk '/=> \// {print $3}' | while read -r lib; do
        case "$(basename "$lib")" in
            libc.so*|libm.so*|libstdc++.so*|libgcc_s.so*|ld-linux*|libpython*) ;;
            *) cp -L "$lib" .gpu-cli/lib/ ;;
        esac
    done
    missing=$(ldd "$b" | grep -v libpython | grep -c 'not found' || true)
    [ "$missing" = 0 ] || { echo "ldd finds no library for $missing of $(basename "$b")'s needs" >&2; exit 2; }
done
tar -cJf - -C .gpu-cli/lib . | split -b "$part" - .gpu-cli/libs.tar.xz.part-
rm -rf .gpu-cli/lib
ls -la .gpu-cli
