#!/usr/bin/env bash
# The bad-input corpus: every line of cases.tsv runs framepass on one broken input and asserts its
# exit code and a word of its message; no case may crash (exit ≥ 128: a signal, ASan's abort) and
# no EXR a case writes may hold a NaN (`framepass inspect --json` counts them).
# Usage: run.sh FRAMEPASS SOURCE_DIR SCRATCH [CASE_NAME_FILTER]
set -u
FP="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"  # absolute: cases run in the inputs folder
SRC="$(cd "$2" && pwd)"; DIR="$3/bad_inputs"; FILTER="${4:-}"
HERE="$SRC/tests/bad_inputs"
rm -rf "$DIR"; mkdir -p "$DIR"; DIR="$(cd "$DIR" && pwd)"
I="$DIR/in"  # the committed small files and the generated ones, side by side
cp -r "$HERE/files" "$I"
python3 "$HERE/make_inputs.py" "$I" || { echo "FAIL make_inputs.py"; exit 1; }
mkdir -p "$I/folder_config.json"  # a config path that is a folder

n=0
# vcfg CAPTURE [SIDECAR]: a config running camera_velocity (depth + camera only) on CAPTURE.
vcfg() {
    n=$((n + 1))
    local cam=""; [ -n "${2:-}" ] && cam="\"camera\": \"$2\","
    cat > "$I/vcfg$n.json" <<JSON
{ "version": 1, "capture": "$1", $cam
  "passes": [ { "type": "camera_velocity" } ],
  "outputs": { "v.####.exr": "camera_velocity.velocity" } }
JSON
    echo "$I/vcfg$n.json"
}
# chain CAPTURE: the whole Unreal 4.27 preset on a depth-only capture, every other buffer a
# constant through an inline profile (so one generated EXR exercises every pass); with a second
# argument the capture's own WorldNormal is read.
chain() {
    n=$((n + 1))
    local normal='"WorldNormal": { "constant": [0, 0, -1] },'
    [ -n "${2:-}" ] && normal=""
    cat > "$I/chain$n.json" <<JSON
{ "version": 1, "capture": "$1",
  "profile": { "base": "canonical", "buffers": {
    $normal "BaseColor": { "constant": 0.5 },
    "Metallic": { "constant": 0 }, "Specular": { "constant": 0.5 },
    "Roughness": { "constant": 0.5 }, "ShadingModel": { "constant": 1 },
    "GBufferAO": { "constant": 1 }, "CustomData": { "constant": 0 },
    "SceneColor": [ { "channels": ["SceneColor.R", "SceneColor.G", "SceneColor.B"] },
                    { "constant": 0.25 } ],
    "PrevSceneColor": { "constant": 0.25 }, "PrevSceneDepth": { "channels": ["SceneDepth.Z"] },
    "TAAHistory": { "constant": 0.25 }, "Velocity": { "constant": 0 } } } }
JSON
    echo "$I/chain$n.json"
}

nan_count() {  # NaN values in the EXRs under $1
    local total=0 f c
    while IFS= read -r f; do
        c=$("$FP" inspect "$f" --json 2>/dev/null | python3 -c '
import json, sys
d = json.load(sys.stdin)
def walk(o):
    if isinstance(o, dict):
        return (o.get("nan", 0) if isinstance(o.get("nan", 0), int) else 0) + sum(walk(v) for v in o.values())
    if isinstance(o, list):
        return sum(walk(v) for v in o)
    return 0
print(walk(d))' || echo "unreadable")
        [ "$c" = "unreadable" ] && { echo "$f: inspect failed" >&2; c=1; }
        total=$((total + c))
    done < <(find "$1" -name '*.exr' -type f 2>/dev/null)
    echo "$total"
}

passed=0; failed=0; crashed=0; cases=0
while IFS=$'\t' read -r name code word cmd; do
    case "$name" in ''|'#'*) continue ;; esac
    [ -n "$FILTER" ] && [[ "$name" != *"$FILTER"* ]] && continue
    cases=$((cases + 1))
    OUT="$DIR/out/$name"; mkdir -p "$OUT"
    (cd "$I" && eval "$cmd") </dev/null >"$DIR/$name.log" 2>&1
    got=$?
    why=""
    if [ "$got" -ge 128 ]; then why="CRASH (exit $got)"; crashed=$((crashed + 1))
    elif [ "$got" != "$code" ]; then why="exit $got, expected $code"
    elif [ "$word" != "-" ] && ! grep -qF -- "$word" "$DIR/$name.log"; then why="no '$word' in the message"
    elif grep -q "internal error" "$DIR/$name.log"; then why="an internal error, not a clear one"
    else
        nans=$(nan_count "$OUT")
        [ "$nans" != 0 ] && why="$nans NaN in its outputs"
    fi
    if [ -z "$why" ]; then
        passed=$((passed + 1)); echo "ok   $name ($code) $(grep -m1 -o 'framepass error: .*' "$DIR/$name.log" | cut -c1-110)"
    else
        failed=$((failed + 1)); echo "FAIL $name: $why"; sed 's/^/     /' "$DIR/$name.log" | tail -8
    fi
done < "$HERE/cases.tsv"
echo "$cases cases: $passed passed, $failed failed ($crashed crashed)"
[ "$failed" = 0 ] && [ "$cases" -gt 0 ]
