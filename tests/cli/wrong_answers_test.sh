#!/usr/bin/env bash
# Inputs that used to give a wrong answer with exit 0, each now converted, refused or reported:
# a scene in other units than its capture (converted when both say their units, an error that
# names the likely cause when they do not line up), an output name without a frame token over
# several frames, an .ini in UTF-8 with a byte-order mark or in UTF-16, a --previous that the
# profile would ignore, reflection figures carried by a reflected light, a memory forecast off the
# process's peak, empty paths, a mistyped option, NaN in compare, plan on a missing capture.
# Usage: wrong_answers_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
source "$(cd "$(dirname "$0")" && pwd)/checks.sh"
FP="$1"; SRC="$2"; DIR="$3/wrong_answers"
rm -rf "$DIR"; mkdir -p "$DIR"; DIR="$(cd "$DIR" && pwd)"
CORNELL="$SRC/examples/cornell"

check "capture the Cornell box (millimetres) at 64×64" "$FP" capture "$CORNELL/scene.json" -o "$DIR/cornell.exr" --width 64 --height 64

# --- 1. Units. The same box written in metres: geometry and lights ×1/1000, and it says so. ---
mkdir -p "$DIR/metres"
awk '$1 == "v" { printf "v %.9g %.9g %.9g\n", $2 / 1000, $3 / 1000, $4 / 1000; next } { print }' \
    "$CORNELL/cornell.obj" > "$DIR/metres/cornell.obj"
cp "$CORNELL/cornell.mtl" "$DIR/metres/"
python3 - "$CORNELL/scene.json" "$DIR/metres" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
for light in scene["lights"]:
    for key in ("position", "halfU", "halfV"):
        light[key] = [v / 1000 for v in light[key]]
scene["sceneUnitsPerMeter"] = 1
json.dump(scene, open(sys.argv[2] + "/declared.json", "w"))
del scene["sceneUnitsPerMeter"]  # undeclared: read as Unreal's 100 per metre
json.dump(scene, open(sys.argv[2] + "/undeclared.json", "w"))
PY
# The millimetre box moved 15 cm up and 30 cm back: another place, as a wrong scene is.
python3 -c "import json, sys; s = json.load(open(sys.argv[1])); s['geometry'] = sys.argv[2]; s['offset'] = [0, 150, 300]; json.dump(s, open(sys.argv[3], 'w'))" \
    "$CORNELL/scene.json" "$CORNELL/cornell.obj" "$DIR/moved_scene.json"
config() {  # config NAME SCENE: the ray-traced chain on the millimetre capture
    printf '{ "version": 1, "engine": "ue4.27-raytracing", "capture": "%s", "scene": "%s" }\n' \
        "$DIR/cornell.exr" "$2" > "$DIR/$1.json"
}
config mm "$CORNELL/scene.json"
config declared "$DIR/metres/declared.json"
config undeclared "$DIR/metres/undeclared.json"
config moved "$DIR/moved_scene.json"
check "the scene in millimetres runs" "$FP" run "$DIR/mm.json" -o "$DIR/mm" --report "$DIR/mm/report.json"
check "a scene declared in metres is converted to the capture's millimetres and says so" \
    expect_exit 0 "the capture in 1000: scaled by 1000" "$FP" run "$DIR/declared.json" -o "$DIR/declared" --report "$DIR/declared/report.json"
# Converted, it traces the same geometry: the lit frame is the millimetre scene's up to the
# float rounding of positions ×1/1000 ×1000 (a shadow ray's hit may flip at an edge: 1e-3).
check "the converted scene lights the frame as the millimetre one" \
    "$FP" compare "$DIR/declared/lit.0001.exr" "$DIR/mm/lit.0001.exr" --max-rmse 1e-3
check "and its shadow rays hit the scene (not zero rays, not an all-black GI)" \
    bash -c "python3 -c \"import json,sys; r=json.load(open('$DIR/declared/report.json')); p=[q for f in r['frames'] for q in f['passes'] if q['name'].startswith('rt_shadows')]; sys.exit(0 if p and p[0]['work']['rays'] > 0 else 1)\""
check "a scene in metres that does not say so is an error naming the units and the setting" \
    expect_exit 2 'Most likely units: scaled by 1000 the scene lines up' "$FP" run "$DIR/undeclared.json" -o "$DIR/undeclared"
