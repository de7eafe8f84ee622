"""Builds the Python package npend with CMake, for pip:

    python3 -m venv --system-site-packages VENV && VENV/bin/pip install --no-build-isolation .

The compiled module npend._npend is the CMake target npend_python; this script configures a
build tree, builds only that target (Release) and puts the package's Python files
(python/npend) and what CMake lays out beside them in build/python/npend (the module,
_version.py and the type stubs) into the wheel. The version is project()'s in CMakeLists.txt, the one source of truth.

Environment:
    NPEND_CMAKE_BUILD_DIR       an existing, configured build tree to build in and take the
                                package from (its interpreter must be the one pip runs);
                                default: a tree of its own in build/pip/cmake
    CMAKE_BUILD_PARALLEL_LEVEL  the parallel jobs of the build (default 2)
"""

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build import build
from setuptools.command.build_ext import build_ext
from setuptools.command.egg_info import egg_info

ROOT = Path(__file__).resolve().parent
# What pip's build writes besides the wheel goes under build/ (ignored by git), so neither the
# source tree nor a CMake build tree called build/ collects setuptools' folders.
EXISTING_TREE = os.environ.get("NPEND_CMAKE_BUILD_DIR")
WORK = Path(EXISTING_TREE).resolve() / "pip" if EXISTING_TREE else ROOT / "build" / "pip"


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*npend\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no `project(npend VERSION x.y.z)` found")
    return match.group(1)


class cmake_build_ext(build_ext):
    """Builds npend._npend with CMake instead of compiling sources itself."""

    def build_extension(self, ext):
        tree = self.cmake_tree()
        command = ["cmake", "--build", str(tree), "--target", "npend_python", "--config", "Release"]
        if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
            command.append("-j2")
        subprocess.run(command, check=True)

        built = tree / "python" / "npend"
        module = built / ("_npend" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not module.is_file():
            raise RuntimeError(
                f"{module} was not built: the build tree {tree} is for another Python than "
                f"{sys.executable} (configure it with -DPython_EXECUTABLE={sys.executable})")
        target = Path(self.get_ext_fullpath(ext.name)).parent
        target.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, self.get_ext_fullpath(ext.name))
        # What CMake writes besides the module: the version and the type stubs (build_py
        # copies the package's Python files from python/npend).
        for name in ["_version.py", "_npend.pyi", "py.typed"]:
            if (built / name).is_file():
                shutil.copy2(built / name, target / name)
        if not (target / "_version.py").is_file():
            raise RuntimeError(f"{built / '_version.py'} missing: CMake writes it when it configures")

    def cmake_tree(self):
        if EXISTING_TREE:
            tree = Path(EXISTING_TREE).resolve()
            if not (tree / "CMakeCache.txt").is_file():
                raise RuntimeError(f"NPEND_CMAKE_BUILD_DIR={EXISTING_TREE}: not a configured CMake build tree")
            return tree
        tree = WORK / "cmake"
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tree), "-DCMAKE_BUILD_TYPE=Release",
                        "-DNPEND_BUILD_PYTHON=ON", "-DNPEND_BUILD_TESTS=OFF",
                        f"-DPython_EXECUTABLE={sys.executable}"], check=True)
        return tree


class work_build(build):
    def finalize_options(self):
        if self.build_base == "build":
            self.build_base = str(WORK / "setuptools")
        super().finalize_options()


class work_egg_info(egg_info):
    def finalize_options(self):
        if self.egg_base is None:
            WORK.mkdir(parents=True, exist_ok=True)
            self.egg_base = os.path.relpath(WORK, ROOT)
        super().finalize_options()


setup(
    version=project_version(),
    packages=["npend"],
    package_dir={"npend": "python/npend"},
    ext_modules=[Extension("npend._npend", sources=[])],
    cmdclass={"build": work_build, "build_ext": cmake_build_ext, "egg_info": work_egg_info},
)
