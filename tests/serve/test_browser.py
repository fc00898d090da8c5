"""The workbench page in a real browser (Playwright driving Debian's Chromium, headless): load it,
see the graph, move a slider and see the image and the time change, wipe A/B, read a pixel probe
equal to the command line's output at that pixel, export the config and run it with `framepass
run` to the same bits. Screenshots of each step land in FP_SCRATCH/serve/browser/; look at them.

playwright-core comes from npm into FP_NODE_PREFIX (the build folder) on the first run.
"""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import framepass as fp
from conftest import FRAMEPASS, SCRATCH

HERE = os.path.dirname(os.path.abspath(__file__))
PLAYWRIGHT = "playwright-core@1.60.0"  # the newest that runs on Debian 12's node 18


def node_prefix():
    prefix = os.environ.get("FP_NODE_PREFIX", os.path.join(SCRATCH, "node"))
    if not os.path.exists(os.path.join(prefix, "node_modules", "playwright-core")):
        os.makedirs(prefix, exist_ok=True)
        subprocess.run(["npm", "install", "--prefix", prefix, "--no-audit", "--no-fund", PLAYWRIGHT],
                       check=True, stdout=subprocess.DEVNULL)
    return prefix


@pytest.fixture(scope="module")
def browser_run(server):
    chromium = shutil.which("chromium")
    if not shutil.which("node") or not shutil.which("npm") or not chromium:
        pytest.skip("needs node, npm and Debian's chromium (make deps installs them)")
    out = os.path.join(SCRATCH, "browser")
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, FP_NODE_PREFIX=node_prefix(), CHROMIUM=chromium)
    run = subprocess.run(["node", os.path.join(HERE, "workbench.mjs"), server.url, out], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    with open(os.path.join(out, "results.json")) as f:
        return json.load(f)


def test_the_page_loads_with_the_chain_and_no_errors(browser_run):
    r = browser_run
    assert r["errors"] == []
    assert r["graphNodes"] >= 10 and r["graphPorts"] >= 10  # capture buffers and passes
    assert r["reportRows"] >= 8 and r["errorRows"] == 4  # passes run; the 4 error measures
    assert r["shown"] == {"a": "ssgi_denoise.diffuse", "b": "Truth.DiffuseIndirectOneBounce"}
    for shot in r["steps"]:
        assert os.path.getsize(shot) > 10_000, shot


def test_a_slider_changes_the_image_and_the_times(browser_run):
    r = browser_run
    assert r["settings"]["cvars"].get("r.SSGI.Quality") == 1
    assert r["imageChanged"]
    assert r["timingAfter"] != r["timingBefore"] and "reused" in r["timingAfter"]


def test_the_error_is_taken_apart_on_the_page(browser_run):
    assert "ssgi_vs_full:" in browser_run["breakdown"] and "screen-space limit" in browser_run["breakdown"]


def test_wipe_shows_a_left_and_b_right(browser_run):
    w = browser_run["wipe"]
    assert w["wipeLeft"] == w["aLeft"]
    assert w["wipeRight"] == w["bRight"]
    assert w["aRight"] != w["bRight"]


def test_the_probe_reads_the_command_lines_value(browser_run, server):
    r = browser_run
    x, y = r["probe"]["pixel"]
    line = next(l for l in r["probe"]["text"].splitlines() if l.startswith("ssgi_denoise.diffuse:"))
    shown = [float(v.split("=")[1]) for v in line.split(": ")[1].split()]
    # The command line with the page's settings, dumping the port as float32.
    out = os.path.join(SCRATCH, "browser", "cli")
    args = [FRAMEPASS, "-q", "run", server.config, "-o", out, "--dump", "ssgi_denoise.diffuse"]
    for name, value in r["settings"]["cvars"].items():
        args += ["--cvar", f"{name}={json.dumps(value)}"]
    for name, value in r["settings"]["set"].items():
        args += ["--set", f"{name}={json.dumps(value)}"]
    subprocess.run(args, check=True)
    (dump,) = os.listdir(os.path.join(out, "dump"))
    cli = fp.read_exr(os.path.join(out, "dump", dump))["ssgi_denoise.diffuse"]
    assert np.float32(shown).tolist() == cli[y, x].tolist()


def test_the_exported_config_runs_to_the_bits_the_page_shows(browser_run):
    r = browser_run
    with open(r["exported"]) as f:
        config = json.load(f)
    assert config["cvars"]["r.SSGI.Quality"] == 1
    out = os.path.join(SCRATCH, "browser", "exported_run")
    subprocess.run([FRAMEPASS, "-q", "run", r["exported"], "-o", out, "--dump",
                    "ssgi_denoise.diffuse"], check=True)
    (dump,) = os.listdir(os.path.join(out, "dump"))
    cli = fp.read_exr(os.path.join(out, "dump", dump))["ssgi_denoise.diffuse"]
    shown = np.fromfile(r["shownA"], dtype=np.float32).reshape(r["shownAShape"])
    assert np.array_equal(shown.view(np.uint32), cli.view(np.uint32))
