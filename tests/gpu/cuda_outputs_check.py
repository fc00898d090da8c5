"""Outputs that stay on the GPU, checked from Python on a GPU machine (docs/gpu.md): a session on
device="cuda" hands back CudaArray objects that torch and CuPy take, with the bits of the same
session on the CPU. CI has no GPU; this runs where the module built for that machine's Python
(FP_OTHER_PYTHON_INCLUDE) and the CUDA backend have been carried.

    python3 tests/gpu/cuda_outputs_check.py CAPTURE.exr   (a capture of examples/cornell/scene.json)
"""
import json
import os
import sys
import tempfile

import numpy as np
import torch

import framepass as fp

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Passes with a CUDA kernel whose bits on the GPU are the CPU's (docs/gpu.md).
OUTPUTS = ["ssgi_denoise.diffuse", "diffuse_indirect_composite.color"]


def same_bits(a, b):
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def main(capture):
    config = os.path.join(tempfile.mkdtemp(), "config.json")
    with open(config, "w") as f:
        json.dump({"version": 1, "capture": os.path.abspath(capture),
                   "scene": os.path.join(ROOT, "examples/cornell/scene.json")}, f)
    cpu = fp.Session(config, device="cpu")
    gpu = fp.Session(config, device="cuda")
    checks = 0
    for layout in ("hwc", "chw"):
        want = cpu.run(outputs=OUTPUTS + ["SceneColor"], layout=layout)
        got = gpu.run(outputs=OUTPUTS + ["SceneColor"], layout=layout)
        assert gpu.report()["transfers"]["downloadBytes"] == 0, gpu.report()["transfers"]
        assert isinstance(got["SceneColor"], np.ndarray)  # a capture buffer is read on the host
        for name in OUTPUTS:
            a = got[name]
            assert isinstance(a, fp.CudaArray), type(a)
            assert a.shape == want[name].shape, (a.shape, want[name].shape)
            cai = a.__cuda_array_interface__
            assert cai["version"] == 3 and cai["typestr"] == "<f4" and cai["data"][1] is True
            view = torch.as_tensor(a, device="cuda")  # through __cuda_array_interface__
            assert view.data_ptr() == cai["data"][0], "torch.as_tensor copied"
            assert same_bits(view.cpu().numpy(), want[name]), (layout, name)
            owned = torch.from_dlpack(a)  # a copy on the GPU, the caller's to write
            assert owned.is_cuda and owned.data_ptr() != view.data_ptr()
            assert same_bits(owned.cpu().numpy(), want[name]), (layout, name)
            owned.fill_(0)
            assert same_bits(view.cpu().numpy(), want[name]), "writing the DLPack copy changed the view"
            assert same_bits(np.asarray(a), want[name]) and same_bits(a.numpy(), want[name])
            try:
                import cupy
                assert same_bits(cupy.asnumpy(cupy.asarray(a)), want[name])
            except ImportError:
                pass
            checks += 1
    # The session's next run leaves what an earlier one handed out as it was.
    kept = gpu.run(outputs=OUTPUTS)["ssgi_denoise.diffuse"]
    before = kept.numpy()
    gpu.set_cvar("r.SSGI.Quality", 1)
    after = gpu.run(outputs=OUTPUTS)["ssgi_denoise.diffuse"]
    assert same_bits(kept.numpy(), before) and not same_bits(after.numpy(), before)
    # on_device=False brings them to the host, as a CPU session's are.
    host = gpu.run(outputs=OUTPUTS, on_device=False)
    assert all(isinstance(host[n], np.ndarray) for n in OUTPUTS)
    print(f"cuda outputs: {checks} outputs × layouts on the GPU, zero-copy through "
          f"__cuda_array_interface__ (torch), a GPU copy through DLPack, each with the CPU's bits; "
          f"{repr(kept)}")


if __name__ == "__main__":
    main(sys.argv[1])
