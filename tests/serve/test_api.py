"""framepass serve's HTTP API through a client (docs/serve.md): every endpoint, every 4xx case,
and the bits against the command line's."""
import json
import os
import signal
import subprocess
import threading
import time
import urllib.error
import urllib.request

import numpy as np

import framepass as fp
from conftest import FRAMEPASS, SCRATCH

SOURCE_PORT = "ssgi_denoise.diffuse"


def raw_array(headers, data):
    h, w = int(headers["X-Height"]), int(headers["X-Width"])
    c = len(headers["X-Channels"].split(","))
    dtype = np.float16 if headers["X-Type"] == "float16" else np.float32
    return np.frombuffer(data, dtype=dtype).reshape(h, w, c)


def buffer(server, name, query=""):
    status, headers, data = server.request("GET", f"/api/buffer/{name}?format=raw{query}")
    assert status == 200, data
    return raw_array(headers, data)


def cli_dump(config, name, *args):
    """What `framepass run` writes for `name` with `args`, as an array."""
    out = os.path.join(SCRATCH, "cli_" + str(abs(hash((config, name) + args))))
    subprocess.run([FRAMEPASS, "-q", "run", config, "-o", out, "--dump", name, *args], check=True)
    (dump,) = [f for f in os.listdir(os.path.join(out, "dump")) if f.startswith(name + ".")]
    return fp.read_exr(os.path.join(out, "dump", dump))[name]


def cli_now(server, name):
    """What `framepass run` writes for `name` with the server's current settings."""
    status, params = server.json("GET", "/api/params")
    args = []
    for name_, value in params["settings"]["cvars"].items():
        args += ["--cvar", f"{name_}={json.dumps(value)}"]
    for name_, value in params["settings"]["set"].items():
        args += ["--set", f"{name_}={json.dumps(value)}"]
    for name_, source in params["settings"]["inputs"].items():
        args += ["--input", f"{name_}={source}"]
    return cli_dump(server.config, name, *args)


def same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_the_page_and_its_files(server):
    for path, kind in (("/", "text/html"), ("/app.js", "text/javascript"), ("/style.css", "text/css")):
        status, headers, data = server.request("GET", path)
        assert status == 200 and headers["Content-Type"].startswith(kind) and len(data) > 500


def test_graph_params_report_buffers_displays(server):
    status, graph = server.json("GET", "/api/graph")
    assert status == 200
    assert [s["name"] for s in graph["steps"]][:3] == ["hzb", "prev_color_reduction", "ssgi"]
    status, params = server.json("GET", "/api/params")
    cvar = {c["name"]: c for c in params["cvars"]}["r.SSGI.Quality"]
    assert (cvar["min"], cvar["max"], cvar["inChain"]) == (1, 4, True)
    ssgi = {p["name"]: p for p in params["passes"]}["ssgi"]
    assert {"rays", "quality", "halfRes"} <= {p["name"] for p in ssgi["params"]}
    status, buffers = server.json("GET", "/api/buffers")
    assert SOURCE_PORT in buffers["passes"] and "SceneColor" in buffers["capture"]
    assert "Truth.DiffuseIndirectFull" in buffers["truth"]
    status, displays = server.json("GET", "/api/displays")
    assert displays["defaultDisplay"] in [d["display"] for d in displays["displays"]]
    status, headers, lut = server.request("GET", "/api/lut")
    assert status == 200 and len(lut) == 3 * 65536 * 4
    buffer(server, SOURCE_PORT)  # waits for the first run
    status, report = server.json("GET", "/api/report")
    assert report["generation"] >= 1 and "ssgi_vs_full" in report["errors"]
    assert report["errors"]["ssgi_vs_full"]["rmse"] > 0


def test_the_error_taken_apart(server):
    status, b = server.json("GET", "/api/breakdown?rays=4")
    assert status == 200 and b["rays"] == 4
    full = {e["name"]: e for e in b["errors"]}["ssgi_vs_full"]
    assert "taken apart" in full["text"] and len(full["decomposition"]["steps"]) >= 3
    status, report = server.json("GET", "/api/report")
    assert full["metrics"]["rmse"] == report["errors"]["ssgi_vs_full"]["rmse"]


