#!/usr/bin/env python3
"""What a framepass.Session.run call costs beyond the library's own run (docs/results/python.md).

Captures the Cornell box at 256x256 and 1920x1080 once (out/bench/cornell_<size>.exr, kept), then
for each size and each output layout times Session.run after a change that re-runs one pass
(display.exposure: "short") and one that re-runs five (ssgi_denoise.denoiser: "long"), and
subtracts the executor's own time for the frame (report()["seconds"]). Medians of --runs calls;
prints one Markdown table.

    PYTHONPATH=build/python /usr/bin/python3 examples/bench/python_overhead.py \
        --framepass build/cli/framepass
"""
import argparse
import os
import statistics
import time

from captures import cornell_capture

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OUTPUT = "diffuse_indirect_composite.color"
CHANGES = {"short": ("display.exposure", (0.0, 0.5)), "long": ("ssgi_denoise.denoiser", (0, 1))}


def main():
    import framepass as fp

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default=os.path.join(ROOT, "build/cli/framepass"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out/bench"))
    ap.add_argument("--runs", type=int, default=9)
    a = ap.parse_args()
    rows = []
    for width, height in ((256, 256), (1920, 1080)):
        exr = cornell_capture(a.framepass, a.out, width, height)
        for layout in ("hwc", "chw"):
            cells = []
            for kind, (param, values) in CHANGES.items():
                s = fp.Session(os.path.join(ROOT, "examples/cornell/config.json"), capture=exr)
                s.run(outputs=[OUTPUT], layout=layout)  # the whole frame once
                library, overhead = [], []
                for i in range(a.runs + 1):
                    # The setting counts: it is checked by planning when it is set.
                    start = time.perf_counter()
                    s.set(param, values[i % 2])
                    s.run(outputs=[OUTPUT], layout=layout)
                    wall = time.perf_counter() - start
                    seconds = s.report()["seconds"]
                    if i > 0:  # the first alternation warms up
                        library.append(seconds)
                        overhead.append(wall - seconds)
                lib, over = statistics.median(library), statistics.median(overhead)
                cells.append(f"{lib * 1e3:.1f} ms / {over * 1e3:.2f} ms ({over / lib * 100:.1f} %)")
            rows.append(f"| {width}×{height} | `{layout}` | " + " | ".join(cells) + " |")
    print("| capture | layout | short run: library / overhead | long run: library / overhead |")
    print("|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
