#!/usr/bin/env python3
"""make stability: the half-float table of docs/results/half-float.md.

Movie Render Queue writes 16-bit (half) EXR by default. This captures the Cornell and hard scenes
three ways into out/stability/<scene>/ (float32; every buffer half; half with the two depth
buffers float32), runs the default lit chain on each with every pass output dumped as float32
(the configs beside this script), and compares every dump of a half capture with the float32
capture's (`framepass compare --json --mask none`). Prints one Markdown table.
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = {"cornell": "examples/cornell/scene.json", "hard": "examples/hard/scene.json"}
# capture variant → the capture command's extra flags
VARIANTS = {"float": [], "half": ["--half"], "half_float_depth": ["--half", "--float-depth"]}


def run(cmd):
    """Runs cmd; stops the script with its stderr if it fails."""
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    if p.returncode != 0:
        sys.exit(f"make stability: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default="build/cli/framepass")
    ap.add_argument("--out", default="out/stability")
    ap.add_argument("--size", type=int, default=256, help="capture width and height")
    args = ap.parse_args()
    rows = []
    for scene, scene_json in SCENES.items():
        folder = os.path.join(args.out, scene)
        for variant, flags in VARIANTS.items():
            capture = os.path.join(folder, f"{variant}.exr")
            run([args.framepass, "-q", "capture", scene_json, "-o", capture, "--width",
                 str(args.size), "--height", str(args.size)] + flags)
            run([args.framepass, "-q", "run", f"examples/stability/{scene}.json", "--capture",
                 capture, "--dump", "all", "-o", os.path.join(folder, variant)])
        dumps = sorted(os.listdir(os.path.join(folder, "float", "dump")))
        for dump in dumps:
            port = dump.rsplit(".", 2)[0]  # pass.port.0001.exr → pass.port
            row = {"scene": scene, "port": port}
            for variant in ("half", "half_float_depth"):
                out = run([args.framepass, "-q", "compare",
                           os.path.join(folder, variant, "dump", dump),
                           os.path.join(folder, "float", "dump", dump),
                           "--mask", "none", "--json"])
                row[variant] = json.loads(out)
            rows.append(row)
    print("| scene | output | all half: RMSE | max error | SMAPE | depth float32: RMSE | max error | SMAPE |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        cells = []
        for variant in ("half", "half_float_depth"):
            m = r[variant]
            cells += [f"{m['rmse']:.3g}", f"{m['maxError']:.3g}", f"{m['smape']:.2g}"]
        print(f"| {r['scene']} | `{r['port']}` | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
