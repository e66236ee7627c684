"""Builds the Python package `caliper` for pip (pyproject.toml; docs/python.md "Installing with pip").

The compiled module comes from CMake: build_ext configures the project in its own folder with only
the module on (no CLI, tests or benchmarks), builds the target caliper_python, and copies the
module and the built-in body models into the package, where the library finds them
(models_dir(): `models/` beside the module). CALIPER_CMAKE_BUILD_DIR=DIR reuses an existing,
configured build folder instead (scripts/setup.sh and the `pip` test do, so nothing is compiled
twice).
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
(ROOT / "build").mkdir(exist_ok=True)  # egg_info writes there


def project_version():
    match = re.search(r"project\(caliper VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        sys.exit("setup.py: no `project(caliper VERSION x.y.z)` in CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = os.environ.get("CALIPER_CMAKE_BUILD_DIR")
        if not build_dir:
            build_dir = str(Path(self.build_temp).resolve() / "cmake")
            generator = ["-G", "Ninja"] if shutil.which("ninja") else []
            subprocess.run(["cmake", "-S", str(ROOT), "-B", build_dir, *generator, "-DCMAKE_BUILD_TYPE=Release",
                            f"-DPython_EXECUTABLE={sys.executable}", "-DCALIPER_BUILD_PYTHON=ON",
                            "-DCALIPER_BUILD_APPS=OFF", "-DCALIPER_BUILD_TESTS=OFF",
                            "-DCALIPER_BUILD_BENCHMARKS=OFF"], check=True)
        subprocess.run(["cmake", "--build", build_dir, "--target", "caliper_python", "-j", str(os.cpu_count() or 2)],
                       check=True)
        target = Path(self.get_ext_fullpath(ext.name))
        built = Path(build_dir) / "python" / "caliper" / target.name
        if not built.is_file():
            sys.exit(f"setup.py: CMake built no {built} (is {build_dir} configured for {sys.executable}?)")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)
        models = target.parent / "models"
        models.mkdir(exist_ok=True)
        for model in sorted((ROOT / "models").glob("*.npz")):
            shutil.copy2(model, models / model.name)


setup(
    version=project_version(),
    packages=["caliper"],
    package_dir={"caliper": "python/caliper"},
    ext_modules=[Extension("caliper._caliper", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' own work folder, inside CMake's build/ (which .gitignore already covers).
    options={"build": {"build_base": "build/pip"}, "egg_info": {"egg_base": "build"}},
    zip_safe=False,
)
