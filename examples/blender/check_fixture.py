#!/usr/bin/python3
# Checks the conventions configs/profiles/blender.json relies on, numerically, on the fixture
# that examples/blender/make_fixture.sh renders (the room of make_fixture_scene.py):
#   Depth   planar view depth (not ray distance): every wall/floor/ceiling pixel rebuilt from
#           Depth.Z x 100 and the sidecar camera lies on its known plane;
#   Normal  world-space, unit, facing the camera, equal to the known inward plane normals and
#           to the rotated box's face normals;
#   Vector  (X, -Y) = pixels to where the surface was in frame N-1, +Y down (framepass's
#           Velocity), by reprojecting each pixel's surface through the sidecar's "previous"
#           camera; (-Z, W) = pixels to frame N+1;
#   AOVs    BaseColor/Metallic/Roughness/Specular equal the materials' values (box: through
#           links), DiffCol = BaseColor x (1 - Metallic);
#   sky     Depth 1e10, Env = the world colour, Combined = Emit + Env there.
# Prints the numbers; exits 1 when a check is out of tolerance.
#
#   /usr/bin/python3 examples/blender/check_fixture.py tests/fixtures/blender
# Needs Debian's python3-numpy and python3-openimageio.
import json
import math
import sys

import numpy as np
import OpenImageIO as oiio

D = sys.argv[1] if len(sys.argv) > 1 else "tests/fixtures/blender"
NAME = sys.argv[2] if len(sys.argv) > 2 else "room"
FRAMES = [1, 2, 3]
VL = "ViewLayer."
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"  FAIL: {what}")


def load(f):
    buf = oiio.ImageBuf(f"{D}/{NAME}.{f:04d}.exr")
    a = buf.get_pixels(oiio.FLOAT)
    return {n: a[..., i] for i, n in enumerate(buf.spec().channelnames)}


def cam(j):
    m = np.array(j["cameraToWorld"], float).reshape(4, 4)
    return dict(pos=m[:3, 3], right=m[:3, 0], up=m[:3, 1], fwd=-m[:3, 2],  # "opengl" axes
                fxp=j["fxPixels"], fyp=j["fyPixels"], cxp=j["cxPixels"], cyp=j["cyPixels"])


def ndc_params(c, W, H):
    # io/CameraIO.cpp cameraViewFromJson
    return (2 * c["fxp"] / W, 2 * c["fyp"] / H, 2 * c["cxp"] / W - 1, 1 - 2 * c["cyp"] / H)


def pixel_grid(W, H):
    py, px = np.mgrid[0:H, 0:W].astype(float)
    return px, py, (px + .5) / W * 2 - 1, 1 - (py + .5) / H * 2  # CameraView::screenX/Y


def unproject(c, depth, W, H):
    fx, fy, cx, cy = ndc_params(c, W, H)
    _, _, sx, sy = pixel_grid(W, H)
    vx, vy = (sx - cx) * depth / fx, (sy - cy) * depth / fy
    return (c["pos"] + vx[..., None] * c["right"] + vy[..., None] * c["up"]
            + depth[..., None] * c["fwd"])


def project(c, P, W, H):  # CameraView::projectOffset: continuous pixels, centres at +0.5
    fx, fy, cx, cy = ndc_params(c, W, H)
    rel = P - c["pos"]
    z = rel @ c["fwd"]
    sx, sy = fx * (rel @ c["right"]) / z + cx, fy * (rel @ c["up"]) / z + cy
    return (sx + 1) * .5 * W, (1 - sy) * .5 * H


L = {f: load(f) for f in FRAMES}
J = {f: json.load(open(f"{D}/{NAME}.{f:04d}.exr.camera.json")) for f in FRAMES}
H, W = L[1][VL + "Depth.Z"].shape
print(f"{D}: {W}x{H}, frames {FRAMES}, {len(L[1])} channels")

# The room (cm): plane name -> (inward normal, axis, coordinate)
PLANES = {"floor": ((0, 0, 1), 2, 0.0), "ceiling": ((0, 0, -1), 2, 200.0),
          "back": ((0, -1, 0), 1, 100.0), "left (red)": ((1, 0, 0), 0, -100.0),
          "right (green)": ((-1, 0, 0), 0, 100.0)}
BOX_CENTRE, BOX_YAW = np.array([35.0, 20.0, 30.0]), math.radians(20.0)

