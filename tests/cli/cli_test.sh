#!/usr/bin/env bash
# End-to-end checks of the framepass executable: capture → plan → run, determinism across thread
# counts and reruns, exit codes and error messages. Usage: cli_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
source "$(cd "$(dirname "$0")" && pwd)/checks.sh"
FP="$1"; SRC="$2"; DIR="$3/cli"
rm -rf "$DIR"; mkdir -p "$DIR"; DIR="$(cd "$DIR" && pwd)"  # absolute: file:// URLs need it

check "capture the Cornell box at 64×64" "$FP" capture "$SRC/examples/cornell/scene.json" -o "$DIR/cornell.exr" --width 64 --height 64
cat > "$DIR/config.json" <<JSON
{ "version": 1, "capture": "cornell.exr" }
JSON
check "inspect lists the buffers and the camera" bash -c "'$FP' inspect '$DIR/cornell.exr' --json | grep -q '\"previous\"'"
cat > "$DIR/reduced_only.json" <<JSON
{ "version": 1, "capture": "cornell.exr", "outputs": { "reduced.####.exr": "prev_color_reduction.color" } }
JSON
check "plan reads only the channels of surviving passes" bash -c "'$FP' plan '$DIR/reduced_only.json' --json > '$DIR/plan.json' && grep -q 'PrevSceneDepth.Z' '$DIR/plan.json' && ! grep -q 'WorldNormal' '$DIR/plan.json' && grep -q '\"ssgi\"' '$DIR/plan.json'"
check "run with 1 thread" "$FP" --threads 1 run "$DIR/config.json" -o "$DIR/t1" --dump all --report "$DIR/t1.json"
check "run with 2 threads" "$FP" --threads 2 run "$DIR/config.json" -o "$DIR/t2" --dump all
check "1-thread and 2-thread outputs are byte-identical" diff -r "$DIR/t1" "$DIR/t2"
check "a rerun is byte-identical" bash -c "'$FP' run '$DIR/config.json' -o '$DIR/t3' --dump all >/dev/null && diff -r '$DIR/t1' '$DIR/t3'"
check "the report has per-pass time and work" grep -q '"texels"' "$DIR/t1.json"
check "the report lists the channels actually read" bash -c "grep -q 'WorldNormal.X' '$DIR/t1.json' && ! grep -q 'Velocity.X' '$DIR/t1.json'"
check "mip chains are written one part per mip" bash -c "'$FP' inspect '$DIR/t1/dump/hzb.furthest.0001.exr' | grep -q '5 part(s)' && '$FP' inspect '$DIR/t1/dump/hzb.furthest.0001.exr' | grep -q 'hzb.furthest.mip4'"
check "--cvar reaches the pass (TAA history instead of leak-free)" bash -c "'$FP' plan '$DIR/config.json' --cvar r.SSGI.LeakFreeReprojection=0 | grep -q 'history←capture:TAAHistory'"

# A config that names a scene gains the light step (rt_shadows → shadow_denoise → deferred_lighting
# per light); its outputs are byte-identical for 1 and 2 threads too.
cat > "$DIR/lit.json" <<JSON
{ "version": 1, "capture": "cornell.exr", "scene": "$SRC/examples/cornell/scene.json" }
JSON
check "a scene with lights adds the light passes" bash -c "'$FP' plan '$DIR/lit.json' > '$DIR/lit_plan.txt' && grep -q 'rt_shadows_ceiling (rt_shadows)' '$DIR/lit_plan.txt' && grep -q 'color←deferred_lighting_ceiling.color' '$DIR/lit_plan.txt' && grep -q 'sceneColor←capture:Emissive' '$DIR/lit_plan.txt'"
check "lit chain: 1 and 2 threads write the same bytes" bash -c "'$FP' --threads 1 run '$DIR/lit.json' -o '$DIR/l1' --dump all >/dev/null && '$FP' --threads 2 run '$DIR/lit.json' -o '$DIR/l2' --dump all >/dev/null && diff -r '$DIR/l1' '$DIR/l2' && test -f '$DIR/l1/shadows.0001.exr' && test -f '$DIR/l1/lit.0001.exr'"
check "bench replays the shadow rays through a bare Embree loop" bash -c "'$FP' bench '$DIR/lit.json' --runs 1 --warmup 0 > '$DIR/lit_bench.txt' && grep -q 'bare loop rtcOccluded8' '$DIR/lit_bench.txt'"
check "the lit chain's denoiser reads the hit distance: bench also replays the closest-hit queries" bash -c "grep -Eq 'bare loop rtcOccluded(8|16) \+ rtcIntersect(8|16) ' '$DIR/lit_bench.txt'"
check "an unknown light name is an error that suggests the right one" expect_exit 1 "no light named 'ceilng' in the scene (did you mean 'ceiling'?)" "$FP" run "$DIR/lit.json" -o "$DIR/l3" --set rt_shadows_ceiling.light=ceilng
check "plan shows the light template as written and what it expanded to" bash -c "grep -q '(preset ue4.27)/passes/5/forEachLight expands for light ceiling: rt_shadows_ceiling, shadow_denoise_ceiling, deferred_lighting_ceiling' '$DIR/lit_plan.txt'"
# The ray-traced preset: RTGI and RTAO in SSGI's place; a config without a scene is told why.
cat > "$DIR/rt.json" <<JSON
{ "version": 1, "engine": "ue4.27-raytracing", "capture": "cornell.exr", "scene": "$SRC/examples/cornell/scene.json" }
JSON
cat > "$DIR/rt_noscene.json" <<JSON
{ "version": 1, "engine": "ue4.27-raytracing", "capture": "cornell.exr" }
JSON
check "the ray-traced preset composites RTGI, RTAO and RTR through their denoisers, no SSGI or SSR" bash -c "'$FP' plan '$DIR/rt.json' > '$DIR/rt_plan.txt' && grep -q 'diffuse←gi_denoise.diffuse' '$DIR/rt_plan.txt' && grep -q 'ao←ao_denoise.ao' '$DIR/rt_plan.txt' && grep -q 'reflection←reflection_denoise.reflection' '$DIR/rt_plan.txt' && grep -q 'diffuse←rt_global_illumination.diffuse' '$DIR/rt_plan.txt' && grep -q 'hitDistance←rt_ambient_occlusion.hitDistance' '$DIR/rt_plan.txt' && ! grep -q '(ssgi)' '$DIR/rt_plan.txt' && ! grep -q '(ssr)' '$DIR/rt_plan.txt' && '$FP' run '$DIR/rt.json' -o '$DIR/rt_out' >/dev/null && test -f '$DIR/rt_out/raytraced.0001.exr' && test -f '$DIR/rt_out/denoised.0001.exr' && test -f '$DIR/rt_out/final.0001.png'"
# The preset traces RTGI at Unreal's 50 %: its layer is half the frame, in an EXR part of its own
# behind the frame-sized one, whose size is the file's.
check "a layer traced at a lower screen percentage gets an EXR part of its size" bash -c "'$FP' inspect '$DIR/rt_out/raytraced.0001.exr' > '$DIR/rt_parts.txt' && grep -q '^[^ ]*raytraced.0001.exr: 64×64, 1 file(s), 2 part(s)' '$DIR/rt_parts.txt' && grep -q '^  rgba/rt_ambient_occlusion.ao.Y' '$DIR/rt_parts.txt' && grep -q '^  rt_global_illumination.diffuse/rt_global_illumination.diffuse.R' '$DIR/rt_parts.txt' && '$FP' run '$DIR/rt.json' -o '$DIR/rt_full' --cvar r.RayTracing.GlobalIllumination.ScreenPercentage=100 >/dev/null && '$FP' inspect '$DIR/rt_full/raytraced.0001.exr' | grep -q '64×64, 1 file(s), 1 part(s)'"
check "bench replays each ray-traced pass's rays through its own bare loops (the Cornell box's rough walls give rt_reflections none)" bash -c "'$FP' bench '$DIR/rt.json' --runs 1 --warmup 0 > '$DIR/rt_bench.txt' && grep -q 'bare loop rtcIntersect1 (rt_global_illumination)' '$DIR/rt_bench.txt' && grep -q 'bare loop rtcOccluded8 (rt_ambient_occlusion)' '$DIR/rt_bench.txt' && grep -q 'bare loop rtcOccluded8 (rt_shadows_ceiling)' '$DIR/rt_bench.txt'"
# Each tracing pass's yardstick: its loops one ray at a time added up, over its own median.
check "bench --json gives each ray-traced pass its bare loops one ray at a time and its share of Embree's speed" bash -c "'$FP' bench '$DIR/rt.json' --runs 1 --warmup 0 --json > '$DIR/rt_bench.json' && python3 - '$DIR/rt_bench.json' <<'PY'
import json, sys
passes = json.load(open(sys.argv[1]))['settings'][0]['passes']
median = {p['name']: p['median'] for p in passes}
checked = 0
for p in passes:
    if p['type'] == 'embree':
        assert 'bareSeconds' not in p, p
        continue
    loops = [median.get(f'bare loop {q} ({p[\"name\"]})', 0.0) for q in ('rtcIntersect1', 'rtcOccluded1')]
    if not any(loops):
        assert 'bareSeconds' not in p, p  # traces nothing through the scene
        continue
    assert abs(p['bareSeconds'] - sum(loops)) <= 1e-12 * sum(loops), (p, loops)
    assert abs(p['bareRatio'] - sum(loops) / p['median']) <= 1e-9 * p['bareRatio'], p
    checked += 1
