#!/usr/bin/env python3
"""make bench: the 1080p speed table of docs/results/speed-1080p.md.

Captures the Cornell, hard and dense scenes at 1920x1080 once (out/bench/<scene>.exr, kept
between runs; the dense terrain's geometry is written there first), times the default lit chain on each with `framepass bench --json` (medians; every pass that
runs in SIMD lanes is also timed, in the same run, as its scalar reference `<pass>.lanes=false`),
and times the capture read: `framepass inspect` against `oiiotool -a --stats` on the same file.
Prints one Markdown table; the bench JSON of each scene stays beside the captures.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

# Each scene and its passes with SIMD lanes (a `lanes` parameter): deferred lighting has lanes for
# rect lights only, so only the Cornell ceiling's step is swept; of rt_shadows, one light's step
# (every setting is a combination of the sweeps, so each one more doubles the runs).
SCENES = {"cornell": ["ssgi", "deferred_lighting_ceiling", "rt_shadows_ceiling"],
          "hard": ["ssgi", "rt_shadows_sun"],
          "dense": ["ssgi", "rt_shadows_sun"]}
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(cmd, **kw):
    """Runs cmd, its progress lines dropped; stops the script with its stderr if it fails."""
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    if p.returncode != 0:
        sys.exit(f"make bench: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
    return p.stdout


def median_seconds(cmd, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        run(cmd)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default=os.path.join(ROOT, "build/cli/framepass"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out/bench"))
    ap.add_argument("--runs", type=int, default=3, help="timed runs per chain (medians)")
    ap.add_argument("--read-runs", type=int, default=5, help="timed reads per tool (medians)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    rows = []
    for scene, laned in SCENES.items():
        exr = os.path.join(a.out, f"{scene}.exr")
        if scene == "dense" and not os.path.exists(os.path.join(a.out, "dense.gltf")):
            # The dense terrain's 50 MB of geometry is made here, not committed.
            print("writing the dense terrain (once) ...", file=sys.stderr)
            run([sys.executable, os.path.join(ROOT, "examples/dense/make_dense_gltf.py"), a.out])
        if not os.path.exists(exr):
            print(f"capturing {scene} at 1920x1080 (once) ...", file=sys.stderr)
            run([a.framepass, "capture", os.path.join(ROOT, "examples", scene, "scene.json"),
                 "-o", exr, "--width", "1920", "--height", "1080"])
        print(f"timing the lit chain on {scene} ({a.runs} runs) ...", file=sys.stderr)
        sweeps = []
        for name in laned:
            sweeps += ["--sweep", f"{name}.lanes=true,false"]
        result = json.loads(run([a.framepass, "bench", os.path.join(HERE, f"{scene}.json"),
                                 "--runs", str(a.runs), *sweeps, "--json"]))
        with open(os.path.join(a.out, f"{scene}.json"), "w") as f:
            json.dump(result, f, indent=2)
        settings = {s["label"]: s for s in result["settings"]}

        def label(scalar_pass=None):
            return " ".join(f"{n}.lanes={'false' if n == scalar_pass else 'true'}" for n in laned)

        setting = settings[label()]
        # Each laned pass's scalar reference: the setting where only its lanes are off.
        scalar = {n: {p["name"]: p for p in settings[label(n)]["passes"]}[n] for n in laned}
        passes = {p["name"]: p for p in setting["passes"]}
        bare8 = passes.get("bare loop rtcOccluded8")
        bare16 = passes.get("bare loop rtcOccluded16")  # where the CPU has AVX-512
        # Where the chain reads the hit distance: the pass's own packets with their closest-hit
        # queries on blocked rays, the same work as the pass's tracing.
        sameWork = next((p for n, p in passes.items() if "+ rtcIntersect" in n), None)
        shadowSteps = sum(p["type"] == "rt_shadows" for p in setting["passes"])
        for p in setting["passes"]:
            if p["name"].startswith("bare loop"):
                continue
            notes = []
            if p["type"] == "rt_shadows" and bare8 and bare8["throughput"] > 0:
                # The bare loop replays the rays of every rt_shadows step of the chain together.
                wide = (f"; rtcOccluded16 {bare16['throughput'] / 1e6:.1f} M rays/s"
                        if bare16 else "")
                notes.append(f"{100 * p['throughput'] / bare8['throughput']:.0f} % of the bare "
                             f"rtcOccluded8 loop ({bare8['throughput'] / 1e6:.1f} M rays/s"
                             f"{', every light' if shadowSteps > 1 else ''}{wide})")
                if sameWork and sameWork["throughput"] > 0:
                    notes.append(f"{100 * p['throughput'] / sameWork['throughput']:.0f} % of "
                                 f"`{sameWork['name']}` ({sameWork['throughput'] / 1e6:.1f} M "
                                 f"rays/s: the same packets with the closest-hit queries of "
                                 f"blocked rays that the denoiser's hit distance needs)")
            if p["name"] in scalar and scalar[p["name"]]["throughput"] > 0:
                reference = scalar[p["name"]]
                notes.append(f"{p['throughput'] / reference['throughput']:.1f}× the scalar "
                             f"reference (`{p['name']}.lanes=false`: "
                             f"{reference['median'] * 1e3:,.0f} ms, "
                             f"{reference['throughput'] / 1e6:.1f} M {p['unit']}/s; same bits)")
            note = "; ".join(notes)
            rate = f"{p['throughput'] / 1e6:.1f} M {p['unit']}/s" if p["work"] else ""
            rows.append((scene, p["name"], f"{p['median'] * 1e3:,.1f}", rate, note))
        pixels = result["width"] * result["height"]
        rows.append((scene, "**the frame**", f"**{setting['frameSeconds']['median'] * 1e3:,.0f}**",
                     "", f"peak {setting['peakBytes'] / 2**20:.0f} MiB of images, "
                         f"{setting['peakBytes'] / pixels:.0f} B/pixel"))
        print(f"timing the capture read on {scene} ({a.read_runs} runs each) ...", file=sys.stderr)
        ours = median_seconds([a.framepass, "inspect", exr], a.read_runs)
        oiio = median_seconds(["oiiotool", "-a", "--stats", exr], a.read_runs)
        rows.append((scene, "capture read (`inspect`)", f"{ours * 1e3:,.0f}", "",
                     f"`oiiotool -a --stats` {oiio * 1e3:,.0f} ms: framepass reads at "
                     f"{100 * oiio / ours:.0f} % of its speed"))

    threads = result["threads"]
    print(f"\n1920x1080, {threads} threads, medians of {a.runs} runs "
          f"(capture read: medians of {a.read_runs})\n")
    print("| scene | pass | ms | throughput | note |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    main()