# ------------------------------------------------------------------ depth
f = 2
Lf, c = L[f], cam(J[f])
d = Lf[VL + "Depth.Z"]
sky = d >= 1e9
check(np.all(d[sky] == 1e10), "sky depth is 1e10")
print(f"\nDepth (frame {f}): {sky.sum()} sky pixels, all Depth.Z = {np.unique(d[sky])}")
N = np.stack([Lf[VL + "Normal." + a] for a in "XYZ"], -1)
fx, fy, cx, cy = ndc_params(c, W, H)
px, py, sx, sy = pixel_grid(W, H)
ray_per_depth = np.sqrt(((sx - cx) / fx) ** 2 + ((sy - cy) / fy) ** 2 + 1)
depth_cm = np.where(sky, 0, d) * 100.0
P = unproject(c, depth_cm, W, H)
P_if_ray = unproject(c, depth_cm / ray_per_depth, W, H)
on_any = np.zeros_like(sky)
for n, ax, val in PLANES.values():
    on_any |= np.abs(P[..., ax] - val) < 0.5
near_box = np.abs(P - BOX_CENTRE).max(-1) < 45
on = {}
for nm, (n, ax, val) in PLANES.items():
    m = (~sky) & (np.abs(N - np.array(n)).max(-1) < 1e-3)
    if nm == "floor":
        m &= P[..., 2] < 30  # not the box top
    ep, er = np.abs(P[..., ax][m] - val), np.abs(P_if_ray[..., ax][m] - val)
    print(f"  {nm:14s} {m.sum():4d} px: distance from the plane, Depth as planar depth: max "
          f"{ep.max():.4f} cm | as ray distance: max {er.max():.2f} cm")
    check(ep.max() < 0.01, f"{nm}: planar depth within 0.01 cm")
    others = np.zeros_like(sky)
    for o, (_, oax, oval) in PLANES.items():
        if o != nm:
            others |= np.abs(P[..., oax] - oval) < 2.0
    on[nm] = (~sky) & (np.abs(P[..., ax] - val) < 0.5) & ~others & ~near_box
m = (~sky) & (np.abs(N - np.array((0, -1, 0))).max(-1) < 1e-3)
ys, xs = np.nonzero(m)
expected = (100.0 - c["pos"][1]) / 100.0
for lab, i in (("centre", np.argmin((xs - W / 2) ** 2 + (ys - H / 2) ** 2)),
               ("corner", np.argmax((xs - W / 2) ** 2 + (ys - H / 2) ** 2))):
    y, x = ys[i], xs[i]
    print(f"  back wall {lab} pixel ({x},{y}): Depth.Z {d[y, x]:.5f} BU; planar depth "
          f"{expected:.5f}; ray distance {expected * ray_per_depth[y, x]:.5f}")

# ------------------------------------------------------------------ normals
print(f"\nNormal (frame {f}):")
nl = np.linalg.norm(N, axis=-1)
print(f"  {(np.abs(nl[~sky] - 1) > 1e-3).sum()} of {(~sky).sum()} surface pixels not unit "
      f"(min |N| {nl[~sky].min():.3f}: samples on two faces); sky: max |N| {nl[sky].max():.3g}")
for nm, (n, ax, val) in PLANES.items():
    err = np.abs(N[on[nm]] - np.array(n)).max()
    print(f"  {nm:14s} {on[nm].sum():4d} px: max |N - {n}| = {err:.1e}")
    check(err < 1e-5, f"{nm}: world normal")
a = BOX_YAW
box_normals = [np.array(v, float) for v in (
    (math.cos(a), math.sin(a), 0), (-math.sin(a), math.cos(a), 0),
    (-math.cos(a), -math.sin(a), 0), (math.sin(a), -math.cos(a), 0), (0, 0, 1))]
box = (~sky) & near_box & ~on_any & (np.abs(nl - 1) < 1e-3)
err = np.min(np.stack([np.abs(N - bn).max(-1) for bn in box_normals]), 0)[box].max()
print(f"  box            {box.sum():4d} px: max distance to a rotated-cube face normal {err:.1e}")
check(err < 1e-5, "box normals")
facing = ((c["pos"] - P) * N).sum(-1)
print(f"  N . (camera - P) > 0 on {(facing[~sky] > 0).sum()} of {(~sky).sum()} surface pixels")
check(np.all(facing[~sky] > 0), "normals face the camera")

