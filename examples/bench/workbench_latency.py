#!/usr/bin/env python3
"""Slider to updated image in `framepass serve`, measured in the page (docs/results/serve.md).

Starts the workbench on the Cornell box (256x256 and 1920x1080, captured once into out/bench/
with truth), drives its page in headless Chromium (tests/serve/workbench.mjs) and moves the
r.SSGI.Quality slider --runs times between 1 and 2. Per move the page records when the change
was sent, when the server said the run finished (and its run time), when the buffer had arrived
and when it was drawn. Prints medians as a Markdown table.

    PYTHONPATH=build/python /usr/bin/python3 examples/bench/workbench_latency.py \
        --framepass build/cli/framepass --node-prefix build/node
"""
import argparse
import json
import os
import re
import signal
import statistics
import subprocess

from captures import workbench_config

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default=os.path.join(ROOT, "build/cli/framepass"))
    ap.add_argument("--node-prefix", default=os.path.join(ROOT, "build/node"),
                    help="folder with node_modules/playwright-core (the browser test installs it)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out/bench"))
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--sizes", default="256x256,1920x1080", help="captures, WxH comma-separated")
    a = ap.parse_args()
    rows = []
    for width, height in (tuple(int(v) for v in s.split("x")) for s in a.sizes.split(",")):
        config = workbench_config(a.framepass, a.out, width, height, "workbench")
        server = subprocess.Popen([a.framepass, "serve", config, "--port", "0"], stdout=subprocess.PIPE, text=True)
        url = re.search(r"(http://\S+/)", server.stdout.readline()).group(1)
        out = os.path.join(a.out, f"workbench_{width}x{height}")
        env = dict(os.environ, FP_NODE_PREFIX=os.path.abspath(a.node_prefix))
        try:
            subprocess.run(["node", os.path.join(ROOT, "tests/serve/workbench.mjs"), url, out,
                            "--latency", str(a.runs)], check=True, env=env)
        finally:
            server.send_signal(signal.SIGINT)
            server.wait()
        with open(os.path.join(out, "results.json")) as f:
            timings = json.load(f)["timings"][-a.runs:]
        # The server's run time arrives with its "frame" event; a move whose image was fetched
        # first (a fetch waits for the newest change) has none, and counts only in the totals.
        med = lambda f: statistics.median(f(t) for t in timings if "run" in t or f is total)
        total = lambda t: t["drawn"] - t["sent"]
        # The 95th percentile of slider → image, by nearest rank (of 20 moves, the largest).
        drawn = sorted(t["drawn"] - t["sent"] for t in timings)
        p95 = drawn[min(len(drawn) - 1, int(0.95 * len(drawn)))]
        rows.append(f"| {width}×{height} | {med(total):.0f} ms | {p95:.0f} ms | "
                    f"{med(lambda t: t['run']):.0f} ms | {med(lambda t: t['event'] - t['sent'] - t['run']):.0f} ms | "
                    f"{med(lambda t: t['fetched'] - t['fetchStart']):.0f} ms ({timings[0]['bytes'] / 1e6:.1f} MB) | "
                    f"{med(lambda t: t['drawn'] - t['fetched']):.0f} ms |")
    print("| capture | slider → image drawn | p95 | re-run (server) | change + event | buffer fetch | upload + draw |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
