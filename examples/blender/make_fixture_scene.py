# Builds framepass's Blender test scene from factory startup and saves it as a .blend:
# a small Cornell-like room (metres, Blender's Z up) lit by one area light under the ceiling,
# seen by a camera that moves 4-7 cm along +X and 1-3 cm up (+Z) per frame over frames 1-3.
#
#   blender -b --factory-startup --python-exit-code 1 -P make_fixture_scene.py -- OUT.blend
#
# examples/blender/make_fixture.sh runs this, then export_gbuffer.py on the saved file.
# The scene deliberately covers the export script's cases:
#   - Principled BSDFs with plain socket values (walls, floor),
#   - a Principled BSDF whose Base Color and Roughness are LINKED (from an RGB and a Value node:
#     the box), so the AOVs must follow the links,
#   - a material without a Principled BSDF (ceiling: a Diffuse BSDF), which gets the defaults,
#   - a lens shift (shift_y), so the intrinsics must carry the off-centre principal point,
#   - sky pixels (the room's open front), for the depth sky threshold and the Env pass,
#   - vertical as well as horizontal camera motion, so both signs of the Vector pass show.
import math
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) != 1:
    print("usage: blender -b --factory-startup -P make_fixture_scene.py -- OUT.blend")
    sys.exit(2)
out_blend = argv[0]

scene = bpy.context.scene
for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob, do_unlink=True)
for block in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
    for item in list(block):
        block.remove(item)

scene.unit_settings.system = 'METRIC'
scene.unit_settings.scale_length = 1.0  # 1 Blender unit = 1 m

# ---------------------------------------------------------------- materials

def principled(name, base, roughness=0.8, metallic=0.0, specular=0.5):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Specular"].default_value = specular
    m.diffuse_color = (*base, 1.0)
    return m


white = principled("white", (0.8, 0.8, 0.8))
red = principled("red", (0.63, 0.065, 0.05))
green = principled("green", (0.14, 0.45, 0.091))

# Ceiling: no Principled BSDF at all (the export script falls back to defaults + diffuse colour).
ceiling = bpy.data.materials.new("ceiling_diffuse")
ceiling.use_nodes = True
nt = ceiling.node_tree
nt.nodes.remove(nt.nodes["Principled BSDF"])
diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
nt.links.new(diffuse.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])

# Box: Base Color and Roughness come through links (an RGB node and a Value node).
box_mat = principled("box", (0.0, 0.0, 0.0), roughness=0.0, metallic=0.25, specular=0.5)
nt = box_mat.node_tree
bsdf = nt.nodes["Principled BSDF"]
rgb = nt.nodes.new("ShaderNodeRGB")
rgb.outputs[0].default_value = (0.7, 0.6, 0.3, 1.0)
val = nt.nodes.new("ShaderNodeValue")
val.outputs[0].default_value = 0.35
nt.links.new(rgb.outputs[0], bsdf.inputs["Base Color"])
nt.links.new(val.outputs[0], bsdf.inputs["Roughness"])

# ---------------------------------------------------------------- geometry (metres)
# Room: x in [-1, 1], y in [-1, 1] (open front at y = -1), z in [0, 2]. Quads face inwards.

def quad(name, verts, mat):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], [(0, 1, 2, 3)])
    me.materials.append(mat)
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


quad("floor", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], white)           # +Z
quad("ceiling", [(-1, -1, 2), (-1, 1, 2), (1, 1, 2), (1, -1, 2)], ceiling)        # -Z
quad("back", [(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)], white)               # -Y
quad("left", [(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)], red)             # +X
quad("right", [(1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0)], green)              # -X

bpy.ops.mesh.primitive_cube_add(size=0.6, location=(0.35, 0.2, 0.3),
                                rotation=(0.0, 0.0, math.radians(20.0)))
box = bpy.context.object
box.name = "box"
box.data.materials.append(box_mat)

# ---------------------------------------------------------------- light
light = bpy.data.lights.new("ceiling_light", 'AREA')
light.shape = 'RECTANGLE'
light.size = 0.5      # local X extent, m
light.size_y = 0.4    # local Y extent, m
light.energy = 50.0   # W (Cycles: radiance = P / (4 A))
light.color = (1.0, 0.9, 0.8)
light_ob = bpy.data.objects.new("ceiling_light", light)
light_ob.location = (0.0, 0.1, 1.98)  # identity rotation: emits down (-Z)
scene.collection.objects.link(light_ob)

# ---------------------------------------------------------------- world (sky)
world = bpy.data.worlds.new("sky")
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (0.05, 0.07, 0.1, 1.0)
bg.inputs["Strength"].default_value = 1.0
scene.world = world

# ---------------------------------------------------------------- camera
cam = bpy.data.cameras.new("camera")
cam.lens = 35.0
cam.sensor_fit = 'AUTO'
cam.sensor_width = 36.0
cam.shift_y = 0.05
cam.clip_start = 0.1
cam.clip_end = 100.0
cam_ob = bpy.data.objects.new("camera", cam)
scene.collection.objects.link(cam_ob)
scene.camera = cam_ob
cam_ob.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # looks along +Y, +Z up
# Keyed at every frame 0-4 (frame 0 is frame 1's "previous", frame 4 frame 3's "next", both of
# which Blender's Vector pass measures against). The steps differ from frame to frame, so motion
# towards the previous frame and towards the next one can be told apart:
# x steps 4, 5, 6, 7 cm; z steps 2, 1, 3, 2 cm.
CAMERA_PATH = {0: (-0.04, 0.98), 1: (0.0, 1.0), 2: (0.05, 1.01), 3: (0.11, 1.04), 4: (0.18, 1.06)}
for f, (x, z) in CAMERA_PATH.items():
    cam_ob.location = (x, -3.0, z)
    cam_ob.keyframe_insert("location", frame=f)
for fc in cam_ob.animation_data.action.fcurves:
    for kp in fc.keyframe_points:
        kp.interpolation = 'LINEAR'

# ---------------------------------------------------------------- render settings
scene.frame_start, scene.frame_end = 1, 3
scene.render.engine = 'CYCLES'
scene.cycles.device = 'CPU'
scene.cycles.samples = 32
scene.cycles.use_adaptive_sampling = False
scene.cycles.use_denoising = False
scene.cycles.seed = 0
scene.cycles.use_animated_seed = False
scene.render.resolution_x = 64
scene.render.resolution_y = 64
scene.render.resolution_percentage = 100
scene.render.use_motion_blur = False
# No date, render time or file name in the EXR headers (the .blend lives in a temporary folder).
scene.render.use_stamp_date = False
scene.render.use_stamp_time = False
scene.render.use_stamp_render_time = False
scene.render.use_stamp_filename = False

scene.frame_set(1)
bpy.ops.wm.save_as_mainfile(filepath=out_blend, compress=False)
print(f"make_fixture_scene: wrote {out_blend}")
