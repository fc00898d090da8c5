"""framepass: Unreal Engine's lighting passes re-run on captured GBuffers, from Python.

A thin door onto framepass's application library (docs/python.md):

    import framepass as fp
    s = fp.Session("examples/cornell/config.json", capture="out/demo/cornell.exr")
    s.cvars["r.SSGI.Quality"] = 2
    out = s.run(frame=1, outputs=["ssgi_denoise.diffuse"])   # numpy float32, (H, W, C)
"""
from collections.abc import Iterator, Mapping
from typing import Any, List, Union

from . import _framepass, _signatures
from ._framepass import (  # noqa: F401
    Camera,
    Cancelled,
    Capture,
    CaptureError,
    ConfigError,
    CudaArray,
    Error,
    SettingTypeError,
    SettingValueError,
    UnknownSettingError,
    __version__,
    bench,
    compare,
    exr_metadata,
    passes,
    read_capture,
    read_exr,
    write_exr,
)

Value = Union[bool, int, float, str]

# Python functions in front of the extension's, with the signatures inspect.signature (and so
# IDEs and help()) read: the extension's own functions carry them only in their docstrings.
bench = _signatures.with_signature(_framepass.bench)
compare = _signatures.with_signature(_framepass.compare)
exr_metadata = _signatures.with_signature(_framepass.exr_metadata)
passes = _signatures.with_signature(_framepass.passes)
read_capture = _signatures.with_signature(_framepass.read_capture)
read_exr = _signatures.with_signature(_framepass.read_exr)
write_exr = _signatures.with_signature(_framepass.write_exr)


class Cvars(Mapping):
    """A session's Unreal cvars as a mapping: s.cvars["r.SSGI.Quality"] reads the value the
    session runs with (the parameter it sets as the plan resolved it: a config parameter that
    shadows the cvar wins there too); assigning sets it, as Session.set_cvar does, and a value
    the cvar does not take is refused there. Names match without regard to case, as in
    Unreal's console; a name framepass does not know is a KeyError (UnknownSettingError)."""

    def __init__(self, session: "Session") -> None:
        self._session = session

    def __getitem__(self, name: str) -> Any:
        return self._session.cvar(name)

    def __setitem__(self, name: str, value: Value) -> None:
        self._session.set_cvar(name, value)

    def __iter__(self) -> Iterator[str]:
        return iter(self._session.cvar_names())

    def __len__(self) -> int:
        return len(self._session.cvar_names())

    def _ipython_key_completions_(self) -> List[str]:
        return self._session.cvar_names()

    def __repr__(self) -> str:
        return "framepass.Cvars({} cvars)".format(len(self))


class Session(_framepass.Session):
    __doc__ = _framepass.Session.__doc__

    @property
    def cvars(self) -> Cvars:
        """The session's cvars as a mapping (framepass.Cvars): read and assign by name."""
        return Cvars(self)


for _name in ("__init__", "set_cvar", "set", "set_input", "run", "plan", "report", "cvar", "cvar_names", "cancel"):
    setattr(Session, _name, _signatures.with_signature(getattr(_framepass.Session, _name), _name))


__all__ = ["Session", "Capture", "Camera", "Cvars", "read_capture", "read_exr", "write_exr",
           "exr_metadata", "compare", "bench", "passes", "Error", "ConfigError",
           "CaptureError", "Cancelled", "SettingValueError", "SettingTypeError",
           "UnknownSettingError", "__version__"]
