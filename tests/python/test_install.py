"""framepass installed as a user installs it (docs/python.md, "Installing"): `pip install .` into a
venv, and `cmake --install` into a prefix; each imported from outside the source tree, its typed
stubs checked by mypy on the documentation's examples. Run by ctest with the python suite's
environment; it reuses the build folder (FRAMEPASS_BUILD_DIR), so it installs in seconds."""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

import pytest

SOURCE = os.environ["FP_SOURCE_DIR"]
BUILD = os.path.dirname(os.path.abspath(os.environ["PYTHONPATH"].split(os.pathsep)[0]))
SCRATCH = os.path.join(os.path.abspath(os.environ["FP_SCRATCH"]), "python-install")
IMPORT = "import framepass, sys; print(framepass.__file__); print(framepass.__version__)"


def run(args, **kw):
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)  # the installed package, not the build's
    env.update(kw.pop("env", {}))
    out = subprocess.run(args, capture_output=True, text=True, env=env, cwd=SCRATCH, **kw)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    return out.stdout


@pytest.fixture(scope="module", autouse=True)
def scratch():
    shutil.rmtree(SCRATCH, ignore_errors=True)
    os.makedirs(SCRATCH)


def test_pip_installs_into_a_venv():
    venv = os.path.join(SCRATCH, "venv")
    # numpy from Debian (offline): the venv sees the system's packages.
    run([sys.executable, "-m", "venv", "--system-site-packages", venv])
    run([os.path.join(venv, "bin/pip"), "install", "-q", "--no-build-isolation", "--no-deps",
         "--no-index", SOURCE], env={"FRAMEPASS_BUILD_DIR": BUILD})
    where, version = run([os.path.join(venv, "bin/python"), "-c", IMPORT]).split()
    assert where.startswith(venv + "/lib/"), where
    assert re.fullmatch(r"\d+\.\d+\.\d+", version)
    package = os.path.dirname(where)
    assert os.path.exists(os.path.join(package, "py.typed"))
    assert os.path.exists(os.path.join(package, "_framepass.pyi"))


def test_cmake_install_honours_the_prefix():
    prefix = os.path.join(SCRATCH, "prefix")
    run(["cmake", "--install", BUILD, "--prefix", prefix])
    site = os.path.relpath(sysconfig.get_path("platlib", "posix_prefix",
                                              vars={"platbase": "/P", "base": "/P"}), "/P")
    where = run([sys.executable, "-c", IMPORT],
                env={"PYTHONPATH": os.path.join(prefix, site)}).split()[0]
    assert where == os.path.join(prefix, site, "framepass", "__init__.py")
    assert os.path.exists(os.path.join(prefix, "bin", "framepass"))


def test_mypy_passes_on_the_documented_examples():
    if shutil.which("mypy") is None:
        pytest.skip("mypy is not installed (make test installs Debian's)")
    text = open(os.path.join(SOURCE, "docs", "python.md")).read()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    path = os.path.join(SCRATCH, "examples.py")
    with open(path, "w") as f:
        for i, block in enumerate(blocks):
            f.write(f"def example_{i}() -> None:\n")
            f.write("".join("    " + line + "\n" for line in block.splitlines()))
    out = subprocess.run(["mypy", "--no-incremental", "--cache-dir=/dev/null", path],
                         capture_output=True, text=True,
                         env=dict(os.environ, MYPYPATH=os.path.join(BUILD, "python")))
    assert out.returncode == 0, out.stdout + out.stderr
