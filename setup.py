"""Builds the Python package `topotet` with the project's own CMake (see pyproject.toml).

The package is python/topotet/; its extension `topotet._core` is one CMake target, `topotet_python`
(python/CMakeLists.txt), built for the
interpreter that runs pip, with the library linked in statically; nothing is compiled twice by
setuptools. TOPOTET_CMAKE_BUILD_DIR reuses an existing build tree (the tests do), and
TOPOTET_CMAKE_ARGS adds configure arguments.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


def project_version():
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(topotet VERSION ([0-9.]+)", f.read())
    if not match:
        raise RuntimeError("CMakeLists.txt: no 'project(topotet VERSION x.y.z'")
    return match.group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        reuse = os.environ.get("TOPOTET_CMAKE_BUILD_DIR")
        build = reuse or os.path.join(os.path.abspath(self.build_temp), "cmake")
        if not reuse:
            # A tree of its own, for the interpreter that runs pip, with only what the module needs.
            configure = ["cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                         f"-DPython3_EXECUTABLE={sys.executable}", "-DTOPOTET_BUILD_PYTHON=ON",
                         "-DTOPOTET_BUILD_TESTS=OFF", "-DTOPOTET_BUILD_BENCH=OFF", "-DTOPOTET_BUILD_CLI=OFF",
                         "-DTOPOTET_BUILD_FORTRAN=OFF", "-DTOPOTET_BUILD_C_API=OFF", "-DTOPOTET_MPI=OFF",
                         "-DTOPOTET_INSTALL=OFF"]
            if shutil.which("ninja") and not os.path.exists(os.path.join(build, "CMakeCache.txt")):
                configure += ["-G", "Ninja"]
            configure += shlex.split(os.environ.get("TOPOTET_CMAKE_ARGS", ""))
            subprocess.check_call(configure)
        # (A reused tree keeps its configuration: its module must be for this interpreter's Python.)
        jobs = str(max(1, os.cpu_count() or 1))
        subprocess.check_call(["cmake", "--build", build, "--target", "topotet_python", "--parallel", jobs])
        package = os.path.join(build, "python", "topotet")
        built = [f for f in os.listdir(package) if f.startswith("_core") and f.endswith(".so")]
        if len(built) != 1:
            raise RuntimeError(f"expected one built extension in {package}, found {built}")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(package, built[0]), target)


# The package's Python files come from python/topotet; its extension topotet._core from CMake.
setup(version=project_version(), packages=["topotet"], package_dir={"topotet": "python/topotet"},
      ext_modules=[CMakeExtension("topotet._core")],
      cmdclass={"build_ext": CMakeBuild},
      zip_safe=False)
