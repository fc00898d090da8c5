# export_gbuffer.py - render a Blender scene as a framepass capture (profile "blender").
#
#   blender -b scene.blend --python export_gbuffer.py -- --out DIR
#           [--frames 1-3] [--width W --height H] [--samples N] [--name NAME]
#           [--filter-width PX] [--denoise on|off]
#
# Writes, for every frame N:
#   DIR/<name>.NNNN.exr              multilayer OpenEXR, float32, ZIP (lossless), view layer
#                                    "ViewLayer": Combined, Depth, Normal, Vector, DiffCol,
#                                    GlossCol, Emit, Env and the AOVs BaseColor, Metallic,
#                                    Roughness, Specular (read with configs/profiles/blender.json)
#   DIR/<name>.NNNN.exr.camera.json  framepass's camera sidecar (this frame and frame N-1)
# and once:
#   DIR/scene.obj + scene.mtl        render-visible geometry at the first frame, centimetres
#   DIR/scene.json                   framepass scene file: geometry, camera, lights, materials
#   DIR/config.json                  a framepass run config for the capture:
#                                    framepass run DIR/config.json
#
# <name> defaults to the .blend's file name. The .blend itself is never saved: every change
# below (passes, AOV nodes, render settings) lives only in this Blender process.
#
# Conventions (verified on tests/fixtures/blender, see its README.md):
#   * World: Blender's world axes unchanged (Z up), scaled to centimetres, framepass's
#     sceneUnitsPerMeter = 100. One Blender unit is scene.unit_settings.scale_length metres, so
#     every position/length is multiplied by K = 100 * scale_length. Directions and normals are
#     unchanged.
#   * Camera: Blender cameras look down local -Z with +Y up, framepass's "opengl" axes.
#     Intrinsics come from Object.calc_matrix_camera (sensor fit, lens shift, pixel aspect).
#   * The Depth pass is in Blender units; the blender profile multiplies it by 100, which is
#     right for scale_length = 1 only. For other scale lengths the run config this script
#     writes (DIR/config.json) replaces the profile's SceneDepth inline, and the script says so.
#   * Pixel filter: Cycles writes Depth from ONE sample per pixel and averages Normal, Vector
#     and the AOVs over all samples. framepass treats every GBuffer pixel as the surface at the
#     pixel centre (as a rasteriser without MSAA writes it), so by default the filter width is
#     set to Cycles' minimum, 0.01 px: every sample then goes through the pixel centre and all
#     passes describe the same point. --filter-width 1.5 restores Blender's default (smooth
#     beauty, blended GBuffer edges).
#   * Light: Cycles' world (background) lights the scene, so Combined (SceneColor) holds its
#     light; framepass's scene 'sky' is a backdrop that lights nothing. Cycles 3.4 lamps are not
#     seen by camera rays, so they are in no pass directly.
import math
import os
import re
import sys
import json

import bpy

PROG = "export_gbuffer"
VIEW_LAYER_NAME = "ViewLayer"  # the profile's channel prefix
AOV_COLOR = ["BaseColor"]
AOV_VALUE = ["Metallic", "Roughness", "Specular"]
DEFAULTS = {"BaseColor": (0.8, 0.8, 0.8), "Metallic": 0.0, "Roughness": 0.5, "Specular": 0.5}
# Principled BSDF socket names per AOV (Blender 4.x renamed Specular to Specular IOR Level).
SOCKETS = {"BaseColor": ["Base Color"], "Metallic": ["Metallic"], "Roughness": ["Roughness"],
           "Specular": ["Specular", "Specular IOR Level"]}
AOV_TAG = "framepass_aov"  # label of the nodes this script adds


class ExportError(Exception):
    pass


def log(msg):
    print(f"{PROG}: {msg}", flush=True)


def warn(msg):
    print(f"{PROG}: warning: {msg}", flush=True)


# ------------------------------------------------------------------------------------ arguments

def parse_frames(spec):
    """'5', '1-3', '1-10x2', '1,3,7-9' -> sorted list of frame numbers."""
    frames = []
    for part in spec.split(","):
        part = part.strip()
        m = re.fullmatch(r"(-?\d+)(?:-(-?\d+)(?:x(\d+))?)?", part)
        if not m:
            raise ExportError(f"--frames: cannot read '{part}' (use 5, 1-3, 1-10x2 or 1,3,5)")
        a = int(m.group(1))
        b = int(m.group(2)) if m.group(2) is not None else a
        step = int(m.group(3) or 1)
        if b < a or step < 1:
            raise ExportError(f"--frames: empty range '{part}'")
        frames.extend(range(a, b + 1, step))
    return sorted(set(frames))


