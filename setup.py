"""pip's entry to the Python package rgbmesh (issue 14): `pip install --no-build-isolation .`

The package is built by this project's CMake, not by setuptools: build_ext below configures the
project with only what the extension needs, builds the one target rgbmesh_python, installs the
CMake component `python` (the same rules as `cmake --install`) into a scratch prefix and hands
those files to the wheel. Only Debian 12's own tools are used (setuptools, wheel, pip, CMake):
nothing is fetched.

Environment:
  RGBMESH_BUILD_DIR   the CMake build directory (default: build-python/ in the source tree,
                      kept between runs, so a second install rebuilds only what changed). An
                      already configured tree (a developer's build/) is used as it is: it is
                      not reconfigured with the options below, only built.
  RGBMESH_CMAKE_ARGS  extra CMake arguments (shell syntax), e.g. "-DRGBMESH_WITH_PETSC=OFF";
                      given last, so they override the defaults, and with an existing tree
                      they are the only ones applied.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = os.path.dirname(os.path.abspath(__file__))


def project_version():
    # The one version of the project is CMake's project(rgbmesh VERSION ...): read it, so that
    # the wheel and the CMake package (rgbmeshConfigVersion.cmake) never disagree.
    with open(os.path.join(SOURCE_DIR, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(\s*rgbmesh\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", f.read())
    if not match:
        raise RuntimeError("setup.py: no project(rgbmesh VERSION ...) in CMakeLists.txt")
    return match.group(1)


DEFAULT_BUILD_DIR = os.path.join(SOURCE_DIR, "build-python")  # ignored by git (/build*/)
BUILD_DIR = os.path.abspath(os.environ.get("RGBMESH_BUILD_DIR") or DEFAULT_BUILD_DIR)
# setuptools' own scratch files (build/lib..., the egg-info) go into the CMake build directory
# too, not into the source tree: its build/ is the developers' CMake tree, and a test run with
# RGBMESH_BUILD_DIR then writes nothing into the sources.
SCRATCH_DIR = os.path.join(BUILD_DIR, "setuptools")
os.makedirs(SCRATCH_DIR, exist_ok=True)  # egg_info refuses an egg_base that does not exist


def is_configured(directory):
    # A cache alone may be what a failed configure left: a generated build system is the sign.
    return os.path.isfile(os.path.join(directory, "CMakeCache.txt")) and any(
        os.path.isfile(os.path.join(directory, name)) for name in ("build.ninja", "Makefile"))


def cache_value(directory, name):
    with open(os.path.join(directory, "CMakeCache.txt"), encoding="utf-8") as f:
        for line in f:
            key, sep, value = line.rstrip("\n").partition("=")
            if sep and key.split(":")[0] == name:
                return value
    return None


def run(command, **kwargs):
    print("setup.py: " + " ".join(shlex.quote(str(c)) for c in command), flush=True)
    subprocess.run(command, check=True, **kwargs)


class CMakeBuild(build_ext):
    """Builds the extension with CMake and copies the installed package into the wheel."""

    def run(self):
        cmake = shutil.which("cmake")
        if not cmake:
            raise RuntimeError("setup.py: cmake not found (Debian: apt-get install cmake ninja-build)")
        extra = shlex.split(os.environ.get("RGBMESH_CMAKE_ARGS", ""))
        if not is_configured(BUILD_DIR) or BUILD_DIR == DEFAULT_BUILD_DIR:
            # A new tree, or setup.py's own: the latter is configured again every time with this
            # interpreter, so that a pip of another Python (or a removed virtual environment)
            # never builds against the interpreter of an earlier run. Unchanged options cost a
            # few seconds and rebuild nothing.
            self.configure(cmake, extra)
        elif extra:
            run([cmake, "-S", SOURCE_DIR, "-B", BUILD_DIR] + extra)

        # Said before building, rather than as ninja's "unknown target": the package's files are
        # copied into the tree when it is configured, and its install rules leave this cache entry.
        if not os.path.isdir(os.path.join(BUILD_DIR, "python", "rgbmesh")):
            raise RuntimeError(f"setup.py: {BUILD_DIR} does not build the Python package: see its CMake "
                               "output (needs RGBMESH_WITH_PYTHON, RGBMESH_WITH_VTK, pybind11-dev, python3-dev)")
        if cache_value(BUILD_DIR, "RGBMESH_PYTHON_INSTALL_DIR") is None:
            raise RuntimeError(f"setup.py: {BUILD_DIR} has no install rules for the Python package "
                               "(configure it with -DRGBMESH_INSTALL=ON)")
        run([cmake, "--build", BUILD_DIR, "--target", "rgbmesh_python", "-j", str(os.cpu_count() or 1)])

        package = self.install_component(cmake)
        destination = os.path.join(os.path.abspath(self.build_lib), "rgbmesh")
        shutil.rmtree(destination, ignore_errors=True)  # no file of an earlier build survives
        shutil.copytree(package, destination)
        self._outputs = [os.path.join(root, name) for root, _, names in os.walk(destination) for name in names]

    def configure(self, cmake, extra):
        command = [cmake, "-S", SOURCE_DIR, "-B", BUILD_DIR,
                   "-DCMAKE_BUILD_TYPE=Release",
                   "-DRGBMESH_WITH_PYTHON=ON", "-DRGBMESH_INSTALL=ON",
                   "-DRGBMESH_BUILD_TESTS=OFF", "-DRGBMESH_BUILD_BENCH=OFF",
                   "-DRGBMESH_BUILD_EXAMPLES=OFF", "-DRGBMESH_WITH_CLI=OFF",
                   "-DPython3_EXECUTABLE=" + sys.executable]
        # Ninja where it is installed (README's set-up installs it); a generator is chosen once,
        # so only a tree that has none yet gets one.
        if not os.path.isfile(os.path.join(BUILD_DIR, "CMakeCache.txt")) and shutil.which("ninja"):
            command += ["-G", "Ninja"]
        run(command + extra)

    def install_component(self, cmake):
        # The component `python` of cmake/install.cmake, into a fresh scratch prefix. DESTDIR
        # also holds an absolute RGBMESH_PYTHON_INSTALL_DIR inside it.
        site = cache_value(BUILD_DIR, "RGBMESH_PYTHON_INSTALL_DIR")
        stage = os.path.join(SCRATCH_DIR, "stage")
        shutil.rmtree(stage, ignore_errors=True)
        prefix = "/prefix"
        run([cmake, "--install", BUILD_DIR, "--component", "python", "--prefix", prefix],
            env=dict(os.environ, DESTDIR=stage))
        package = os.path.join(stage + (site if os.path.isabs(site) else os.path.join(prefix, site)), "rgbmesh")
        # An existing tree may have been built for another Python: its extension would not load.
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        if not os.path.isfile(os.path.join(package, "_rgbmesh" + suffix)):
            found = sorted(os.listdir(package)) if os.path.isdir(package) else []
            raise RuntimeError(f"setup.py: no _rgbmesh{suffix} for {sys.executable} installed from {BUILD_DIR} "
                               f"(found {found}): that tree was configured for another Python; "
                               "set RGBMESH_BUILD_DIR to a new directory")
        return package

    def get_outputs(self):
        return list(getattr(self, "_outputs", []))


setup(
    name="rgbmesh",
    version=project_version(),
    description="Adaptive triangle meshes on subdivision surfaces (RGB subdivision), from Python",
    # What a built package may be distributed under: the default build links rgbmesh::fit and
    # rgbmesh::repair, which compile CGAL's GPL-3.0-or-later packages (rgbmesh's own sources are
    # BSD-3-Clause, LICENSE; docs/licensing.md).
    license="GPL-3.0-or-later",
    python_requires=">=3.9",
    install_requires=["numpy"],
    # Nothing for setuptools to collect: the package's files come from CMake (build_ext). The
    # empty lists also stop setuptools from taking the repository's C++ folders for packages.
    packages=[],
    py_modules=[],
    # Declared so that the wheel is tagged for this Python and platform; built by CMakeBuild.
    ext_modules=[Extension("rgbmesh._rgbmesh", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": SCRATCH_DIR}, "egg_info": {"egg_base": SCRATCH_DIR}},
    zip_safe=False,
)
