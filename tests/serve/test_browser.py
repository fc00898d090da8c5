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


def browser_env():
    chromium = shutil.which("chromium")
    if not shutil.which("node") or not shutil.which("npm") or not chromium:
        pytest.skip("needs node, npm and Debian's chromium (make deps installs them)")
    return dict(os.environ, FP_NODE_PREFIX=node_prefix(), CHROMIUM=chromium, FRAMEPASS=FRAMEPASS)


def node(script, out, *args, env):
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run(["node", os.path.join(HERE, script), *args], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    with open(os.path.join(out, "results.json")) as f:
        return json.load(f)


@pytest.fixture(scope="module")
def browser_run(server):
    env = browser_env()
    # The PNG `framepass run` writes for the config as loaded: what the canvas must show.
    for key, folder, args in (("FP_RUN_PNG", "browser_png", []),
                              ("FP_RUN_FILM_PNG", "browser_film_png",
                               ["--set", "display.tonemapper=ue4.27-film"])):
        png_run = os.path.join(SCRATCH, folder)
        subprocess.run([FRAMEPASS, "-q", "run", server.config, "-o", png_run, *args], check=True)
        (png,) = [f for f in os.listdir(png_run) if f.startswith("final.") and f.endswith(".png")]
        env[key] = os.path.join(png_run, png)
    out = os.path.join(SCRATCH, "browser")
    return node("workbench.mjs", out, server.url, out, env=env)


@pytest.fixture(scope="module")
def failures_run(config, missing_capture_config, pinned_quality_config):
    out = os.path.join(SCRATCH, "browser_failures")
    return node("workbench_failures.mjs", out, out, config, missing_capture_config,
                pinned_quality_config, env=browser_env())


def test_the_page_loads_with_the_chain_and_no_errors(browser_run):
    r = browser_run
    assert r["errors"] == []
    assert r["graphNodes"] >= 10 and r["graphPorts"] >= 10  # capture buffers and passes
    assert r["reportRows"] >= 8 and r["errorRows"] == 4  # passes run; the 4 error measures
    assert r["shown"] == {"a": "ssgi_denoise.diffuse", "b": "Truth.DiffuseIndirectOneBounce"}
    for shot in r["steps"]:
        assert os.path.getsize(shot) > 10_000, shot


def test_flip_shows_beside_the_error_figures_when_a_measure_takes_it(browser_run):
    f = browser_run["flip"]
    assert f["heads"] == ["measure", "rmse", "relMse", "bias", "flip"]
    assert 0 < f["api"] <= 1 and float(f["rows"]["ssgi_vs_full"]) == pytest.approx(f["api"], rel=5e-3)
    assert f["rows"]["ao_vs_truth"] == ""  # the measures that do not take it
    assert "flip" not in browser_run["flipAfter"]


def test_a_slider_changes_the_image_and_the_times(browser_run):
    r = browser_run
    # The methods plot: this run's three measures bright, the settings before dimmed.
    assert sorted(r["methods"]["now"]) == ["ao_vs_truth", "ssgi_vs_full", "ssgi_vs_one_bounce"]
    assert r["methods"]["earlier"] >= 3
    assert r["settings"]["cvars"].get("r.SSGI.Quality") == 1
    assert r["imageChanged"]
    assert r["timingAfter"] != r["timingBefore"] and "reused" in r["timingAfter"]


def test_the_error_is_taken_apart_on_the_page(browser_run):
    assert "ssgi_vs_full:" in browser_run["breakdown"] and "screen-space limit" in browser_run["breakdown"]
    # As bars: one per step of each measure taken apart, as long as its share says.
    bars = browser_run["breakdownBars"]
    assert len(bars) >= 4 and any(b["name"] == "screen-space limit" for b in bars)
    for b in bars:
        assert abs(b["width"] - min(100, abs(float(b["value"].rstrip(" %"))))) <= 0.5 + 1e-9, b


def test_wipe_shows_a_left_and_b_right(browser_run):
    w = browser_run["wipe"]
    assert w["wipeLeft"] == w["aLeft"]
    assert w["wipeRight"] == w["bRight"]
    assert w["aRight"] != w["bRight"]


def test_both_ways_of_drawing_give_the_same_canvas(browser_run):
    # Once an image pixel into an 8-bit image then placed, or once a canvas pixel: the same
    # shader values written to an 8-bit target either way, so the same bytes.
    paths = browser_run["drawPaths"]
    assert set(paths) == {"a", "b", "wipe", "diff", "falseColour"}
    for mode, p in paths.items():
        assert p["perImagePixel"] == p["perCanvasPixel"], mode
    # The modes drew different things (the comparison is not of blank canvases).
    assert paths["a"]["perImagePixel"] != paths["b"]["perImagePixel"]
    assert paths["diff"]["perImagePixel"] != paths["a"]["perImagePixel"]


def test_the_probe_reads_the_command_lines_value(browser_run, server):
    r = browser_run
    # The pixel the probe read, as it says (the mouse was put on the centre of this one).
    first = r["probe"]["text"].splitlines()[0]
    x, y = (int(v) for v in first.removeprefix("pixel ").split(", "))
    assert [x, y] == r["probe"]["pixel"]
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


def test_the_canvas_draws_each_buffer_as_run_writes_its_png(browser_run):
    """display.image (display-referred, drawn as it is) and the display's input (colour, through
    the view on the page) both equal the PNG of `framepass run`, pixel for pixel. ±1: the PNG
    rounds to 8 bits, the canvas too, after the view's table is interpolated between halves."""
    c = browser_run["colour"]
    for drawn in (c["display"], c["composite"]):
        for got, want in zip(drawn, c["png"]):
            assert max(abs(g - w) for g, w in zip(got[:3], want[:3])) <= 1, (got, want)
    assert "as it is" in c["displayLabel"] and "colour, via Standard" in c["compositeLabel"]


def test_unreals_film_view_draws_what_run_writes_with_it(browser_run):
    """The page's "UE 4.27 film" view (the library's curve baked into a 65³ table over log2, read
    trilinearly) against the PNG of `run` with the display's tonemapper set to ue4.27-film (the
    curve per pixel)."""
    c = browser_run["colour"]
    for got, want in zip(c["film"], c["filmPng"]):
        assert max(abs(g - w) for g, w in zip(got[:3], want[:3])) <= 1, (got, want)
    assert "UE 4.27 film" in c["filmLabel"]


def test_a_and_b_are_named_on_the_image(browser_run):
    labels = browser_run["labels"]
    assert "ssgi_denoise.diffuse" in labels["a"] and "Truth.DiffuseIndirectOneBounce" in labels["b"]


def test_the_graph_fits_its_panel_and_names_fit_their_boxes(browser_run):
    g = browser_run["graph"]
    assert g["svgWidth"] <= g["panelWidth"] + 1 and g["overflowing"] == []


def test_tev_keys_work_with_the_focus_on_a_slider(browser_run):
    k = browser_run["keys"]
    assert k["e"]["exposure"] == "0.5" and k["E"]["exposure"] == "0"
    assert (k["r"]["channel"], k["r again"]["channel"]) == ("1", "0")
    assert (k["l"]["channel"], k["l again"]["channel"]) == ("5", "0")
    assert (k["2"]["mode"], k["d"]["mode"], k["1"]["mode"]) == ("b", "diff", "a")
    assert k["+"]["zoom"] > k["1"]["zoom"] and k["0"]["zoom"] == 1 and abs(k["-"]["zoom"] - 0.8) < 1e-9
    assert k["f"]["fitted"] and not k["0"]["fitted"]
    # The slider kept its value and the focus: the keys were the viewer's, not the slider's.
    assert k["sliderUnchanged"] and k["focusStayed"] == "r.SSGI.Quality"
    # In a number field a key types: the exposure stayed.
    assert k["e in a number field"]["exposure"] == "0"


def test_resizing_keeps_a_zoomed_centre_and_refits_a_fitted_image(browser_run):
    r = browser_run["resize"]
    assert all(abs(a - b) < 0.5 for a, b in zip(r["zoomedCentreBefore"], r["zoomedCentreAfter"]))
    f = r["fitted"]
    fit = min(f["canvas"][0] / f["image"][0], f["canvas"][1] / f["image"][1])
    assert f["fitted"] and abs(f["zoom"] - fit) < 1e-9


def test_a_failed_first_frame_a_lost_server_and_a_shadowed_cvar_are_shown(failures_run):
    r = failures_run
    assert "first frame failed" in r["firstFrame"]["status"] and "no_such_capture" in r["firstFrame"]["status"]
    assert "error" in r["firstFrame"]["error"]
    assert r["lost"]["connection"] == "lost" and "lost the server" in r["lost"]["status"]
    # Back on a restarted server: the controls show its settings (as loaded), not the old ones.
    assert r["back"]["connection"] == "open" and "reconnected" in r["back"]["status"]
    assert r["back"]["slider"] == str(r["back"]["server"]) == r["back"]["loaded"]
    assert "no effect" in r["shadowed"]["note"] and "/params/quality" in r["shadowed"]["note"]
    assert "shadowed" in r["shadowed"]["marked"]


def test_a_snapshot_compared_over_a_rectangle(browser_run, server):
    """A pinned at the settings as loaded (quality 4), the slider moved to 1, the snapshot shown as
    B: the rectangle's statistics are A's mean and the RMSE of A against B, as numpy computes them
    from the command line's dumps (float64 sums on both sides: 1e-9 relative)."""
    r = browser_run
    assert "ssgi_denoise.diffuse" in r["snapshotLabel"] and "as loaded" in r["snapshotLabel"]
    assert "snapshot: ssgi_denoise.diffuse" in r["snapshotB"]
    stats = r["rect"]["stats"]
    x0, y0, x1, y1 = r["rect"]["asked"]
    assert stats["rect"] == [x0, y0, x1, y1] and stats["pixels"] == (x1 - x0) * (y1 - y0)
    a = np.fromfile(r["shownA"], dtype=np.float32).reshape(r["shownAShape"])[y0:y1, x0:x1]
    out = os.path.join(SCRATCH, "browser", "as_loaded")
    subprocess.run([FRAMEPASS, "-q", "run", server.config, "-o", out, "--dump", "ssgi_denoise.diffuse"],
                   check=True)
    (dump,) = os.listdir(os.path.join(out, "dump"))
    b = fp.read_exr(os.path.join(out, "dump", dump))["ssgi_denoise.diffuse"][y0:y1, x0:x1]
    assert not np.array_equal(a, b)  # quality 1 against 4: something to measure
    mean = a.astype(np.float64).reshape(-1, a.shape[2]).mean(axis=0)
    rmse = np.sqrt(((a.astype(np.float64) - b) ** 2).mean())
    assert np.allclose(stats["mean"], mean, rtol=1e-9, atol=0)
    assert abs(stats["rmse"] - rmse) <= 1e-9 * rmse
    assert "RMSE of A against B" in r["rect"]["text"]