def format_frames(frames):
    """[1, 2, 3, 7] -> '1-3,7' (framepass/oiiotool frame spec)."""
    parts, i = [], 0
    while i < len(frames):
        j = i
        while j + 1 < len(frames) and frames[j + 1] == frames[j] + 1:
            j += 1
        parts.append(str(frames[i]) if i == j else f"{frames[i]}-{frames[j]}")
        i = j + 1
    return ",".join(parts)


def parse_args(argv):
    import argparse
    p = argparse.ArgumentParser(prog=PROG, description="Render a framepass capture from Blender.")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--frames", help="frames, e.g. 1-3 (default: the scene's frame range)")
    p.add_argument("--width", type=int, help="width in pixels (default: the scene's)")
    p.add_argument("--height", type=int, help="height in pixels (default: the scene's)")
    p.add_argument("--samples", type=int, help="Cycles samples per pixel (default: the scene's)")
    p.add_argument("--name", help="file name stem (default: the .blend's name)")
    p.add_argument("--filter-width", type=float, default=0.01,
                   help="Cycles pixel filter width in pixels (default 0.01: pixel-centre GBuffer)")
    p.add_argument("--denoise", choices=["on", "off"],
                   help="Cycles denoiser on the Combined pass (default: the scene's setting)")
    return p.parse_args(argv)


# ------------------------------------------------------------------------------------ helpers

def units_scale(scene):
    """K: framepass scene units (cm) per Blender unit."""
    s = scene.unit_settings.scale_length
    return 100.0 * (s if s > 0.0 else 1.0)


def render_visible(ob, view_layer):
    return (not ob.hide_render) and ob.visible_get(view_layer=view_layer)


def camera_json(scene, depsgraph, cam_ob, width, height, K):
    """framepass camera (io/CameraIO.cpp cameraViewFromJson) for the current frame."""
    cam = cam_ob.data
    if cam.type != 'PERSP':
        raise ExportError(f"camera '{cam_ob.name}' is {cam.type}; framepass needs a perspective camera")
    r = scene.render
    # OpenGL-style projection (column vectors): clip = P * (x, y, z, 1) in camera space, w = -z.
    # ndc_x = P00 * x/(-z) - P02, so in framepass's terms (ndc.x = fx * x/depth + cx):
    # fx = P00, cx = -P02, fy = P11, cy = -P12.
    P = cam_ob.calc_matrix_camera(depsgraph, x=width, y=height,
                                  scale_x=r.pixel_aspect_x, scale_y=r.pixel_aspect_y)
    fx, fy = P[0][0], P[1][1]
    cx, cy = -P[0][2], -P[1][2]
    # cameraViewFromJson: fx = 2 fxPixels / W, cx = 2 cxPixels / W - 1,
    #                     fy = 2 fyPixels / H, cy = 1 - 2 cyPixels / H  (pixel y down).
    fx_px = 0.5 * fx * width
    fy_px = 0.5 * fy * height
    cx_px = 0.5 * (cx + 1.0) * width
    cy_px = 0.5 * (1.0 - cy) * height
    M = cam_ob.matrix_world
    cols = []
    for c in range(3):
        v = M.col[c].to_3d()
        if v.length == 0.0:
            raise ExportError(f"camera '{cam_ob.name}' has a zero scale")
        cols.append(v.normalized())
    t = M.col[3].to_3d() * K
    m16 = [cols[0][0], cols[1][0], cols[2][0], t[0],
           cols[0][1], cols[1][1], cols[2][1], t[1],
           cols[0][2], cols[1][2], cols[2][2], t[2],
           0.0, 0.0, 0.0, 1.0]
    return {"cameraToWorld": [float(x) for x in m16], "axes": "opengl",
            "fxPixels": fx_px, "fyPixels": fy_px, "cxPixels": cx_px, "cyPixels": cy_px,
            "near": cam.clip_start * K}


# ------------------------------------------------------------------------------------ AOVs

def active_output(nt):
    outs = [n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    for n in outs:
        if n.is_active_output and n.target in {'ALL', 'CYCLES'}:
            return n
    for n in outs:
        if n.target in {'ALL', 'CYCLES'}:
            return n
    return outs[0] if outs else None


def upstream(nt, socket):
    """Nodes feeding `socket`, breadth first (through mix shaders, reroutes, ...)."""
    seen, order, queue = set(), [], [socket]
    while queue:
        s = queue.pop(0)
        for link in s.links if s.is_linked else []:
            n = link.from_node
            if n.name in seen:
                continue
            seen.add(n.name)
            order.append(n)
            queue.extend(i for i in n.inputs if i.is_linked)
    return order


def find_input(node, names):
    for name in names:
        if name in node.inputs:
            return node.inputs[name]
    return None


def socket_value(sock):
    """Constant value of an input socket: its default, or an RGB/Value node it is linked from.
    Returns (value, exact)."""
    if sock.is_linked:
        link = sock.links[0]
        n = link.from_node
        if n.bl_idname in {"ShaderNodeRGB", "ShaderNodeValue"}:
            return link.from_socket.default_value, True
        return (sock.default_value if hasattr(sock, "default_value") else None), False
    return sock.default_value, True


def add_aov_node(nt, name, is_color, x, y):
    n = nt.nodes.new("ShaderNodeOutputAOV")
    n.label = f"{AOV_TAG}_{name}"
    if hasattr(n, "aov_name"):  # Blender >= 4
        n.aov_name = name
    else:  # Blender 2.92-3.x: the node's 'name' property is the AOV name
        n.name = name
    n.location = (x, y)
    return n, n.inputs["Color" if is_color else "Value"]


def feed(nt, sock_in, target, fallback):
    """Link `target` from whatever feeds `sock_in`, or set it to sock_in's value / fallback."""
    if sock_in is not None and sock_in.is_linked:
        nt.links.new(sock_in.links[0].from_socket, target)
        return
    value = sock_in.default_value if sock_in is not None else fallback
    if target.type == 'RGBA':
        rgb = tuple(value)[:3] if not isinstance(value, float) else (value,) * 3
        target.default_value = (*rgb, 1.0)
    else:
        target.default_value = float(value if isinstance(value, float) else value[0])


def instrument_material(mat, report):
    """Add AOV Output nodes writing BaseColor, Metallic, Roughness, Specular."""
    if not mat.use_nodes:
        # Cycles shades a node-less material as a Diffuse BSDF of its diffuse_color: build
        # exactly that tree so the AOVs can be attached.
        mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.clear()
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = tuple(mat.diffuse_color)
        o = nt.nodes.new("ShaderNodeOutputMaterial")
        nt.links.new(d.outputs[0], o.inputs["Surface"])
    nt = mat.node_tree
    for n in [n for n in nt.nodes if n.label.startswith(AOV_TAG)]:
        nt.nodes.remove(n)
    out = active_output(nt)
    feeding = upstream(nt, out.inputs["Surface"]) if out else []
    bsdf = next((n for n in feeding if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)
    if bsdf is None:  # a Principled BSDF anywhere in the tree (e.g. an unplugged one) is no use
        diffuse = next((n for n in feeding if n.bl_idname == "ShaderNodeBsdfDiffuse"), None)
        if any(n.bl_idname == "ShaderNodeGroup" for n in feeding):
            warn(f"material '{mat.name}': shader inside a node group; writing default AOVs")
        x0, y0 = (out.location.x, out.location.y - 300) if out else (0, 0)
        for i, name in enumerate(AOV_COLOR + AOV_VALUE):
            _, target = add_aov_node(nt, name, name in AOV_COLOR, x0, y0 - 120 * i)
            src = find_input(diffuse, ["Color"]) if (diffuse and name == "BaseColor") else None
            feed(nt, src, target, DEFAULTS[name])
        report.append((mat.name, "defaults" + (" + diffuse colour" if diffuse else "")))
        return None
    if sum(1 for n in feeding if n.bl_idname == "ShaderNodeBsdfPrincipled") > 1:
        warn(f"material '{mat.name}': several Principled BSDFs; the AOVs follow '{bsdf.name}'")
    for i, name in enumerate(AOV_COLOR + AOV_VALUE):
        _, target = add_aov_node(nt, name, name in AOV_COLOR,
                                 bsdf.location.x + 400, bsdf.location.y - 300 - 120 * i)
        feed(nt, find_input(bsdf, SOCKETS[name]), target, DEFAULTS[name])
    linked = [n for n in AOV_COLOR + AOV_VALUE
              if (s := find_input(bsdf, SOCKETS[n])) is not None and s.is_linked]
    report.append((mat.name, "principled" + (f" (linked: {', '.join(linked)})" if linked else "")))
    return bsdf


def material_params(mat, bsdf):
    """framepass scene.json material override (constants; textures cannot be represented)."""
    out, approx = {}, []
    if bsdf is not None:
        for key, names, kind in (("baseColor", ["Base Color"], "rgb"),
                                 ("metallic", ["Metallic"], "f"),
                                 ("specular", SOCKETS["Specular"], "f"),
                                 ("roughness", ["Roughness"], "f")):
            s = find_input(bsdf, names)
            if s is None:
                continue
            v, exact = socket_value(s)
            if not exact:
                approx.append(names[0])
            out[key] = [round(float(c), 6) for c in tuple(v)[:3]] if kind == "rgb" \
                else round(float(v), 6)
        es = find_input(bsdf, ["Emission"]) or find_input(bsdf, ["Emission Color"])
        ss = find_input(bsdf, ["Emission Strength"])
        if es is not None:
            ev, e_exact = socket_value(es)
            sv, s_exact = socket_value(ss) if ss is not None else (1.0, True)
            em = [float(c) * float(sv) for c in tuple(ev)[:3]]
            if not (e_exact and s_exact):
                approx.append("Emission")
            if any(c != 0.0 for c in em):
                out["emission"] = [round(c, 6) for c in em]
    else:
        nt = mat.node_tree
        d = next((n for n in nt.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse"), None) if nt else None
        if d is not None:
            v, exact = socket_value(d.inputs["Color"])
            if not exact:
                approx.append("Color")
            out["baseColor"] = [round(float(c), 6) for c in tuple(v)[:3]]
        else:
            out["baseColor"] = list(DEFAULTS["BaseColor"])
        out.update(metallic=DEFAULTS["Metallic"], specular=DEFAULTS["Specular"],
                   roughness=DEFAULTS["Roughness"])
    return out, approx


def setup_aovs(view_layer):
    for name in AOV_COLOR + AOV_VALUE:
        aov = next((a for a in view_layer.aovs if a.name == name), None)
        if aov is None:
            aov = view_layer.aovs.add()
            aov.name = name
        aov.type = 'COLOR' if name in AOV_COLOR else 'VALUE'


def default_material():
    m = bpy.data.materials.get("framepass_default")
    if m is None:
        m = bpy.data.materials.new("framepass_default")
        m.diffuse_color = (0.8, 0.8, 0.8, 1.0)
        m.use_nodes = False  # instrument_material gives it Cycles' default diffuse tree
    return m


# ------------------------------------------------------------------------------------ lights

def light_json(ob, K):
    """Blender light -> framepass light (io/SceneLoader.cpp parseLight).

    Units, measured in Cycles 3.4 on a white Lambert plane lit directly (numbers in
    tests/fixtures/blender/README.md), the area light's also against Cycles' kernel
    (light/area.h: eval_fac = 0.25 * invarea) and in the fixture room (pi x DiffDir equals
    framepass's rect irradiance from the exported light within 0.03 % RMS):
      POINT  power P [W]: radiant intensity I = P / (4 pi) [W/sr per Blender unit^2].
             framepass point 'intensity' is I with distances in scene units (irradiance
             I cos/r^2, r in cm), so intensity = P / (4 pi) * K^2. (A point with radius r is
             a disk in Cycles: on-axis E = I/(d^2 + r^2); framepass uses I/d^2 and r only for
             soft shadows.)
      SPOT   same I = P / (4 pi) * K^2 on the axis. Cycles 3.4 additionally multiplies by
             cos(angle off axis) and a smoothstep blend; framepass's (Unreal's) spot mask is
             saturate((cos - cosOuter)/(cosInner - cosOuter))^2 with no cosine term, so off
             axis the two differ (e.g. x0.87 at 30 deg). outer = spot_size/2,
             inner = acos(cosOuter + (1 - cosOuter) * spot_blend).
      SUN    strength S [W/m^2] is the irradiance: directional intensity = S (unit-free).
      AREA   power P over the light's world area A (Blender units^2, object scale included;
             disk/ellipse: A = pi/4 * sx * sy): one-sided radiance L = P / (4 A). Radiance
             does not depend on length units, so rect intensity = P / (4 A). (A Lambertian
             emitter of radiance L sends pi L A = pi P / 4 watts: Cycles' "watts" for area
             lights are not radiometric watts, hence 4 and not pi.) Disks/ellipses become
             rects of the same area and radiance (half extents x sqrt(pi)/2).
    Colour: framepass 'color' = the light's colour; 'intensity' carries the power.
    """
    L = ob.data
    M = ob.matrix_world
    pos = M.translation * K
    down = -(M.col[2].to_3d())
    down = down.normalized() if down.length > 0 else down
    j = {"name": ob.name, "color": [round(float(c), 6) for c in L.color]}
    if getattr(L, "use_nodes", False) and L.node_tree is not None:
        warn(f"light '{ob.name}' uses nodes: only its colour and power are exported")
    if L.type == 'POINT':
        j.update(type="point", position=list(pos), intensity=L.energy / (4 * math.pi) * K * K,
                 radius=L.shadow_soft_size * K)
    elif L.type == 'SPOT':
        outer = 0.5 * L.spot_size
        cos_outer = math.cos(outer)
        inner = math.acos(min(1.0, cos_outer + (1.0 - cos_outer) * L.spot_blend))
        j.update(type="spot", position=list(pos), direction=list(down),
                 intensity=L.energy / (4 * math.pi) * K * K, radius=L.shadow_soft_size * K,
                 outerConeDegrees=math.degrees(outer), innerConeDegrees=math.degrees(inner))
    elif L.type == 'SUN':
        j.update(type="directional", direction=list(down), intensity=L.energy,
                 sourceAngleDegrees=math.degrees(L.angle))
    elif L.type == 'AREA':
        sx = L.size
        sy = L.size_y if L.shape in {'RECTANGLE', 'ELLIPSE'} else L.size
        ax, ay = M.col[0].to_3d(), M.col[1].to_3d()
        area = ax.cross(ay).length * sx * sy  # Blender units^2, object scale included
        f = 0.5
        if L.shape in {'DISK', 'ELLIPSE'}:
            area *= math.pi / 4.0
            f = 0.5 * math.sqrt(math.pi) / 2.0
            warn(f"light '{ob.name}': {L.shape.lower()} area light exported as a rect of equal area")
        if getattr(L, "spread", math.pi) < math.pi - 1e-6:
            warn(f"light '{ob.name}': spread {math.degrees(L.spread):.0f} deg is not exported "
                 "(framepass rect lights emit over the full hemisphere)")
        if area <= 0.0:
            warn(f"light '{ob.name}': zero area, skipped")
            return None
        # framepass emits along halfU x halfV: X x (-Y) = -Z, the direction Blender's area
        # light shines.
        half_u = ax * (sx * f * K)
        half_v = -ay * (sy * f * K)
        j.update(type="rect", position=list(pos), halfU=list(half_u), halfV=list(half_v),
                 intensity=L.energy / (4.0 * area))
    else:
        warn(f"light '{ob.name}': type {L.type} not exported")
        return None
    for k, v in list(j.items()):  # (+ 0.0 turns -0.0 into 0.0)
        if isinstance(v, list):
            j[k] = [round(float(x), 6) + 0.0 for x in v]
        elif isinstance(v, float):
            j[k] = round(v, 6) + 0.0
    return j


def world_sky(scene):
    w = scene.world
    if w is None:
        return [0.0, 0.0, 0.0]
    if not w.use_nodes or w.node_tree is None:
        return [round(float(c), 6) for c in w.color]
    nt = w.node_tree
    out = next((n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputWorld" and n.is_active_output),
               None) or next((n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputWorld"), None)
    if out is None or not out.inputs["Surface"].is_linked:
        return [0.0, 0.0, 0.0]
    bg = out.inputs["Surface"].links[0].from_node
    if bg.bl_idname != "ShaderNodeBackground":
        warn("world shader is not a plain Background: scene.json gets no 'sky'")
        return None
    c, ce = socket_value(bg.inputs["Color"])
    s, se = socket_value(bg.inputs["Strength"])
    if not (ce and se):
        warn("world background is textured: scene.json gets no 'sky' (the capture's Env pass has it)")
        return None
    return [round(float(x) * float(s), 6) for x in tuple(c)[:3]]


# ------------------------------------------------------------------------------------ geometry

def export_obj(context, scene, view_layer, path, K):
    visible = [ob for ob in scene.objects if render_visible(ob, view_layer)
               and ob.type in {'MESH', 'CURVE', 'SURFACE', 'META', 'FONT'}]
    # Select exactly the render-visible objects: the exporter's use_selection=False would take
    # every object of the scene, hidden ones included.
    for ob in scene.objects:
        ob.select_set(False)
    for ob in visible:
        ob.select_set(True)
    if visible:
        view_layer.objects.active = visible[0]
    res = bpy.ops.export_scene.obj(filepath=path, check_existing=False, use_selection=True,
                                   use_animation=False, use_mesh_modifiers=True,
                                   use_normals=True, use_uvs=False, use_materials=True,
                                   use_triangles=True, use_blen_objects=True,
                                   group_by_object=False, path_mode='AUTO',
                                   axis_forward='Y', axis_up='Z', global_scale=K)
    if 'FINISHED' not in res:
        raise ExportError(f"OBJ export failed: {res}")
    # Check the axes really stay Blender's: the OBJ's bounding box must be the evaluated
    # objects' world bounding box times K.
    depsgraph = context.evaluated_depsgraph_get()
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for ob in visible:
        ev = ob.evaluated_get(depsgraph)
        try:
            me = ev.to_mesh()
        except RuntimeError:
            continue
        for v in me.vertices:
            w = ev.matrix_world @ v.co
            for i in range(3):
                lo[i], hi[i] = min(lo[i], w[i] * K), max(hi[i], w[i] * K)
        ev.to_mesh_clear()
    olo, ohi = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                xyz = [float(t) for t in line.split()[1:4]]
                for i in range(3):
                    olo[i], ohi[i] = min(olo[i], xyz[i]), max(ohi[i], xyz[i])
    if visible:
        err = max(max(abs(a - b) for a, b in zip(lo, olo)), max(abs(a - b) for a, b in zip(hi, ohi)))
        size = max(1e-9, max(h - l for l, h in zip(lo, hi)))
        if err > 1e-4 * size + 1e-3:
            raise ExportError(f"OBJ axes check failed: Blender bbox {lo}..{hi} cm, OBJ {olo}..{ohi}")
        log(f"OBJ axes check: bbox matches Blender's world bbox x{K:g} within {err:.2g} scene units")
    return visible


def mtl_names(path):
    names = []
    if os.path.exists(path):
        with open(path) as f:
            names = [line.split(None, 1)[1].strip() for line in f if line.startswith("newmtl ")]
    return names


def name_compat(name):  # io_scene_obj's material name mangling
    return "None" if name is None else name.replace(" ", "_")


# ------------------------------------------------------------------------------------ main

def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    context = bpy.context
    scene = context.scene
    view_layer = context.view_layer

    cam_ob = scene.camera
    if cam_ob is None or cam_ob.type != 'CAMERA':
        raise ExportError(f"scene '{scene.name}' has no camera: set one (Scene Properties > Camera)")

    out_dir = os.path.abspath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    name = args.name or (os.path.splitext(os.path.basename(bpy.data.filepath))[0] or "capture")
    frames = parse_frames(args.frames) if args.frames else \
        list(range(scene.frame_start, scene.frame_end + 1, max(1, scene.frame_step)))
    K = units_scale(scene)

    # ---- render settings
    r = scene.render
    r.engine = 'CYCLES'
    if args.width:
        r.resolution_x = args.width
    if args.height:
        r.resolution_y = args.height
    r.resolution_percentage = 100
    W, H = r.resolution_x, r.resolution_y
    r.use_border = False
    r.use_motion_blur = False  # the Vector pass needs it off
    r.use_compositing = False  # raw render passes, untouched
    r.use_sequencer = False
    if args.samples:
        scene.cycles.samples = args.samples
    scene.cycles.filter_width = max(0.01, args.filter_width)
    if args.denoise:
        scene.cycles.use_denoising = args.denoise == "on"
    if scene.cycles.use_denoising and scene.cycles.denoiser != 'OPTIX':
        try:
            import _cycles
            has_oidn = bool(getattr(_cycles, "with_openimagedenoise", True))
        except ImportError:
            has_oidn = True
        if not has_oidn:  # e.g. Debian's Blender: rendering would stop with an error
            if args.denoise == "on":
                raise ExportError("--denoise on: this Blender is built without OpenImageDenoise")
            warn("this Blender has no OpenImageDenoise: denoising turned off")
            scene.cycles.use_denoising = False
    if abs(scene.cycles.film_exposure - 1.0) > 1e-6:
        warn(f"Cycles film exposure is {scene.cycles.film_exposure:g}: it scales Cycles' light passes (Combined, ...) "
             "but not the lights written to scene.json")
    im = r.image_settings
    im.file_format = 'OPEN_EXR_MULTILAYER'
    im.color_depth = '32'
    im.exr_codec = 'ZIP'
    if hasattr(im, "use_preview"):
        im.use_preview = False
    r.use_file_extension = True

    # ---- one view layer, named as the profile expects
    for vl in scene.view_layers:
        vl.use = vl == view_layer
    if view_layer.name != VIEW_LAYER_NAME:
        other = scene.view_layers.get(VIEW_LAYER_NAME)
        if other is not None:
            other.name = VIEW_LAYER_NAME + "_unused"
        log(f"view layer '{view_layer.name}' renamed to '{VIEW_LAYER_NAME}' for this export")
        view_layer.name = VIEW_LAYER_NAME
    view_layer.use = True
    for attr in ("use_pass_combined", "use_pass_z", "use_pass_normal", "use_pass_vector",
                 "use_pass_diffuse_color", "use_pass_glossy_color", "use_pass_emit",
                 "use_pass_environment", "use_pass_object_index"):
        setattr(view_layer, attr, True)
    setup_aovs(view_layer)
    # InstanceId: Cycles' Object Index pass (IndexOB) with every drawn object numbered 1, 2, …
    # in name order, so ray-traced passes can tell an object from its neighbour.
    drawn = sorted((ob for ob in scene.objects
                    if ob.type in {'MESH', 'CURVE', 'SURFACE', 'META', 'FONT'}
                    and render_visible(ob, view_layer)), key=lambda ob: ob.name)
    for index, ob in enumerate(drawn, start=1):
        ob.pass_index = index
    log(f"object index pass: {len(drawn)} objects numbered 1..{len(drawn)}")

    # ---- materials: every object drawn gets a material with the AOV outputs
    for ob in scene.objects:
        if ob.type in {'MESH', 'CURVE', 'SURFACE', 'META', 'FONT'} and render_visible(ob, view_layer):
            if len(ob.material_slots) == 0 and hasattr(ob.data, "materials"):
                ob.data.materials.append(default_material())
            for slot in ob.material_slots:
                if slot.material is None:
                    slot.material = default_material()
    report, bsdfs = [], {}
    for mat in bpy.data.materials:
        if mat.users == 0 or mat.is_grease_pencil:
            continue
        bsdfs[mat.name] = instrument_material(mat, report)
    for mname, how in report:
        log(f"material '{mname}': AOVs from {how}")

    # ---- geometry, lights, materials, scene.json at the first frame
    scene.frame_set(frames[0])
    obj_path = os.path.join(out_dir, "scene.obj")
    export_obj(context, scene, view_layer, obj_path, K)
    depsgraph = context.evaluated_depsgraph_get()
    lights = []
    for ob in scene.objects:
        if ob.type == 'LIGHT' and render_visible(ob, view_layer):
            j = light_json(ob, K)
            if j is not None:
                lights.append(j)
    materials = {}
    by_compat = {name_compat(m.name): m for m in bpy.data.materials}
    for mtl in mtl_names(os.path.join(out_dir, "scene.mtl")):
        mat = by_compat.get(mtl)
        if mat is None:
            warn(f"scene.mtl material '{mtl}' has no Blender material of that name")
            continue
        params, approx = material_params(mat, bsdfs.get(mat.name))
        if approx:
            warn(f"material '{mat.name}': {', '.join(approx)} textured/driven; scene.json holds "
                 "the socket's default (the capture's AOVs hold the real values)")
        materials[mtl] = params
    cam_first = camera_json(scene, depsgraph, cam_ob, W, H, K)
    scene.frame_set(frames[0] - 1)
    cam_prev = camera_json(scene, context.evaluated_depsgraph_get(), cam_ob, W, H, K)
    scene.frame_set(frames[0])
    scene_json = {
        "version": 1,
        "description": f"exported from Blender {bpy.app.version_string} by export_gbuffer.py "
                       f"('{os.path.basename(bpy.data.filepath) or 'unsaved'}', frame {frames[0]}); "
                       "Blender world axes (Z up) in centimetres",
        "geometry": "scene.obj",
        "sceneUnitsPerMeter": 100,
        "resolution": [W, H],
        "camera": cam_first,
        "previousCamera": cam_prev,
        "lights": lights,
        "materials": materials,
    }
    sky = world_sky(scene)
    if sky is not None:
        scene_json["sky"] = sky
    with open(os.path.join(out_dir, "scene.json"), "w") as f:
        json.dump(scene_json, f, indent=2)
        f.write("\n")
    log(f"wrote scene.json ({len(lights)} lights, {len(materials)} materials), scene.obj, scene.mtl")

    # ---- a run config for this capture: framepass run DIR/config.json
    profile = "blender"
    if abs(scene.unit_settings.scale_length - 1.0) > 1e-9:
        # The profile's depth scale (x100) assumes 1 Blender unit = 1 m: replace its SceneDepth
        # (PrevSceneDepth follows, being SceneDepth of frame N-1).
        profile = {"base": "blender", "buffers": {"SceneDepth": {
            "channels": [f"{VIEW_LAYER_NAME}.Depth.Z"], "scale": float(f"{K:.7g}"), "skyAbove": 1e9,
            "doc": f"Blender units x {K:g} (scale_length {scene.unit_settings.scale_length:g})"}}}
        warn(f"unit scale_length is {scene.unit_settings.scale_length:g}: the blender profile's "
             f"depth scale (x100) does not fit this capture; {out_dir}/config.json carries an "
             f"inline profile with depth x{K:g}: use it, or copy its \"profile\"")
    config = {"version": 1,
              "description": f"framepass run config for the Blender capture '{name}' "
                             "(written by export_gbuffer.py)",
              "capture": f"{name}.####.exr", "frames": format_frames(frames),
              "profile": profile, "scene": "scene.json"}
    with open(os.path.join(out_dir, "config.json"), "w") as fh:
        json.dump(config, fh, indent=2)
        fh.write("\n")

    # ---- frames
    for i, f in enumerate(frames):
        scene.frame_set(f - 1)
        prev = camera_json(scene, context.evaluated_depsgraph_get(), cam_ob, W, H, K)
        scene.frame_set(f)
        cur = camera_json(scene, context.evaluated_depsgraph_get(), cam_ob, W, H, K)
        cur["sceneUnitsPerMeter"] = 100
        cur["previous"] = prev  # frame f-1: what Blender's Vector pass measures against
        log(f"frame {f} ({i + 1}/{len(frames)}): rendering {W}x{H}, "
            f"{scene.cycles.samples} samples")
        # A still render does not expand '#', so each frame gets its own explicit path.
        r.filepath = os.path.join(out_dir, f"{name}.{f:04d}")
        path = r.filepath + ".exr"
        if os.path.exists(path):
            os.remove(path)
        bpy.ops.render.render(write_still=True)
        if not os.path.exists(path):
            raise ExportError(f"Blender did not write {path}")
        with open(path + ".camera.json", "w") as fh:
            json.dump(cur, fh, indent=2)
            fh.write("\n")
        log(f"frame {f} ({i + 1}/{len(frames)}): wrote {path} and {os.path.basename(path)}.camera.json")
    log(f"done: {len(frames)} frame(s) in {out_dir}")


if __name__ == "__main__":
    try:
        main()
    except ExportError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr, flush=True)
        sys.exit(1)
    except Exception as e:  # noqa: BLE001 - any failure must end Blender with a non-zero code
        import traceback
        traceback.print_exc()
        print(f"{PROG}: error: {e}", file=sys.stderr, flush=True)
        sys.exit(1)
