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
    with pytest.raises(fp.ConfigError, match="quality"):
        s.set("ssgi.quality", 9)  # out of range: refused when it is set (test_settings.py)
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


def capture_of(config):
    return json.load(open(config))["capture"]


def test_a_capture_in_memory_runs_as_its_file(config):
    c = fp.read_capture(capture_of(config))
    assert {"SceneDepth", "WorldNormal", "BaseColor", "SceneColor"} <= set(c.keys())
    assert (c.width, c.height) == (64, 48) and c.camera is not None
    assert c["WorldNormal"].shape == (48, 64, 3) and c["SceneDepth"].dtype == np.float32
    from_file = fp.Session(config).run(outputs=OUTPUTS)
    # The capture read into memory, and the same pixels handed over as plain numpy arrays.
    rebuilt = fp.Capture.from_arrays({k: np.array(c[k]) for k in c.keys()}, camera=c.camera,
                                     frame=c.frame)
    for capture in (c, rebuilt):
        images = fp.Session(config, capture=capture).run(outputs=OUTPUTS)
        for name in OUTPUTS:
            assert same_bits(images[name], from_file[name]), name
    # A camera given as its sidecar JSON plans and runs too.
    from_dict = fp.Capture.from_arrays(c.buffers(), camera=c.camera.to_dict())
    assert fp.Session(config, capture=from_dict).run(outputs=OUTPUTS)[OUTPUTS[1]].shape == (48, 64, 3)


def test_from_arrays_names_the_buffer_that_is_wrong(config):
    c = fp.read_capture(capture_of(config))
    good = c.buffers()

    def rejected(change, match, error=ValueError):
        buffers = dict(good)
        buffers.update(change)
        with pytest.raises(error, match=match):
            fp.Capture.from_arrays(buffers, camera=c.camera)

    rejected({"SceneDepth": np.ones((48, 64), np.int32)}, "SceneDepth.*dtype")
    rejected({"SceneColor": good["SceneColor"].astype(np.complex64)}, "SceneColor.*dtype")
    rejected({"WorldNormal": good["WorldNormal"][:, :, :2]}, "WorldNormal.*2 channels")
    rejected({"BaseColor": good["BaseColor"][:24]}, "'BaseColor' is 64×24|64×24.*'BaseColor'")
    rejected({"BaseColor": good["BaseColor"][None]}, "BaseColor.*shape")
    rejected({"Truth.Thing": np.zeros((48, 64, 2), np.float32)}, "Truth.Thing.*2 channels")
    rejected({"Albedo": good["BaseColor"]}, "'Albedo' is not a capture buffer")
    rejected({"SceneDepth": "depth.exr"}, "SceneDepth.*numpy array")
    rejected({"SceneDepth": np.zeros((0, 64), np.float32)}, "SceneDepth.*empty")
    # A broadcast array of 10^12 pixels is refused from its shape, before any copy.
    rejected({"SceneDepth": np.broadcast_to(np.float32(1), (1 << 20, 1 << 20))},
             "SceneDepth.*larger than framepass reads")
    with pytest.raises(ValueError, match="no buffers"):
        fp.Capture.from_arrays({})
    with pytest.raises(TypeError, match="camera"):
        fp.Capture.from_arrays(good, camera=42)
    with pytest.raises(fp.ConfigError, match="fovYDegrees"):
        fp.Capture.from_arrays(good, camera={"position": [0, 0, 0], "target": [0, 0, 1]})
    # Bad pixels are replaced as a run replaces them read from a file, and said.
    color = good["SceneColor"].copy()
    color[0, 0] = [np.nan, -1.0, np.inf]
    c2 = fp.Capture.from_arrays(dict(good, SceneColor=color), camera=c.camera)
    assert any("SceneColor" in n and "non-finite" in n for n in c2.notes)
    assert (c2["SceneColor"][0, 0] == 0).all()
    out = fp.Session(config, capture=c2).run(outputs=OUTPUTS)
    assert all(np.isfinite(a).all() for a in out.values())
    # A capture without a camera plans, and a chain that needs one says so.
    with pytest.raises(fp.Error, match="camera"):
        fp.Session(config, capture=fp.Capture.from_arrays(good)).run(outputs=OUTPUTS)


def test_the_planar_layout_is_a_view_of_the_librarys_pixels(config):
    s = fp.Session(config)
    hwc = s.run(outputs=OUTPUTS)
    chw = s.run(outputs=OUTPUTS, layout="chw")
    again = s.run(outputs=OUTPUTS, layout="chw")  # nothing changed: the same kept images
    for name in OUTPUTS:
        assert chw[name].shape == (hwc[name].shape[2],) + hwc[name].shape[:2]
        assert same_bits(np.ascontiguousarray(chw[name].transpose(1, 2, 0)), hwc[name])
        assert not chw[name].flags.writeable and chw[name].base is not None
        assert np.shares_memory(chw[name], again[name])  # no copy was made
    keep = chw[OUTPUTS[1]]
    expected = keep.copy()
    del s, chw, again
    gc.collect()
    assert same_bits(keep, expected)
    with pytest.raises(ValueError, match="layout"):
        fp.Session(config).run(outputs=OUTPUTS, layout="whc")


