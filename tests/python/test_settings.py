"""Typed settings, Python's errors, Ctrl-C, threads, capture buffers as outputs and write_exr
(docs/python.md). Run by ctest as test_framepass.py is; every comparison is of bits."""
import glob
import json
import logging
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import framepass as fp

FRAMEPASS = os.environ["FRAMEPASS"]
SOURCE = os.environ["FP_SOURCE_DIR"]
SCRATCH = os.path.join(os.path.abspath(os.environ["FP_SCRATCH"]), "python-settings")
OUTPUTS = ["ssgi_denoise.diffuse", "diffuse_indirect_composite.color"]


def capture(name, width, height):
    os.makedirs(SCRATCH, exist_ok=True)
    path = os.path.join(SCRATCH, name + ".exr")
    if not os.path.exists(path):
        subprocess.run([FRAMEPASS, "-q", "capture", os.path.join(SOURCE, "examples/cornell/scene.json"),
                        "-o", path, "--width", str(width), "--height", str(height), "--truth",
                        "--truth-spp", "4", "--light-samples", "2"], check=True)
    return path


def write_config(name, body):
    path = os.path.join(SCRATCH, name + ".json")
    with open(path, "w") as f:
        json.dump(dict({"version": 1, "exr": {"colorPrecision": "float"}}, **body), f)
    return path


@pytest.fixture(scope="module")
def config():
    return write_config("config", {"capture": capture("small", 64, 48)})


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_a_refused_setting_raises_at_the_call_and_leaves_the_session_as_it_was(config):
    s = fp.Session(config)
    default = s.cvars["r.SSGI.Quality"]
    with pytest.raises(fp.SettingValueError) as e:
        s.cvars["r.SSGI.Quality"] = 9
    assert isinstance(e.value, ValueError) and isinstance(e.value, fp.ConfigError)
    assert str(e.value).startswith("set_cvar('r.SSGI.Quality'): ")
    assert "--cvar" not in str(e.value)
    with pytest.raises(fp.SettingTypeError) as e:
        s.set_cvar("r.SSGI.Quality", "high")
    assert isinstance(e.value, TypeError)
    with pytest.raises(fp.UnknownSettingError, match="quality") as e:
        s.set("ssgi.qualty", 2)  # did you mean 'quality'
    assert isinstance(e.value, KeyError)
    assert "set('ssgi.qualty')" in str(e.value)
    with pytest.raises(fp.UnknownSettingError, match="r.SSGI.Quality"):
        s.set_cvar("r.SSGI.Qualty", 1)
    with pytest.raises(fp.UnknownSettingError):
        s.set("no_such_pass.quality", 1)
    with pytest.raises(TypeError, match="list"):
        s.set_cvar("r.SSGI.Quality", [2])
    # Nothing stuck: the session reads and runs as a fresh one does.
    assert s.cvars["r.SSGI.Quality"] == default
    fresh = fp.Session(config).run(outputs=OUTPUTS)
    for name, image in s.run(outputs=OUTPUTS).items():
        assert same_bits(image, fresh[name]), name
    # numpy's scalars are numbers, as Python's are.
    s.set_cvar("r.SSGI.Quality", np.int64(2))
    s.set("ssgi_denoise.temporalAccumulation", np.bool_(False).item())
    assert s.cvars["r.SSGI.Quality"] == 2