check "and names the units to declare" grep -q '"sceneUnitsPerMeter": 1 ' "$DIR/out.log"
check "a scene in another place is an error before any output is written" \
    bash -c "'$FP' run '$DIR/moved.json' -o '$DIR/moved' > '$DIR/moved.log' 2>&1; test \$? = 2 && grep -q 'does not line up with the capture' '$DIR/moved.log' && ! ls '$DIR/moved'/*.exr 2>/dev/null"

# --- 2. Blender's emitters. framepass's capture rewritten in Cycles' layout (ViewLayer.*, its
# Emissive as the Emit pass) and read through the blender profile (depth in the capture's mm). ---
f="$DIR/c128.exr"
check "capture the Cornell box at 128×128 (its light quad seen on the ceiling)" "$FP" capture "$CORNELL/scene.json" -o "$f" --width 128 --height 128
layer() { oiiotool -i "$f" --subimage "$1" --ch "$2" -o "$DIR/bl_$1.exr"; }
layer SceneDepth ViewLayer.Depth.Z=SceneDepth.Z && layer WorldNormal ViewLayer.Normal.X=WorldNormal.X,ViewLayer.Normal.Y=WorldNormal.Y,ViewLayer.Normal.Z=WorldNormal.Z &&
layer BaseColor ViewLayer.BaseColor.R=BaseColor.R,ViewLayer.BaseColor.G=BaseColor.G,ViewLayer.BaseColor.B=BaseColor.B &&
layer SceneColor ViewLayer.Combined.R=SceneColor.R,ViewLayer.Combined.G=SceneColor.G,ViewLayer.Combined.B=SceneColor.B &&
layer Emissive ViewLayer.Emit.R=Emissive.R,ViewLayer.Emit.G=Emissive.G,ViewLayer.Emit.B=Emissive.B &&
layer Velocity ViewLayer.Vector.X=Velocity.X,ViewLayer.Vector.Y=Velocity.Y &&
oiiotool "$DIR"/bl_{SceneDepth,WorldNormal,BaseColor,SceneColor,Emissive,Velocity}.exr --chappend --chappend --chappend --chappend --chappend -o "$DIR/bl.exr" &&
oiiotool "$DIR/bl_Emissive.exr" --ch R=ViewLayer.Emit.R -o "$DIR/emitters.exr"
blender_config() {  # blender_config NAME SHADING_MODEL_MAPPING
    printf '{ "version": 1, "capture": "bl.exr", "previous": "bl.exr", "outputs": { "gi.####.exr": "ssgi.diffuse" },
  "profile": { "base": "blender", "sceneUnitsPerMeter": 1000,
    "buffers": { "SceneDepth": ["ViewLayer.Depth.Z"] %s } } }\n' "$2" > "$DIR/$1.json"
}
blender_config emit ""
blender_config unlit_ignored ', "ShadingModel": { "constant": 1 }'
check "the blender profile runs SSGI on it" "$FP" run "$DIR/emit.json" -o "$DIR/emit"
check "the profile's old mapping (every pixel Default Lit) runs too" "$FP" run "$DIR/unlit_ignored.json" -o "$DIR/unlit_ignored"
oiiotool "$DIR/emit/gi.0001.exr" --mulc 0 -o "$DIR/nogi.exr"
check "the emitting pixels get no GI (Unlit, as in Cycles, whose indirect light there is zero)" \
    bash -c "'$FP' compare '$DIR/emit/gi.0001.exr' '$DIR/nogi.exr' --mask '$DIR/emitters.exr' --max-rmse 0 | grep -Eq ': ([5-9][0-9]|[1-9][0-9]{2,}) pixels \(mask'"
check "where the old mapping wrote GI on them" \
    expect_exit 1 "is above --max-rmse 0" "$FP" compare "$DIR/unlit_ignored/gi.0001.exr" "$DIR/nogi.exr" --mask "$DIR/emitters.exr" --max-rmse 0

# --- 3. An output without a frame token over several frames. ---
check "capture two frames" "$FP" capture "$CORNELL/scene.json" -o "$DIR/seq/c.####.exr" --frames 1-2 --width 32 --height 32
printf '{ "version": 1, "capture": "%s", "outputs": { "x.exr": "ssgi.diffuse" } }\n' "$DIR/seq/c.####.exr" > "$DIR/notoken.json"
check "an output without #### over two frames is refused before the first frame" \
    bash -c "'$FP' run '$DIR/notoken.json' --frames 1-2 -o '$DIR/notoken' > '$DIR/nt.log' 2>&1; test \$? = 2 && grep -q 'name it \"x.####.exr\"' '$DIR/nt.log' && ! test -e '$DIR/notoken/x.exr'"