def test_a_change_reruns_downstream_and_gives_the_command_lines_bits(server):
    status, outcome = server.json("PUT", "/api/params", {"cvars": {"r.SSGI.Quality": 2},
                                                          "set": {"ssgi_denoise.denoiser": 0}})
    assert status == 200 and outcome["status"] == "done", outcome
    reused = {p["name"] for p in outcome["report"]["passes"] if p.get("reused")}
    assert "hzb" in reused and "ssgi" not in reused
    served = buffer(server, SOURCE_PORT)
    cli = cli_dump(server.config, SOURCE_PORT, "--cvar", "r.SSGI.Quality=2", "--set",
                   "ssgi_denoise.denoiser=0")
    assert same_bits(served, cli)
    half = buffer(server, SOURCE_PORT, "&type=half")
    assert half.dtype == np.float16 and np.array_equal(half, served.astype(np.float16))
    # Export: the settings as a config that `framepass run` turns into the same bits.
    status, exported = server.json("GET", "/api/export")
    assert "r.SSGI.Quality=2" in exported["ini"]
    path = os.path.join(SCRATCH, "exported.json")
    with open(path, "w") as f:
        json.dump(exported["config"], f)
    assert same_bits(cli_dump(path, SOURCE_PORT), served)


def test_an_input_is_rebound_under_inputs_with_the_command_lines_bits(server):
    def refused(body, match):
        code, headers, data = server.request("PUT", "/api/params", body)
        j = json.loads(data)
        assert code == 400 and match in j["error"], (code, j)
        return j["pointer"]

    assert refused({"inputs": {"ssgi_vs_full.source": 3}}, "a source's name") == "/inputs/ssgi_vs_full.source"
    assert refused({"inputs": {"ssgi_vs_full.sorce": "ssgi.diffuse"}},
                   "did you mean 'source'") == "/inputs/ssgi_vs_full.sorce"
    assert refused({"set": {"ssgi_vs_full.source": "ssgi.diffuse"}},
                   "not a parameter") == "/set/ssgi_vs_full.source"
    # The error measure compares the raw SSGI instead of the denoised one.
    status, outcome = server.json("PUT", "/api/params", {"inputs": {"ssgi_vs_full.source": "ssgi.diffuse"}})
    assert status == 200 and outcome["status"] == "done", outcome
    status, params = server.json("GET", "/api/params")
    assert params["settings"]["inputs"] == {"ssgi_vs_full.source": "ssgi.diffuse"}
    assert same_bits(buffer(server, "ssgi_vs_full.heat"), cli_now(server, "ssgi_vs_full.heat"))
    status, exported = server.json("GET", "/api/export")
    assert exported["config"]["inputs"] == {"ssgi_vs_full.source": "ssgi.diffuse"}
    # Bound back as the config binds it, for the tests after this one.
    status, outcome = server.json("PUT", "/api/params", {"inputs": {"ssgi_vs_full.source": SOURCE_PORT}})
    assert status == 200 and outcome["status"] == "done", outcome


def test_a_breakdown_in_flight_holds_no_setting_back_and_is_cancelled_by_a_change(server):
    """A long breakdown (1,024 rays: seconds) runs beside the session: a change made meanwhile is
    answered at once and cancels it (its figures would be of settings gone), as DELETE does."""
    answers = {}

    def take(key):
        answers[key] = server.json("GET", "/api/breakdown?rays=1024")

    status, params = server.json("GET", "/api/params")
    exposure = next(p["value"] for q in params["passes"] if q["name"] == "display"
                    for p in q["params"] if p["name"] == "exposure")
    for key in ("changed", "deleted"):
        t = threading.Thread(target=take, args=(key,))
        t.start()
        time.sleep(0.5)  # under way (it takes about 2 s here)
        t0 = time.monotonic()
        if key == "changed":
            status, _ = server.json("PUT", "/api/params?wait=0", {"set": {"display.exposure": exposure + 0.25}})
            assert status == 202
        else:
            status, j = server.json("DELETE", "/api/breakdown")
            assert status == 200 and j["status"] == "cancelled"
        assert time.monotonic() - t0 < 2.0  # not held back by the breakdown
        t.join(timeout=60)
        assert not t.is_alive()
        status, j = answers[key]
        assert status == 409 and "the breakdown was cancelled" in j["error"], j
        assert ("replaced the settings" if key == "changed" else "DELETE /api/breakdown") in j["error"]
    # A breakdown after them runs to its end.
    status, b = server.json("GET", "/api/breakdown?rays=4")
    assert status == 200 and b["errors"], b
    status, _ = server.json("PUT", "/api/params", {"set": {"display.exposure": exposure}})
    assert status == 200


