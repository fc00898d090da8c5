#!/usr/bin/env python3
"""The workbench's server side of slider to image, over its HTTP API (docs/results/serve.md):
where no browser runs (a GPU machine), what the page waits for after a slider moves.

Captures the Cornell box with truth at --size, serves examples/cornell/bench.json on it with each
--devices in turn (one server at a time, the page's default buffers shown), then moves
r.SSGI.Quality between 1 and 2 --runs times: per move, the change (PUT /api/params, answered
once the re-run has finished) and the fetch of the shown buffer as the page fetches it (raw
float32). Prints medians and 95th percentiles as a Markdown table. The page's own upload and draw
come after this (a few ms: results/serve.md).

    python3 examples/bench/workbench_api_latency.py --framepass build/cli/framepass \
        --size 1920x1080 --devices cuda,cpu --runs 20
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHOWN = ["ssgi_denoise.diffuse", "Truth.DiffuseIndirectOneBounce"]  # the page's A and B


def request(url, method="GET", body=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method)
    with urllib.request.urlopen(req, timeout=300) as r:
        return r.read()


def percentile(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(round(p / 100 * (len(s) - 1))))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default=os.path.join(ROOT, "build/cli/framepass"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out/bench"))
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--devices", default="cpu", help="comma-separated: cpu, cuda")
    ap.add_argument("--runs", type=int, default=20)
    a = ap.parse_args()
    width, height = (int(v) for v in a.size.split("x"))
    os.makedirs(a.out, exist_ok=True)
    capture = os.path.join(a.out, f"cornell_api_{width}x{height}.exr")
    if not os.path.exists(capture):
        subprocess.run([a.framepass, "-q", "capture", os.path.join(ROOT, "examples/cornell/scene.json"),
                        "-o", capture, "--width", str(width), "--height", str(height), "--truth",
                        "--truth-spp", "4", "--light-samples", "2"], check=True)
    with open(os.path.join(ROOT, "examples/cornell/bench.json")) as f:
        config = json.load(f)
    config["capture"] = os.path.abspath(capture)
    config["scene"] = os.path.join(ROOT, "examples/cornell/scene.json")
    config_path = os.path.join(a.out, f"cornell_api_{width}x{height}.json")
    with open(config_path, "w") as f:
        json.dump(config, f)

    rows = []
    for device in a.devices.split(","):
        server = subprocess.Popen([a.framepass, "serve", config_path, "--port", "0", "--device", device],
                                  stdout=subprocess.PIPE, text=True)
        try:
            url = re.search(r"(http://\S+/)", server.stdout.readline()).group(1)
            for _ in range(600):  # the first frame
                status = json.loads(request(url + "api/status"))
                if status["status"] != "none":
                    break
                time.sleep(0.2)
            assert status["status"] == "done", status
            request(url + "api/params", "PUT", {"show": SHOWN})
            change, fetch, total = [], [], []
            for i in range(a.runs + 1):
                t0 = time.perf_counter()
                request(url + "api/params", "PUT", {"cvars": {"r.SSGI.Quality": 1 + i % 2}})
                t1 = time.perf_counter()
                size = len(request(url + f"api/buffer/{SHOWN[0]}?format=raw"))
                t2 = time.perf_counter()
                if i == 0:
                    continue  # a warm-up move
                change.append((t1 - t0) * 1e3)
                fetch.append((t2 - t1) * 1e3)
                total.append((t2 - t0) * 1e3)
            report = json.loads(request(url + "api/report"))
        finally:
            server.terminate()
            server.wait(timeout=60)
        rows.append((device, total, change, fetch, size, report["wallMs"]))
    print(f"Cornell {width}×{height}, examples/cornell/bench.json, r.SSGI.Quality 1 ↔ 2, {a.runs} moves:\n")
    print("| device | change → shown buffer fetched: median / p95 | re-run answered (PUT): median / p95 | buffer fetch: median / p95 | last run's wall |")
    print("|---|---|---|---|---|")
    for device, total, change, fetch, size, wall in rows:
        m = lambda v: f"{percentile(v, 50):.1f} / {percentile(v, 95):.1f} ms"
        print(f"| {device} | {m(total)} | {m(change)} | {m(fetch)} ({size / 1e6:.1f} MB) | {wall:.1f} ms |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