check "one frame of it is fine" "$FP" run "$DIR/notoken.json" -o "$DIR/notoken1" --frames 2

# --- 4. .ini files as Unreal on Windows writes them. ---
printf '[SystemSettings]\nr.SSGI.Quality=1\n' > "$DIR/plain.ini"
printf '\xef\xbb\xbf[SystemSettings]\r\nr.SSGI.Quality=1\r\n' > "$DIR/bom.ini"
python3 -c "open('$DIR/utf16.ini','wb').write('[SystemSettings]\r\nr.SSGI.Quality=1\r\n'.encode('utf-16'))"
python3 -c "open('$DIR/utf16be.ini','wb').write(b'\xfe\xff' + '[ConsoleVariables]\nr.SSGI.Quality=1\n'.encode('utf-16-be'))"
printf '[/Script/Engine.RendererSettings]\nr.SSGI.Quality=1\n' > "$DIR/none.ini"
printf '{ "version": 1, "capture": "%s" }\n' "$DIR/cornell.exr" > "$DIR/plain.json"
for ini in bom utf16 utf16be; do
    check "a $ini .ini sets its cvar" bash -c "'$FP' plan '$DIR/plain.json' --cvars '$DIR/$ini.ini' --json | grep -q '\"quality\": 1'"
done
check "the plain .ini gives the same plan" bash -c "'$FP' plan '$DIR/plain.json' --cvars '$DIR/plain.ini' --json | grep -q '\"quality\": 1'"
check "an .ini that gives no cvar is a warning with the count" \
    expect_exit 0 "0 cvars read" "$FP" plan "$DIR/plain.json" --cvars "$DIR/none.ini"
check "and an error under --strict" \
    expect_exit 2 "--strict makes this an error" "$FP" run "$DIR/plain.json" --cvars "$DIR/none.ini" --strict -o "$DIR/strict"

# --- 5. --previous with a profile that reads no previous frame. ---
check "--previous with the canonical profile is refused, saying why" \
    expect_exit 2 "reads no buffer from a previous frame's file" "$FP" run "$DIR/plain.json" --previous "$DIR/seq/c.0001.exr" -o "$DIR/prev"
oiiotool --pattern constant:color=1,0,0 4x4 3 -d uint8 -o "$DIR/not_a_capture.png"
printf '{ "version": 1, "capture": "%s", "profile": "blender" }\n' "$SRC/tests/fixtures/blender/room.0002.exr" > "$DIR/blender.json"
check "a --previous that is no capture is refused before a frame" \
    expect_exit 2 "not_a_capture.png" "$FP" run "$DIR/blender.json" --previous "$DIR/not_a_capture.png" -o "$DIR/prev2"
check "a --previous the profile reads is listed in the report's inputs" \
    bash -c "'$FP' run '$DIR/blender.json' --previous '$SRC/tests/fixtures/blender/room.0001.exr' -o '$DIR/prev3' --report '$DIR/prev3.json' >/dev/null 2>&1 && grep -q 'room.0001.exr' '$DIR/prev3.json'"

# --- 8. Reflection figures off the highlight: the truth marks the pixels whose reflection sees an
# emitter, error_measure (exclude) and compare (--mask reflected-emitter) leave them out alike, and
# a framepass reflection method is within 0.7 × SSR's error there on the glossy and hard captures
# (RTR with its hits' indirect light traced on the glossy room; Unreal's RTR on the hard scene). ---
rmse_of() {  # rmse_of BENCH_JSON MEASURE
    python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print([e for e in r['settings'][0]['errors'] if e['name']==sys.argv[2]][0]['metrics']['rmse'])" "$1" "$2"
}
for scene in glossy hard; do
    check "capture the $scene scene with its truth" "$FP" capture "$SRC/examples/$scene/scene.json" -o "$DIR/$scene.exr" --truth
    check "measure every $scene method against its truth" bash -c "'$FP' bench '$SRC/examples/$scene/beyond.json' --capture '$DIR/$scene.exr' \
        --runs 1 --decompose-rays 0 --json > '$DIR/$scene.json'"