def test_an_input_is_rebound_by_set_input_checked_when_set_with_the_command_lines_bits():
    with open(os.path.join(SOURCE, "examples/cornell/methods.json")) as f:
        methods = json.load(f)
    methods.update(capture=capture("small", 64, 48),
                   scene=os.path.join(SOURCE, "examples/cornell/scene.json"))
    methods.pop("description")
    config = write_config("methods", methods)
    s = fp.Session(config)
    steps = lambda: {step["name"] for step in s.plan()["steps"]}
    assert "ssgi" in steps() and "rtgi_denoise" not in steps()
    s.set_input("gi_vs_full.source", "rtgi_denoise.diffuse")
    assert "rtgi_denoise" in steps() and "ssgi" not in steps()  # the method left is culled
    with pytest.raises(fp.UnknownSettingError, match="did you mean 'source'") as e:
        s.set_input("gi_vs_full.sorce", "ssgi_denoise.diffuse")
    assert isinstance(e.value, KeyError) and "set_input('gi_vs_full.sorce')" in str(e.value)
    with pytest.raises(fp.SettingValueError, match="no_such"):
        s.set_input("gi_vs_full.source", "no_such.diffuse")
    with pytest.raises(fp.UnknownSettingError, match=r"not a parameter: rebind it with "
                                                     r"set_input\('gi_vs_full.source'\)"):
        s.set("gi_vs_full.source", "ssgi_denoise.diffuse")
    with pytest.raises(TypeError):
        s.set_input("gi_vs_full.source", 3)
    assert "rtgi_denoise" in steps()  # every refusal left the rebinding as it was
    assert "1 input set" in repr(s)
    heat = s.run(outputs=["gi_vs_full.heat"])["gi_vs_full.heat"]
    out = os.path.join(SCRATCH, "methods-cli")
    subprocess.run([FRAMEPASS, "-q", "run", config, "-o", out, "--input",
                    "gi_vs_full.source=rtgi_denoise.diffuse", "--dump", "gi_vs_full.heat"], check=True)
    (dump,) = glob.glob(os.path.join(out, "dump", "gi_vs_full.heat.*.exr"))
    written = fp.read_exr(dump)["gi_vs_full.heat"]
    assert same_bits(heat, written)


def test_on_device_on_the_cpu_gives_host_arrays(config):
    # Only a pass that ran on the GPU leaves its output there (a CudaArray: tests/gpu/
    # cuda_outputs_check.py checks those on a GPU machine); a CPU session's come back as numpy's.
    s = fp.Session(config)
    kept = s.run(outputs=OUTPUTS, on_device=True)
    plain = fp.Session(config).run(outputs=OUTPUTS)
    for name in OUTPUTS:
        assert isinstance(kept[name], np.ndarray) and same_bits(kept[name], plain[name]), name
    assert "__cuda_array_interface__" in dir(fp.CudaArray) and "__dlpack__" in dir(fp.CudaArray)


def test_a_cvar_that_a_config_parameter_shadows_reads_as_resolved_and_warns(caplog):
    shadowed = write_config("shadowed", {"capture": capture("small", 64, 48),
                                         "set": {"ssgi.quality": 3}})
    s = fp.Session(shadowed)
    with caplog.at_level(logging.WARNING, logger="framepass"):
        s.cvars["r.SSGI.Quality"] = 1
    assert s.cvars["r.SSGI.Quality"] == 3  # what the planner resolved: the config's parameter
    assert any("set_cvar('r.SSGI.Quality')" in r.getMessage() and "no effect" in r.getMessage()
               for r in caplog.records)


def test_capture_buffers_and_truth_layers_are_outputs(config):
    s = fp.Session(config)
    names = ["SceneColor", "Truth.DiffuseIndirectFull", "ssgi_denoise.diffuse"]
    out = s.run(outputs=names)
    assert sorted(out) == sorted(names)
    c = fp.read_capture(json.load(open(config))["capture"])
    assert same_bits(out["SceneColor"], c["SceneColor"])
    assert same_bits(out["Truth.DiffuseIndirectFull"], c["Truth.DiffuseIndirectFull"])
    # Only capture buffers: nothing runs.
    assert sorted(fp.Session(config).run(outputs=["SceneDepth"])) == ["SceneDepth"]


def test_cancel_says_it_was_cancelled(config):
    s = fp.Session(write_config("cancel", {"capture": capture("mid", 320, 240)}))
    t = threading.Timer(0.05, s.cancel)
    t.start()
    try:
        s.run(outputs=OUTPUTS)
    except fp.Cancelled as e:
        assert "cancelled by Session.cancel()" in str(e)
    t.join()


