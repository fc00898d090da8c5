#!/usr/bin/env bash
# Packs framepass_gpu_check and the Debian shared libraries it needs (everything ldd resolves
# except glibc, libstdc++ and the loader, which the GPU machine has) into .gpu/, a folder git
# ignores, so the check can be carried to a GPU machine without Debian packages (docs/gpu.md).
#   tests/gpu/pack_for_device.sh [BUILD_DIR]
# On the GPU machine, from the repository root:
#   mkdir -p /tmp/fp && tar -xJf .gpu/libs.tar.xz -C /tmp/fp
#   LD_LIBRARY_PATH=/tmp/fp FRAMEPASS_SOURCE_DIR=$PWD FRAMEPASS_CONFIG_DIR=$PWD/configs \
#     .gpu/framepass_gpu_check [--bench --size 1920x1080 --runs 10]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
bin=$build/tests/framepass_gpu_check
[ -x "$bin" ] || { echo "no $bin: build with CUDA first (cmake finds /usr/local/cuda)" >&2; exit 2; }
exclude=$(git rev-parse --git-path info/exclude)
mkdir -p "$(dirname "$exclude")"
grep -qx '/.gpu/' "$exclude" 2>/dev/null || echo '/.gpu/' >> "$exclude"
rm -rf .gpu && mkdir -p .gpu/lib
cp "$bin" .gpu/
ldd "$bin" | awk '/=> \// {print $3}' | while read -r lib; do
    case "$(basename "$lib")" in
        libc.so*|libm.so*|libstdc++.so*|libgcc_s.so*|ld-linux*) ;;
        *) cp -L "$lib" .gpu/lib/ ;;
    esac
done
tar -cJf .gpu/libs.tar.xz -C .gpu/lib .
rm -rf .gpu/lib
du -sh .gpu/*
