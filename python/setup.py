"""Builds the extension spinmotor._spinmotor by running CMake on the repository (the folder above
python/) with SPINMOTOR_PYTHON=ON, then copies the module into the wheel. Offline: needs only cmake,
a C++20 compiler and the Debian packages of the C++ library plus pybind11-dev.

Environment:
  SPINMOTOR_BUILD_DIR   CMake build directory to use (reused between installs; default:
                        python/build/cmake-<python tag>). A new one is configured for the module
                        alone (no tests, examples, benchmarks, viewer, renderer); one that exists keeps
                        its options and only gets SPINMOTOR_PYTHON=ON, so README's build (which has
                        the module already) installs it without building anything again
  SPINMOTOR_CMAKE_ARGS  extra CMake arguments, e.g. "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache
                        -DSPINMOTOR_NATIVE=OFF" (-march=native is on by default: build on the machine
                        that runs it, or turn it off for a portable module)
  SPINMOTOR_JOBS        parallel build jobs (default 2)
"""
import os
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        if not os.path.exists(os.path.join(ROOT, "CMakeLists.txt")):
            raise RuntimeError(f"spinmotor: the C++ project is expected at {ROOT} (python/ inside the repository)")
        tag = sysconfig.get_config_var("SOABI") or "py"
        build = os.environ.get("SPINMOTOR_BUILD_DIR") or os.path.join(HERE, "build", f"cmake-{tag}")
        fresh = not os.path.exists(os.path.join(build, "CMakeCache.txt"))
        os.makedirs(build, exist_ok=True)
        generator = ["-G", "Ninja"] if shutil.which("ninja") and fresh else []
        module_only = [
            "-DCMAKE_BUILD_TYPE=Release",
            "-DSPINMOTOR_BUILD_TESTS=OFF", "-DSPINMOTOR_BUILD_EXAMPLES=OFF",
            "-DSPINMOTOR_BUILD_BENCHMARKS=OFF", "-DSPINMOTOR_BUILD_VIEWER=OFF", "-DSPINMOTOR_BUILD_RENDER=OFF",
        ] if fresh else []
        args = [
            "cmake", "-S", ROOT, "-B", build, *generator, *module_only,
            "-DSPINMOTOR_PYTHON=ON",
            f"-DPython3_EXECUTABLE={sys.executable}",
            *shlex.split(os.environ.get("SPINMOTOR_CMAKE_ARGS", "")),
        ]
        subprocess.check_call(args)
        jobs = os.environ.get("SPINMOTOR_JOBS", "2")
        subprocess.check_call(["cmake", "--build", build, "--target", "spinmotor_python", "-j", jobs])
        built = os.path.join(build, "python", "spinmotor")
        so = [f for f in os.listdir(built) if f.startswith("_spinmotor") and f.endswith((".so", ".pyd"))]
        if not so:
            raise RuntimeError(f"spinmotor: no extension module in {built}")
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(os.path.join(built, so[0]), dest)


setup(ext_modules=[Extension("spinmotor._spinmotor", sources=[])], cmdclass={"build_ext": CMakeBuild})
