"""Outputs that stay on the GPU, checked from Python on a GPU machine (docs/gpu.md): a session on
device="cuda" hands back CudaArray objects that torch and CuPy view without a copy, with the bits
of the same session on the CPU, each the caller's own. CI has no GPU; this runs where the module built for that machine's Python
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
            assert cai["version"] == 3 and cai["typestr"] == "<f4" and cai["data"][1] is False
            view = torch.as_tensor(a, device="cuda")  # through __cuda_array_interface__
            assert view.data_ptr() == cai["data"][0], "torch.as_tensor copied"
            assert same_bits(view.cpu().numpy(), want[name]), (layout, name)
            shared = torch.from_dlpack(a)  # through __dlpack__: the same memory
            assert shared.is_cuda and shared.data_ptr() == view.data_ptr(), "from_dlpack copied"
            assert same_bits(shared.cpu().numpy(), want[name]), (layout, name)
            assert same_bits(np.asarray(a), want[name]) and same_bits(a.numpy(), want[name])
            try:
                import cupy
                assert same_bits(cupy.asnumpy(cupy.asarray(a)), want[name])
                assert cupy.asarray(a).data.ptr == cai["data"][0], "cupy copied"
            except ImportError:
                pass
            # The array is its own: writing into it leaves the session's pixels as they were.
            shared.fill_(0)
            assert not a.numpy().any()
            again = gpu.run(outputs=OUTPUTS, layout=layout)[name]
            assert same_bits(again.numpy(), want[name]), "writing an output changed the session's"
            assert all(p.get("reused") for p in gpu.report()["passes"] if p["name"] == name.split(".")[0])
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
    # What handing the outputs over costs once every pass is reused (a run that changes nothing):
    # the copies on the GPU against the copies to the host.
    import time
    def median_ms(on_device):
        times = []
        for _ in range(9):
            t0 = time.perf_counter()
            gpu.run(outputs=OUTPUTS, on_device=on_device)
            times.append(time.perf_counter() - t0)
        return sorted(times)[4] * 1e3
    print(f"a run whose passes are all reused, {len(OUTPUTS)} outputs at {a.shape}: "
          f"{median_ms(True):.3f} ms kept on the GPU, {median_ms(False):.3f} ms brought to the host "
          f"(medians of 9)")
    print(f"cuda outputs: {checks} outputs × layouts on the GPU, each with the CPU's bits, viewed "
          f"without a copy through __cuda_array_interface__ (torch, CuPy) and DLPack (torch), "
          f"each its own; {repr(kept)}")


if __name__ == "__main__":
    main(sys.argv[1])
