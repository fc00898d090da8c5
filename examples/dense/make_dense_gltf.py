#!/usr/bin/env python3
"""Writes dense.gltf and dense.bin: a terrain of 2,097,152 triangles (1024² cells over 200 m, four
octaves of sines up to ±4.6 m), a camera above it and a sun 35° over the horizon whose hills cast
long shadows. Its shadow rays cost what a production scene's do: each one crosses a bounding
volume hierarchy of millions of triangles, a quarter of them ending on a hill, where the Cornell
box and the hard scene have a few hundred triangles.

`make bench` writes it to out/bench/ (50 MB, not committed):
`python3 make_dense_gltf.py OUT_DIR [CELLS]`.
"""
import array
import json
import math
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "."
cells = int(sys.argv[2]) if len(sys.argv) > 2 else 1024
size = 20000.0  # cm


def height(x, z):
    return (300 * math.sin(x * 0.0011) * math.cos(z * 0.0013)
            + 120 * math.sin(x * 0.0047 + 1.3) * math.sin(z * 0.0039)
            + 35 * math.sin(x * 0.021) * math.cos(z * 0.017 + 0.5)
            + 8 * math.sin(x * 0.09 + z * 0.07))


pos, nrm, idx = array.array("f"), array.array("f"), array.array("I")
step = size / cells
for j in range(cells + 1):
    z = -size / 2 + j * step
    for i in range(cells + 1):
        x = -size / 2 + i * step
        # The normal from central differences of the height 1 cm either side.
        dx = (height(x + 1, z) - height(x - 1, z)) / 2
        dz = (height(x, z + 1) - height(x, z - 1)) / 2
        inv = 1 / math.sqrt(dx * dx + 1 + dz * dz)
        pos.extend((x, height(x, z), z))
        nrm.extend((-dx * inv, inv, -dz * inv))
for j in range(cells):
    for i in range(cells):
        a = j * (cells + 1) + i
        b = a + cells + 1
        idx.extend((a, b, a + 1, a + 1, b, b + 1))  # counter-clockwise seen from above

blob = pos.tobytes() + nrm.tobytes() + idx.tobytes()
with open(os.path.join(out, "dense.bin"), "wb") as f:
    f.write(blob)
n = len(pos) // 3
gltf = {
    "asset": {"version": "2.0", "generator": "framepass examples/dense/make_dense_gltf.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "intensity": 3.0, "color": [1.0, 0.95, 0.9]}]}},
    "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [
        {"name": "terrain", "mesh": 0},
        # 25 m up, 90 m back, looking along +Z (180° about y) and 20° down.
        {"name": "camera", "camera": 0, "translation": [0.0, 2500.0, -9000.0],
         "rotation": [0.0, 0.98481, 0.17365, 0.0]},
        # 35° down, turned 40° about y.
        {"name": "sun", "rotation": [-0.28258, 0.32619, 0.10285, 0.89620],
         "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "meshes": [{"name": "terrain", "primitives": [
        {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 10.0, "aspectRatio": 1.0}}],
    "materials": [{"name": "ground", "pbrMetallicRoughness": {
        "baseColorFactor": [0.4, 0.35, 0.3, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
         "min": [min(pos[k::3]) for k in range(3)], "max": [max(pos[k::3]) for k in range(3)]},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
        {"buffer": 0, "byteOffset": 12 * n, "byteLength": 12 * n, "target": 34962},
        {"buffer": 0, "byteOffset": 24 * n, "byteLength": 4 * len(idx), "target": 34963}],
    "buffers": [{"byteLength": len(blob), "uri": "dense.bin"}],
}
with open(os.path.join(out, "dense.gltf"), "w") as f:
    json.dump(gltf, f, indent=1)