def test_ctrl_c_stops_a_run_at_the_next_pass():
    path = write_config("interrupt", {"capture": capture("mid", 320, 240)})
    whole = fp.Session(path, threads=1)
    start = time.perf_counter()
    reference = whole.run(outputs=OUTPUTS)
    seconds = time.perf_counter() - start
    # Where each pass of the whole run ended, from its start.
    ends = np.cumsum([p["seconds"] for p in whole.report()["passes"]])
    s = fp.Session(path, threads=1)
    # SIGINT from another thread a quarter into the run, as a terminal's Ctrl-C or a notebook's
    # "interrupt kernel" sends it to the process.
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    t = threading.Timer(seconds / 4, interrupt)
    start = time.perf_counter()
    t.start()
    with pytest.raises(KeyboardInterrupt):
        s.run(outputs=OUTPUTS)
    interrupted = time.perf_counter() - start
    t.join()
    # The run stops when the pass in flight at the signal ends: that pass's end on the whole
    # run's clock, with room for a busier machine (×1.5) and the signal's way to Python (50 ms).
    in_flight_end = next((e for e in ends if e >= fired[0] - start), ends[-1])
    assert in_flight_end < ends[-1], "the signal came during the last pass: nothing to stop"
    assert interrupted < 1.5 * in_flight_end + 0.05, (interrupted, in_flight_end, ends[-1])
    assert s.report() is None  # the interrupted run reported nothing
    again = s.run(outputs=OUTPUTS)  # and the session runs whole afterwards
    for name in OUTPUTS:
        assert same_bits(again[name], reference[name]), name


def test_a_session_shared_between_threads_neither_crashes_nor_loses_a_setting(config):
    s = fp.Session(config)
    baseline = {q: fp.Session(config) for q in (1, 2)}
    for q, session in baseline.items():
        session.set_cvar("r.SSGI.Quality", q)
    expected = {q: session.run(outputs=OUTPUTS) for q, session in baseline.items()}
    stop = threading.Event()
    errors = []

    def runner():
        while not stop.is_set():
            try:
                s.run(outputs=OUTPUTS)
            except fp.Cancelled:
                pass
            except Exception as e:  # noqa: BLE001 - any other error is the test failing
                errors.append(e)
                return

    threads = [threading.Thread(target=runner) for _ in range(2)]
    for t in threads:
        t.start()
    deadline = time.monotonic() + 4
    quality = 1
    i = 0
    while time.monotonic() < deadline:
        quality = 1 + i % 2
        s.set_cvar("r.SSGI.Quality", quality)
        assert s.cvars["r.SSGI.Quality"] == quality
        s.report()
        s.plan(OUTPUTS if i % 3 else ["ssgi.hitMask"])
        if i % 7 == 0:
            s.cancel()
        i += 1
    stop.set()
    for t in threads:
        t.join()
    assert not errors, errors
    # The last setting holds: the next run gives that quality's bits.
    assert s.cvars["r.SSGI.Quality"] == quality
    out = s.run(outputs=OUTPUTS)
    for name in OUTPUTS:
        assert same_bits(out[name], expected[quality][name]), name


def test_a_setting_made_during_a_run_applies_to_the_next(config):
    s = fp.Session(write_config("during", {"capture": capture("mid", 320, 240)}))
    other = fp.Session(write_config("during", {"capture": capture("mid", 320, 240)}))
    other.set_cvar("r.SSGI.Quality", 3)
    expected = other.run(outputs=OUTPUTS)
    for _ in range(5):
        t = threading.Thread(target=lambda: s.run(outputs=OUTPUTS))
        t.start()
        s.set_cvar("r.SSGI.Quality", 3)
        t.join()
        out = s.run(outputs=OUTPUTS)
        for name in OUTPUTS:
            assert same_bits(out[name], expected[name]), name
        s.set_cvar("r.SSGI.Quality", 1)


