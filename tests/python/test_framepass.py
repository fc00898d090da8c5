"""The Python module against the command line and itself (docs/python.md).

Run by ctest with PYTHONPATH=build/python, FRAMEPASS (the executable), FP_SOURCE_DIR and
FP_SCRATCH set. Every comparison is of bits: the module and the CLI call the same library.
"""
import gc
import glob
import json
import logging
import os
import subprocess
import threading

import numpy as np
import pytest

import framepass as fp

FRAMEPASS = os.environ["FRAMEPASS"]
SOURCE = os.environ["FP_SOURCE_DIR"]
SCRATCH = os.path.join(os.path.abspath(os.environ["FP_SCRATCH"]), "python")
OUTPUTS = ["ssgi_denoise.diffuse", "diffuse_indirect_composite.color"]


@pytest.fixture(scope="module")
def config():
    """A 64×48 Cornell capture with truth, and the 4.27 preset on it writing float EXRs."""
    os.makedirs(SCRATCH, exist_ok=True)
    capture = os.path.join(SCRATCH, "cornell.exr")
    subprocess.run([FRAMEPASS, "-q", "capture", os.path.join(SOURCE, "examples/cornell/scene.json"),
                    "-o", capture, "--width", "64", "--height", "48", "--truth", "--truth-spp", "8",
                    "--light-samples", "2"], check=True)
    path = os.path.join(SCRATCH, "config.json")
    with open(path, "w") as f:
        json.dump({"version": 1, "capture": capture, "exr": {"colorPrecision": "float"},
                   "cvars": {"r.SSGI.LeakFreeReprojection": 1}}, f)
    return path


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_run_gives_the_bits_the_command_line_writes(config):
    out = os.path.join(SCRATCH, "cli")
    args = [FRAMEPASS, "-q", "run", config, "-o", out]
    for o in OUTPUTS:
        args += ["--dump", o]
    subprocess.run(args, check=True)
    images = fp.Session(config).run(outputs=OUTPUTS)
    assert sorted(images) == sorted(OUTPUTS)
    for name in OUTPUTS:
        (dump,) = glob.glob(os.path.join(out, "dump", name + ".*.exr"))
        written = fp.read_exr(dump)[name]
        array = images[name]
        assert array.dtype == np.float32 and array.ndim == 3 and array.shape[:2] == (48, 64)
        assert same_bits(array, written), name


def test_a_change_reruns_only_what_it_reaches(config):
    s = fp.Session(config)
    first = s.run(outputs=OUTPUTS)
    s.set("ssgi_denoise.denoiser", 0)
    changed = s.run(outputs=OUTPUTS)
    reused = {p["name"] for p in s.report()["passes"] if p.get("reused")}
    assert {"hzb", "prev_color_reduction", "ssgi"} <= reused
    assert "ssgi_denoise" not in reused
    assert not same_bits(first[OUTPUTS[0]], changed[OUTPUTS[0]])
    # The same bits as a session that had the setting from the start.
    fresh = fp.Session(config)
    fresh.set("ssgi_denoise.denoiser", 0)
    assert same_bits(fresh.run(outputs=OUTPUTS)[OUTPUTS[0]], changed[OUTPUTS[0]])
    s.set_cvar("r.SSGI.Quality", 2)
    s.run(outputs=OUTPUTS)
    assert "hzb" in {p["name"] for p in s.report()["passes"] if p.get("reused")}


def test_plan_and_passes_are_the_commands_json(config):
    plan = fp.Session(config).plan(OUTPUTS)
    cli = json.loads(subprocess.run([FRAMEPASS, "plan", config, "--json"] +
                                    sum([["--dump", o] for o in OUTPUTS], []),
                                    capture_output=True, text=True, check=True).stdout)
    assert [s["name"] for s in plan["steps"]] == [s["name"] for s in cli["steps"]]
    types = {t["type"]: t for t in fp.passes()}
    assert "rays" in {p["name"] for p in types["ssgi"]["params"]}
    assert "Session" in fp.Session.__doc__ and "incremental" in fp.Session.__doc__


def test_bad_input_is_a_python_exception_with_the_cli_message(config, tmp_path):
    with pytest.raises(fp.ConfigError):
        fp.Session(str(tmp_path / "missing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text('{"version": 1, "capture": "x.exr", "pases": []}')
    with pytest.raises(fp.ConfigError, match="pases"):
        fp.Session(str(bad))
    s = fp.Session(config)
    with pytest.raises(fp.ConfigError, match="no_such_pass"):
        s.run(outputs=["no_such_pass.image"])
    with pytest.raises(TypeError):
        s.set_cvar("r.SSGI.Quality", [2])
    s.set("ssgi.quality", 9)  # out of range: said when the chain is planned
    with pytest.raises(fp.ConfigError, match="quality"):
        s.run(outputs=OUTPUTS)
    assert issubclass(fp.ConfigError, fp.Error) and issubclass(fp.CaptureError, fp.Error)


def test_sessions_in_threads_give_the_bits_of_one_after_the_other(config):
    def run(quality):
        s = fp.Session(config)
        s.set_cvar("r.SSGI.Quality", quality)
        return s.run(outputs=OUTPUTS)

    alone = [run(q) for q in (1, 4)]
    results = [None, None]

    def worker(i, q):
        results[i] = run(q)

    threads = [threading.Thread(target=worker, args=(i, q)) for i, q in enumerate((1, 4))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, results):
        for name in OUTPUTS:
            assert same_bits(a[name], b[name])


def test_an_output_outlives_its_session(config):
    s = fp.Session(config)
    array = s.run(outputs=OUTPUTS)[OUTPUTS[1]]
    copy = array.copy()
    del s
    gc.collect()
    assert same_bits(array, copy)
    assert np.isfinite(array).all() and array.max() > 0


def test_compare_is_the_commands_figures(config):
    capture = json.load(open(config))["capture"]
    figures = fp.compare(capture, capture, layer="Truth.DiffuseIndirectOneBounce",
                         ref_layer="Truth.DiffuseIndirectFull")
    cli = json.loads(subprocess.run([FRAMEPASS, "compare", capture, capture, "--layer",
                                     "Truth.DiffuseIndirectOneBounce", "--ref-layer",
                                     "Truth.DiffuseIndirectFull", "--json"],
                                    capture_output=True, text=True, check=True).stdout)
    assert figures["rmse"] == cli["rmse"] and figures["rmse"] > 0


def test_warnings_go_to_python_logging(config, caplog):
    # Two frames of one file without a frame token: the library warns, through logging.
    with caplog.at_level(logging.INFO, logger="framepass"):
        fp.Session(config, frames="1-2")
    assert any("frame token" in r.getMessage() and r.levelno == logging.WARNING
               for r in caplog.records)
