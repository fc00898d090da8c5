"""A `framepass serve` on a small Cornell capture with truth, shared by the API and browser tests.

Run by ctest (tests `serve` and `serve_browser`) with FRAMEPASS, PYTHONPATH (the framepass module,
to read EXRs), FP_SOURCE_DIR and FP_SCRATCH set.
"""
import json
import os
import re
import signal
import subprocess
import urllib.error
import urllib.request

import pytest

FRAMEPASS = os.environ["FRAMEPASS"]
SOURCE = os.environ["FP_SOURCE_DIR"]
SCRATCH = os.path.join(os.path.abspath(os.environ["FP_SCRATCH"]), "serve")


class Server:
    def __init__(self, config, capture):
        self.config, self.capture = config, capture
        self.process = subprocess.Popen([FRAMEPASS, "serve", config, "--port", "0"],
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.process.stdout.readline()
        match = re.search(r"(http://127\.0\.0\.1:\d+/)", line)
        assert match, f"serve printed {line!r}; stderr: {self.process.stderr.read()}"
        self.url = match.group(1)

    def request(self, method, path, body=None, headers=None):
        """(status, headers, body bytes); 4xx and 5xx are answers too."""
        data = body if isinstance(body, (bytes, type(None))) else json.dumps(body).encode()
        req = urllib.request.Request(self.url + path.lstrip("/"), data=data, method=method,
                                     headers=headers or {})
        try:
            with urllib.request.urlopen(req, timeout=120) as r:
                return r.status, dict(r.headers), r.read()
        except urllib.error.HTTPError as e:
            return e.code, dict(e.headers), e.read()

    def json(self, method, path, body=None):
        status, _, data = self.request(method, path, body)
        return status, json.loads(data)

    def stop(self):
        self.process.send_signal(signal.SIGINT)
        out, err = self.process.communicate(timeout=60)
        return self.process.returncode, out, err


@pytest.fixture(scope="session")
def capture():
    os.makedirs(SCRATCH, exist_ok=True)
    path = os.path.join(SCRATCH, "cornell.exr")
    if not os.path.exists(path):
        subprocess.run([FRAMEPASS, "-q", "capture", os.path.join(SOURCE, "examples/cornell/scene.json"),
                        "-o", path, "--width", "96", "--height", "64", "--truth", "--truth-spp", "8",
                        "--light-samples", "2"], check=True)
    return path


@pytest.fixture(scope="session")
def config(capture):
    """examples/cornell/bench.json (the SSGI chain, its display and error measures) on the
    capture, writing float EXRs so that dumps hold the bits the server sends."""
    with open(os.path.join(SOURCE, "examples/cornell/bench.json")) as f:
        j = json.load(f)
    j["capture"] = capture
    j["exr"] = {"colorPrecision": "float"}
    path = os.path.join(SCRATCH, "config.json")
    with open(path, "w") as f:
        json.dump(j, f)
    return path


def variant(config, name, change):
    """A copy of `config` changed by `change(json)`, written as SCRATCH/NAME.json."""
    with open(config) as f:
        j = json.load(f)
    change(j)
    path = os.path.join(SCRATCH, name + ".json")
    with open(path, "w") as f:
        json.dump(j, f)
    return path


@pytest.fixture(scope="session")
def missing_capture_config(config):
    """The config on a capture that does not exist: the workbench starts, its first frame fails."""
    return variant(config, "missing_capture",
                   lambda j: j.update(capture=os.path.join(SCRATCH, "no_such_capture.exr")))


@pytest.fixture(scope="session")
def pinned_quality_config(config):
    """The config with ssgi's quality fixed by its params (3): r.SSGI.Quality has no effect."""
    def pin(j):
        next(p for p in j["passes"] if p["name"] == "ssgi")["params"] = {"quality": 3}
    return variant(config, "pinned_quality", pin)


@pytest.fixture(scope="session")
def server(config, capture):
    s = Server(config, capture)
    yield s
    code, out, err = s.stop()
    assert code == 0, err
    assert "stopped" in out


def pytest_sessionfinish(session, exitstatus):
    """A run whose every test skipped (the browser suite without node, npm or Chromium) exits 77,
    ctest's SKIP_RETURN_CODE (tests/CMakeLists.txt): ctest reports it skipped, not passed."""
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    stats = reporter.stats if reporter else {}
    if exitstatus == 0 and stats.get("skipped") and not stats.get("passed"):
        session.exitstatus = 77
