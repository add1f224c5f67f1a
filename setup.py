"""pip's way in: CMake builds the module `tavis` for the running Python and installs the package
(its extension, Python files and robot files) into the wheel's tree with `cmake --install
--component python`; the build rules stay in batch/python/CMakeLists.txt. docs/python.md.

Environment: TAVIS_PIP_BUILD_DIR, CMake's build folder (default build-pip/ in the source tree;
setuptools' scratch goes in its setuptools/ subfolder); CMAKE_BUILD_PARALLEL_LEVEL, the build's jobs (default: all cores);
CMAKE_CXX_COMPILER_LAUNCHER / CMAKE_C_COMPILER_LAUNCHER (e.g. ccache), read by CMake itself;
TAVIS_CMAKE_ARGS, more arguments for CMake's configure, split as a shell would (e.g.
"-DTAVIS_WERROR=ON", which tests/python/test_install.py passes when the build tree has it, so
that every compile command equals the build tree's and ccache serves its objects)."""

import os
import shlex
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = os.path.dirname(os.path.abspath(__file__))
BUILD_DIR = os.path.abspath(os.environ.get("TAVIS_PIP_BUILD_DIR") or os.path.join(SOURCE_DIR, "build-pip"))
SETUPTOOLS_DIR = os.path.join(BUILD_DIR, "setuptools")


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        cmake_dir = BUILD_DIR
        # The folder that holds the package in the wheel (the extension's path less "tavis/_tavis...").
        package_root = os.path.dirname(os.path.dirname(os.path.abspath(self.get_ext_fullpath(ext.name))))
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        # The folder setup.py really lives in: a checkout laid out with symbolic links (as
        # tests/tools/docs lays one out) then compiles with its build tree's paths, so ccache
        # serves those objects.
        source_dir = os.path.dirname(os.path.realpath(__file__))
        self._run(["cmake", "-S", source_dir, "-B", cmake_dir, "-DCMAKE_BUILD_TYPE=Release",
                   f"-DPython3_EXECUTABLE={sys.executable}", "-DTAVIS_BUILD_PYTHON=ON", "-DTAVIS_BUILD_TESTS=OFF",
                   "-DTAVIS_BUILD_BENCHMARKS=OFF", "-DTAVIS_PYTHON_INSTALL_DIR=.",
                   *shlex.split(os.environ.get("TAVIS_CMAKE_ARGS", ""))])
        self._run(["cmake", "--build", cmake_dir, "--target", "tavis_python", "--parallel", jobs])
        self._run(["cmake", "--install", cmake_dir, "--component", "python", "--prefix", package_root])

    @staticmethod
    def _run(command):
        print(" ".join(command), flush=True)
        subprocess.run(command, check=True)


os.makedirs(SETUPTOOLS_DIR, exist_ok=True)
setup(
    ext_modules=[Extension("tavis._tavis", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={
        "build": {"build_base": SETUPTOOLS_DIR},
        "egg_info": {"egg_base": os.path.relpath(SETUPTOOLS_DIR, SOURCE_DIR)},
    },
)
