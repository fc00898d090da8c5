"""framepass: Unreal Engine's lighting passes re-run on captured GBuffers, from Python.

A thin door onto framepass's application library (docs/python.md):

    import framepass as fp
    s = fp.Session("examples/cornell/config.json", capture="out/demo/cornell.exr")
    s.cvars["r.SSGI.Quality"] = 2
    out = s.run(frame=1, outputs=["ssgi_denoise.diffuse"])   # numpy float32, (H, W, C)
"""
from collections.abc import Mapping

from . import _framepass
from ._framepass import (  # noqa: F401
    Camera,
    Cancelled,
    Capture,
    CaptureError,
    ConfigError,
    Error,
    bench,
    compare,
    passes,
    read_capture,
    read_exr,
)


class Cvars(Mapping):
    """A session's Unreal cvars as a mapping: s.cvars["r.SSGI.Quality"] reads the value the
    session runs with (as set, else as the config gives it, else the default of the parameter
    it sets); assigning sets it, as Session.set_cvar does. Names match without regard to case,
    as in Unreal's console; a name framepass does not know is a KeyError."""

    def __init__(self, session):
        self._session = session

    def __getitem__(self, name):
        try:
            return self._session.cvar(name)
        except ConfigError as e:
            raise KeyError(str(e)) from None

    def __setitem__(self, name, value):
        self._session.set_cvar(name, value)

    def __iter__(self):
        return iter(self._session.cvar_names())

    def __len__(self):
        return len(self._session.cvar_names())

    def __repr__(self):
        return "framepass.Cvars({} cvars)".format(len(self))


class Session(_framepass.Session):
    __doc__ = _framepass.Session.__doc__

    @property
    def cvars(self):
        """The session's cvars as a mapping (framepass.Cvars): read and assign by name."""
        return Cvars(self)


__all__ = ["Session", "Capture", "Camera", "Cvars", "read_capture", "read_exr", "compare",
           "bench", "passes", "Error", "ConfigError", "CaptureError", "Cancelled"]