def test_a_run_hands_back_only_the_shown_outputs(server):
    # Shown: the measured source and a truth layer (which needs no run).
    status, outcome = server.json("PUT", "/api/params", {"set": {"ssgi.rays": 4},
                                                          "show": [SOURCE_PORT, "Truth.AO"]})
    assert status == 200 and outcome["status"] == "done", outcome
    # Every pass ran or was reused (none culled), and the error figures are there.
    status, plan = server.json("GET", "/api/graph")
    assert plan["culled"] == [] and len(outcome["report"]["passes"]) == len(plan["steps"])
    status, report = server.json("GET", "/api/report")
    assert "ssgi_vs_full" in report["errors"]
    # A pass output not shown is fetched by a run that executes only what had not made it:
    # the debug hit mask re-runs the trace alone.
    served = buffer(server, "ssgi.hitMask")
    assert same_bits(served, cli_now(server, "ssgi.hitMask"))
    status, report = server.json("GET", "/api/report")
    executed = [p["name"] for p in report["passes"] if not p.get("reused")]
    assert executed == ["ssgi"], executed
    # … and a pass output made already (the display) runs nothing at all.
    buffer(server, "display.image")
    status, report = server.json("GET", "/api/report")
    assert report["executedSteps"] == 0


def test_a_newer_change_replaces_the_run_in_flight(server):
    first = server.json("PUT", "/api/params?wait=0", {"set": {"ssgi.rays": 16}})
    second = server.json("PUT", "/api/params?wait=0", {"set": {"ssgi.rays": 0}})
    assert first[0] == 202 and second[0] == 202
    assert second[1]["generation"] > first[1]["generation"]
    served = buffer(server, SOURCE_PORT)  # waits for the newest change
    assert same_bits(served, cli_now(server, SOURCE_PORT))
    status, report = server.json("GET", "/api/report")
    assert report["generation"] == second[1]["generation"]


def test_events_stream_progress(server):
    lines = []
    opened = threading.Event()

    done = threading.Event()

    def read():  # every line of the stream, until the test ends (a daemon thread)
        with urllib.request.urlopen(server.url + "api/events", timeout=60) as r:
            opened.set()
            for raw in r:
                lines.append(raw.decode())
                if done.is_set():
                    break  # closes the stream: the server frees its place

    threading.Thread(target=read, daemon=True).start()
    assert opened.wait(10)
    status, queued = server.json("PUT", "/api/params?wait=0", {"set": {"display.exposure": 0.5}})
    assert status == 202
    mine = []
    for _ in range(600):
        events = [json.loads(l[6:]) for l in list(lines) if l.startswith("data: ")]
        mine = [e for e in events if e.get("generation") == queued["generation"]]
        if mine and mine[-1]["type"] == "frame":
            break
        time.sleep(0.05)
    done.set()
    assert any(e["type"] == "pass" and e["pass"] == "display" for e in mine)
    assert mine[-1]["type"] == "frame" and mine[-1]["executed"] >= 1


