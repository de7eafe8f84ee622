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


FIRST_HOUR = """
import concurrent.futures, json, sys
import numpy as np
import npend
from scipy.integrate import solve_ivp

chain = npend.Chain(3, masses=[1.0, 2.0, 1.5])
x0 = [0.4, -0.3, 0.2, 0.0, 0.1, 0.0]
# SciPy's solve_ivp on npend's right-hand side, against npend's own integration
sol = solve_ivp(chain.fun, (0, 5), x0, method="DOP853", rtol=1e-11, atol=1e-11)
t, X = npend.simulate(chain, x0, 5.0, stepper="taylor")
ivp_gap = float(np.max(np.abs(sol.y[:, -1] - X[-1])))

# Chains go to worker processes (pickled), and each worker's energy is this process's
chains = [npend.Chain(2, masses=[1.0, m]) for m in (0.5, 1.0, 2.0)]
with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
    energies = list(pool.map(npend.Chain.hamiltonian, chains, [[1.0, 0.5, 0.0, 0.0]] * 3))
local = [c.hamiltonian([1.0, 0.5, 0.0, 0.0]) for c in chains]

# An animation as a notebook shows it inline
import matplotlib
matplotlib.use("Agg")
import npend.plot
t2, X2 = npend.simulate(npend.Chain(2), [2.0, 1.0, 0.0, 0.0], 1.0)
html = npend.plot.animation(npend.Chain(2), t2, X2, fps=10).to_jshtml()

# A resumable map: the second call finds every tile done
folder = sys.argv[1]
axes = dict(x=("phi1", -3.0, 3.0, 12), y=("phi2", -3.0, 3.0, 10), t_end=5.0)
first = np.asarray(npend.map(npend.Chain(2), out=folder, **axes))
again = np.asarray(npend.map(npend.Chain(2), out=folder, resume=True, **axes))
print(json.dumps({"ivp_gap": ivp_gap, "energies": energies, "local": local,
                  "frames_html": len(html), "has_frames": "data:image/png;base64" in html,
                  "map_equal": bool(np.array_equal(first, again, equal_nan=True)),
                  "map_shape": list(first.shape), "file": npend.__file__}))
"""


def test_first_hour_in_the_venv(installed, tmp_path):
    """A new user's first hour, from the venv alone (no build tree on PYTHONPATH), as
    docs/python.md's "A first hour" has it: solve_ivp on chain.fun, a process pool over
    chains, an inline animation, a resumable map, and the tour notebook on a kernel of the
    venv."""
    python, home = installed
    env = clean_environment(MPLCONFIGDIR=str(tmp_path / "matplotlib"))
    out = subprocess.run([str(python), "-c", FIRST_HOUR, str(tmp_path / "map")], check=True,
                         env=env, cwd=home, capture_output=True, text=True).stdout
    found = json.loads(out)
    venv_dir = os.path.realpath(python.parent.parent)
    assert os.path.realpath(found["file"]).startswith(venv_dir + os.sep), found["file"]
    assert found["ivp_gap"] < 1e-8
    assert found["energies"] == found["local"]
    assert found["has_frames"] and found["frames_html"] > 10_000
    assert found["map_shape"] == [10, 12] and found["map_equal"]
    assert any((tmp_path / "map").rglob("*")), "the map's tiles stay for --resume"

    try:
        import ipykernel  # noqa: F401
        import nbconvert  # noqa: F401
    except ImportError:
        pytest.skip("nbconvert or ipykernel is missing (tools/setup.sh --test installs them)")
    # The venv's own kernel, as a user registers it, so that the notebook imports the venv's
    # npend: Debian's "python3" kernel runs /usr/bin/python3, which does not see it.
    jupyter_env = clean_environment(MPLCONFIGDIR=str(tmp_path / "matplotlib"),
                                    JUPYTER_RUNTIME_DIR=str(tmp_path / "jupyter"),
                                    IPYTHONDIR=str(tmp_path / "ipython"),
                                    PYDEVD_DISABLE_FILE_VALIDATION="1")
    subprocess.run([str(python), "-m", "ipykernel", "install", "--prefix",
                    str(python.parent.parent), "--name", "npend-venv"],
                   check=True, env=jupyter_env, capture_output=True)
    subprocess.run([str(python), "-m", "nbconvert", "--to", "notebook", "--execute",
                    "--ExecutePreprocessor.timeout=120",
                    "--ExecutePreprocessor.kernel_name=npend-venv",
                    "--output-dir", str(tmp_path / "notebook"),
                    str(ROOT / "examples" / "python" / "tour.ipynb")],
                   check=True, env=jupyter_env, cwd=home, capture_output=True)
    executed = json.loads((tmp_path / "notebook" / "tour.ipynb").read_text())
    errors = [o for cell in executed["cells"] for o in cell.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors, errors
    assert sum(1 for cell in executed["cells"] if cell.get("outputs")) >= 3
