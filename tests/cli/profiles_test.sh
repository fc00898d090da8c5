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
config() {  # config NAME CAPTURE PROFILE
    echo "{ \"version\": 1, \"capture\": \"$2\", \"profile\": \"$3\", \"camera\": \"cam.####.json\", \"frames\": \"1-2\" }" > "$1"
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
check "--profile on the command line overrides the config's" bash -c "'$FP' plan mrq.json --profile canonical 2>&1 | grep -q 'SceneDepth'; test \${PIPESTATUS[0]} = 2"
oiiotool -i shot0002_Metallic.exr -o shot0002_Velocity.exr
check "inspect names the dump files the profile leaves out, and why" bash -c "'$FP' inspect shot0002 --profile ue-bufvis | grep -q \"not read: shot0002_Velocity.exr (the _Velocity material's encoding is not documented\""
check "inspect a buffer dump by any of its files, with the profile's buffers" bash -c "'$FP' inspect shot0002_BaseColor.exr --profile ue-bufvis > bv.txt && grep -q 'SceneDepth *← SceneDepthWorldUnits:R' bv.txt && grep -q 'WorldNormal *← WorldNormal:R WorldNormal:G WorldNormal:B' bv.txt"

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