# RTGI, RTAO and the ceiling light's shadows trace on the Cornell box (its rough walls give RTR none).
assert checked >= 3, checked
PY"
cat > "$DIR/methods.json" <<JSON
{ "version": 1, "capture": "cornell.exr", "scene": "$SRC/examples/cornell/scene.json",
  "passes": [
    { "name": "hzb", "type": "hzb" },
    { "name": "prev", "type": "prev_color_reduction", "inputs": { "furthestHzb": "hzb.furthest" } },
    { "name": "ssgi", "type": "ssgi", "inputs": { "furthestHzb": "hzb.furthest", "reducedColor": "prev.color" } },
    { "name": "rtgi", "type": "rt_global_illumination", "params": { "samplesPerPixel": 1 } },
    { "name": "gi", "type": "error_measure", "inputs": { "source": "ssgi.diffuse", "reference": "capture:SceneColor" } } ],
  "outputs": { "gi.####.exr": "gi.heat" } }
JSON
check "--input PASS.INPUT=SOURCE rebinds an input, and the method it leaves is culled" bash -c "'$FP' plan '$DIR/methods.json' | grep -q '3. ssgi (ssgi)' && ! '$FP' plan '$DIR/methods.json' | grep -q '[0-9]. rtgi' && '$FP' plan '$DIR/methods.json' --input gi.source=rtgi.diffuse > '$DIR/methods_plan.txt' && grep -q 'source←rtgi.diffuse' '$DIR/methods_plan.txt' && grep -q '1. rtgi (rt_global_illumination)' '$DIR/methods_plan.txt' && ! grep -q '[0-9]. ssgi' '$DIR/methods_plan.txt'"
check "a --set on neither a parameter nor an input is an error" expect_exit 2 "gi" "$FP" plan "$DIR/methods.json" --set gi.sorce=rtgi.diffuse
check "a --set on an input is an error that says to use --input" expect_exit 2 "--set gi.source: 'source' is an input of pass 'gi', not a parameter: rebind it with --input gi.source" "$FP" plan "$DIR/methods.json" --set gi.source=rtgi.diffuse
check "an --input on no input of the pass is an error with a did-you-mean" expect_exit 2 "--input gi.sorce: pass 'gi' (error_measure) has no input 'sorce' (did you mean 'source'?)" "$FP" plan "$DIR/methods.json" --input gi.sorce=rtgi.diffuse
check "the config's \"inputs\" rebind as --input does" bash -c "python3 -c 'import json,sys; c=json.load(open(sys.argv[1])); c[\"inputs\"]={\"gi.source\": \"rtgi.diffuse\"}; json.dump(c, open(sys.argv[2], \"w\"))' '$DIR/methods.json' '$DIR/methods_inputs.json' && '$FP' plan '$DIR/methods_inputs.json' | grep -q 'source←rtgi.diffuse'"
check "tune searches across methods through an error's source" bash -c "'$FP' tune '$DIR/methods.json' --target 'gi<=1000' --sweep gi.source=ssgi.diffuse,rtgi.diffuse --runs 1 --warmup 0 2>/dev/null | grep -q 'cheapest setting that meets'"
check "tune names the Unreal setting of the method it chose, and the method as an --input line" bash -c "'$FP' tune '$DIR/methods.json' --target 'gi<=1000' --sweep gi.source=rtgi.diffuse --sweep rtgi.samplesPerPixel=1,2 --runs 1 --warmup 0 2>/dev/null > '$DIR/tune_method.txt' && grep -q '; the method rt_global_illumination runs: r.RayTracing.GlobalIllumination=1' '$DIR/tune_method.txt' && grep -q '^; framepass only (no Unreal cvar): --input gi.source=rtgi.diffuse' '$DIR/tune_method.txt' && grep -q '^; framepass only (no Unreal cvar): --set rtgi.samplesPerPixel=' '$DIR/tune_method.txt'"
check "tune leaves out a cvar the chosen method's chain does not read" bash -c "'$FP' tune '$DIR/methods.json' --target 'gi<=1000' --sweep gi.source=rtgi.diffuse --sweep r.SSGI.Quality=1,4 --runs 1 --warmup 0 2>/dev/null > '$DIR/tune_idle.txt' && grep -q '^; r.SSGI.Quality=[14] left out: no pass of this chain reads it' '$DIR/tune_idle.txt' && ! grep -q '^r.SSGI.Quality=' '$DIR/tune_idle.txt'"
check "bench pairs each error measure with the time of the passes its source depends on" bash -c "'$FP' bench '$DIR/methods.json' --input gi.source=rtgi.diffuse --runs 1 --warmup 0 --json --html '$DIR/methods_bench.html' > '$DIR/methods_bench.json' && python3 - '$DIR/methods_bench.json' <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); s = j['settings'][0]
(e,) = s['errors']
assert e['methodPasses'] == ['rtgi'], e['methodPasses']  # not the error measure, not the culled SSGI
median = {p['name']: p['median'] for p in s['passes']}
assert abs(e['methodSeconds'] - median['rtgi']) < 1e-12 and j['device'] == 'cpu'
PY
grep -q '<svg id=\"methods\"' '$DIR/methods_bench.html' && ! grep -q 'class=\"budget\"' '$DIR/methods_bench.html'"
check "tune --budget picks the most accurate setting whose method fits" bash -c "'$FP' tune '$DIR/methods.json' --target gi --budget 100000ms --sweep gi.source=ssgi.diffuse,rtgi.diffuse --sweep rtgi.samplesPerPixel=1,2 --runs 1 --warmup 0 --json > '$DIR/tune_budget.json' 2>/dev/null && python3 - '$DIR/tune_budget.json' <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
fits = [t for t in j['settings'] if t['methodMs'] <= j['budgetMs']]
assert j['met'] and j['budgetMs'] == 100000 and j['target']['max'] is None and len(fits) == len(j['settings'])
assert j['choice']['value'] == min(t['value'] for t in fits), j['choice']
PY"
check "tune --budget below every method's time says which is fastest" expect_exit 1 "the fastest method" "$FP" tune "$DIR/methods.json" --target gi --budget 0.000001s --sweep gi.source=ssgi.diffuse,rtgi.diffuse --runs 1 --warmup 0
check "tune --budget takes a time a frame" expect_exit 2 "a time a frame" "$FP" tune "$DIR/methods.json" --target gi --budget 4fps
check "tune without --budget needs a bound" expect_exit 2 "ERROR_PASS<=VALUE" "$FP" tune "$DIR/methods.json" --target gi
check "the ray-traced preset without a scene takes the one the capture was made from" \
    bash -c "'$FP' run '$DIR/rt_noscene.json' -o '$DIR/rt_none' 2>'$DIR/rt_none.log' >/dev/null && grep -q 'using .*examples/cornell/scene.json, the scene the capture was made from' '$DIR/rt_none.log' && cmp '$DIR/rt_none/raytraced.0001.exr' '$DIR/rt_out/raytraced.0001.exr'"
mkdir -p "$DIR/elsewhere" && cp "$DIR/cornell.exr" "$DIR/elsewhere/cornell.exr"
check "a capture whose recorded scene is not there: the error names the \"scene\" key" \
    expect_exit 2 'which is not there: add "scene"' "$FP" run "$DIR/rt_noscene.json" --capture "$DIR/elsewhere/cornell.exr" -o "$DIR/rt_none2"
cat > "$DIR/rt_bad.json" <<JSON
{ "version": 1, "engine": "ue4.27-raytrace", "capture": "cornell.exr" }
JSON
cat > "$DIR/hybrid_preset.json" <<JSON
{ "version": 1, "engine": "framepass-hybrid", "capture": "cornell.exr", "scene": "$SRC/examples/cornell/scene.json" }
JSON
check "the hybrid preset composites the hybrid through the GI denoiser, no SSGI" bash -c "'$FP' plan '$DIR/hybrid_preset.json' > '$DIR/hy_plan.txt' && grep -q 'diffuse←hybrid_denoise.diffuse' '$DIR/hy_plan.txt' && grep -q 'hybrid_denoise (gi_denoise)' '$DIR/hy_plan.txt' && ! grep -q '(ssgi)' '$DIR/hy_plan.txt' && grep -q '(ssr)' '$DIR/hy_plan.txt' && '$FP' run '$DIR/hybrid_preset.json' -o '$DIR/hy_out' >/dev/null && test -f '$DIR/hy_out/hybrid.0001.exr' && test -f '$DIR/hy_out/final.0001.png'"
check "an unknown engine lists the known ones" expect_exit 2 "known: ue4.27, ue5, ue4.27-raytracing, framepass-hybrid" "$FP" plan "$DIR/rt_bad.json"
cat > "$DIR/lights_only.json" <<JSON
{ "version": 1, "capture": "cornell.exr", "scene": "$SRC/examples/cornell/scene.json",
  "passes": [ { "name": "light", "type": "deferred_lighting", "params": { "light": "ceiling" } } ],
  "outputs": { "lit.####.exr": "light.color" } }
JSON
check "a chain that only shades reads the scene's lights, not its meshes" bash -c "'$FP' plan '$DIR/lights_only.json' | grep -q 'geometry: not needed (lights only)' && '$FP' run '$DIR/lights_only.json' -o '$DIR/lo' >/dev/null && test -f '$DIR/lo/lit.0001.exr'"

# The glossy room: a lat-long sky light lights the truth and, after the lights, reflection_environment.
check "capture the glossy room with its lat-long sky light" "$FP" capture "$SRC/examples/glossy/scene.json" -o "$DIR/glossy.exr" --width 48 --height 48 --truth --truth-spp 4
cat > "$DIR/glossy.json" <<JSON
{ "version": 1, "capture": "glossy.exr", "scene": "$SRC/examples/glossy/scene.json",
  "outputs": { "r.####.exr": ["reflection_environment.color", "reflection_environment.specular"] } }
