"""pip installs the package with its metadata: `pip install --no-build-isolation .` from the
repository root into a fresh virtual environment that sees Debian's numpy, without network.

setup.py builds in the test's own build tree (NPEND_CMAKE_BUILD_DIR, set by ctest), where
npend_python is up to date, so the test takes seconds instead of a rebuild.
"""

import json
import os
import re
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def project_version():
    # Read here on its own rather than through setup.py, so a mistake there shows.
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(npend VERSION ([0-9.]+)", text).group(1)


def clean_environment(**extra):
    # Without the build tree's PYTHONPATH: the venv's package must be the one imported.
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(PYTHONDONTWRITEBYTECODE="1", PIP_DISABLE_PIP_VERSION_CHECK="1", **extra)
    return env


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    build_dir = os.environ.get("NPEND_CMAKE_BUILD_DIR")
    if not build_dir:
        pytest.skip("NPEND_CMAKE_BUILD_DIR (a build tree with npend_python) is not set; ctest sets it")
    home = tmp_path_factory.mktemp("install")
    prefix = home / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=True, symlinks=True).create(prefix)
    python = prefix / "bin" / "python"
    env = clean_environment(NPEND_CMAKE_BUILD_DIR=build_dir, PIP_CACHE_DIR=str(home / "cache"))
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-index",
                    "--no-build-isolation", str(ROOT)], check=True, env=env, cwd=home)
    return python, home


def test_install_metadata_and_version(installed):
    python, home = installed
    check = """
import importlib.metadata, json, npend
t, X = npend.simulate(npend.Chain(2), [1.0, 0.0, 0.0, 0.0], 1.0)
print(json.dumps({"version": npend.__version__, "metadata": importlib.metadata.version("npend"),
                  "file": npend.__file__, "shape": list(X.shape),
                  "requires": importlib.metadata.requires("npend")}))
"""
    # From outside the source tree, in a fresh process.
    out = subprocess.run([str(python), "-c", check], check=True, env=clean_environment(),
                         cwd=home, capture_output=True, text=True).stdout
    found = json.loads(out)
    assert found["version"] == project_version()
    assert found["metadata"] == project_version()
    venv_dir = os.path.realpath(python.parent.parent)
    assert os.path.realpath(found["file"]).startswith(venv_dir + os.sep), found["file"]
    assert found["shape"] == [1001, 4]  # t_end / dt + 1 rows of 2n
    assert found["requires"] is not None and "numpy" in found["requires"]


def test_install_ships_the_type_stubs(installed):
    python, home = installed
    out = subprocess.run([str(python), "-c", "import npend, os; print(os.path.dirname(npend.__file__))"],
                         check=True, env=clean_environment(), cwd=home, capture_output=True,
                         text=True).stdout.strip()
    package = Path(out)
    built = Path(os.environ["NPEND_CMAKE_BUILD_DIR"]) / "python" / "npend"
    for name in ("_npend.pyi", "py.typed"):
        if (built / name).is_file():  # the build tree has them when mypy is installed
            assert (package / name).is_file(), name
    assert (package / "_version.py").is_file()


def test_cmake_install_carries_the_version_and_stubs(tmp_path):
    build_dir = os.environ.get("NPEND_CMAKE_BUILD_DIR")
    if not build_dir:
        pytest.skip("NPEND_CMAKE_BUILD_DIR (a build tree with npend_python) is not set; ctest sets it")
    # The install rules of python/ alone: quicker than `cmake --install`, and it writes no
    # install_manifest.txt into the build tree, which the package test's install also writes.
    subprocess.run(["cmake", f"-DCMAKE_INSTALL_PREFIX={tmp_path}", "-P",
                    str(Path(build_dir) / "python" / "cmake_install.cmake")],
                   check=True, capture_output=True)
    packages = list(tmp_path.glob("lib/python3*/dist-packages/npend"))
    assert len(packages) == 1, packages
    env = clean_environment(PYTHONPATH=str(packages[0].parent))
    out = subprocess.run([sys.executable, "-c", "import npend; print(npend.__version__, npend.__file__)"],
                         check=True, env=env, cwd=tmp_path, capture_output=True, text=True).stdout.split()
    assert out[0] == project_version()
    assert out[1].startswith(str(packages[0]))
    built = Path(build_dir) / "python" / "npend"
    for name in ("_npend.pyi", "py.typed"):
        if (built / name).is_file():
            assert (packages[0] / name).is_file(), name
