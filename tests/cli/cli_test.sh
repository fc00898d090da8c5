#!/usr/bin/env bash
# End-to-end checks of the framepass executable: capture → plan → run, determinism across thread
# counts and reruns, exit codes and error messages. Usage: cli_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
FP="$1"; SRC="$2"; DIR="$3/cli"
rm -rf "$DIR"; mkdir -p "$DIR"
passed=0; failed=0
check() {  # check NAME COMMAND...
    local name="$1"; shift
    if "$@" >"$DIR/last.log" 2>&1; then passed=$((passed + 1)); echo "ok   $name"
    else failed=$((failed + 1)); echo "FAIL $name"; sed 's/^/     /' "$DIR/last.log" | tail -20; fi
}
expect_exit() {  # expect_exit CODE PATTERN COMMAND...
    local code="$1" pattern="$2"; shift 2
    "$@" >"$DIR/out.log" 2>&1; local got=$?
    [ "$got" = "$code" ] || { echo "exit $got, expected $code"; cat "$DIR/out.log"; return 1; }
    grep -qF -- "$pattern" "$DIR/out.log" || { echo "missing: $pattern"; cat "$DIR/out.log"; return 1; }
}

check "capture the Cornell box at 64×64" "$FP" capture "$SRC/examples/cornell/scene.json" -o "$DIR/cornell.exr" --width 64 --height 64
cat > "$DIR/config.json" <<JSON
{ "version": 1, "capture": "cornell.exr" }
JSON
check "inspect lists the buffers and the camera" bash -c "'$FP' inspect '$DIR/cornell.exr' --json | grep -q '\"previous\"'"
check "plan reads only the channels of surviving passes" bash -c "'$FP' plan '$DIR/config.json' --json > '$DIR/plan.json' && grep -q 'PrevSceneDepth.Z' '$DIR/plan.json' && ! grep -q 'WorldNormal' '$DIR/plan.json'"
check "run with 1 thread" "$FP" --threads 1 run "$DIR/config.json" -o "$DIR/t1" --dump all --report "$DIR/t1.json"
check "run with 2 threads" "$FP" --threads 2 run "$DIR/config.json" -o "$DIR/t2" --dump all
check "1-thread and 2-thread outputs are byte-identical" diff -r "$DIR/t1" "$DIR/t2"
check "a rerun is byte-identical" bash -c "'$FP' run '$DIR/config.json' -o '$DIR/t3' --dump all >/dev/null && diff -r '$DIR/t1' '$DIR/t3'"
check "the report has per-pass time and work" grep -q '"texels"' "$DIR/t1.json"
check "the report lists the channels actually read" bash -c "grep -q 'SceneColor.R' '$DIR/t1.json' && ! grep -q 'BaseColor' '$DIR/t1.json'"
check "mip chains are written one part per mip" bash -c "'$FP' inspect '$DIR/t1/hzb.0001.exr' | grep -q '10 part(s)' && '$FP' inspect '$DIR/t1/hzb.0001.exr' | grep -q 'hzb.furthest.mip4'"
check "--cvar reaches the pass (TAA history instead of leak-free)" bash -c "'$FP' plan '$DIR/config.json' --cvar r.SSGI.LeakFreeReprojection=0 | grep -q 'history←capture:TAAHistory'"

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
check "passes documents every type" bash -c "'$FP' passes | grep -q prev_color_reduction && '$FP' passes hzb | grep -q halfPrecision"
check "an unknown pass type gets a suggestion" expect_exit 2 "did you mean 'display'?" "$FP" passes dispaly
check "the hard-case glTF scene captures (10^7 from the origin)" "$FP" capture "$SRC/examples/hard/scene.json" -o "$DIR/hard.exr" --width 64 --height 64
check "outputs never overwrite an input" bash -c "cp '$DIR/cornell.exr' '$DIR/final.0001.png'; cat > '$DIR/self.json' <<J
{ \"version\": 1, \"capture\": \"final.0001.png\" }
J
! '$FP' run '$DIR/self.json' -o '$DIR' >/dev/null 2>&1; cmp '$DIR/cornell.exr' '$DIR/final.0001.png'"

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