# ------------------------------------------------------------------ Vector
print("\nVector (pixels; framepass Velocity = to the previous position, +Y down):")
worst = 0.0
for f in FRAMES:
    Lf, c, cp = L[f], cam(J[f]), cam(J[f]["previous"])
    d = Lf[VL + "Depth.Z"]
    sky = d >= 1e9
    Pf = unproject(c, np.where(sky, 1, d) * 100.0, W, H)
    px, py, _, _ = pixel_grid(W, H)
    qx, qy = project(cp, Pf, W, H)
    vel = np.stack([qx - (px + .5), qy - (py + .5)], -1)[~sky]
    V = np.stack([Lf[VL + "Vector." + k] for k in "XYZW"], -1)[~sky]
    rows = {"(X, -Y)": np.stack([V[:, 0], -V[:, 1]], -1), "(X, Y)": V[:, :2],
            "(-X, Y)": np.stack([-V[:, 0], V[:, 1]], -1), "(Z, -W)": np.stack([V[:, 2], -V[:, 3]], -1)}
    errs = {k: np.linalg.norm(v - vel, axis=-1).max() for k, v in rows.items()}
    worst = max(worst, errs["(X, -Y)"])
    print(f"  frame {f}: expected |v| {np.linalg.norm(vel, axis=-1).min():.3f}.."
          f"{np.linalg.norm(vel, axis=-1).max():.3f} px; max error of " +
          ", ".join(f"{k} {e:.4f}" for k, e in errs.items()))
    if f + 1 in J:
        nx, ny = project(cam(J[f + 1]), Pf, W, H)
        to_next = np.stack([nx - (px + .5), ny - (py + .5)], -1)[~sky]
        e = np.linalg.norm(np.stack([-V[:, 2], V[:, 3]], -1) - to_next, axis=-1).max()
        print(f"  frame {f}: motion to frame {f + 1} = (-Z, W): max error {e:.4f}")
        check(e < 0.01, f"frame {f}: (-Z, W) is the motion to the next frame")
print(f"  Velocity = (Vector.X, -Vector.Y): max error over all frames {worst:.4f} px")
check(worst < 0.01, "Velocity = (X, -Y) within 0.01 px")

# ------------------------------------------------------------------ AOVs
Lf = L[2]
sky = Lf[VL + "Depth.Z"] >= 1e9
print("\nAOVs (frame 2): max |value - material value|")
BC = np.stack([Lf[VL + "BaseColor." + k] for k in "RGB"], -1)
DC = np.stack([Lf[VL + "DiffCol." + k] for k in "RGB"], -1)
Me, Ro, Sp = (Lf[VL + k + ".X"] for k in ("Metallic", "Roughness", "Specular"))
EXPECT = {"floor": ((0.8, 0.8, 0.8), 0, 0.8, 0.5), "back": ((0.8, 0.8, 0.8), 0, 0.8, 0.5),
          "ceiling": ((0.8, 0.8, 0.8), 0, 0.5, 0.5),  # Diffuse BSDF: export defaults
          "left (red)": ((0.63, 0.065, 0.05), 0, 0.8, 0.5),
          "right (green)": ((0.14, 0.45, 0.091), 0, 0.8, 0.5)}
masks = dict(on)
masks["box"] = box
EXPECT["box"] = ((0.7, 0.6, 0.3), 0.25, 0.35, 0.5)  # Base Color, Roughness through links
for nm, (bc, me, ro, sp) in EXPECT.items():
    m = masks[nm]
    e = [np.abs(BC[m] - bc).max(), np.abs(Me[m] - me).max(), np.abs(Ro[m] - ro).max(),
         np.abs(Sp[m] - sp).max(), np.abs(DC[m] - BC[m] * (1 - Me[m])[:, None]).max()]
    print(f"  {nm:14s} BaseColor {e[0]:.1e} Metallic {e[1]:.1e} Roughness {e[2]:.1e} "
          f"Specular {e[3]:.1e}; DiffCol - BaseColor*(1-Metallic) {e[4]:.1e}")
    check(max(e) < 1e-5, f"{nm}: AOVs")

# ------------------------------------------------------------------ sky / emission
E = np.stack([Lf[VL + "Emit." + k] for k in "RGB"], -1)
Env = np.stack([Lf[VL + "Env." + k] for k in "RGB"], -1)
C = np.stack([Lf[VL + "Combined." + k] for k in "RGB"], -1)
print(f"\nSky (frame 2): Env there {Env[sky].min(0)}..{Env[sky].max(0)}, on surfaces max "
      f"{Env[~sky].max():.3g}; Emit max {E.max():.3g}; max |Combined - (Emit + Env)| on sky "
      f"{np.abs(C[sky] - (E + Env)[sky]).max():.1e}")
check(np.allclose(Env[sky], (0.05, 0.07, 0.1), atol=1e-6), "Env = world colour on sky")
check(np.abs(C[sky] - (E + Env)[sky]).max() < 1e-6, "Combined = Emit + Env on sky")

print("\nall checks passed" if not failures else f"\n{len(failures)} check(s) failed")
sys.exit(1 if failures else 0)
