"""Builds the plumetrace Python package with the project's CMake (pybind11's cmake_example
pattern): configures a build of the Python module alone (Release, ccache when installed), builds
the target plumetrace_python, and packs the folder it assembles (python/plumetrace, its package
data and plumetrace/_core; cmake/python_package.cmake). Metadata: pyproject.toml.

Environment:
  PLUMETRACE_CMAKE_BUILD_DIR  the CMake build folder (default: build-pip/ in the source tree).
                              An existing configured build (e.g. build/) is only built, never
                              reconfigured, so its own options are kept.
  CMAKE_ARGS                  extra arguments for the configure step (e.g. -DCMAKE_CXX_COMPILER=...).
  CMAKE_BUILD_PARALLEL_LEVEL  build jobs (default: every core).
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, find_packages, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    """The CMake project's VERSION: one version for the command, the library and the package."""
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(plumetrace\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise RuntimeError("setup.py: no 'project(plumetrace VERSION x.y.z' in CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    """build_ext that runs CMake instead of compiling the extension's sources itself."""

    def build_extension(self, ext):
        given = os.environ.get("PLUMETRACE_CMAKE_BUILD_DIR")
        build_dir = Path(given).resolve() if given else ROOT / "build-pip"
        env = dict(os.environ)
        # why: relative paths in ccache's keys, so that another checkout or build folder at the
        # same depth hits the same cache entries
        env.setdefault("CCACHE_BASEDIR", str(ROOT.parent))
        if not (given and (build_dir / "CMakeCache.txt").is_file()):
            self._configure(build_dir, env)
        build = ["cmake", "--build", str(build_dir), "--target", "plumetrace_python"]
        if "CMAKE_BUILD_PARALLEL_LEVEL" not in env:
            build += ["--parallel", str(os.cpu_count() or 1)]
        subprocess.run(build, check=True, env=env)

        package = build_dir / "python" / "plumetrace"
        module = "_core" + sysconfig.get_config_var("EXT_SUFFIX")
        if not (package / module).is_file():
            raise RuntimeError(
                f"setup.py: the CMake build in {build_dir} made no {module} for this Python "
                f"({sys.executable}); configure it with -DPython3_EXECUTABLE={sys.executable}, "
                "or unset PLUMETRACE_CMAKE_BUILD_DIR")
        target = Path(self.get_ext_fullpath(ext.name)).parent
        if self.inplace:
            # an editable install (pip install -e .): the module beside the sources; the
            # package data is found in the repository (plumetrace.studies)
            shutil.copy2(package / module, target / module)
            return
        # the package as CMake assembled it, with this Python's module only
        shutil.copytree(package, target, dirs_exist_ok=True,
                        ignore=lambda folder, names: [
                            n for n in names
                            if n == "__pycache__" or n.endswith(".pyc")
                            or (n.startswith("_core.") and n != module)])

    def _configure(self, build_dir, env):
        args = ["cmake", "-S", str(ROOT), "-B", str(build_dir),
                "-DCMAKE_BUILD_TYPE=Release",
                f"-DPython3_EXECUTABLE={sys.executable}",
                "-DPLUMETRACE_BUILD_PYTHON=ON",
                "-DPLUMETRACE_BUILD_TESTS=OFF",
                "-DPLUMETRACE_BUILD_BENCHMARKS=OFF",
                "-DPLUMETRACE_BUILD_EXAMPLES=OFF",
                "-DPLUMETRACE_MPI=OFF"]
        if shutil.which("ccache"):
            args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        args += shlex.split(env.get("CMAKE_ARGS", ""))
        subprocess.run(args, check=True, env=env)


setup(
    version=project_version(),
    packages=find_packages("python", include=["plumetrace", "plumetrace.*"]),
    package_dir={"": "python"},
    ext_modules=[Extension("plumetrace._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # why: setuptools' own build folder away from the CMake build in build/
    options={"build": {"build_base": "build-pip/setuptools"}},
    zip_safe=False,
)