def test_compare_of_arrays_is_compare_of_files(config):
    capture = capture_of(config)
    layers = fp.read_exr(capture, ["Truth.DiffuseIndirectOneBounce", "Truth.DiffuseIndirectFull"])
    files = fp.compare(capture, capture, layer="Truth.DiffuseIndirectOneBounce",
                       ref_layer="Truth.DiffuseIndirectFull", masks=["none"])
    arrays = fp.compare(layers["Truth.DiffuseIndirectOneBounce"], layers["Truth.DiffuseIndirectFull"])
    for key in ("rmse", "relMse", "smape", "mae", "bias", "maxError", "pixels"):
        assert arrays[key] == files[key], key
    assert fp.compare(layers["Truth.DiffuseIndirectOneBounce"], layers["Truth.DiffuseIndirectFull"],
                      metric="rmse") == files["rmse"]
    # A mask keeps the pixels where it is > 0: all of them is no mask.
    ones = np.ones((48, 64), np.float32)
    assert fp.compare(layers["Truth.DiffuseIndirectOneBounce"], layers["Truth.DiffuseIndirectFull"],
                      mask=ones)["rmse"] == files["rmse"]
    with pytest.raises(ValueError, match="one shape"):
        fp.compare(np.zeros((4, 4, 3)), np.zeros((4, 4, 1)))
    with pytest.raises(TypeError, match="one of each"):
        fp.compare(capture, np.zeros((4, 4, 3)))
    with pytest.raises(ValueError, match="metric 'psnr'"):
        fp.compare(np.zeros((4, 4)), np.zeros((4, 4)), metric="psnr")


def test_bench_is_the_commands_sweep(config):
    result = fp.bench(config, sweep={"r.SSGI.Quality": [1, 2]}, runs=1, warmup=0,
                      decompose_rays=0)
    cli = json.loads(subprocess.run([FRAMEPASS, "bench", config, "--sweep", "r.SSGI.Quality=1,2",
                                     "--runs", "1", "--warmup", "0", "--decompose-rays", "0",
                                     "--json"], capture_output=True, text=True,
                                    check=True).stdout)
    assert set(result) == set(cli)
    assert [s["label"] for s in result["settings"]] == [s["label"] for s in cli["settings"]]
    assert len(result["settings"]) == 2
    with pytest.raises(TypeError, match="list of values"):
        fp.bench(config, sweep={"r.SSGI.Quality": 2})


def test_cvars_read_and_set_like_set_cvar(config):
    s = fp.Session(config)
    assert s.cvars["r.SSGI.LeakFreeReprojection"] == 1  # the config's
    ssgi = {p["name"]: p for p in {t["type"]: t for t in fp.passes()}["ssgi"]["params"]}
    assert s.cvars["r.ssgi.quality"] == ssgi["quality"]["default"]  # Unreal's console ignores case
    assert "r.SSGI.Quality" in s.cvars and len(s.cvars) == len(list(s.cvars))
    s.cvars["r.SSGI.Quality"] = 2
    assert s.cvars["r.SSGI.Quality"] == 2
    other = fp.Session(config)
    other.set_cvar("r.SSGI.Quality", 2)
    assert same_bits(s.run(outputs=OUTPUTS)[OUTPUTS[0]], other.run(outputs=OUTPUTS)[OUTPUTS[0]])
    with pytest.raises(KeyError, match="r.SSGI.Qualty"):
        s.cvars["r.SSGI.Qualty"]
    with pytest.raises(fp.UnknownSettingError):
        s.cvars["r.SSGI.Qualty"] = 1


def test_a_config_error_says_where(config, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"version": 1, "capture": capture_of(config),
                               "cvars": {"r.SSGI.Quality": "high"}}))
    with pytest.raises(fp.ConfigError) as e:
        fp.Session(str(bad))
    assert e.value.path == str(bad)
    assert e.value.pointer == "/cvars/r.SSGI.Quality"
    assert ("/cvars/r.SSGI.Quality", e.value.problems[0][1]) in e.value.problems
    assert "/cvars/r.SSGI.Quality" in str(e.value)


def test_threads_limit_a_session_without_changing_its_bits(config):
    one = fp.Session(config, threads=1).run(outputs=OUTPUTS)
    every = fp.Session(config).run(outputs=OUTPUTS)
    for name in OUTPUTS:
        assert same_bits(one[name], every[name])
    with pytest.raises(ValueError):
        fp.Session(config, threads=-1)