done
# The glossy chain with its colour dumped in float32, so compare reads the bits error_measure saw.
python3 -c "import json, sys; c = json.load(open(sys.argv[1])); c['scene'] = sys.argv[2]; c['exr'] = {'colorPrecision': 'float'}; json.dump(c, open(sys.argv[3], 'w'))" \
    "$SRC/examples/glossy/beyond.json" "$SRC/examples/glossy/scene.json" "$DIR/glossy_float.json"
check "dump SSR's glossy reflections" "$FP" run "$DIR/glossy_float.json" --capture "$DIR/glossy.exr" \
    -o "$DIR/glossy" --dump reflection_environment.specular
check "the glossy capture marks the pixels that reflect the ceiling light" \
    expect_exit 0 "pixels reflect an emitter" "$FP" capture "$SRC/examples/glossy/scene.json" -o "$DIR/glossy_again.exr" --truth --width 64 --height 64
ssr=$(rmse_of "$DIR/glossy.json" ssr_vs_specular); ssr_off=$(rmse_of "$DIR/glossy.json" ssr_vs_specular_off_emitters)
traced_off=$(rmse_of "$DIR/glossy.json" rtr_traced_vs_specular_off_emitters)
echo "glossy: SSR $ssr, off the emitters $ssr_off; RTR with traced hit light $traced_off"
check "most of SSR's glossy error is on the pixels that reflect the light (all ≥ 2 × masked)" \
    python3 -c "import sys; sys.exit(0 if $ssr >= 2 * $ssr_off else 1)"
check "glossy, emitters masked: RTR with traced hit light ≤ 0.7 × SSR" \
    python3 -c "import sys; sys.exit(0 if $traced_off <= 0.7 * $ssr_off else 1)"
hard_ssr=$(rmse_of "$DIR/hard.json" ssr_vs_specular_off_emitters); hard_rtr=$(rmse_of "$DIR/hard.json" rtr_raw_vs_specular_off_emitters)
echo "hard: SSR $hard_ssr, RTR $hard_rtr (no emitter: nothing masked)"
check "hard, emitters masked: Unreal's RTR ≤ 0.7 × SSR" \
    python3 -c "import sys; sys.exit(0 if $hard_rtr <= 0.7 * $hard_ssr else 1)"
# compare's mask is error_measure's: the same pixels, the same figure (one measureError).
check "compare --mask reflected-emitter gives error_measure's figure" \
    bash -c "'$FP' compare '$DIR/glossy/dump/reflection_environment.specular.0001.exr' '$DIR/glossy.exr' --ref-layer Truth.Specular --mask sky --mask reflected-emitter --json > '$DIR/masked.json' && python3 -c \"import json; j=json.load(open('$DIR/masked.json')); s=j.get('stats', j); assert abs(s['rmse'] - $ssr_off) <= 1e-6 * $ssr_off, (s['rmse'], $ssr_off)\""
check "a reflected-emitter mask without a truth capture names the command that writes one" \
    expect_exit 2 "framepass capture --truth" "$FP" compare "$DIR/glossy/dump/reflection_environment.specular.0001.exr" \
    "$DIR/glossy/dump/reflection_environment.specular.0001.exr" --mask reflected-emitter

# --- 16. Memory. A run's forecast (what the process holds, a frame's images at the plan's peak,
# the pass scratch, the histories, what is read ahead and written) is within 20 % of the peak the
# process reached (getrusage): one frame of Unreal's chain at 1024², its ray-traced chain at 512²,
# three frames read ahead at 512². compare is checked before it reads; inspect streams. ---
check "capture the box at 1024² and a three-frame sequence at 512²" bash -c \
    "'$FP' capture '$CORNELL/scene.json' -o '$DIR/m1024.exr' --width 1024 --height 1024 >/dev/null && \
     '$FP' capture '$CORNELL/scene.json' -o '$DIR/mseq.####.exr' --frames 1-3 --width 512 --height 512 >/dev/null"
printf '{ "version": 1, "engine": "ue4.27", "capture": "%s" }\n' "$DIR/m1024.exr" > "$DIR/m1024.json"
printf '{ "version": 1, "engine": "ue4.27-raytracing", "capture": "%s", "scene": "%s" }\n' \
    "$DIR/mseq.0001.exr" "$CORNELL/scene.json" > "$DIR/mrt.json"
