"""framepass: Unreal Engine's lighting passes re-run on captured GBuffers, from Python.

A thin door onto framepass's application library (docs/python.md):

    import framepass as fp
    s = fp.Session("examples/cornell/config.json", capture="out/demo/cornell.exr")
    s.set_cvar("r.SSGI.Quality", 2)
    out = s.run(frame=1, outputs=["ssgi_denoise.diffuse"])   # numpy float32, (H, W, C)
"""
from ._framepass import (  # noqa: F401
    Cancelled,
    CaptureError,
    ConfigError,
    Error,
    Session,
    compare,
    passes,
    read_exr,
)

__all__ = ["Session", "passes", "read_exr", "compare",
           "Error", "ConfigError", "CaptureError", "Cancelled"]
