"""Builds the package hullmap for pip: CMake configures this checkout in build-pip/ (or
$HULLMAP_PIP_BUILD_DIR) and builds the target hullmap_python (the extension hullmap._hullmap) for the
interpreter pip runs; setuptools packages it with python/hullmap/, its own files in that directory's
setuptools/. A build directory beside build/, with the same generator, compiles the same commands,
so ccache serves what build/ compiled. Use `pip install --no-build-isolation .` (docs/PYTHON.md): the build needs Debian's
setuptools, wheel, cmake, pybind11-dev, python3-dev, python3-numpy and hullmap's C++ dependencies
(setup.sh's list), nothing from a package index."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
BUILD = Path(os.environ.get("HULLMAP_PIP_BUILD_DIR", ROOT / "build-pip"))
BUILD.mkdir(parents=True, exist_ok=True)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        # Ninja for a new build directory, as setup.sh chooses for build/: the same generator runs the
        # same compile commands, which ccache then serves.
        generator = []
        if not (BUILD / "CMakeCache.txt").exists() and shutil.which("ninja"):
            generator = ["-G", "Ninja"]
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), *generator, "-DCMAKE_BUILD_TYPE=Release",
                        "-DHULLMAP_BUILD_TESTS=OFF", "-DHULLMAP_BUILD_CLI=OFF", "-DHULLMAP_BUILD_ROS=OFF",
                        f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(BUILD), "--target", "hullmap_python",
                        "-j", os.environ.get("JOBS", str(os.cpu_count() or 1))], check=True)
        built = next((BUILD / "python" / "hullmap").glob("_hullmap*.so"))
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(
    packages=["hullmap"],
    package_dir={"": "python"},
    ext_modules=[Extension("hullmap._hullmap", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(BUILD / "setuptools")}, "egg_info": {"egg_base": str(BUILD)}},
    zip_safe=False,
)
