#!/usr/bin/env python3
"""Writes the inputs of the bad-input corpus that are binary or large.

    make_inputs.py OUT_DIR

The small text cases (configs, sidecars, scenes, glTFs) are committed under files/; this writes
the rest at test time: EXRs built byte by byte (so a header can lie about its sizes), JSON nested
tens of thousands deep, and glTF node chains deeper than the limit. Pure Python, no numpy.
"""
import json
import math
import os
import struct
import sys


# --- a minimal OpenEXR writer (scanline, uncompressed; OpenEXR file layout) -----------------------
def attr(name, type_, payload):
    return name.encode() + b"\0" + type_.encode() + b"\0" + struct.pack("<i", len(payload)) + payload


def chlist(names):
    out = b""
    for n in sorted(names):
        out += n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1)  # FLOAT, 1×1 sampling
    return out + b"\0"


def m44f(rows):
    return struct.pack("<16f", *[v for r in rows for v in r])


def m44d(rows):
    return struct.pack("<16d", *[v for r in rows for v in r])


def exr(path, width, height, channels, extra=b"", declared=None, pixels=True, raw_header=None):
    """channels: {name: function(x, y) -> float}. declared: (w, h) written in the header instead."""
    dw, dh = declared or (width, height)
    header = b""
    header += attr("channels", "chlist", chlist(channels))
    header += attr("compression", "compression", b"\0")
    header += attr("dataWindow", "box2i", struct.pack("<4i", 0, 0, dw - 1, dh - 1))
    header += attr("displayWindow", "box2i", struct.pack("<4i", 0, 0, dw - 1, dh - 1))
    header += attr("lineOrder", "lineOrder", b"\0")
    header += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += attr("screenWindowCenter", "v2f", struct.pack("<2f", 0.0, 0.0))
    header += attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    header += extra
    if raw_header is not None:
        header = raw_header
    data = struct.pack("<ii", 20000630, 2) + header + b"\0"
    if pixels:
        names = sorted(channels)
        rows = []
        for y in range(height):
            row = b"".join(struct.pack("<%df" % width, *[channels[n](x, y) for x in range(width)])
                           for n in names)
            rows.append(struct.pack("<ii", y, len(row)) + row)
        offset = len(data) + 8 * height
        table = b""
        for r in rows:
            table += struct.pack("<Q", offset)
            offset += len(r)
        data += table + b"".join(rows)
    with open(path, "wb") as f:
        f.write(data)


