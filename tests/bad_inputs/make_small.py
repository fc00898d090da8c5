#!/usr/bin/env python3
"""Regenerates the committed glTF cases of the bad-input corpus under files/gltf/.

    make_small.py

Each case is base.gltf (one lit triangle) with one mistake, and a scene JSON of the same name
that points `framepass capture` at it. Run it after changing a case; commit what it writes.
"""
import base64
import copy
import json
import os
import struct

FILES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "files")
HERE = os.path.join(FILES, "gltf")

positions = struct.pack("<9f", -1, -1, 0, 1, -1, 0, 0, 1, 0)
normals = struct.pack("<9f", 0, 0, 1, 0, 0, 1, 0, 0, 1)
indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
blob = positions + normals + indices
BASE = {
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 1, 1], "intensity": 100000}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0},
              {"translation": [0, 0, 300], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "meshes": [{"name": "tri", "primitives": [
        {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
         "min": [-1, -1, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 36},
        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
        {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}


def case(name, edit, camera=None):
    g = copy.deepcopy(BASE)
    edit(g)
    with open(os.path.join(HERE, name + ".gltf"), "w") as f:
        json.dump(g, f, indent=1)
    scene = {"geometry": name + ".gltf",
             "camera": camera or {"position": [0, 0, 500], "target": [0, 0, 0],
                                  "fovYDegrees": 40}}
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        json.dump(scene, f, indent=1)


def setter(path, value):
    def edit(g):
        obj = g
        for k in path[:-1]:
            obj = obj[k]
        obj[path[-1]] = value
    return edit


def light(**fields):
    return setter(["extensions", "KHR_lights_punctual", "lights", 0], {"type": "point", **fields})


def main():
    os.makedirs(HERE, exist_ok=True)
    case("base", lambda g: None)
    case("light_no_color", light(intensity=100000))
    case("light_index", setter(["nodes", 1, "extensions", "KHR_lights_punctual", "light"], 4))
    case("light_type", light(type="area", color=[1, 1, 1]))
    case("light_color_negative", light(color=[1, -1, 1]))
    case("light_spot_angles", light(type="spot", spot={"innerConeAngle": 1.0,
                                                        "outerConeAngle": 0.5}))
    case("accessor_count_wrap", setter(["accessors", 0, "count"], 6148914691236517206))
    case("accessor_past_end", setter(["accessors", 0, "count"], 1000))
    case("accessor_index", setter(["meshes", 0, "primitives", 0, "attributes", "POSITION"], 9))
    case("indices_index", setter(["meshes", 0, "primitives", 0, "indices"], 9))
    case("mesh_index", setter(["nodes", 0, "mesh"], 7))
    case("node_index", setter(["scenes", 0, "nodes"], [0, 5]))
    case("child_index", setter(["nodes", 0, "children"], [9]))
    case("scene_index", setter(["scene"], 3))
    case("bufferview_index", setter(["accessors", 0, "bufferView"], 4))
    case("buffer_index", setter(["bufferViews", 0, "buffer"], 2))
    case("bufferview_outside", setter(["bufferViews", 0, "byteOffset"], 1 << 40))
    case("camera_index", setter(["nodes", 0, "camera"], 3))
    case("material_index", setter(["meshes", 0, "primitives", 0, "material"], 9))
    case("node_cycle", lambda g: (g["nodes"].append({"children": [3]}),
                                  g["nodes"].append({"children": [2]}),
                                  g["scenes"][0]["nodes"].append(2)))
    case("node_self_cycle", setter(["nodes", 0, "children"], [0]))
    case("two_parents", lambda g: (g["nodes"].append({"children": [0]}),
                                   g["nodes"].append({"children": [0]})))
    case("index_value", lambda g: g["buffers"][0].update(
        uri="data:application/octet-stream;base64," + base64.b64encode(
            positions + normals + struct.pack("<3H", 0, 1, 60000) + b"\0\0").decode()))
    case("stride", setter(["bufferViews", 0, "byteStride"], 4096))
    case("normal_count", setter(["accessors", 1, "count"], 2))
    case("zero_scale", setter(["nodes", 0, "scale"], [0, 0, 0]))
    case("camera_yfov0", lambda g: (g.update(cameras=[{"type": "perspective", "perspective":
                                                        {"yfov": 0, "znear": 1}}]),
                                    g["nodes"].append({"camera": 0, "translation": [0, 0, 500]}),
                                    g["scenes"][0]["nodes"].append(2)), camera=None)
    case("emissive_strength", lambda g: g["materials"][0].update(extensions={
        "KHR_materials_emissive_strength": {"emissiveStrength": "bright"}}))
    case("base_color_short", setter(["materials", 0, "pbrMetallicRoughness", "baseColorFactor"],
                                    [0.5]))
    # The glTF camera case needs the scene to take the glTF's camera: drop the scene's own.
    with open(os.path.join(HERE, "camera_yfov0.json"), "w") as f:
        json.dump({"geometry": "camera_yfov0.gltf"}, f, indent=1)
    with open(os.path.join(HERE, "not_json.gltf"), "w") as f:
        f.write("{ this is not glTF")
    with open(os.path.join(HERE, "not_json.json"), "w") as f:
        json.dump({"geometry": "not_json.gltf",
                   "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "fovYDegrees": 40}}, f)


def sidecars():
    """Camera sidecars, each good but for one field (files/cam/NAME.camera.json)."""
    d = os.path.join(FILES, "cam")
    os.makedirs(d, exist_ok=True)
    ident = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    good = {"cameraToWorld": ident, "axes": "opengl", "fovYDegrees": 40, "near": 10,
            "sceneUnitsPerMeter": 100}
    good["previous"] = dict(good)
    cases = {
        "good": {},
        "fov0": {"fovYDegrees": 0},
        "fov180": {"fovYDegrees": 180},
        "fovx_negative": {"fovYDegrees": None, "fovXDegrees": -30},
        "fov_string": {"fovYDegrees": "40"},
        "near0": {"near": 0},
        "near_string": {"near": "10"},
        "units_string": {"sceneUnitsPerMeter": "100"},
        "units_zero": {"sceneUnitsPerMeter": 0},
        "axes_number": {"axes": 3},
        "axes_unknown": {"axes": "directx"},
        "matrix_string": {"cameraToWorld": ident[:3] + ["0"] + ident[4:]},
        "matrix_short": {"cameraToWorld": ident[:9]},
        "matrix_singular": {"cameraToWorld": [0] * 16},
        "matrix_huge": {"cameraToWorld": [1e308] * 16},
        "fx_zero": {"fovYDegrees": None, "fxPixels": 0, "fyPixels": 0, "cxPixels": 4,
                    "cyPixels": 4},
        "fx_string": {"fovYDegrees": None, "fxPixels": "8", "fyPixels": 8, "cxPixels": 4,
                      "cyPixels": 4},
        "previous_fov0": {"previous": dict(good, fovYDegrees=0)},
        "previous_not_object": {"previous": [1, 2]},
        "target_is_position": {"cameraToWorld": None, "position": [0, 0, 0],
                               "target": [0, 0, 0]},
        "rotation_string": {"cameraToWorld": None, "position": [0, 0, 0],
                            "rotation": {"pitch": "0", "yaw": 0, "roll": 0}, "fovXDegrees": 60},
    }
    for name, edit in cases.items():
        cam = dict(good)
        for k, v in edit.items():
            if v is None:
                cam.pop(k, None)
            else:
                cam[k] = v
        with open(os.path.join(d, name + ".camera.json"), "w") as f:
            json.dump(cam, f, indent=1)
    with open(os.path.join(d, "not_object.camera.json"), "w") as f:
        f.write("[1, 2, 3]\n")
    with open(os.path.join(d, "broken.camera.json"), "w") as f:
        f.write('{"fovYDegrees": 40,\n')


if __name__ == "__main__":
    main()
    sidecars()
