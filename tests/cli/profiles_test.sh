#!/usr/bin/env bash
# End-to-end checks of capture profiles: a framepass capture rewritten (with oiiotool) in Unreal
# Movie Render Queue's layout and as Unreal buffer-visualisation dumps runs through the chain with
# --profile ue-mrq / ue-bufvis and gives the same bytes both ways; and the traps that used to give
# wrong pixels with exit 0 are errors or warnings. Usage: profiles_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
source "$(cd "$(dirname "$0")" && pwd)/checks.sh"
FP="$1"; SRC="$2"; DIR="$3/profiles"
rm -rf "$DIR"; mkdir -p "$DIR"; DIR="$(cd "$DIR" && pwd)"; cd "$DIR"

# A 2-frame canonical capture and its camera as a sidecar every layout shares.
check "capture a 2-frame sequence" "$FP" capture "$SRC/examples/cornell/scene.json" -o seq.####.exr --frames 1-2 --width 48 --height 48
sidecar() {  # sidecar CAPTURE OUT: the capture's camera (and previous camera) as a sidecar
    "$FP" inspect "$1" --json | python3 -c '
import json, sys
c = json.load(sys.stdin)["camera"]
keys = ("position", "forward", "up", "fovYDegrees", "near")
s = {k: c[k] for k in keys}
s["sceneUnitsPerMeter"] = c["sceneUnitsPerMeter"]
s["previous"] = {k: c["previous"][k] for k in keys}
json.dump(s, open(sys.argv[1], "w"))' "$2"
}
# One capture file in Movie Render Queue's layout: FinalImage unnamed, MRQ's WorldDepth layer and
# FP_<Buffer> post-process material layers.
to_mrq() {  # to_mrq IN OUT TYPE
    local f="$1"
    oiiotool -i "$f" --subimage SceneColor --ch R=SceneColor.R,G=SceneColor.G,B=SceneColor.B \
        -i "$f" --subimage SceneDepth --ch FinalImageMovieRenderQueue_WorldDepth.R=SceneDepth.Z --chappend \
        -i "$f" --subimage WorldNormal --ch FinalImageFP_WorldNormal.R=WorldNormal.X,FinalImageFP_WorldNormal.G=WorldNormal.Y,FinalImageFP_WorldNormal.B=WorldNormal.Z --chappend \
        -i "$f" --subimage BaseColor --ch FinalImageFP_BaseColor.R=BaseColor.R,FinalImageFP_BaseColor.G=BaseColor.G,FinalImageFP_BaseColor.B=BaseColor.B --chappend \
        -i "$f" --subimage Metallic --ch FinalImageFP_Metallic.R=Metallic.Y --chappend \
        -i "$f" --subimage Roughness --ch FinalImageFP_Roughness.R=Roughness.Y --chappend \
        -i "$f" --subimage Specular --ch FinalImageFP_Specular.R=Specular.Y --chappend \
        -i "$f" --subimage GBufferAO --ch FinalImageFP_AO.R=GBufferAO.Y --chappend \
        -d "$3" -o "$2"
}
# One capture as buffer-visualisation dumps: <base>_<Material>.exr, each plain R, G, B.
to_bufvis() {  # to_bufvis IN BASE
    local f="$1" b="$2"
    oiiotool -i "$f" --subimage SceneDepth --ch R=SceneDepth.Z -o "${b}_SceneDepthWorldUnits.exr" &&
    oiiotool -i "$f" --subimage WorldNormal --ch R=WorldNormal.X,G=WorldNormal.Y,B=WorldNormal.Z -o "${b}_WorldNormal.exr" &&
    oiiotool -i "$f" --subimage BaseColor --ch R=BaseColor.R,G=BaseColor.G,B=BaseColor.B -o "${b}_BaseColor.exr" &&
    oiiotool -i "$f" --subimage SceneColor --ch R=SceneColor.R,G=SceneColor.G,B=SceneColor.B -o "${b}_PreTonemapHDRColor.exr" &&
    oiiotool -i "$f" --subimage Metallic --ch R=Metallic.Y -o "${b}_Metallic.exr" &&
    oiiotool -i "$f" --subimage Roughness --ch R=Roughness.Y -o "${b}_Roughness.exr" &&
    oiiotool -i "$f" --subimage Specular --ch R=Specular.Y -o "${b}_Specular.exr" &&
    oiiotool -i "$f" --subimage GBufferAO --ch R=GBufferAO.Y -o "${b}_MaterialAO.exr"
}
for f in 1 2; do
    check "frame $f: sidecar, MRQ (float, half) and buffer-dump layouts" bash -c "$(declare -f sidecar to_mrq to_bufvis); FP='$FP'
        sidecar seq.000$f.exr cam.000$f.json && to_mrq seq.000$f.exr mrq.000$f.exr float && to_mrq seq.000$f.exr mrqh.000$f.exr half && to_bufvis seq.000$f.exr shot000$f"