def test_write_exr_reads_back_bit_for_bit(tmp_path):
    rng = np.random.default_rng(7)
    color = rng.uniform(-2, 70000, (5, 7, 3)).astype(np.float32)
    alpha = rng.uniform(0, 1, (5, 7, 4)).astype(np.float32)
    depth = rng.uniform(1, 1e6, (5, 7)).astype(np.float32)
    path = str(tmp_path / "w.exr")
    fp.write_exr(path, {"beauty": alpha, "depth": depth, "half": color}, half=["half"],
                 metadata={"comment": "from python"}, frame=12)
    back = fp.read_exr(path)
    assert sorted(back) == ["beauty", "depth", "half"]
    assert same_bits(back["beauty"], alpha)
    assert same_bits(back["depth"], depth[:, :, None])
    # Half rounds as numpy's float16 does, and saturates beyond its range instead of overflowing.
    assert np.array_equal(back["half"], np.clip(color, -65504, 65504).astype(np.float16).astype(np.float32))
    meta = fp.exr_metadata(path)
    assert meta["comment"] == "from python" and meta["framepass:frame"] == 12
    with pytest.raises(ValueError, match="one size"):
        fp.write_exr(path, {"a": depth, "b": depth[:2]})
    with pytest.raises(ValueError, match="compression"):
        fp.write_exr(path, {"a": depth}, compression="lzma")


def test_version_and_reprs(config):
    cli = subprocess.run([FRAMEPASS, "--version"], capture_output=True, text=True, check=True).stdout
    assert fp.__version__ and fp.__version__ in cli
    s = fp.Session(config)
    s.set_cvar("r.SSGI.Quality", 2)
    assert repr(s) == f"framepass.Session('{config}', frames 1, 1 cvar, 0 parameters and 0 inputs set)"
    assert repr(s.cvars).startswith("framepass.Cvars(")
    assert "r.SSGI.Quality" in s.cvars._ipython_key_completions_()


def test_inspect_reads_the_signatures(config):
    """inspect.signature (help(), IDEs, notebooks' completion) reads every function and Session
    method, from the extension's docstrings: names, keyword-only parameters, literal defaults."""
    import inspect

    bench = inspect.signature(fp.bench).parameters
    assert list(bench)[:3] == ["config", "sweep", "runs"]
    assert bench["runs"].default == 5 and bench["sweep"].kind is inspect.Parameter.KEYWORD_ONLY
    run = inspect.signature(fp.Session(config).run).parameters
    assert list(run) == ["frame", "outputs", "layout", "on_device"] and run["layout"].default == "hwc"
    assert run["on_device"].kind is inspect.Parameter.KEYWORD_ONLY and run["on_device"].default is None
    assert list(inspect.signature(fp.Session(config).set_input).parameters) == ["input", "source"]
    session = inspect.signature(fp.Session).parameters
    assert list(session)[0] == "config" and session["threads"].default == 0
    for f in (fp.compare, fp.read_exr, fp.write_exr, fp.read_capture, fp.exr_metadata):
        assert "path" in str(inspect.signature(f)) or "a" in inspect.signature(f).parameters, f
    assert str(inspect.signature(fp.passes)).startswith("()")  # it takes nothing
    assert fp.bench.__doc__.startswith("bench(")  # help() keeps the docstring


def test_outputs_and_captures_cross_into_torch_through_dlpack(config):
    torch = pytest.importorskip("torch")  # Debian's python3-torch (make test installs it)
    s = fp.Session(config)
    out = s.run(outputs=OUTPUTS)
    for name in OUTPUTS:
        t = torch.from_dlpack(out[name])
        assert t.data_ptr() == out[name].ctypes.data  # the array's memory: no copy
        assert t.dtype == torch.float32 and tuple(t.shape) == out[name].shape
    # Tensors in: a capture made of torch tensors runs as the file does.
    c = fp.read_capture(json.load(open(config))["capture"])
    tensors = {k: torch.from_numpy(np.array(c[k])) for k in c.keys()}
    rebuilt = fp.Capture.from_arrays(tensors, camera=c.camera, frame=c.frame)
    images = fp.Session(config, capture=rebuilt).run(outputs=OUTPUTS)
    for name in OUTPUTS:
        assert same_bits(images[name], out[name]), name
    assert fp.compare(tensors["SceneColor"], tensors["SceneColor"], metric="rmse") == 0