printf '{ "version": 1, "engine": "ue4.27", "capture": "%s", "frames": "1-3" }\n' "$DIR/mseq.####.exr" > "$DIR/mseq.json"
within20() {  # within20 REPORT: the forecast within 20 % of the measured peak
    python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['memory']; f=m['forecast']['totalBytes']; p=m['peakResidentBytes']; print(f, p); sys.exit(0 if abs(f - p) <= 0.2 * p else 1)" "$1"
}
for run in m1024 mrt mseq; do
    check "$run: the memory forecast is within 20 % of the process's peak" bash -c \
        "'$FP' run '$DIR/$run.json' -o '$DIR/$run' --report '$DIR/$run.report.json' >/dev/null 2>&1 && $(declare -f within20); within20 '$DIR/$run.report.json'"
done
check "the sequence's forecast counts the frame its writers hold, and none without writers" bash -c \
    "'$FP' run '$DIR/mseq.json' -o '$DIR/mseq0' --writers 0 --report '$DIR/mseq0.report.json' >/dev/null 2>&1 && \
     python3 -c \"import json; q = lambda p: json.load(open(p))['memory']['forecast']['queuedBytes']; \
a, b = q('$DIR/mseq.report.json'), q('$DIR/mseq0.report.json'); assert a > 0 and b == 0, (a, b)\" && \
     $(declare -f within20); within20 '$DIR/mseq0.report.json'"
check "the run's last line sets its peak beside the forecast" \
    expect_exit 0 "memory: the process peaked at" "$FP" run "$DIR/m1024.json" -o "$DIR/m1024b"
check "compare refuses a comparison over --max-memory before it reads" \
    expect_exit 2 "at its peak (both images" "$FP" compare "$DIR/m1024.exr" "$DIR/m1024.exr" --layer SceneColor --max-memory 1M
# inspect reads a band of rows at a time: on a 4096² four-channel part (256 MiB of floats) its
# peak stays within 128 MiB of its peak on a tiny file (a 64 MiB band and OpenEXR's buffers).
oiiotool --pattern constant:color=0.5,0.25,1,1 4096x4096 4 -d float -o "$DIR/big.exr"
oiiotool --pattern constant:color=0.5,0.25,1,1 16x16 4 -d float -o "$DIR/tiny.exr"
check "inspect streams a 256 MiB part through a bounded band" python3 - "$FP" "$DIR" <<'PY'
import resource, subprocess, sys
fp, d = sys.argv[1], sys.argv[2]
def peak(path):  # the child's peak resident memory, KiB (the largest child so far: tiny first)
    subprocess.run([fp, "inspect", path, "--json"], check=True, stdout=subprocess.DEVNULL)
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
tiny = peak(d + "/tiny.exr"); big = peak(d + "/big.exr")
print("inspect peak: tiny", tiny // 1024, "MiB, 4096² part", big // 1024, "MiB")
sys.exit(0 if big - tiny <= 128 * 1024 else 1)
PY

# --- 17. Empty paths, a mistyped option. ---
check "-o '' is an error" expect_exit 2 "an empty path names no file or folder" "$FP" run "$DIR/plain.json" -o ''
check "--report '' is an error" expect_exit 2 "an empty path names no file or folder" "$FP" run "$DIR/plain.json" --report ''
check "a mistyped option gets a did-you-mean" expect_exit 2 "(did you mean '--output-dir'?)" "$FP" run "$DIR/plain.json" --ouput-dir x

# --- 18. compare and NaN; plan on a missing capture. ---
oiiotool --pattern constant:color=nan,nan,nan 4x4 3 -d float -o "$DIR/nan.exr"
oiiotool --pattern constant:color=2,2,2 4x4 3 -d float -o "$DIR/two.exr"
check "an all-NaN image against a constant is 100 % over tolerance, max error inf" \
    bash -c "'$FP' compare '$DIR/nan.exr' '$DIR/two.exr' --json > '$DIR/nan.json' && python3 -c \"import json; j=json.load(open('$DIR/nan.json')); s=j.get('stats', j); assert s['nonFinitePixels'] == 16 and s['overTolerance'] == 1.0 and s['maxError'] is None, s\""
check "and fails --max-rmse" expect_exit 1 "non-finite pixels fail --max-rmse" "$FP" compare "$DIR/nan.exr" "$DIR/two.exr" --max-rmse 1
check "a NaN tolerance is refused" expect_exit 2 "tolerance" "$FP" compare "$DIR/two.exr" "$DIR/two.exr" --tolerance nan
check "plan on a missing capture says so" expect_exit 0 "is not on disk" "$FP" plan "$DIR/plain.json" --capture "$DIR/missing.exr"
finish