JSON
check "reflection_environment adds to the last light's colour under SSGI's AO" bash -c "'$FP' plan '$DIR/glossy.json' > '$DIR/glossy_plan.txt' && grep -q 'reflection_environment (reflection_environment)  in: ao←ssgi_denoise.ao.*color←deferred_lighting_ceiling.color' '$DIR/glossy_plan.txt'"
check "glossy room: 1 and 2 threads write the same bytes" bash -c "'$FP' --threads 1 run '$DIR/glossy.json' -o '$DIR/g1' >/dev/null && '$FP' --threads 2 run '$DIR/glossy.json' -o '$DIR/g2' > '$DIR/g2.txt' && diff -r '$DIR/g1' '$DIR/g2' && grep -Eq 'reflection_environment .* pixels=[1-9]' '$DIR/g2.txt'"

# Sequences: the denoiser's history goes from frame to frame; a chunk that warms up on the
# frames before it writes the same bytes as a sequential run.
check "capture a 6-frame sequence" "$FP" capture "$SRC/examples/cornell/scene.json" -o "$DIR/seq.####.exr" --frames 1-6 --width 48 --height 48
echo '{ "version": 1, "capture": "seq.####.exr" }' > "$DIR/seq.json"
check "sequential run over frames 1-6" "$FP" run "$DIR/seq.json" --frames 1-6 -o "$DIR/seq_all"
check "chunk 1-3" "$FP" run "$DIR/seq.json" --frames 1-3 -o "$DIR/seq_chunks"
check "chunk 4-6 warming up on 3 frames" bash -c "'$FP' run '$DIR/seq.json' --frames 4-6 --warmup-frames 3 -o '$DIR/seq_chunks' > '$DIR/chunk.log' && grep -q 'warm-up frame 1' '$DIR/chunk.log'"
check "chunked and sequential runs are byte-identical" diff -r "$DIR/seq_all" "$DIR/seq_chunks"
check "without warm-up frame 4 differs (the history is used)" bash -c "'$FP' run '$DIR/seq.json' --frames 4 -o '$DIR/seq_cold' >/dev/null && ! cmp -s '$DIR/seq_all/ssgi.0004.exr' '$DIR/seq_cold/ssgi.0004.exr'"

cat > "$DIR/bad.json" <<JSON
{ "version": 1, "capture": "cornell.exr", "cvar": {},
  "passes": [ { "type": "hzb", "params": { "halfPrecison": true } } ] }
JSON
check "a bad config exits 2 with every error, pointer and suggestion" expect_exit 2 \
    "/passes/0/params/halfPrecison: unknown parameter 'halfPrecison' (did you mean 'halfPrecision'?)" \
    "$FP" plan "$DIR/bad.json"
check "an unknown top-level key gets a did-you-mean" expect_exit 2 "/cvar: unknown config key 'cvar' (did you mean 'cvars'?)" "$FP" plan "$DIR/bad.json"
echo "{ \"version\": 1, " > "$DIR/broken.json"
check "broken JSON exits 2 naming the file" expect_exit 2 "broken.json: not valid JSON" "$FP" plan "$DIR/broken.json"
cat > "$DIR/missing.json" <<JSON
{ "version": 1, "capture": "nowhere.exr" }
JSON
check "a missing capture exits 1 naming the file" expect_exit 1 "nowhere.exr: no such file" "$FP" run "$DIR/missing.json" -o "$DIR/m"
check "--set with a bad value exits 2 naming the flag" expect_exit 2 "--set hzb.halfPrecision: 'halfPrecision' must be a boolean" \
    "$FP" plan "$DIR/config.json" --set hzb.halfPrecision=maybe
# The GPU backend: placement shown by plan; without a usable GPU (or without CUDA in the build)
# run says why and exits 2 before reading a pixel.
if "$FP" plan "$DIR/config.json" --device cuda > "$DIR/plan_cuda.txt" 2>&1; then
    check "plan --device cuda marks the GPU passes" bash -c "grep -q 'ssgi (ssgi) \[gpu\]' '$DIR/plan_cuda.txt' && grep -q 'display (display) \[gpu\]' '$DIR/plan_cuda.txt'"
    check "plan --json gives each step's device" bash -c "'$FP' plan '$DIR/config.json' --device cuda --json | grep -q '\"device\": \"cuda\"'"
    check "plan --device cuda puts the whole lit chain on the GPU, shadow rays included" bash -c "'$FP' plan '$DIR/lit.json' --device cuda > '$DIR/lit_cuda.txt' 2>&1; grep -q 'shadow_denoise_ceiling (shadow_denoise) \[gpu\]' '$DIR/lit_cuda.txt' && grep -q 'deferred_lighting_ceiling (deferred_lighting) \[gpu\]' '$DIR/lit_cuda.txt' && grep -q 'reflection_environment (reflection_environment) \[gpu\]' '$DIR/lit_cuda.txt' && grep -q 'rt_shadows_ceiling (rt_shadows) \[gpu\]' '$DIR/lit_cuda.txt' && ! grep -q ') \[cpu\]' '$DIR/lit_cuda.txt'"
    check "passes --json says which types have a GPU kernel" bash -c "'$FP' passes --json | python3 -c 'import json,sys; c={p[\"type\"]: p[\"cuda\"] for p in json.load(sys.stdin)}; sys.exit(not (c[\"ssr\"] and c[\"shadow_denoise\"] and c[\"deferred_lighting\"] and c[\"rt_shadows\"]))'"
    if ! grep -q "not usable here" "$DIR/plan_cuda.txt"; then
        echo "  (a GPU is here: run --device cuda is checked by framepass_gpu_check)"
    else
        check "run --device cuda without a GPU exits 2 saying why" expect_exit 2 "--device cuda: no" \
            "$FP" run "$DIR/config.json" -o "$DIR/gpu_out" --device cuda
    fi
else
    check "a build without CUDA says so" expect_exit 2 "no GPU backend" "$FP" plan "$DIR/config.json" --device cuda
    check "passes --json says no type runs on a GPU in this build" bash -c "'$FP' passes --json | python3 -c 'import json,sys; sys.exit(any(p[\"cuda\"] for p in json.load(sys.stdin)))'"
