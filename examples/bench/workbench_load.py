#!/usr/bin/env python3
"""The workbench under load (docs/results/serve.md): 16 clients at once for a fixed time, each
asking in turn for the shown buffer (raw float32), the parameters, and every tenth request a
settings change (PUT /api/params?wait=0, the exposure of the display: a re-run of one pass), with
32 idle event streams open beside them. Prints the latency percentiles of buffer and parameter
requests, the request rate and any answer that was not 2xx.

    PYTHONPATH=build/python /usr/bin/python3 examples/bench/workbench_load.py \\
        --framepass build/cli/framepass --seconds 20
"""
import argparse
import http.client
import json
import os
import re
import signal
import socket
import subprocess
import threading
import time

from captures import workbench_config

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def percentile(values, q):
    """Nearest rank."""
    v = sorted(values)
    return v[min(len(v) - 1, int(q * len(v)))] if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--framepass", default=os.path.join(ROOT, "build/cli/framepass"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out/bench"))
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--clients", type=int, default=16)
    ap.add_argument("--idle-streams", type=int, default=32)
    ap.add_argument("--seconds", type=float, default=20)
    a = ap.parse_args()
    width, height = (int(v) for v in a.size.split("x"))
    config = workbench_config(a.framepass, a.out, width, height, "workbench_load")
    server = subprocess.Popen([a.framepass, "serve", config, "--port", "0"], stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, text=True)
    try:
        port = int(re.search(r"http://127\.0\.0\.1:(\d+)/", server.stdout.readline()).group(1))
        run(a, port)
    finally:
        server.send_signal(signal.SIGINT)
        server.wait()


def run(a, port):
    host = f"127.0.0.1:{port}"
    streams = []
    for _ in range(a.idle_streams):
        s = socket.create_connection(("127.0.0.1", port))
        s.sendall(f"GET /api/events HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
        streams.append(s)
    # The first frame, and the shown buffer made once, before the clock starts.
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    c.request("GET", "/api/buffer/ssgi_denoise.diffuse?format=raw")
    c.getresponse().read()
    latencies = {"buffer": [], "params": [], "change": []}
    failures = []
    lock = threading.Lock()
    stop = time.monotonic() + a.seconds

    def client(index):
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        n = 0
        while time.monotonic() < stop:
            n += 1
            if n % 10 == 0:
                kind, method, path = "change", "PUT", "/api/params?wait=0"
                body = json.dumps({"set": {"display.exposure": (index + n) % 5 * 0.25}})
            elif n % 2:
                kind, method, path, body = "buffer", "GET", "/api/buffer/ssgi_denoise.diffuse?format=raw", None
            else:
                kind, method, path, body = "params", "GET", "/api/params", None
            start = time.perf_counter()
            conn.request(method, path, body=body)
            r = conn.getresponse()
            r.read()
            ms = (time.perf_counter() - start) * 1e3
            with lock:
                latencies[kind].append(ms)
                if r.status >= 300:
                    failures.append(f"{method} {path}: {r.status}")

    threads = [threading.Thread(target=client, args=(i,)) for i in range(a.clients)]
    begin = time.monotonic()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    elapsed = time.monotonic() - begin
    for s in streams:
        s.close()
    total = sum(len(v) for v in latencies.values())
    print(f"{a.clients} clients, {a.idle_streams} idle event streams, {elapsed:.1f} s: {total} requests "
          f"({total / elapsed:.0f}/s), {len(failures)} not 2xx")
    print("| requests | count | p50 | p95 | p99 | max |")
    print("|---|---|---|---|---|---|")
    for kind, values in latencies.items():
        print(f"| {kind} | {len(values)} | {percentile(values, 0.5):.0f} ms | {percentile(values, 0.95):.0f} ms | "
              f"{percentile(values, 0.99):.0f} ms | {max(values):.0f} ms |")
    for f in failures[:10]:
        print(f)


if __name__ == "__main__":
    main()
