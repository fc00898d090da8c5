#!/usr/bin/env python3
"""Writes hard.gltf: the hard-case geometry of docs/design.md, Numerics and determinism, in Unreal units (cm), y up.

A 400 m floor seen at a grazing angle, a 1 cm thin pole (about a pixel wide at 256 px), a
mirror-smooth and a fully rough sphere. The scene JSON moves it all 10^7 units from the origin.
Regenerate with `python3 make_hard_gltf.py` (the output is committed).
"""
import base64, json, math, struct

def sphere(cx, cy, cz, r, seg=24, rings=12):
    pos, nrm, idx = [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(seg + 1):
            ph = 2 * math.pi * j / seg
            n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            pos.append((cx + r * n[0], cy + r * n[1], cz + r * n[2])); nrm.append(n)
    for i in range(rings):
        for j in range(seg):
            a, b = i * (seg + 1) + j, (i + 1) * (seg + 1) + j
            idx += [a, a + 1, b, a + 1, b + 1, b]
    return pos, nrm, idx

def cylinder(cx, cz, r, h, seg=12):
    pos, nrm, idx = [], [], []
    for j in range(seg + 1):
        ph = 2 * math.pi * j / seg
        n = (math.cos(ph), 0.0, math.sin(ph))
        pos += [(cx + r * n[0], 0.0, cz + r * n[2]), (cx + r * n[0], h, cz + r * n[2])]; nrm += [n, n]
    for j in range(seg):
        a = 2 * j
        idx += [a, a + 2, a + 1, a + 1, a + 2, a + 3]
    return pos, nrm, idx

def quad(half):
    return ([(-half, 0, -half), (half, 0, -half), (half, 0, half), (-half, 0, half)],
            [(0, 1, 0)] * 4, [0, 2, 1, 0, 3, 2])

meshes = [("floor", quad(20000.0), 0), ("pole", cylinder(-60.0, 900.0, 0.5, 300.0), 1),
          ("mirror_sphere", sphere(-120.0, 60.0, 600.0, 60.0), 2),
          ("rough_sphere", sphere(120.0, 60.0, 600.0, 60.0), 3)]
blob, views, accessors, gmeshes, nodes = b"", [], [], [], []
def add(data, fmt, count, target, acc_type, comp, extra=None):
    global blob
    while len(blob) % 4: blob += b"\0"
    raw = b"".join(struct.pack(fmt, *d) if isinstance(d, tuple) else struct.pack(fmt, d) for d in data)
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(raw), "target": target})
    blob += raw
    acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": acc_type}
    if extra: acc.update(extra)
    accessors.append(acc)
    return len(accessors) - 1
for name, (pos, nrm, idx), mat in meshes:
    lo = [min(p[k] for p in pos) for k in range(3)]; hi = [max(p[k] for p in pos) for k in range(3)]
    p = add(pos, "<3f", len(pos), 34962, "VEC3", 5126, {"min": lo, "max": hi})
    n = add(nrm, "<3f", len(nrm), 34962, "VEC3", 5126)
    i = add(idx, "<I", len(idx), 34963, "SCALAR", 5125)
    gmeshes.append({"name": name, "primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": mat}]})
    nodes.append({"name": name, "mesh": len(gmeshes) - 1})
# Camera 20 cm above the floor looking almost horizontally: the floor is seen at grazing angles.
nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 20.0, 0.0],
              "rotation": [0.0, 1.0, 0.0, 0.0]})  # 180° about y: -Z (glTF forward) → +Z
nodes.append({"name": "sun", "rotation": [-0.3826834, 0.0, 0.0, 0.9238795],
              "extensions": {"KHR_lights_punctual": {"light": 0}}})
gltf = {
    "asset": {"version": "2.0", "generator": "framepass examples/hard/make_hard_gltf.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"name": "sun", "type": "directional", "intensity": 3.0, "color": [1.0, 0.95, 0.9]}]}},
    "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": gmeshes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 10.0, "aspectRatio": 1.0}}],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.8}},
        {"name": "pole", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"name": "mirror", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1], "metallicFactor": 1, "roughnessFactor": 0}},
        {"name": "rough", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
    "accessors": accessors, "bufferViews": views,
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open("hard.gltf", "w") as f:
    json.dump(gltf, f, indent=1)