done
config() {  # config NAME CAPTURE PROFILE: the Cornell box is in millimetres, Unreal's layouts in cm
    echo "{ \"version\": 1, \"capture\": \"$2\", \"profile\": { \"base\": \"$3\", \"sceneUnitsPerMeter\": 1000 }, \"camera\": \"cam.####.json\", \"frames\": \"1-2\" }" > "$1"
}
config mrq.json "mrq.####.exr" ue-mrq
config mrqh.json "mrqh.####.exr" ue-mrq
config bufvis.json "shot####" ue-bufvis
check "plan reads MRQ's layers and frame N-1's FinalImage" bash -c "'$FP' plan mrq.json --json > plan_mrq.json && grep -q 'FinalImageMovieRenderQueue_WorldDepth.R' plan_mrq.json && grep -q 'frame N-1 SceneColor' plan_mrq.json"
check "run the SSGI chain on the MRQ layout" bash -c "'$FP' run mrq.json -o out_mrq --report mrq_report.json 2> mrq.err && test -f out_mrq/indirect.0002.exr && grep -q 'frame N-1 R' mrq_report.json"
check "the first frame has no history and says so" grep -q "frame 1: no previous frame" mrq.err
check "run the same chain on the buffer dumps; the report lists every file read" bash -c "'$FP' run bufvis.json -o out_bufvis --report bv_report.json && grep -q 'shot0002_SceneDepthWorldUnits.exr' bv_report.json && grep -q '\"previous frame capture\"' bv_report.json && grep -q 'cam.0002.json' bv_report.json"
check "MRQ layout and buffer dumps give the same bytes" diff -r out_mrq out_bufvis
check "a half-float MRQ capture runs and warns about half depth, once" bash -c "'$FP' run mrqh.json -o out_mrqh > mrqh.log 2>&1 && [ \$(grep -c 'is half float' mrqh.log) = 1 ] && test -f out_mrqh/indirect.0002.exr"
check "--profile on the command line overrides the config's" expect_exit 2 "the capture has no 'SceneDepth' buffer" "$FP" plan mrq.json --profile canonical
oiiotool -i shot0002_Metallic.exr -o shot0002_Velocity.exr
check "inspect names the dump files the profile leaves out, and why" bash -c "'$FP' inspect shot0002 --profile ue-bufvis | grep -q \"not read: shot0002_Velocity.exr (the _Velocity material's encoding is not documented\""
check "inspect a buffer dump by any of its files, with the profile's buffers" bash -c "'$FP' inspect shot0002_BaseColor.exr --profile ue-bufvis > bv.txt && grep -q 'SceneDepth *← SceneDepthWorldUnits:R' bv.txt && grep -q 'WorldNormal *← WorldNormal:R WorldNormal:G WorldNormal:B' bv.txt"