fi
check "an unknown device is a usage error" expect_exit 2 "--device: tpu not in {cpu,cuda}" "$FP" plan "$DIR/config.json" --device tpu
check "passes documents every type" bash -c "'$FP' passes | grep -q prev_color_reduction && '$FP' passes hzb | grep -q halfPrecision"
check "an unknown pass type gets a suggestion" expect_exit 2 "did you mean 'display'?" "$FP" passes dispaly
check "passes --cvars lists the cvars, of one type with TYPE" bash -c "'$FP' passes --cvars | grep -q '^r.SSGI.Enable .*not emulated' && '$FP' passes ssgi --cvars | grep -q '^r.SSGI.Quality .*ssgi.quality = 4' && ! '$FP' passes ssgi --cvars | grep -q r.SSR.Quality"
check "the hard-case glTF scene captures (10^7 from the origin)" "$FP" capture "$SRC/examples/hard/scene.json" -o "$DIR/hard.exr" --width 64 --height 64
check "outputs never overwrite an input" bash -c "cp '$DIR/cornell.exr' '$DIR/final.0001.png'; cat > '$DIR/self.json' <<J
{ \"version\": 1, \"capture\": \"final.0001.png\" }
J
! '$FP' run '$DIR/self.json' -o '$DIR' >/dev/null 2>&1; cmp '$DIR/cornell.exr' '$DIR/final.0001.png'"

# --- truth, compare, error_measure, bench (issue 3) ---------------------------------------------
check "capture --truth adds Truth.* layers with standard errors" bash -c "'$FP' capture '$SRC/examples/cornell/scene.json' -o '$DIR/truth.exr' --width 48 --height 48 --truth --truth-spp 8 | grep -q 'truth 8 spp' && '$FP' inspect '$DIR/truth.exr' | grep -q 'Truth.DiffuseIndirectFull.StdErr.R' && '$FP' inspect '$DIR/truth.exr' | grep -q 'Truth.Shadow.ceiling.Y'"
check "the same seed gives the same truth, byte for byte, on 1 or 2 threads" bash -c "'$FP' --threads 1 capture '$SRC/examples/cornell/scene.json' -o '$DIR/truth1.exr' --width 48 --height 48 --truth --truth-spp 8 >/dev/null && cmp '$DIR/truth.exr' '$DIR/truth1.exr'"
check "compare of a layer with itself is exact" bash -c "'$FP' compare '$DIR/truth.exr' '$DIR/truth.exr' --layer Truth.AO --json > '$DIR/self.json.out' && grep -q '\"rmse\": 0.0' '$DIR/self.json.out' && grep -q '\"maxError\": 0.0' '$DIR/self.json.out'"
check "compare reports the reference's noise floor and writes a heat map" bash -c "'$FP' compare '$DIR/truth.exr' '$DIR/truth.exr' --layer Truth.DiffuseIndirectOneBounce --ref-layer Truth.DiffuseIndirectFull --heatmap '$DIR/heat.exr' > '$DIR/cmp.txt' && grep -q 'reference noise' '$DIR/cmp.txt' && test -s '$DIR/heat.png' && '$FP' inspect '$DIR/heat.exr' | grep -q 'Heat.R'"
check "compare names the layers when one is missing" expect_exit 2 "did you mean 'Truth.AO'?" "$FP" compare "$DIR/truth.exr" "$DIR/truth.exr" --layer Truth.A0
check "compare --max-rmse fails a comparison above it" expect_exit 1 "above --max-rmse" "$FP" compare "$DIR/truth.exr" "$DIR/truth.exr" --layer Truth.DiffuseIndirectOneBounce --ref-layer Truth.DiffuseIndirectFull --max-rmse 0.000001
# A measure against a truth of another definition says so (issue 46): the header records the AO
# radius; Unreal's RTAO (200 cm) against truth.exr's 1 m Truth.AO names the settings that match,
# and against a 2 m truth says nothing.
check "capture records the truth's definition in the header" bash -c "'$FP' capture '$SRC/examples/cornell/scene.json' -o '$DIR/ao2m.exr' --width 48 --height 48 --truth --truth-spp 2 --truth-ao-radius 2 >/dev/null && head -c 65536 '$DIR/ao2m.exr' | grep -aq 'framepass:truth.AO.radius' && head -c 65536 '$DIR/truth.exr' | grep -aq 'framepass:truth.AOAnyDistance.radius'"
for c in truth ao2m; do cat > "$DIR/rtao_$c.json" <<JSON
{ "version": 1, "capture": "$c.exr", "scene": "$SRC/examples/cornell/scene.json",
  "passes": [ { "name": "rt_ambient_occlusion", "type": "rt_ambient_occlusion" },
              { "name": "rtao_vs_truth", "type": "error_measure",
                "inputs": { "source": "rt_ambient_occlusion.ao", "reference": "capture:Truth.AO" } } ],
  "outputs": { "rtao.####.exr": "rtao_vs_truth.absError" } }
JSON
done
check "error_measure of RTAO at 200 cm against a 1 m Truth.AO warns, naming the matching settings" bash -c "'$FP' plan '$DIR/rtao_truth.json' 2>&1 | grep 'rtao_vs_truth judges rt_ambient_occlusion.ao' | grep 'set rt_ambient_occlusion.radius=100' | grep -q -- '--truth-ao-radius 2'"
check "the same measure at the truth's radius says nothing" bash -c "! '$FP' plan '$DIR/rtao_truth.json' --set rt_ambient_occlusion.radius=100 2>&1 | grep -q 'another definition' && ! '$FP' plan '$DIR/rtao_ao2m.json' 2>&1 | grep -q 'another definition'"
check "bench lists the warning with its error measure, in JSON and HTML" bash -c "'$FP' bench '$DIR/rtao_truth.json' --runs 1 --warmup 0 --json --html '$DIR/rtao.html' 2>/dev/null | python3 -c 'import json,sys; e=json.load(sys.stdin)[\"settings\"][0][\"errors\"][0]; assert any(\"radius=100\" in w for w in e[\"warnings\"]), e' && grep -q 'set rt_ambient_occlusion.radius=100' '$DIR/rtao.html'"
check "compare warns that two Truth.AO layers of different radii measure different things" bash -c "'$FP' compare '$DIR/truth.exr' '$DIR/ao2m.exr' --layer Truth.AO --mask none 2>&1 >/dev/null | grep -q 'counts occluders within 1 m but .* counts occluders within 2 m'; r=\$?; [ \$r = 0 ] || exit 1; ! '$FP' compare '$DIR/truth.exr' '$DIR/truth.exr' --layer Truth.AO 2>&1 | grep -q 'different things'"
cat > "$DIR/bench.json" <<JSON
{ "version": 1, "capture": "truth.exr",
  "passes": [ { "name": "hzb", "type": "hzb" },
              { "name": "limit", "type": "error_measure",
                "inputs": { "source": "capture:Truth.DiffuseIndirectOneBounce",
                            "reference": "capture:Truth.DiffuseIndirectFull",
                            "referenceStdErr": "capture:Truth.DiffuseIndirectFull.StdErr" } } ],
  "outputs": { "hzb.####.exr": "hzb.furthest", "limit.####.exr": ["limit.heat", "limit.absError"] } }
JSON
check "run reports error_measure's metrics next to its time" bash -c "'$FP' run '$DIR/bench.json' -o '$DIR/b' --report '$DIR/b.json' | grep -q 'rmse=' && grep -q '\"referenceNoiseRmse\"' '$DIR/b.json'"
check "error_measure and compare agree on the RMSE" bash -c "a=\$('$FP' compare '$DIR/truth.exr' '$DIR/truth.exr' --layer Truth.DiffuseIndirectOneBounce --ref-layer Truth.DiffuseIndirectFull --json | grep '\"rmse\"' | tr -dc '0-9.e-'); b=\$(grep '\"rmse\"' '$DIR/b.json' | head -1 | tr -dc '0-9.e-'); [ -n \"\$a\" ] && [ \"\$a\" = \"\$b\" ]"
check "bench reports medians, throughput and a Pareto front over a sweep grid" bash -c "'$FP' bench '$DIR/bench.json' --runs 3 --warmup 1 --sweep hzb.halfPrecision=false,true --sweep r.SSGI.LeakFreeReprojection=0..1 --json > '$DIR/bench.out' && [ \$(grep -c '\"label\"' '$DIR/bench.out') = 4 ] && grep -q '\"throughput\"' '$DIR/bench.out' && grep -q '\"pareto\": true' '$DIR/bench.out'"
check "bench reports the most image memory a frame held, per pixel too" bash -c "'$FP' bench '$DIR/bench.json' --runs 1 --warmup 0 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); s=d[\"settings\"][0]; assert s[\"peakBytes\"] > d[\"width\"] * d[\"height\"] * 4, s; assert abs(s[\"peakBytesPerPixel\"] * d[\"width\"] * d[\"height\"] - s[\"peakBytes\"]) < 1e-3 * s[\"peakBytes\"], s'"
check "bench rejects a malformed sweep" expect_exit 2 "--sweep hzb.halfPrecision: expected NAME=V1,V2" "$FP" bench "$DIR/bench.json" --sweep hzb.halfPrecision
check "bench --html writes a report that renders in headless Chromium" bash -c "'$FP' bench '$DIR/bench.json' --runs 2 --sweep hzb.halfPrecision=false,true --html '$DIR/bench.html' >/dev/null && timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --dump-dom 'file://$DIR/bench.html' 2>/dev/null > '$DIR/dom.html' && grep -q 'data-rendered=\"ok\"' '$DIR/dom.html' && grep -q 'data-images=\"[3-9]' '$DIR/dom.html' && grep -q '<circle' '$DIR/dom.html'"

cat > "$DIR/ssgi_bench.json" <<JSON
{ "version": 1, "capture": "truth.exr",
  "passes": [ { "name": "hzb", "type": "hzb" },
              { "name": "prev_color_reduction", "type": "prev_color_reduction", "inputs": { "furthestHzb": "hzb.furthest" } },
              { "name": "ssgi", "type": "ssgi",
                "inputs": { "furthestHzb": "hzb.furthest", "reducedColor": "prev_color_reduction.color" } },
              { "name": "ssgi_denoise", "type": "ssgi_denoise", "inputs": { "diffuse": "ssgi.diffuse", "ao": "ssgi.ao" } },
              { "name": "vs_full", "type": "error_measure",
                "inputs": { "source": "ssgi_denoise.diffuse", "reference": "capture:Truth.DiffuseIndirectFull" } },
              { "name": "ao", "type": "error_measure", "inputs": { "source": "ssgi.ao", "reference": "capture:Truth.AO" } },
              { "name": "limit", "type": "error_measure",
                "inputs": { "source": "capture:Truth.DiffuseIndirectOneBounce", "reference": "capture:Truth.DiffuseIndirectFull" } } ],
  "outputs": {} }
JSON
# The decomposition's arithmetic holds on the printed figures: the steps' biases add up to the
# total bias and their shares to one (to double rounding, 1e-9), and its total is error_measure's
# own RMSE and bias (summed in another order: 1e-9 relative).
check "bench takes a screen-space error apart: steps, telescoping biases, shares" bash -c "set -o pipefail; '$FP' bench '$DIR/ssgi_bench.json' --runs 1 --warmup 0 --decompose-rays 16 --json 2>/dev/null | python3 -c '
import json, sys
d = json.load(sys.stdin)
errs = {e[\"name\"]: e for e in d[\"settings\"][0][\"errors\"]}
assert \"decomposition\" not in errs[\"limit\"]  # no screen-space pass behind it
for name, steps in ((\"vs_full\", [\"noise\", \"approximation\", \"screen-space limit\", \"multi-bounce\"]),
                    (\"ao\", [\"noise\", \"approximation\", \"screen-space limit\"])):
    e = errs[name]; t = e[\"decomposition\"]
    assert [s[\"name\"] for s in t[\"steps\"]] == steps, t
    assert abs(sum(s[\"bias\"] for s in t[\"steps\"]) - t[\"bias\"]) < 1e-9, t
    assert abs(sum(s[\"share\"] for s in t[\"steps\"]) - 1) < 1e-9, t
    assert abs(t[\"rmse\"] - e[\"metrics\"][\"rmse\"]) <= 1e-9 * e[\"metrics\"][\"rmse\"], (t, e)
    assert abs(t[\"bias\"] - e[\"metrics\"][\"bias\"]) <= 1e-9 * abs(e[\"metrics\"][\"bias\"]), (t, e)
    assert t[\"steps\"][0][\"rmse\"] > 0 and t[\"steps\"][-1][\"to\"] == e[\"reference\"], t
    assert t[\"sentence\"].startswith(\"Most of the error is \"), t
    # The rungs measure their own noise; the sentence says when it is not small beside the steps.
    noise = (t[\"convergedNoiseRmse\"] ** 2 + t[\"oracleNoiseRmse\"] ** 2) ** 0.5
    assert t[\"convergedNoiseRmse\"] > 0 and t[\"oracleNoiseRmse\"] > 0, t
    largest = max(t[\"steps\"], key=lambda s: s[\"share\"])[\"rmse\"]
    assert (\"partly noise\" in t[\"sentence\"]) == (noise > 0.25 * largest), t
'"
cat > "$DIR/rtgi_bench.json" <<JSON
{ "version": 1, "capture": "truth.exr", "scene": "$SRC/examples/cornell/scene.json",
  "passes": [ { "name": "rt_global_illumination", "type": "rt_global_illumination", "params": { "samplesPerPixel": 1, "maxBounces": 2 } },
              { "name": "rtgi_vs_full", "type": "error_measure",
                "inputs": { "source": "rt_global_illumination.diffuse", "reference": "capture:Truth.DiffuseIndirectFull" } } ],
  "outputs": {} }
JSON
# A ray-traced GI error has its own ladder: noise, the bounces not traced, what the pass leaves out.
# Its arithmetic telescopes as the screen-space one's; and at maxBounces = 8 (the ladder's "every
# bounce" rung) the converged and every-bounce chains are the same chain, so that step is 0 exactly.
check "bench takes a ray-traced GI error apart: noise, bounces not traced, left out" bash -c "set -o pipefail; for b in 2 8; do '$FP' bench '$DIR/rtgi_bench.json' --set rt_global_illumination.maxBounces=\$b --runs 1 --warmup 0 --decompose-rays 16 --json 2>/dev/null | python3 -c '
import json, sys
d = json.load(sys.stdin)
e = d[\"settings\"][0][\"errors\"][0]; t = e[\"decomposition\"]
assert [s[\"name\"] for s in t[\"steps\"]] == [\"noise\", \"bounces not traced\", \"left out\"], t
assert abs(sum(s[\"bias\"] for s in t[\"steps\"]) - t[\"bias\"]) < 1e-9, t
assert abs(sum(s[\"share\"] for s in t[\"steps\"]) - 1) < 1e-9, t
assert abs(t[\"rmse\"] - e[\"metrics\"][\"rmse\"]) <= 1e-9 * e[\"metrics\"][\"rmse\"], (t, e)
bounces = t[\"steps\"][1]
assert (bounces[\"rmse\"] == 0) == (sys.argv[1] == \"8\"), t
if sys.argv[1] == \"2\": assert bounces[\"bias\"] < 0, t  # the light of bounces 3 to 8 is missing
' \$b || exit 1; done"
check "bench --decompose-rays 0 leaves the decomposition out" bash -c "'$FP' bench '$DIR/ssgi_bench.json' --runs 1 --warmup 0 --decompose-rays 0 --json 2>/dev/null > '$DIR/nodec.json' && grep -q '\"rmse\"' '$DIR/nodec.json' && ! grep -q decomposition '$DIR/nodec.json'"
check "the bench report draws the decomposition" bash -c "'$FP' bench '$DIR/ssgi_bench.json' --runs 1 --warmup 0 --decompose-rays 8 --html '$DIR/dec.html' >/dev/null 2>&1 && grep -q 'Why the error is what it is' '$DIR/dec.html' && grep -q 'class=\"decomposition\"' '$DIR/dec.html'"

# tune: a target between the errors of quality 1 and 4 is met by exactly one of them; tune must
# pick it, and a separate bench of its cvars must measure the same error (the chain is
# deterministic), at or under the target.
check "tune picks the setting that meets the target, and bench confirms it" bash -c "set -o pipefail; '$FP' bench '$DIR/ssgi_bench.json' --runs 1 --warmup 0 --decompose-rays 0 --sweep r.SSGI.Quality=1,4 --json 2>/dev/null > '$DIR/tq.json' && target=\$(python3 -c 'import json; d=json.load(open(\"$DIR/tq.json\")); v=[[e[\"metrics\"][\"rmse\"] for e in s[\"errors\"] if e[\"name\"]==\"vs_full\"][0] for s in d[\"settings\"]]; assert v[0] != v[1], v; print((v[0]+v[1])/2)') && '$FP' tune '$DIR/ssgi_bench.json' --target \"vs_full<=\$target\" --sweep r.SSGI.Quality=1,4 --runs 1 --json 2>/dev/null > '$DIR/tune.json' && quality=\$(python3 -c 'import json; d=json.load(open(\"$DIR/tune.json\")); assert d[\"met\"]; print(d[\"choice\"][\"setting\"][\"cvars\"][\"r.SSGI.Quality\"])') && grep -q 'r.SSGI.Quality=' '$DIR/tune.json' && '$FP' bench '$DIR/ssgi_bench.json' --cvar r.SSGI.Quality=\$quality --runs 1 --warmup 0 --decompose-rays 0 --json 2>/dev/null | python3 -c 'import json,sys; d=json.load(sys.stdin); v=[e[\"metrics\"][\"rmse\"] for e in d[\"settings\"][0][\"errors\"] if e[\"name\"]==\"vs_full\"][0]; assert v <= float(sys.argv[1]), (v, sys.argv[1])' \$target"
check "tune refines between grid values along the Pareto front" bash -c "set -o pipefail; '$FP' bench '$DIR/ssgi_bench.json' --runs 1 --warmup 0 --decompose-rays 0 --sweep ssgi.rays=4,64 --json 2>/dev/null > '$DIR/tr.json' && target=\$(python3 -c 'import json; d=json.load(open(\"$DIR/tr.json\")); v=[[e[\"metrics\"][\"rmse\"] for e in s[\"errors\"] if e[\"name\"]==\"ao\"][0] for s in d[\"settings\"]]; assert v[1] < v[0], v; print((v[0]+v[1])/2)') && '$FP' tune '$DIR/ssgi_bench.json' --target \"ao<=\$target\" --sweep ssgi.rays=4,64 --runs 1 --json 2>/dev/null | python3 -c 'import json,sys; d=json.load(sys.stdin); r=[s for s in d[\"settings\"] if s[\"refined\"]]; assert r and all(4 < s[\"setting\"][\"params\"][\"ssgi.rays\"] < 64 for s in r), d; assert d[\"met\"]'"
check "tune says when no setting meets the target, and what stands in the way" expect_exit 1 "what stands in the way:" "$FP" tune "$DIR/ssgi_bench.json" --target "vs_full<=0.00001" --sweep r.SSGI.Quality=1,4 --runs 1 --warmup 0 --decompose-rays 8
# Half-float captures (Movie Render Queue's 16-bit EXR) against float32, the default lit chain with
# every output dumped as float32. Half rounding is at most 2^-11 relative per value. With depth
# kept float32 the HZB is the same bits (it reads depth only), and a colour output is at most a
# product of two rounded inputs (colour × DiffuseColor): its mean relative difference (SMAPE)
# stays within 2·2^-11 = 2^-10. With half depth, device Z moves by ≤ 2^-11 relative and the HZB
# texel rounds once more: ≤ 2^-10 absolute (device Z ≤ 1).
check "capture --half writes half buffers (and --float-depth keeps depth float32)" bash -c "'$FP' capture '$SRC/examples/cornell/scene.json' -o '$DIR/h_float.exr' --width 48 --height 48 >/dev/null && '$FP' capture '$SRC/examples/cornell/scene.json' -o '$DIR/h_half.exr' --width 48 --height 48 --half >/dev/null && '$FP' capture '$SRC/examples/cornell/scene.json' -o '$DIR/h_hfd.exr' --width 48 --height 48 --half --float-depth >/dev/null && '$FP' inspect '$DIR/h_half.exr' | grep -E '^ *SceneDepth' | grep -q half && '$FP' inspect '$DIR/h_hfd.exr' | grep -E '^ *SceneDepth' | grep -q float && '$FP' inspect '$DIR/h_hfd.exr' | grep -E '^ *BaseColor' | grep -q half"
check "half captures: HZB and colour outputs within half rounding of float32" bash -c "for v in float half hfd; do '$FP' -q run '$SRC/examples/stability/cornell.json' --capture \"$DIR/h_\$v.exr\" --dump all -o \"$DIR/h_\$v\" || exit 1; done && cmpd() { '$FP' -q compare \"$DIR/h_\$1/dump/\$2.0001.exr\" \"$DIR/h_float/dump/\$2.0001.exr\" --mask none --json | python3 -c 'import json,sys; m=json.load(sys.stdin); v=m[sys.argv[1]]; assert v <= float(sys.argv[2]), (sys.argv[3], m)' \$3 \$4 \$2; } && cmpd hfd hzb.furthest rmse 0 && cmpd half hzb.furthest maxError 0.0009765625 && for port in prev_color_reduction.color ssgi_denoise.diffuse diffuse_indirect_composite.color deferred_lighting_ceiling.color display.image; do cmpd hfd \$port smape 0.0009765625 || exit 1; done"
# run --decompose-rays takes the frame's errors apart into the output and the report: the same
# result, oracle and converged chain as bench's, so the same figures to the last bit; the error
# source it needs is kept in memory, not written as a dump.
check "run --decompose-rays reports bench's decomposition and writes no extra dump" bash -c "'$FP' run '$DIR/ssgi_bench.json' --dump vs_full.heat --decompose-rays 8 -o '$DIR/rdec' --report '$DIR/rdec.json' 2>/dev/null | grep -q 'taken apart' && '$FP' bench '$DIR/ssgi_bench.json' --decompose-rays 8 --runs 1 --warmup 0 --json 2>/dev/null > '$DIR/bdec.json' && [ \"\$(ls '$DIR/rdec/dump')\" = vs_full.heat.0001.exr ] && python3 -c '
import json
r = json.load(open(\"$DIR/rdec.json\")); b = json.load(open(\"$DIR/bdec.json\"))
rd = r[\"frames\"][0][\"errorDecomposition\"][\"vs_full\"]
bd = [e for e in b[\"settings\"][0][\"errors\"] if e[\"name\"] == \"vs_full\"][0][\"decomposition\"]
assert rd == bd, (rd, bd)
assert [s[\"name\"] for s in rd[\"steps\"]] == [\"noise\", \"approximation\", \"screen-space limit\", \"multi-bounce\"], rd
'"
# A config's explicit params beat cvars: sweeping a cvar they shadow measures one setting several
# times, so bench says so (once) instead of printing a table of identical rows.
check "bench warns when the config's params shadow a swept cvar" bash -c "sed 's/\"type\": \"ssgi\",/\"type\": \"ssgi\", \"params\": { \"quality\": 2 },/' '$DIR/ssgi_bench.json' > '$DIR/shadowed.json' && grep -q '\"quality\": 2' '$DIR/shadowed.json' && '$FP' bench '$DIR/shadowed.json' --runs 1 --warmup 0 --decompose-rays 0 --sweep r.SSGI.Quality=1,3 2>&1 >/dev/null | grep -c 'sets it too and wins' | grep -qx 1"
check "several frames of one capture file are a warning" bash -c "'$FP' bench '$DIR/ssgi_bench.json' --frames 1-2 --runs 1 --warmup 0 --decompose-rays 0 2>&1 >/dev/null | grep -q 'one file without a frame token: each of the 2 frames reads it'"
# bench over a sequence runs its frames in order with the temporal history, as run does: the
# error of the last frame is run's error on that frame (the chain is deterministic: the same
# bits), and the first frame's is a one-frame bench's.
check "capture a 3-frame truth sequence" "$FP" capture "$SRC/examples/cornell/scene.json" -o "$DIR/tseq.####.exr" --frames 1-3 --width 48 --height 48 --truth --truth-spp 8
check "bench --frames measures the last frame with history, as run does" bash -c "set -o pipefail; '$FP' bench '$DIR/ssgi_bench.json' --capture '$DIR/tseq.####.exr' --frames 1-3 --runs 2 --warmup 1 --decompose-rays 0 --json 2>/dev/null > '$DIR/seqb.json' && '$FP' bench '$DIR/ssgi_bench.json' --capture '$DIR/tseq.####.exr' --frames 1-3 --runs 1 --warmup 0 --decompose-rays 0 --html '$DIR/seq.html' >/dev/null 2>&1 && grep -q 'Error over the sequence' '$DIR/seq.html' && grep -q '<svg id=\"sequence\"' '$DIR/seq.html' && '$FP' bench '$DIR/ssgi_bench.json' --capture '$DIR/tseq.####.exr' --frames 1 --runs 1 --warmup 0 --decompose-rays 0 --json 2>/dev/null > '$DIR/seq1.json' && '$FP' run '$DIR/ssgi_bench.json' --capture '$DIR/tseq.####.exr' --frames 1-3 --dump vs_full.heat -o '$DIR/seqrun' --report '$DIR/seqrun.json' >/dev/null 2>&1 && python3 -c '
import json
b = json.load(open(\"$DIR/seqb.json\")); one = json.load(open(\"$DIR/seq1.json\")); run = json.load(open(\"$DIR/seqrun.json\"))
assert b[\"frames\"] == [1, 2, 3] and b[\"frame\"] == 3, b[\"frames\"]
e = {x[\"name\"]: x for x in b[\"settings\"][0][\"errors\"]}[\"vs_full\"]
byFrame = e[\"rmseByFrame\"]
assert len(byFrame) == 3 and byFrame[-1] == e[\"metrics\"][\"rmse\"], e
assert byFrame[0] == {x[\"name\"]: x for x in one[\"settings\"][0][\"errors\"]}[\"vs_full\"][\"metrics\"][\"rmse\"]
ran = [p[\"metrics\"][\"rmse\"] for f in run[\"frames\"] for p in f[\"passes\"] if p[\"name\"] == \"vs_full\"]
assert ran == byFrame, (ran, byFrame)
'"
check "tune names the error_measure passes when the target names none" expect_exit 2 "has no error_measure pass 'vs_ful' (did you mean 'vs_full'?)" "$FP" tune "$DIR/ssgi_bench.json" --target "vs_ful<=0.1"
check "tune rejects a malformed target" expect_exit 2 "expected ERROR_PASS<=VALUE" "$FP" tune "$DIR/ssgi_bench.json" --target "vs_full=0.1"

# --- contact sheet -------------------------------------------------------------------------------
# The 64×64 capture has one tile per buffer; --columns 4 --tile 64 gives 4 columns × ⌈n/4⌉ rows of
# 64 × (30-px label + 64) pixels.
check "sheet of a capture: one tile per layer, kinds by buffer, PNG sized by the layout" bash -c "set -o pipefail; '$FP' sheet '$DIR/cornell.exr' -o '$DIR/sheet.png' --columns 4 --tile 64 --json > '$DIR/sheet.json' && python3 - '$DIR/sheet.json' '$DIR/sheet.png' <<'PY'
import json, struct, sys
j = json.load(open(sys.argv[1]))
kinds = {t['layer']: t['kind'] for t in j['tiles']}
expected = {'SceneDepth': 'depth', 'PrevSceneDepth': 'depth', 'WorldNormal': 'normal',
            'SceneColor': 'colour', 'BaseColor': 'colour', 'Emissive': 'colour',
            'PrevSceneColor': 'colour', 'TAAHistory': 'colour', 'ShadingModel': 'id',
            'Roughness': 'data', 'Metallic': 'data', 'Velocity': 'data'}
for layer, kind in expected.items():
    assert kinds.get(layer) == kind, (layer, kinds.get(layer), kind)
n = len(j['tiles'])
assert n == 17, n  # the 17 buffers framepass capture writes
depth = next(t for t in j['tiles'] if t['layer'] == 'SceneDepth')
assert depth['range']['scale'] == 'log' and 0 < depth['range']['min'] < depth['range']['max'], depth
assert depth['skyPixels'] > 0, depth  # the box's open front shows sky
assert next(t for t in j['tiles'] if t['layer'] == 'SceneColor')['range'] is None
rows = (n + 3) // 4
png = open(sys.argv[2], 'rb').read(24)
w, h = struct.unpack('>II', png[16:24])
assert (w, h) == (4 * 64, rows * (30 + 64)) == (j['width'], j['height']), (w, h, rows)
PY"
check "sheet of a run's dumps labels each tile file: layer" bash -c "'$FP' sheet '$DIR/t1/dump' -o '$DIR/dump_sheet.png' > '$DIR/dump_sheet.txt' && grep -q 'hzb.furthest.0001.exr: hzb.furthest' '$DIR/dump_sheet.txt' && grep -q 'ssgi.ao.0001.exr: ssgi.ao' '$DIR/dump_sheet.txt' && test -s '$DIR/dump_sheet.png'"
mkdir -p "$DIR/empty"
check "sheet of a folder with no EXR exits 2" expect_exit 2 "no .exr files" "$FP" sheet "$DIR/empty" -o "$DIR/none.png"
check "compare's heat-map PNG carries a 30-px colour bar with its scale" bash -c "python3 -c \"import struct,sys; d=open('$DIR/heat.png','rb').read(24); w,h=struct.unpack('>II',d[16:24]); sys.exit(0 if (w,h)==(48,48+30) else 1)\""
check "the bench report shows each heat map's scale" grep -q 'data-heat-scale=' "$DIR/dom.html"

# --- CLI habits ----------------------------------------------------------------------------------
check "--threads after the subcommand works like before it" bash -c "'$FP' run '$DIR/config.json' --threads 2 -o '$DIR/t4' --dump all >/dev/null && diff -r '$DIR/t1' '$DIR/t4'"
check "-q prints nothing on stderr; without it, progress goes to stderr, not stdout" bash -c "'$FP' -q run '$DIR/config.json' -o '$DIR/t5' 2> '$DIR/q.err' > '$DIR/q.out' && [ ! -s '$DIR/q.err' ] && grep -q 'frame 1:' '$DIR/q.out' && '$FP' run '$DIR/config.json' -o '$DIR/t5' 2> '$DIR/n.err' > '$DIR/n.out' && grep -q 'Progress: 100%' '$DIR/n.err' && ! grep -q Progress '$DIR/n.out'"
check "-v prints each pass's time on stderr as it runs" bash -c "'$FP' run '$DIR/config.json' -o '$DIR/t5' -v 2> '$DIR/v.err' >/dev/null && grep -Eq '^  hzb +[0-9.]+ ms texels=' '$DIR/v.err' && grep -q '^frame 1:' '$DIR/v.err'"
check "-q and -v together are a usage error" expect_exit 2 "excludes" "$FP" -q -v plan "$DIR/config.json"
for cmd in "bench '$DIR/bench.json' --runs 1 --warmup 0 --sweep hzb.halfPrecision=false,true" \
           "inspect '$DIR/cornell.exr'" "plan '$DIR/config.json'" "passes" "passes hzb" \
           "compare '$DIR/truth.exr' '$DIR/truth.exr' --layer Truth.AO --heatmap '$DIR/heat2.exr'" \
           "sheet '$DIR/cornell.exr' -o '$DIR/sheet2.png'" \
           "tune '$DIR/ssgi_bench.json' --target 'vs_full<=1' --sweep r.SSGI.Quality=1,2 --runs 1"; do
    check "${cmd%% *} --json prints only JSON on stdout" bash -c "set -o pipefail; '$FP' $cmd --json 2>/dev/null | python3 -m json.tool >/dev/null"
done
check "an unknown --cvar is an error with a did-you-mean" expect_exit 2 "--cvar r.SSGI.Qualty: unknown cvar 'r.SSGI.Qualty' (did you mean 'r.SSGI.Quality'?)" "$FP" plan "$DIR/config.json" --cvar r.SSGI.Qualty=2
echo '{ "version": 1, "capture": "cornell.exr", "cvars": { "r.SSGI.Qualty": 2 } }' > "$DIR/typo.json"
check "an unknown cvar in the config is an error naming its pointer" expect_exit 2 "/cvars/r.SSGI.Qualty: unknown cvar" "$FP" run "$DIR/typo.json" -o "$DIR/typo"
check "--allow-unknown-cvars makes it a warning" expect_exit 0 "warning: /cvars/r.SSGI.Qualty: unknown cvar 'r.SSGI.Qualty' is ignored" "$FP" plan "$DIR/typo.json" --allow-unknown-cvars
check "a recognised but unemulated cvar stays a warning" expect_exit 0 "is not emulated by framepass" "$FP" plan "$DIR/config.json" --cvar r.DynamicGlobalIlluminationMethod=1
check "report.json records version, command line, threads and every input file" python3 - "$DIR/t1.json" "$DIR/config.json" "$DIR/cornell.exr" <<'PY'
import json, os, sys
r = json.load(open(sys.argv[1]))
assert r['framepass']['version'] == '0.1.0', r['framepass']
assert r['commandLine'].split()[1:3] == ['--threads', '1'] and 'run' in r['arguments'], r['commandLine']
assert r['threads'] == {'requested': 1, 'used': 1}, r['threads']
byRole = {}
for f in r['inputs']:
    byRole.setdefault(f['role'], []).append(f)
for role, path in (('config', sys.argv[2]), ('capture', sys.argv[3])):
    f = byRole[role][0]
    assert os.path.samefile(f['path'], path), f
    assert f['bytes'] == os.path.getsize(path), f
    assert f['mtimeNs'] == os.stat(path).st_mtime_ns, f
    assert f['mtime'].endswith('Z'), f
assert byRole['preset'][0]['path'].endswith('ue4.27.json')
assert byRole['ocioConfig'][0]['path'].endswith('config.ocio')
PY
check "report.json lists the scene and its geometry when the chain traces rays" bash -c "'$FP' run '$DIR/lit.json' -o '$DIR/l4' --report '$DIR/l4.json' >/dev/null && python3 -c \"import json; r=json.load(open('$DIR/l4.json')); roles={f['role'] for f in r['inputs']}; assert {'scene','geometry','capture','config'} <= roles, roles\""

# Command-line habits: typos, `version`, error prefixes, "-" for stdin and stdout, cvars as
# Unreal takes them, the resolved parameters and the chain as a Graphviz graph.
check "a mistyped command gets a did-you-mean, exit 2" expect_exit 2 "'rn' is not a framepass command (did you mean 'run'?)" "$FP" rn "$DIR/config.json"
check "framepass version" bash -c "'$FP' version | grep -qx 'framepass 0.1.0'"
check "an unknown option carries the framepass error: prefix" expect_exit 2 "framepass error: The following argument was not expected: --bogus" "$FP" plan "$DIR/config.json" --bogus
check "a config on stdin (-), its paths relative to the working directory" bash -c "cd '$DIR' && '$FP' plan - < config.json | grep -q 'plan for - (1 frame, capture cornell.exr)'"
check "--report - prints the report as the only thing on stdout" bash -c "set -o pipefail; '$FP' run '$DIR/config.json' -o '$DIR/rstd' --report - 2>/dev/null | python3 -c 'import json, sys; r = json.load(sys.stdin); assert r[\"frames\"][0][\"status\"] == \"ok\", r[\"frames\"]'"
check "cvar names in any case and \"NAME VALUE\" as the console takes them" bash -c "'$FP' plan '$DIR/config.json' --cvar 'r.ssgi.quality 2' | grep -q 'quality=2'"
printf '; tune wrote this\n[SystemSettings]\nr.SSGI.Quality=3\n[/Script/Engine.RendererSettings]\nr.SSGI.Quality=1\n' > "$DIR/tuned.ini"
check "--cvars reads [SystemSettings] of an Unreal .ini and skips other sections, saying so" bash -c "'$FP' plan '$DIR/config.json' --cvars '$DIR/tuned.ini' > '$DIR/ini.txt' 2> '$DIR/ini.err' && grep -q 'quality=3' '$DIR/ini.txt' && grep -q '1 line of \[/Script/Engine.RendererSettings\] skipped' '$DIR/ini.err'"
check "--cvar wins over --cvars" bash -c "'$FP' plan '$DIR/config.json' --cvars '$DIR/tuned.ini' --cvar r.SSGI.Quality=1 2>/dev/null | grep -q 'quality=1'"
check "tune's [SystemSettings] snippet reads back in" bash -c "'$FP' tune '$DIR/ssgi_bench.json' --target 'vs_full<=1' --sweep r.SSGI.Quality=1,2 --runs 1 2>/dev/null | sed -n '/^\[SystemSettings\]/,/^\$/p' > '$DIR/tune.ini' && grep -q '^r.SSGI.Quality=' '$DIR/tune.ini' && '$FP' plan '$DIR/config.json' --cvars '$DIR/tune.ini' > /dev/null"
check "plan --dot writes the chain as a Graphviz graph, culled passes greyed" bash -c "'$FP' plan '$DIR/reduced_only.json' --dot '$DIR/chain.dot' > /dev/null && grep -q '\"hzb\":\"out_furthest\" -> \"prev_color_reduction\":\"in_furthestHzb\"' '$DIR/chain.dot' && grep -q '\"ssgi\" \[shape=box, style=\"filled,dashed\"' '$DIR/chain.dot' && grep -q '^}' '$DIR/chain.dot'"
check "a bad OCIO display fails when planning, naming the pass" expect_exit 2 "(display): OCIO display transform (space 'scene_linear', display 'Nope'" "$FP" plan "$DIR/config.json" --set display.display=Nope
check "a bad \$OCIO fails when planning" bash -c "OCIO='$DIR/nope.ocio' '$FP' run '$DIR/config.json' -o '$DIR/bad_ocio' > '$DIR/ocio.log' 2>&1; [ \$? = 2 ] && grep -q 'cannot load the OCIO config' '$DIR/ocio.log' && test ! -e '$DIR/bad_ocio/indirect.0001.exr'"
# compare measures what users compare: one channel, a product of layers, a mask, a PNG.
cmpjson() { "$FP" compare "$@" --json 2>/dev/null; }
check "compare one channel of a layer" bash -c "$(declare -f cmpjson); FP='$FP'; cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer WorldNormal.Y | python3 -c 'import json, sys; j = json.load(sys.stdin); assert j[\"rmse\"] == 0 and j[\"a\"][\"layer\"] == \"WorldNormal.Y\", j'"
# GBufferAO is 1 on every surface of the Cornell box: BaseColor × GBufferAO is BaseColor exactly.
check "compare a product of two layers (Blender's light × colour)" bash -c "$(declare -f cmpjson); FP='$FP'; cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer 'BaseColor*GBufferAO' --ref-layer BaseColor | python3 -c 'import json, sys; j = json.load(sys.stdin); assert j[\"rmse\"] == 0 and j[\"pixels\"] > 3000, j'"
check "a mask picture keeps the pixels where it is above 0" bash -c "oiiotool --create 64x64 3 --fill:color=1,1,1 32x64+0+0 -d uint8 -o '$DIR/left.png' && $(declare -f cmpjson); FP='$FP'; cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor --mask none --mask '$DIR/left.png' | python3 -c 'import json, sys; j = json.load(sys.stdin); assert j[\"pixels\"] == 32 * 64, j'"
check "--mask shading-model=N keeps one shading model (every surface of the box is default lit)" bash -c "$(declare -f cmpjson); FP='$FP'; a=\$(cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor --mask shading-model=1 | python3 -c 'import json, sys; print(json.load(sys.stdin)[\"pixels\"])'); b=\$(cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor | python3 -c 'import json, sys; print(json.load(sys.stdin)[\"pixels\"])'); n=\$(cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor --mask shading-model=7 | python3 -c 'import json, sys; print(json.load(sys.stdin)[\"pixels\"])'); [ \$a = \$b ] && [ \$n = 0 ] && [ \$a -gt 3000 ]"
check "--mask id=N keeps one object, and masks multiply" bash -c "$(declare -f cmpjson); FP='$FP'; a=\$(cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor --mask id=1 | python3 -c 'import json, sys; print(json.load(sys.stdin)[\"pixels\"])'); b=\$(cmpjson '$DIR/cornell.exr' '$DIR/cornell.exr' --layer SceneColor --mask id=1 --mask '$DIR/left.png' | python3 -c 'import json, sys; print(json.load(sys.stdin)[\"pixels\"])'); [ \$a -gt 0 ] && [ \$b -lt \$a ]"
# An 8-bit PNG holds each value to within half a step: |error| ≤ 0.5/255 on values in 0..1.
check "compare reads PNG through OpenImageIO (8-bit: RMSE ≤ 0.5/255 against the EXR)" bash -c "oiiotool '$DIR/cornell.exr' --subimage BaseColor --ch R=BaseColor.R,G=BaseColor.G,B=BaseColor.B -d uint8 -o '$DIR/base.png' &&
    oiiotool '$DIR/cornell.exr' --subimage BaseColor --ch R=BaseColor.R,G=BaseColor.G,B=BaseColor.B -d float -o '$DIR/base.exr' &&
    '$FP' compare '$DIR/base.png' '$DIR/base.exr' --mask none --max-rmse 0.00197"

# The bash completion and the man page the build makes, and `cmake --install`.
BUILD="$(cd "$(dirname "$FP")/.." && pwd)"
complete_words() {  # complete_words WORD...: what bash completion offers for the last word
    bash -c 'source "$1/cli/framepass.bash"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _framepass; echo "${COMPREPLY[@]}"' _ "$BUILD" "$@"
}
check "bash completion: commands" bash -c "[ \"\$($(declare -f complete_words); BUILD='$BUILD'; complete_words framepass ru)\" = run ]"
check "bash completion: a subcommand's options" bash -c "$(declare -f complete_words); BUILD='$BUILD'; complete_words framepass run cfg.json --warm | grep -qx -- '--warmup-frames'"
check "bash completion: cvar names after --cvar, pass parameters after --set" bash -c "$(declare -f complete_words); BUILD='$BUILD'; complete_words framepass run cfg.json --cvar r.SSGI.Qu | grep -q 'r.SSGI.Quality=' && complete_words '$FP' plan '$DIR/config.json' --set ssgi_denoise.temp | grep -q 'ssgi_denoise.temporalAccumulation='"
check "the man page is made from --help" bash -c "grep -q '^.TH FRAMEPASS' '$BUILD/cli/framepass.1' && grep -q 'tune' '$BUILD/cli/framepass.1'"

# Completion after --set and --dump: the names of the chain the config resolves to (the preset's
# light template expanded: rt_shadows_ceiling, never the type's rt_shadows), for bash, zsh and fish;
# the zsh and fish scripts parse; the man page has every command, the exit codes and examples.
check "completion --names: the chain's own passes, its parameters, inputs and ports" bash -c "'$FP' plan '$DIR/rt.json' --json > '$DIR/rt_plan.json' 2>/dev/null && '$FP' completion --names '$DIR/rt.json' > '$DIR/rt_names.txt' && python3 - '$DIR/rt_plan.json' '$DIR/rt_names.txt' <<'PY'
import json, sys
plan = json.load(open(sys.argv[1])); names = open(sys.argv[2]).read().split()
passes = {s['name'] for s in plan['steps']} | {c['name'] for c in plan['culled']}
assert {n.split('.')[0] for n in names} == passes, ({n.split('.')[0] for n in names} ^ passes)
for s in plan['steps']:
    for p in s['params']: assert f\"{s['name']}.{p}=\" in names, (s['name'], p)
    for p in s['inputs']: assert f\"{s['name']}.{p}=\" in names, (s['name'], p)
    for o in s['outputs']: assert f\"{s['name']}.{o}\" in names, (s['name'], o)
assert 'rt_shadows_ceiling.shadow' in names and not any(n.startswith('rt_shadows.') for n in names)
PY"
check "completion --names --for: --set's parameters, --input's inputs and --dump's ports apart" bash -c "for k in set input dump; do '$FP' completion --names '$DIR/rt.json' --for \$k > '$DIR/rt_names_'\$k.txt || exit 1; done; python3 - '$DIR/rt_plan.json' '$DIR' <<'PY'
import json, sys
plan = json.load(open(sys.argv[1])); d = sys.argv[2]
got = {k: open(f'{d}/rt_names_{k}.txt').read().split() for k in ('set', 'input', 'dump')}
assert sorted(sum(got.values(), [])) == sorted(open(f'{d}/rt_names.txt').read().split())
for s in plan['steps']:
    for p in s['params']: assert f\"{s['name']}.{p}=\" in got['set'], (s['name'], p)
    for p in s['inputs']: assert f\"{s['name']}.{p}=\" in got['input'], (s['name'], p)
    for o in s['outputs']: assert f\"{s['name']}.{o}\" in got['dump'], (s['name'], o)
assert not set(got['set']) & set(got['input'])
PY"
check "every name --names offers for --dump is one the chain takes (and rt_shadows.shadow is not)" bash -c "'$FP' plan '$DIR/rt.json' --dump rt_shadows_ceiling.shadow > /dev/null 2>&1 && ! '$FP' plan '$DIR/rt.json' --dump rt_shadows.shadow > /dev/null 2>&1 && for n in \$(grep -v '=\$' '$DIR/rt_names.txt'); do '$FP' -q plan '$DIR/rt.json' --dump \$n > /dev/null || { echo \"--dump \$n fails\"; exit 1; }; done"
check "completion --names of a config that does not plan is a usage error" expect_exit 2 "framepass error" "$FP" completion --names "$DIR/no_such_config.json"
check "bash completion: --set, --input and --dump offer the config's chain" bash -c "$(declare -f complete_words); BUILD='$BUILD'; complete_words '$FP' plan '$DIR/rt.json' --dump rt_sh | tr ' ' '\n' > '$DIR/bash_dump.txt' && grep -qx 'rt_shadows_ceiling.shadow' '$DIR/bash_dump.txt' && ! grep -q '^rt_shadows\.' '$DIR/bash_dump.txt' && complete_words '$FP' run '$DIR/rt.json' -o out --set rt_shadows_c | grep -q 'rt_shadows_ceiling.light=' && [ -z \"\$(complete_words '$FP' run --set rt_sh)\" ] && complete_words '$FP' run '$DIR/rt.json' --input rt_shadows_c | tr ' ' '\n' > '$DIR/bash_input.txt' && grep -q '^rt_shadows_ceiling\..*=\$' '$DIR/bash_input.txt' && ! grep -q 'rt_shadows_ceiling.light=' '$DIR/bash_input.txt'"
for shell in zsh fish; do
    check "completion $shell: the build's script is what the command prints" bash -c "'$FP' completion $shell | cmp - '$BUILD/cli/framepass.$shell'"
    if command -v $shell > /dev/null; then
        check "completion $shell: $shell -n parses the script" $shell -n "$BUILD/cli/framepass.$shell"
    else
        echo "skip completion $shell: $shell -n (no $shell here: apt-get install $shell)"
    fi
done
if command -v zsh > /dev/null; then
    check "completion zsh: --set and --dump offer the config's chain" bash -c "zsh -fc 'compdef() { :; }; source \"\$1\"; words=(\"\$2\" plan \"\$3\" --dump \"\"); CURRENT=5; _framepass_names dump' _ '$BUILD/cli/framepass.zsh' '$FP' '$DIR/rt.json' | grep -qx 'rt_shadows_ceiling.shadow' && zsh -fc 'compdef() { :; }; source \"\$1\"; words=(\"\$2\" --threads 2 run \"\$3\" -o out --set \"\"); CURRENT=8; _framepass_names set' _ '$BUILD/cli/framepass.zsh' '$FP' '$DIR/rt.json' | grep -qx 'rt_shadows_ceiling.light='"
fi
if command -v fish > /dev/null; then
    check "completion fish: commands, options, and the config's chain after --set and --dump" env FP="$FP" SCRIPT="$BUILD/cli/framepass.fish" CFG="$DIR/rt.json" bash -c "fish --no-config -c 'function framepass; \"\$FP\" \$argv; end; source \"\$SCRIPT\"; complete -C\"framepass ru\"; complete -C\"framepass run \$CFG --warm\"; complete -C\"framepass plan \$CFG --dump rt_sh\"; complete -C\"framepass plan \$CFG --set rt_shadows_c\"' > '$DIR/fish.txt' && grep -q '^run' '$DIR/fish.txt' && grep -q '^--warmup-frames' '$DIR/fish.txt' && grep -q '^rt_shadows_ceiling.shadow' '$DIR/fish.txt' && grep -q '^rt_shadows_ceiling.light=' '$DIR/fish.txt' && ! grep -q '^rt_shadows\.' '$DIR/fish.txt'"
fi
check "the man page: a section per command, exit status, examples, no '???' (help2man under UTF-8)" bash -c "page='$BUILD/cli/framepass.1'; ! grep -q '???' \"\$page\" && grep -q 'framepass \\\\(em re\\\\-run\\|framepass — re' \"\$page\" && grep -q '^.SH \"EXIT STATUS\"' \"\$page\" && grep -q '^.SH EXAMPLES' \"\$page\" && grep -q '^.B 143\\|130, 143' \"\$page\" && for c in \$('$FP' --help | sed -n '/^Subcommands:/,\$p' | grep -o '^  [a-z]*'); do grep -q \"^.SS \\\"framepass \$c\\\"\" \"\$page\" || { echo \"no section for \$c\"; exit 1; }; done"
check "dot renders plan --dot" bash -c "command -v dot >/dev/null || { echo 'no dot (apt-get install graphviz)'; exit 1; }; dot -Tsvg '$DIR/chain.dot' -o '$DIR/chain.svg' && grep -q '<svg' '$DIR/chain.svg'"
check "cmake --install puts the binary, the completion, the man page and the configs in place" bash -c "cmake --install '$BUILD' --prefix '$DIR/prefix' > /dev/null &&
    test -x '$DIR/prefix/bin/framepass' && test -f '$DIR/prefix/share/bash-completion/completions/framepass' &&
    test -f '$DIR/prefix/share/man/man1/framepass.1' && test -f '$DIR/prefix/share/framepass/configs/ue4.27.json' &&
    '$DIR/prefix/bin/framepass' passes > /dev/null"

finish