def framepass_camera(fx=1.0, fy=1.0, near=10.0, view=None):
    """framepass:worldToView / viewToClip (row-vector Imath order = transpose of column-vector)."""
    v = view or [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    # column-vector projection: P00 = fx, P11 = fy, P23 = near, P32 = 1 (reversed Z, infinite)
    p = [[fx, 0, 0, 0], [0, fy, 0, 0], [0, 0, 0, near], [0, 0, 1, 0]]
    t = lambda m: [[m[j][i] for j in range(4)] for i in range(4)]
    # This frame's camera, and the same as last frame's (camera_velocity and the reprojecting
    # passes need one).
    return (attr("framepass:worldToView", "m44d", m44d(t(v))) +
            attr("framepass:viewToClip", "m44d", m44d(t(p))) +
            attr("framepass:prevWorldToView", "m44d", m44d(t(v))) +
            attr("framepass:prevViewToClip", "m44d", m44d(t(p))) +
            attr("framepass:sceneUnitsPerMeter", "double", struct.pack("<d", 100.0)))


def main(out):
    os.makedirs(out, exist_ok=True)
    W = H = 8
    nan, inf = float("nan"), float("inf")
    depth = lambda x, y: 100.0 + x
    good_cam = framepass_camera()

    # A small valid capture: depth only, camera in the header (the runner's reference case).
    exr(f"{out}/good.exr", W, H, {"SceneDepth.Z": depth}, good_cam)
    # Depth holding NaN, +inf, 0 and negative pixels (sanitised to sky; --strict fails the frame).
    exr(f"{out}/depth_nan.exr", W, H,
        {"SceneDepth.Z": lambda x, y: [nan, inf, -5.0, 100.0][(x + y) % 4]}, good_cam)
    exr(f"{out}/depth_zero.exr", W, H, {"SceneDepth.Z": lambda x, y: 0.0}, good_cam)
    # Normals of zero length on surfaces (and NaN), for --strict.
    exr(f"{out}/normal_zero.exr", W, H,
        {"SceneDepth.Z": depth, "WorldNormal.X": lambda x, y: 0.0,
         "WorldNormal.Y": lambda x, y: 0.0, "WorldNormal.Z": lambda x, y: 0.0}, good_cam)
    # NaN and Inf colour in SceneColor.
    exr(f"{out}/color_nan.exr", W, H,
        {"SceneDepth.Z": depth, "SceneColor.R": lambda x, y: nan,
         "SceneColor.G": lambda x, y: inf, "SceneColor.B": lambda x, y: -inf}, good_cam)
    # Header cameras that would fill every position with NaN.
    exr(f"{out}/cam_fx0.exr", W, H, {"SceneDepth.Z": depth}, framepass_camera(fx=0.0, fy=0.0))
    exr(f"{out}/cam_nan.exr", W, H, {"SceneDepth.Z": depth}, framepass_camera(fx=nan))
    exr(f"{out}/cam_near0.exr", W, H, {"SceneDepth.Z": depth}, framepass_camera(near=0.0))
    zero = [[0.0] * 4 for _ in range(4)]
    exr(f"{out}/cam_singular_view.exr", W, H, {"SceneDepth.Z": depth}, framepass_camera(view=zero))
    # Standard worldToCamera / worldToNDC, both singular.
    exr(f"{out}/cam_singular_std.exr", W, H, {"SceneDepth.Z": depth},
        attr("worldToCamera", "m44f", m44f(zero)) + attr("worldToNDC", "m44f", m44f(zero)))
    # A header that claims a 100000×100000 image (and holds 8×8 pixels' worth of nothing).
    exr(f"{out}/huge_declared.exr", W, H, {"SceneDepth.Z": depth}, good_cam,
        declared=(100000, 100000), pixels=False)
    # 4 KB whose header claims a 2 GB string attribute.
    big = (b"comment\0string\0" + struct.pack("<i", 2_000_000_000) + b"x" * 4000)
    exr(f"{out}/attr_2gb.exr", W, H, {"SceneDepth.Z": depth}, good_cam + big, pixels=False)
    # A negative attribute size.
    neg = b"comment\0string\0" + struct.pack("<i", -7) + b"xx"
    exr(f"{out}/attr_negative.exr", W, H, {"SceneDepth.Z": depth}, good_cam + neg, pixels=False)
    # A valid header, then the pixels cut off.
    exr(f"{out}/truncated.exr", W, H, {"SceneDepth.Z": depth}, good_cam)
    with open(f"{out}/truncated.exr", "r+b") as f:
        f.truncate(os.path.getsize(f"{out}/truncated.exr") - 100)
    # A header without its end (a name that never terminates).
    with open(f"{out}/header_cut.exr", "wb") as f:
        f.write(struct.pack("<ii", 20000630, 2) + b"channels\0chl")
    # A valid lat-long sky, and one with a NaN pixel (a scene's skyLight.latLong).
    exr(f"{out}/good_sky.exr", 4, 2, {"R": lambda x, y: 1.0 - y, "G": lambda x, y: 0.5,
                                      "B": lambda x, y: float(y)})
    # A valid 4² cubemap strip (six faces stacked) for a reflection capture.
    exr(f"{out}/good_cube.exr", 4, 24, {"R": lambda x, y: 0.1 * (y // 4), "G": lambda x, y: 0.5,
                                        "B": lambda x, y: 0.25})
    exr(f"{out}/sky_nan.exr", 4, 2, {"R": lambda x, y: nan if (x, y) == (2, 1) else 1.0,
                                     "G": lambda x, y: 1.0, "B": lambda x, y: 1.0})
    # Not an EXR at all.
    with open(f"{out}/text.exr", "w") as f:
        f.write("this is not an OpenEXR file\n")
    # A folder named like a capture.
    os.makedirs(f"{out}/folder.exr", exist_ok=True)

    # JSON nested 60,000 deep (360 KB): in a config's params, a sidecar, a scene, a profile.
    deep = "[" * 60000 + "]" * 60000
    with open(f"{out}/deep_params.json", "w") as f:
        f.write('{"version": 1, "capture": "good.exr", "passes": [{"type": "hzb", "params": '
                '{"x": %s}}]}' % deep)
    with open(f"{out}/deep_sidecar.json", "w") as f:
        f.write('{"fovYDegrees": 40, "x": %s}' % deep)
    with open(f"{out}/deep_cvars.json", "w") as f:
        f.write('{"version": 1, "capture": "good.exr", "cvars": {"r.SSGI.Quality": %s}}' % deep)
    with open(f"{out}/deep_set.txt", "w") as f:
        f.write("[" * 5000 + "]" * 5000)

    # glTF: a node chain deeper than the limit (each node the only child of the one before).
    nodes = [{"children": [i + 1]} for i in range(999)] + [{"mesh": 0}]
    gltf = json.load(open(os.path.join(os.path.dirname(__file__), "files", "gltf",
                                       "base.gltf")))
    gltf["nodes"] = nodes
    gltf["scenes"] = [{"nodes": [0]}]
    gltf["scene"] = 0
    with open(f"{out}/gltf_deep.gltf", "w") as f:
        json.dump(gltf, f)
    with open(f"{out}/gltf_deep.json", "w") as f:
        json.dump({"geometry": "gltf_deep.gltf",
                   "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "fovYDegrees": 40}}, f)


if __name__ == "__main__":
    main(sys.argv[1])
