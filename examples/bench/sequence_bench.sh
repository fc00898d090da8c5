#!/usr/bin/env bash
# The figures of docs/results/sequence.md: a 1080p shot (the glossy room, half-float capture,
# Unreal 4.27's chain, its default outputs: two EXRs and a PNG) run end to end by `framepass run`,
# files in and out, with and without the pipeline; every pass's thread scaling (bench at 2 threads
# against all); the bytes compared between the ways. On a machine without a GPU the CUDA runs
# are left out.
#   examples/bench/sequence_bench.sh FRAMEPASS WORK_DIR [FRAMES] [FRAMEPASS_BEFORE]
# FRAMEPASS_BEFORE: an earlier build, run the same way beside it (CPU only) for a paired ratio.
# Prints one JSON summary on stdout (WORK_DIR/summary.json too); progress goes to stderr.
set -euo pipefail
FP=$(realpath "$1"); WORK=$2; FRAMES=${3:-1-12}; BEFORE=${4:-}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$WORK" && cd "$WORK"
say() { echo "sequence_bench: $*" >&2; }

if [ ! -e cap/g.0001.exr ]; then
    say "capturing frames $FRAMES at 1920x1080"
    "$FP" -q capture "$SRC/examples/glossy/scene.json" -o 'cap/g.####.exr' --frames "$FRAMES" \
        --width 1920 --height 1080 --half --float-depth >&2
fi
echo '{ "version": 1, "capture": "cap/g.####.exr" }' > cfg.json
echo '{ "version": 1, "capture": "cap/g.####.exr", "exr": { "compression": "none" } }' > cfg_none.json

gpu=0  # a GPU answers, and this build runs passes on it
if nvidia-smi -L > /dev/null 2>&1 && "$FP" plan cfg.json --frames 1 --device cuda 2>&1 |
        grep -q '^device: cuda (' && ! "$FP" plan cfg.json --frames 1 --device cuda 2>&1 |
        grep -q 'not usable here'; then gpu=1; fi
cores=$(nproc)
runs=()
shot() {  # shot LABEL BINARY CONFIG ARGS...: one run of the shot, its report kept
    local label=$1 bin=$2 cfg=$3; shift 3
    say "$label"
    rm -rf "o_$label"
    /usr/bin/time -f "%e %M %U %S" -o "time_$label.txt" "$bin" -q run "$cfg" --frames "$FRAMES" \
        -o "o_$label" --report "rep_$label.json" "$@" > "log_$label.txt" 2>&1
    runs+=("$label")
}
shot cpu "$FP" cfg.json
shot cpu_serial "$FP" cfg.json --writers 0 --no-read-ahead
[ -n "$BEFORE" ] && shot cpu_before "$(realpath "$BEFORE")" cfg.json
if [ $gpu = 1 ]; then
    shot cuda "$FP" cfg.json --device cuda
    shot cuda_serial "$FP" cfg.json --device cuda --writers 0 --no-read-ahead
    shot cuda_read8_writers8 "$FP" cfg.json --device cuda --read-ahead 8 --writers 8
    shot cuda_uncompressed "$FP" cfg_none.json --device cuda
fi
# Every pass at 2 threads and at all: the second frame (with history), 5 timed runs each.
for t in 2 "$cores" 2x "${cores}x"; do
    say "bench at ${t%x} threads"
    "$FP" -q --threads "${t%x}" bench cfg.json --frames 1-2 --runs 5 --json > "bench_$t.json" 2> /dev/null
    [ -n "$BEFORE" ] && "$(realpath "$BEFORE")" -q --threads "${t%x}" bench cfg.json --frames 1-2 \
        --runs 5 --json > "bench_before_$t.json" 2> /dev/null
done

python3 - "$cores" "$gpu" "${runs[@]}" > summary.json <<'PY'
import filecmp, json, os, sys
cores, gpu, runs = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3:]
out = {"cores": cores, "gpu": bool(gpu), "runs": {}, "sameBytes": {}, "threadScaling": {}}
for label in runs:
    rep = json.load(open(f"rep_{label}.json"))
    wall, rss, user, system = open(f"time_{label}.txt").read().split()[-4:]
    frames = [f for f in rep["frames"] if f.get("status") == "ok"]
    t = rep.get("throughput", {})
    out["runs"][label] = {
        "processSeconds": float(wall), "peakKiB": int(rss), "frames": len(frames),
        # every core's time, user and system: what a frame costs the machine
        "cpuSecondsPerFrame": (float(user) + float(system)) / max(len(frames), 1),
        "framesPerSecond": t.get("framesPerSecond", len(frames) / float(wall)),
        "boundBy": t.get("boundBy"), "perFrame": t.get("perFrame"),
        # frames 2.. (the first opens the scene, the OCIO config and the GPU)
        "frameSeconds": [f["seconds"] for f in frames[1:]],
    }
def same(a, b):
    if not (os.path.isdir(f"o_{a}") and os.path.isdir(f"o_{b}")): return None
    names = sorted(n for n in os.listdir(f"o_{a}") if n.endswith(".exr"))
    return bool(names) and all(filecmp.cmp(f"o_{a}/{n}", f"o_{b}/{n}", shallow=False) for n in names)
for a, b in [("cpu", "cpu_serial"), ("cpu", "cpu_before"), ("cuda", "cuda_serial"),
             ("cuda", "cuda_read8_writers8"), ("cuda", "cpu")]:
    if a in runs and b in runs: out["sameBytes"][f"{a} = {b} (EXR)"] = same(a, b)
def scaling(prefix, again=""):
    bench = {t: json.load(open(f"{prefix}_{t}{again}.json")) for t in ("2", str(cores))}
    def passes(b):
        return {p["name"]: p["median"] for p in b["settings"][0]["passes"]}
    lo, hi = passes(bench["2"]), passes(bench[str(cores)])
    s = {n: {"2": lo[n], str(cores): hi[n], "speedup": lo[n] / hi[n]}
         for n in lo if n in hi and hi[n] > 0}
    f2, fc = (bench[t]["settings"][0]["frameSeconds"]["median"] for t in ("2", str(cores)))
    s["(frame)"] = {"2": f2, str(cores): fc, "speedup": f2 / fc}
    return s
# Twice each, interleaved with the earlier build's: the spread between the two is the noise.
out["threadScaling"] = [scaling("bench"), scaling("bench", "x")]
if os.path.exists(f"bench_before_{cores}.json"):
    out["threadScalingBefore"] = [scaling("bench_before"), scaling("bench_before", "x")]
print(json.dumps(out, indent=1))
PY
cat summary.json
