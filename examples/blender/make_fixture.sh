#!/bin/sh
# Makes framepass's Blender fixture (tests/fixtures/blender/) from nothing but Blender:
#   examples/blender/make_fixture.sh OUTDIR
# builds the room with make_fixture_scene.py into a temporary .blend (never kept), then renders
# it with export_gbuffer.py: 64x64, frames 1-3, Cycles 32 samples, denoiser off, seed 0,
# 2 threads. Needs `blender` (Debian's 3.4.1 made the checked-in fixture) on PATH or in $BLENDER.
set -eu
if [ $# -ne 1 ]; then
    echo "usage: $0 OUTDIR" >&2
    exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
out=$1
blender=${BLENDER:-blender}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM

"$blender" -b --factory-startup -t 2 --python-exit-code 1 \
    -P "$here/make_fixture_scene.py" -- "$tmp/room.blend"
"$blender" -b "$tmp/room.blend" -t 2 --python-exit-code 1 \
    -P "$here/export_gbuffer.py" -- --out "$out" --frames 1-3 --width 64 --height 64 \
    --samples 32 --denoise off
