"""Builds framepass's Python module with CMake for `pip install .` (pyproject.toml).

The module is the CMake target `_framepass` (python/CMakeLists.txt); this builds it in the build
folder `make` uses (FRAMEPASS_BUILD_DIR, default ./build), so that a checkout already built
installs in seconds, and puts the package CMake assembled there (the extension, __init__.py,
py.typed and the .pyi stubs) into the wheel.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
BUILD = Path(os.environ.get("FRAMEPASS_BUILD_DIR", ROOT / "build")).resolve()


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(framepass VERSION ([0-9.]+)", text).group(1)


def cached_interpreter(build):
    """The interpreter an existing build folder was configured for, or None."""
    cache = build / "CMakeCache.txt"
    if not cache.exists():
        return None
    m = re.search(r"^_?Python3_EXECUTABLE:\w+=(.*)$", cache.read_text(), re.M)
    return m.group(1) if m else None


def same_abi(interpreter):
    """Whether `interpreter` builds modules this interpreter imports (same version and ABI)."""
    probe = "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))"
    try:
        out = subprocess.run([interpreter, "-c", probe], capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        return False
    return out.stdout.strip() == sysconfig.get_config_var("EXT_SUFFIX")


class CMakeBuild(build_ext):
    def run(self):
        build = BUILD
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release"]
        cached = cached_interpreter(build)
        # A folder built for this interpreter's ABI is reused as it is (configuring it for
        # another path of the same interpreter, a venv's, would change it for `make` too).
        if cached is None or not same_abi(cached):
            # The interpreter itself, not a venv's link to it: CMake finds its headers there.
            base = getattr(sys, "_base_executable", sys.executable)
            configure.append(f"-DPython3_EXECUTABLE={base}")
            if cached is None and shutil.which("nvidia-smi") is None:
                configure.append("-DFP_CUDA=OFF")  # no GPU answers: its kernels only cost time
            subprocess.run(configure, check=True)
        jobs = str(os.cpu_count() or 2)
        subprocess.run(["cmake", "--build", str(build), "--target", "_framepass", "-j", jobs],
                       check=True)
        package = build / "python" / "framepass"
        ext = next(package.glob("_framepass*" + sysconfig.get_config_var("EXT_SUFFIX")))
        out = Path(self.get_ext_fullpath("framepass._framepass")).parent
        out.mkdir(parents=True, exist_ok=True)
        for f in [ext, *package.glob("*.pyi"), package / "py.typed"]:
            if f.exists():
                shutil.copy2(f, out / f.name)


# setuptools' own work (its build and egg-info folders) goes into the build folder, not the tree.
(BUILD / "setuptools").mkdir(parents=True, exist_ok=True)
setup(
    version=version(),
    options={"build": {"build_base": str(BUILD / "setuptools")},
             "egg_info": {"egg_base": str(BUILD / "setuptools")}},
    ext_modules=[Extension("framepass._framepass", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    package_data={"framepass": ["py.typed", "*.pyi"]},
    zip_safe=False,
)