# Unreal G-buffer datasets (ue-dataset): <Scene><Buffer>.<NNNN>.exr with depth in cm × 1e-4,
# motion as (current − previous) pixels with +y up, and the camera as Unreal's row-vector
# matrices in <Scene>Matrix.<NNNN>.txt, one per frame (no previous camera in it).
to_dataset() {  # to_dataset IN FRAME: frame FRAME of the canonical capture in the dataset layout
    local f="$1" n="$2"
    oiiotool -i "$f" --subimage SceneDepth --ch R=SceneDepth.Z --mulc 0.0001 -o "dsSceneDepth.$n.exr" &&
    oiiotool -i "$f" --subimage WorldNormal --ch R=WorldNormal.X,G=WorldNormal.Y,B=WorldNormal.Z -o "dsWorldNormal.$n.exr" &&
    oiiotool -i "$f" --subimage BaseColor --ch R=BaseColor.R,G=BaseColor.G,B=BaseColor.B -o "dsBaseColor.$n.exr" &&
    oiiotool -i "$f" --subimage SceneColor --ch R=SceneColor.R,G=SceneColor.G,B=SceneColor.B -o "dsPreTonemapHDRColor.$n.exr" &&
    oiiotool -i "$f" --subimage Metallic --ch R=Metallic.Y -o "dsMetallic.$n.exr" &&
    oiiotool -i "$f" --subimage Roughness --ch R=Roughness.Y -o "dsRoughness.$n.exr" &&
    oiiotool -i "$f" --subimage Specular --ch R=Specular.Y -o "dsSpecular.$n.exr" &&
    oiiotool -i "$f" --subimage Velocity --ch R=Velocity.X,G=Velocity.Y --mulc -1,1 -o "dsMotionVector.$n.exr" &&
    "$FP" inspect "$f" --json | python3 -c '
import json, sys
c = json.load(sys.stdin)["camera"]
p, f, u = c["position"], c["forward"], c["up"]
r = [f[1]*u[2] - f[2]*u[1], f[2]*u[0] - f[0]*u[2], f[0]*u[1] - f[1]*u[0]]  # forward × up
dot = lambda a, b: sum(x * y for x, y in zip(a, b))
fy = 1 / __import__("math").tan(__import__("math").radians(c["fovYDegrees"]) / 2)
fx = fy * c["height"] / c["width"]
view = [[r[0], u[0], f[0], 0], [r[1], u[1], f[1], 0], [r[2], u[2], f[2], 0], [-dot(r, p), -dot(u, p), -dot(f, p), 1]]
proj = [[fx, 0, 0, 0], [0, fy, 0, 0], [0, 0, 0, 1], [0, 0, c["near"], 0]]
m = lambda rows: "".join("[" + " ".join(repr(float(v)) for v in row) + "] " for row in rows)
open(sys.argv[1], "w").write("ClipToView: " + m([[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]) + "\nViewMatrix: " + m(view) +
    "\nProjectionMatrix: " + m(proj) + "\nFOV: 90\nNearClipDistance: " + repr(c["near"]) + "\nFarClipDistance: 0\n")' "dsMatrix.$n.txt"
}
check "frames 1-2 in the Unreal G-buffer dataset layout" bash -c "$(declare -f to_dataset); FP='$FP'; to_dataset seq.0001.exr 0001 && to_dataset seq.0002.exr 0002"
# Depth: ×1e-4 in float32 and back is within 2 ulps at 5 m (0.0001 cm).
check "ue-dataset: depth in Unreal's units comes back in cm (RMSE ≤ 0.001 cm)" \
    "$FP" compare 'ds{file}.0002.exr' seq.0002.exr --layer SceneDepth --profile ue-dataset --ref-profile canonical --max-rmse 0.001
check "ue-dataset: the motion vectors' sign convention gives framepass's Velocity exactly" \
    "$FP" compare 'ds{file}.0002.exr' seq.0002.exr --layer Velocity --profile ue-dataset --ref-profile canonical --max-rmse 0
cat > ds_velocity.json <<J
{ "version": 1, "capture": "ds{file}.####.exr", "profile": "ue-dataset", "camera": "dsMatrix.####.txt", "frames": "2",
  "passes": [ { "type": "camera_velocity" } ], "outputs": { "v.####.exr": "camera_velocity.velocity" } }
J
# The camera: this frame's matrices and, as last frame's camera, frame 1's file. Reprojection
# through them must give the capture's own motion (float32 velocity: 1e-3 px is ~100 ulps).
check "ue-dataset: the matrix files' cameras reproject as the capture's own motion (RMSE ≤ 0.001 px)" bash -c "'$FP' run ds_velocity.json -o out_ds_v > /dev/null && '$FP' compare out_ds_v/v.0002.exr seq.0002.exr --layer camera_velocity.velocity --ref-layer Velocity --max-rmse 0.001"
echo '{ "version": 1, "capture": "ds{file}.####.exr", "profile": "ue-dataset", "camera": "dsMatrix.####.txt", "frames": "1-2" }' > ds.json
check "ue-dataset: the SSGI chain runs on the dataset layout" bash -c "'$FP' run ds.json -o out_ds > /dev/null && test -f out_ds/indirect.0002.exr"

# The camera inspect shows is the one run uses: a sidecar beside the capture wins over the header.
cp cam.0002.json seq.0002.exr.camera.json
check "inspect reports the sidecar beside the capture, as run would use it" bash -c "'$FP' inspect seq.0002.exr | grep -q 'camera (sidecar .*seq.0002.exr.camera.json)'"
rm seq.0002.exr.camera.json

# Traps that gave wrong pixels with exit 0.
cat > two.json <<J
{ "version": 1, "capture": "seq.0001.exr",
  "profile": { "base": "canonical", "buffers": { "WorldNormal": ["WorldNormal.X", "WorldNormal.Y"] } } }
J
check "a WorldNormal mapped to two channels is an error with its JSON pointer" expect_exit 2 \
    "two.json: /profile/buffers/WorldNormal/channels: WorldNormal has 3 channels (X, Y, Z); this lists 2" "$FP" plan two.json
python3 -c '
import json; c = json.load(open("cam.0001.json")); del c["near"]; del c["sceneUnitsPerMeter"]; del c["previous"]["near"]
json.dump(c, open("bare.0001.json", "w"))'
echo '{ "version": 1, "capture": "seq.0001.exr", "camera": "bare.0001.json" }' > bare.json
check "a sidecar without near or units: a warning naming the assumed values" bash -c "'$FP' run bare.json -o out_bare 2> bare.err && grep -q \"no 'near': assumed 10 cm (10 scene units)\" bare.err && grep -q \"no 'sceneUnitsPerMeter': assumed 100\" bare.err"
check "--strict makes an assumed value an error" expect_exit 2 "--strict: nothing is assumed" "$FP" run bare.json -o out_bare2 --strict
check "compare finds the sky mask through a profile" bash -c "'$FP' compare shot0002_PreTonemapHDRColor.exr shot0002_PreTonemapHDRColor.exr --profile ue-bufvis | grep -q 'sky masked by SceneDepth'"
check "an unknown profile suggests a known one" expect_exit 2 "did you mean 'ue-mrq'?" "$FP" inspect seq.0001.exr --profile ue-mrg

# --- Blender: the fixture rendered by examples/blender/make_fixture.sh (tests/fixtures/blender) ---
BL="$SRC/tests/fixtures/blender"
check "inspect --profile blender: its buffers and the sidecar the export script wrote" bash -c "'$FP' inspect '$BL/room.0002.exr' --profile blender > bl.txt && grep -q 'SceneDepth *← ViewLayer.Depth.Z' bl.txt && grep -q 'Emissive *← ViewLayer.Emit.R ViewLayer.Emit.G ViewLayer.Emit.B ViewLayer.Env.R' bl.txt && grep -q 'camera (sidecar .*room.0002.exr.camera.json)' bl.txt && ! grep -q 'assumed' bl.txt"
check "the SSGI chain runs on the Blender capture alone" bash -c "'$FP' run '$BL/ssgi_only.json' -o bl_ssgi > bl_ssgi.log 2>&1 && test -f bl_ssgi/indirect.0003.exr"
check "the lit chain runs on the Blender capture with the geometry the script exported" bash -c "'$FP' run '$BL/config.json' -o bl_lit --report bl_lit.json > bl_lit.log 2>&1 && test -f bl_lit/lit.0003.exr && test -f bl_lit/shadows.0003.exr && grep -q 'ViewLayer.IndexOB.X' bl_lit.json"
check "sheet of the Blender capture: its buffers through the profile, then the layers none reads" bash -c "'$FP' sheet '$BL/room.0002.exr' --profile blender -o bl_sheet.png --tile 32 --json > bl_sheet.json && python3 -c '
import json; t = {x[\"layer\"]: x for x in json.load(open(\"bl_sheet.json\"))[\"tiles\"]}
assert t[\"SceneDepth\"][\"kind\"] == \"depth\" and t[\"SceneDepth\"][\"range\"][\"min\"] > 100, t[\"SceneDepth\"]  # centimetres
assert t[\"WorldNormal\"][\"kind\"] == \"normal\" and t[\"InstanceId\"][\"kind\"] == \"id\"
assert \"(not read)\" in t[\"ViewLayer.GlossCol\"][\"label\"]
assert \"PrevSceneColor\" not in t and len(t) == 16, sorted(t)'"
# A profile file extends a built-in one ("base"), and a config's profile path resolves against
# the config's folder. Its Truth layer (here Cycles' DiffCol, as a stand-in for a renderer's own
# truth pass) is what compare reads through --ref-profile: that call used to crash (exit 139).
mkdir -p prof_dir
cat > prof_dir/bl_truth.json <<J
{ "version": 1, "base": "blender", "buffers": {
  "Truth.DiffuseIndirectFull": ["ViewLayer.DiffCol.R", "ViewLayer.DiffCol.G", "ViewLayer.DiffCol.B"] } }
J
check "compare reads a Truth layer a profile file maps (it crashed)" bash -c "'$FP' compare '$BL/room.0002.exr' '$BL/room.0002.exr' --layer ViewLayer.DiffCol --profile blender --ref-layer Truth.DiffuseIndirectFull --ref-profile prof_dir/bl_truth.json --json > cmp_truth.json && python3 -c '
import json; j = json.load(open(\"cmp_truth.json\")); assert j[\"pixels\"] > 1000 and j[\"rmse\"] == 0, j'"
cat > prof_dir/bl_ao.json <<J
{ "version": 1, "base": "blender", "buffers": { "Truth.AO": ["ViewLayer.Metallic.X"] } }
J
cat > prof_dir/ao_cfg.json <<J
{ "version": 1, "capture": "$BL/room.####.exr", "frames": "2", "profile": "bl_ao.json",
  "passes": [ { "name": "e", "type": "error_measure", "inputs": { "source": "capture:Metallic", "reference": "capture:Truth.AO" } } ],
  "outputs": { "e.####.exr": "e.absError" } }
J
check "run reads a 1-channel Truth layer a profile maps, as inspect shows it (run refused it)" bash -c "'$FP' inspect '$BL/room.0002.exr' --profile prof_dir/bl_ao.json | grep -q 'Truth.AO *← ViewLayer.Metallic.X' && '$FP' run prof_dir/ao_cfg.json -o prof_dir/ao_out --report - 2>/dev/null | python3 -c '
import json, sys; r = json.load(sys.stdin); m = r[\"frames\"][0][\"passes\"][0][\"metrics\"]; assert m[\"rmse\"] == 0, m'"
check "a profile file with a base keeps the base's other buffers" bash -c "'$FP' inspect '$BL/room.0002.exr' --profile prof_dir/bl_truth.json | grep -q 'SceneDepth *← ViewLayer.Depth.Z'"
echo "{ \"version\": 1, \"capture\": \"$BL/room.####.exr\", \"frames\": \"2\", \"profile\": \"bl_truth.json\" }" > prof_dir/cfg.json
check "a config's profile file resolves against the config's folder" bash -c "cd / && '$FP' plan '$DIR/prof_dir/cfg.json' > /dev/null"
# A Blender user's day: two renders (cur.exr, prev.exr) rather than a numbered sequence; a frame
# whose sidecar has no previous camera; a sidecar in another unit; Combined counted twice.
mkdir -p bl_pair bl_first
cp "$BL/room.0002.exr" bl_pair/cur.exr && cp "$BL/room.0002.exr.camera.json" bl_pair/cur.exr.camera.json
cp "$BL/room.0001.exr" bl_pair/prev.exr && cp "$BL/room.0001.exr.camera.json" bl_pair/prev.exr.camera.json
echo '{ "version": 1, "capture": "cur.exr", "profile": "blender" }' > bl_pair/cfg.json
check "--previous FILE: a lone capture and the frame before it give the sequence's frame 2" bash -c "
    '$FP' run bl_pair/cfg.json --previous bl_pair/prev.exr --frames 2 -o bl_pair/out > bl_pair.log 2>&1 &&
    '$FP' run '$BL/ssgi_only.json' --frames 2 -o bl_seq > /dev/null 2>&1 && cmp bl_pair/out/ssgi.0002.exr bl_seq/ssgi.0002.exr"
echo '{ "version": 1, "capture": "cur.exr", "profile": "blender", "previous": "prev.exr" }' > bl_pair/cfg_prev.json
check "the config key \"previous\" is the same as --previous" bash -c "'$FP' plan bl_pair/cfg_prev.json > /dev/null && '$FP' run bl_pair/cfg_prev.json --frames 2 -o bl_pair/out2 > /dev/null 2>&1 && diff -r bl_pair/out bl_pair/out2"
python3 -c '
import json; c = json.load(open("bl_pair/cur.exr.camera.json")); c.pop("previous")
json.dump(c, open("bl_pair/cur.exr.camera.json", "w"))'
check "a capture whose camera has no previous camera takes it from the previous frame's" bash -c "'$FP' run bl_pair/cfg.json --previous bl_pair/prev.exr --frames 2 -o bl_pair/out3 > bl_pair3.log 2>&1 && '$FP' compare bl_pair/out3/ssgi.0002.exr bl_seq/ssgi.0002.exr --layer ssgi.diffuse --mask none --max-rmse 1e-4"
check "a lone capture with no previous frame says what SSGI loses, and how to give it" bash -c "'$FP' run bl_pair/cfg.json -o bl_pair/alone 2>&1 | grep -q 'find no light on this frame; give the previous frame.s capture with --previous FILE'"
python3 -c '
import json; c = json.load(open("'"$BL"'/room.0001.exr.camera.json")); c.pop("previous", None)
json.dump(c, open("bl_first/room.0001.exr.camera.json", "w"))
c["sceneUnitsPerMeter"] = 1; json.dump(c, open("bl_first/metres.json", "w"))'
cp "$BL/room.0001.exr" bl_first/room.0001.exr
echo '{ "version": 1, "capture": "room.####.exr", "frames": "1", "profile": "blender" }' > bl_first/cfg.json
# Frame 1 of a sequence has no previous camera: the profile's Velocity (Cycles' Vector pass)
# reprojects instead of failing ("no previous camera and no velocity").
check "a first frame with no previous camera reprojects with the capture's velocity" bash -c "'$FP' run bl_first/cfg.json -o bl_first/out > bl_first.log 2>&1 && test -f bl_first/out/ssgi.0001.exr && grep -q 'ViewLayer.Vector.X' <('$FP' run bl_first/cfg.json -o bl_first/out2 --report - 2>/dev/null)"
echo '{ "version": 1, "capture": "room.####.exr", "frames": "1", "profile": "blender", "camera": "metres.json" }' > bl_first/metres_cfg.json
check "a sidecar in metres against the blender profile's centimetres is an error" expect_exit 2 "/sceneUnitsPerMeter is 1, but the capture profile's buffers are in 100 scene units per metre" "$FP" run bl_first/metres_cfg.json -o bl_first/m
check "inspect and the first frame warn that Combined holds the indirect light already" bash -c "'$FP' inspect '$BL/room.0002.exr' --profile blender | grep -q 'warning: SceneColor: SceneColor is Cycles. Combined pass' && grep -q 'counted twice' bl_first.log"
# blender-direct: SceneColor = DiffDir·DiffCol + GlossDir·GlossCol + Emit + Env. The fixture has
# no direct passes; here DiffDir = 2 and GlossDir = 0 everywhere, so SceneColor = 2·DiffCol +
# Emit + Env, which compare computes another way.
check "a capture with Cycles' direct light passes" bash -c "oiiotool '$BL/room.0002.exr' --ch ViewLayer.DiffCol.R,ViewLayer.DiffCol.G,ViewLayer.DiffCol.B --mulc 0 --addc 2 --chnames ViewLayer.DiffDir.R,ViewLayer.DiffDir.G,ViewLayer.DiffDir.B -o dd.exr &&
    oiiotool dd.exr --mulc 0 --chnames ViewLayer.GlossDir.R,ViewLayer.GlossDir.G,ViewLayer.GlossDir.B -o gd.exr &&
    oiiotool '$BL/room.0002.exr' dd.exr --chappend gd.exr --chappend -d float -o direct.exr"
check "blender-direct reads SceneColor as the direct light only" bash -c "'$FP' inspect direct.exr --profile blender-direct | grep -q 'SceneColor *← ViewLayer.DiffDir.R' &&
    oiiotool direct.exr --ch ViewLayer.DiffCol.R,ViewLayer.DiffCol.G,ViewLayer.DiffCol.B --mulc 2 --chnames R,G,B direct.exr --ch ViewLayer.Emit.R,ViewLayer.Emit.G,ViewLayer.Emit.B --chnames R,G,B --add direct.exr --ch ViewLayer.Env.R,ViewLayer.Env.G,ViewLayer.Env.B --chnames R,G,B --add --chnames SceneColor.R,SceneColor.G,SceneColor.B -d float -o expected_direct.exr &&
    '$FP' compare direct.exr expected_direct.exr --layer SceneColor --profile blender-direct --ref-profile canonical --mask none --max-rmse 0"
# framepass's own render of the scene the script exported must see what Cycles saw: the same
# depth, normals and motion, read through the blender profile against the canonical one.
check "framepass captures the exported scene (frame 1)" "$FP" capture "$BL/scene.json" -o canon.exr --width 64 --height 64
# Depth: float32 planar depth at ≤ 5 m (ulp 0.06 mm); 0.001 cm is 16 ulps.
check "Blender's depth equals framepass's render of the exported scene (RMSE ≤ 0.001 cm)" \
    "$FP" compare "$BL/room.0001.exr" canon.exr --layer SceneDepth --profile blender --ref-profile canonical --max-rmse 0.001
# Motion: the profile's sign convention against reprojection through the cameras; Cycles' own
# float maths is off by ≤ 0.005 px (measured by examples/blender/check_fixture.py).
check "Blender's Vector pass is framepass's Velocity (RMSE ≤ 0.01 px)" \
    "$FP" compare "$BL/room.0001.exr" canon.exr --layer Velocity --profile blender --ref-profile canonical --max-rmse 0.01
# Normals: equal on faces; a pixel centre on an edge may average two faces (0.13 % of pixels).
check "Blender's world normals are framepass's (RMSE ≤ 0.01)" \
    "$FP" compare "$BL/room.0001.exr" canon.exr --layer WorldNormal --profile blender --ref-profile canonical --max-rmse 0.01

finish