def test_capture_and_truth_buffers_in_every_format(server, capture):
    scene = buffer(server, "SceneColor")
    assert same_bits(scene, fp.read_capture(capture)["SceneColor"])
    truth = buffer(server, "Truth.DiffuseIndirectFull")
    assert same_bits(truth, fp.read_exr(capture, ["Truth.DiffuseIndirectFull"])["Truth.DiffuseIndirectFull"])
    status, headers, data = server.request("GET", f"/api/buffer/{SOURCE_PORT}?format=exr")
    assert status == 200 and data[:4] == b"\x76\x2f\x31\x01"
    path = os.path.join(SCRATCH, "served.exr")
    with open(path, "wb") as f:
        f.write(data)
    assert same_bits(fp.read_exr(path)[SOURCE_PORT], buffer(server, SOURCE_PORT))
    status, headers, data = server.request("GET", "/api/buffer/display.image?format=png")
    assert status == 200 and data[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_requests_are_4xx_with_a_json_error(server):
    def error(method, path, body=None, status=400, match=""):
        code, headers, data = server.request(method, path, body)
        assert code == status, (path, code, data)
        j = json.loads(data)
        assert j["status"] == status and match in j["error"], j
        return j

    error("GET", "/api/buffer/ssgi.difuse", status=404, match="did you mean 'ssgi.diffuse'")
    error("GET", "/api/buffer/..%2F..%2Fetc%2Fpasswd", match="not a buffer name")
    error("GET", "/api/buffer/%2Fetc%2Fpasswd", match="not a buffer name")
    error("GET", f"/api/buffer/{SOURCE_PORT}?format=jpeg", match="raw, exr or png")
    error("GET", f"/api/buffer/{SOURCE_PORT}?frame=7", match="not one of the config's frames")
    error("GET", f"/api/buffer/{SOURCE_PORT}?frame=x", match="not a frame number")
    error("GET", "/api/nothing", status=404, match="no GET /api/nothing")
    error("GET", "/api/lut?view=Filmic", status=404, match="no view 'Filmic'")
    error("GET", "/api/breakdown?rays=0", match="?rays=0: 1 to 1024")
    error("GET", "/api/breakdown?rays=many", match="a whole number")
    error("PUT", "/api/params", b"{not json", match="not valid JSON")
    error("PUT", "/api/params", b"[1, 2]", match="JSON object")
    error("PUT", "/api/params", {"cvar": {}}, match="unknown key 'cvar'")
    error("PUT", "/api/params", {"cvars": {"r.SSGI.Quality": [2]}}, match="/cvars/r.SSGI.Quality")
    j = error("PUT", "/api/params", {"set": {"ssgi.quality": 9}}, match="out of range")
    assert j["pointer"] == "/set/ssgi.quality"  # its place in the body
    error("PUT", "/api/params", {"cvars": {"r.SSGI.Qualty": 2}}, match="r.SSGI.Quality")
    error("PUT", "/api/params", {"frame": 3}, match="not one of the config's frames")
    error("PUT", "/api/params?wait=maybe", {}, match="?wait=maybe")
    error("PUT", "/api/params", b"[" * 100 + b"]" * 100, match="nested more than")
    error("PUT", "/api/params", b" " * (65 * 1024), status=413)
    error("PUT", "/api/params", {"show": SOURCE_PORT}, match="/show: a list")
    error("PUT", "/api/params", {"show": [SOURCE_PORT] * 17}, match="at most 16")
    error("PUT", "/api/params", {"show": [3]}, match="/show/0")
    error("PUT", "/api/params", {"show": ["../x"]}, match="not a buffer name")
    j = error("PUT", "/api/params", {"show": [SOURCE_PORT, "ssgi.difuse"]}, status=404, match="no buffer 'ssgi.difuse'")
    assert j["pointer"] == "/show/1"
    error("POST", "/api/tev", {"buffers": [SOURCE_PORT], "host": "example.com:1"}, match="not this machine")
    error("POST", "/api/tev", {"buffers": []}, match="buffers")
    # A rejected change leaves the settings as they were: the server still runs and answers.
    status, params = server.json("GET", "/api/params")
    assert status == 200 and params["settings"]["set"].get("ssgi.quality") != 9
    assert buffer(server, SOURCE_PORT).shape == (64, 96, 3)


class FakeTev:
    """A socket on 127.0.0.1 that records the images tev's protocol would create."""

    def __init__(self):
        import socket
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(4)
        self.address = "127.0.0.1:%d" % self.sock.getsockname()[1]
        self.created = []
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            data = b""
            while chunk := conn.recv(65536):
                data += chunk
            conn.close()
            at = 0
            while at < len(data):
                length, kind = int.from_bytes(data[at:at + 4], "little"), data[at + 4]
                if kind == 4:  # CreateImage: grab focus, then the name
                    self.created.append(data[at + 6:data.index(b"\0", at + 6)].decode())
                at += length

    def close(self):
        self.sock.close()


def test_images_reach_tev_from_the_page_and_from_run(server):
    tev = FakeTev()
    try:
        status, sent = server.json("POST", "/api/tev", {"host": tev.address, "buffers": [SOURCE_PORT, "SceneColor"]})
        assert status == 200 and len(sent["images"]) == 2
        out = os.path.join(SCRATCH, "tev_run")
        subprocess.run([FRAMEPASS, "-q", "run", server.config, "-o", out, "--dump", SOURCE_PORT,
                        "--tev", tev.address], check=True)
        for _ in range(100):
            if len(tev.created) >= 3:
                break
            time.sleep(0.05)
        assert tev.created[:2] == sent["images"]
        assert SOURCE_PORT in tev.created[2:]  # run's dump, named after its layer
    finally:
        tev.close()
    # Nothing listening: run fails before its first frame, saying so.
    import socket
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    free = "127.0.0.1:%d" % probe.getsockname()[1]
    probe.close()
    r = subprocess.run([FRAMEPASS, "run", server.config, "-o", os.path.join(SCRATCH, "tev_none"),
                        "--tev", free], capture_output=True, text=True)
    assert r.returncode == 1 and "is tev running?" in r.stderr


def test_only_its_user_reaches_the_server(server, config):
    port = server.url.rsplit(":", 1)[1].strip("/")
    # DNS rebinding: a page elsewhere whose name points at 127.0.0.1 sends its own Host.
    for method, path in (("GET", "/api/params"), ("PUT", "/api/params"), ("GET", "/")):
        status, _, data = server.request(method, path, {} if method == "PUT" else None,
                                         headers={"Host": f"evil.example:{port}"})
        assert status == 403 and "evil.example" in json.loads(data)["error"]
    # Another site's page in the browser: its Origin.
    status, _, data = server.request("PUT", "/api/params", {}, headers={"Origin": "http://evil.example"})
    assert status == 403 and "another site" in json.loads(data)["error"]
    # The names of this machine, and the page's own origin, are answered.
    for host in (f"127.0.0.1:{port}", f"localhost:{port}"):
        assert server.request("GET", "/api/graph", headers={"Host": host})[0] == 200
    assert server.request("GET", "/api/graph", headers={"Origin": server.url.rstrip("/")})[0] == 200
    # A second workbench on the same port is refused, naming it.
    second = subprocess.run([FRAMEPASS, "serve", config, "--port", port], capture_output=True,
                            text=True, timeout=120)
    assert second.returncode == 2 and f"--port {port}: the port is in use" in second.stderr


def test_a_workbench_open_to_the_network_needs_its_token(config):
    process = subprocess.Popen([FRAMEPASS, "serve", config, "--host", "0.0.0.0", "--port", "0"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = process.stdout.readline()
        url = line.split()[2]
        assert "?token=" in url and "127.0.0.1" not in url, line
        port = url.split(":")[2].split("/")[0]
        token = url.split("?token=")[1]
        local = f"http://127.0.0.1:{port}"

        def status(path, headers=None):
            try:
                with urllib.request.urlopen(urllib.request.Request(local + path, headers=headers or {}),
                                            timeout=60) as r:
                    return r.status, r.headers
            except urllib.error.HTTPError as e:
                return e.code, e.headers

        assert status("/api/graph")[0] == 403
        assert status("/api/graph?token=wrong")[0] == 403
        code, headers = status(f"/?token={token}")
        assert code == 200 and f"framepass_token={token}" in headers["Set-Cookie"]
        assert status("/api/graph", {"Cookie": f"framepass_token={token}"})[0] == 200
    finally:
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
    assert "open to every machine" in err


def test_a_display_output_is_drawn_as_it_is(server):
    # display.image is already display-encoded: the page must not put it through a view again.
    status, headers, _ = server.request("GET", "/api/buffer/display.image?format=raw")
    assert status == 200 and headers["X-Color"] == "0"
    status, headers, _ = server.request("GET", "/api/buffer/diffuse_indirect_composite.color?format=raw")
    assert status == 200 and headers["X-Color"] == "1"


def test_idle_event_streams_and_connections_leave_requests_answered(server):
    """32 open event streams (the most served) and 16 connections that send nothing hold threads
    of their own: a request is still answered at once. A 33rd stream is refused with 503."""
    import socket

    port = int(server.url.rsplit(":", 1)[1].strip("/"))

    def connect():
        return socket.create_connection(("127.0.0.1", port), timeout=10)

    def open_streams():
        opened = []
        for _ in range(32):
            s = connect()
            s.sendall(f"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
            opened.append(s)
        if all(s.recv(12) == b"HTTP/1.1 200" for s in opened):
            return opened
        for s in opened:
            s.close()
        return None

    # An earlier test's stream may still be closing (a stream notices a closed client at its
    # next keep-alive, once a second).
    streams = None
    for _ in range(20):
        streams = open_streams()
        if streams:
            break
        time.sleep(0.5)
    assert streams, "32 event streams could not be opened"
    try:
        idle = [connect() for _ in range(16)]
        streams += idle
        # An idle connection holds a thread until the read timeout (2 s): answered sooner than
        # that, the request did not wait for one to give up.
        start = time.monotonic()
        status, params = server.json("GET", "/api/params")
        assert status == 200 and params["cvars"] and time.monotonic() - start < 1.5
        status, body = server.json("GET", "/api/events")
        assert status == 503 and "32 event streams" in body["error"]
    finally:
        for s in streams:
            s.close()
    # Closed streams free their places (the stream notices at its next keep-alive, within 1 s).
    reopened = None
    for _ in range(100):
        try:
            with urllib.request.urlopen(server.url + "api/events", timeout=10) as r:
                reopened = r.status
                break
        except urllib.error.HTTPError as e:
            reopened = e.code
            time.sleep(0.1)
    assert reopened == 200


def test_status_reads_while_a_run_is_in_flight(server):
    status, queued = server.json("PUT", "/api/params?wait=0", {"set": {"ssgi.rays": 12}})
    assert status == 202
    status, s = server.json("GET", "/api/status")
    assert status == 200 and s["requested"] >= queued["generation"]
    assert s["status"] in ("done", "cancelled", "error")
    buffer(server, SOURCE_PORT)
    status, s = server.json("GET", "/api/status")
    assert s["finished"] == s["requested"] and s["status"] == "done"


def wait_for_first_frame(s):
    for _ in range(1200):
        st = s.json("GET", "/api/status")[1]
        if st["finished"] >= 1:
            return st
        time.sleep(0.05)
    raise AssertionError(f"no frame finished: {st}")


def test_a_first_frame_that_fails_is_said_and_a_pinned_cvar_is_marked(missing_capture_config,
                                                                       pinned_quality_config):
    """A config whose capture is missing: the server starts, and /api/status says why the first
    frame failed. A config whose params fix ssgi's quality: r.SSGI.Quality says it has no effect,
    naming the config's key, and reused passes keep their last executed time."""
    from conftest import Server

    s = Server(missing_capture_config, None)
    try:
        st = wait_for_first_frame(s)
        assert st["status"] == "error" and "no_such_capture.exr" in st["message"], st
        assert s.json("GET", "/api/report")[1] is None
    finally:
        s.stop()

    s = Server(pinned_quality_config, None)
    try:
        cvar = {c["name"]: c for c in s.json("GET", "/api/params")[1]["cvars"]}["r.SSGI.Quality"]
        with open(pinned_quality_config) as f:
            ssgi = next(i for i, p in enumerate(json.load(f)["passes"]) if p["name"] == "ssgi")
        assert cvar["shadowedBy"] == [f"/passes/{ssgi}/params/quality"] and cvar["value"] == 3
        others = [c for c in s.json("GET", "/api/params")[1]["cvars"]
                  if c["inChain"] and c["name"] != "r.SSGI.Quality" and c.get("passType") == "ssgi"]
        assert others and not any("shadowedBy" in c for c in others)
        wait_for_first_frame(s)
        status, outcome = s.json("PUT", "/api/params", {"cvars": {"r.SSGI.Quality": 1}})
        assert status == 200 and any("has no effect" in w["message"] for w in outcome["warnings"])
        # Nothing changed: every pass was reused, and each keeps the time it last ran in.
        report = outcome["report"]
        assert report["executedSteps"] == 0
        for p in report["passes"]:
            assert report["lastExecuted"][p["name"]]["ms"] > 0
            assert report["lastExecuted"][p["name"]]["generation"] < report["generation"]
        status, graph = s.json("GET", "/api/graph")
        assert all("ms" in t and t["reused"] for t in graph["times"].values())
    finally:
        s.stop()


def test_each_method_is_paired_with_the_time_of_what_it_depends_on(server):
    buffer(server, SOURCE_PORT)  # a finished run
    status, report = server.json("GET", "/api/report")
    methods = {m["measure"]: m for m in report["methods"]}
    # one_bounce_limit compares two capture layers: no method behind it.
    assert set(methods) == {"ssgi_vs_one_bounce", "ssgi_vs_full", "ao_vs_truth"}
    m = methods["ssgi_vs_full"]
    assert m["source"] == SOURCE_PORT
    assert m["passes"] == ["hzb", "prev_color_reduction", "ssgi", "ssgi_denoise"]
    assert m["rmse"] == report["errors"]["ssgi_vs_full"]["rmse"]
    assert abs(m["ms"] - sum(report["lastExecuted"][p]["ms"] for p in m["passes"])) < 1e-9
