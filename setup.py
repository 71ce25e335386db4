"""Builds the extension stiffmsa._core with this repository's CMake (STIFFMSA_BUILD_PYTHON) and
packages it with python/stiffmsa. The version is the CMake project's."""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def cmake_version() -> str:
    match = re.search(r"project\(stiffmsa VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        raise RuntimeError("CMakeLists.txt: no `project(stiffmsa VERSION ...)`")
    return match.group(1)


class CMakeBuild(build_ext):
    """Configures and builds the target stiffmsa_python (the library, no tests or examples) in
    build-python/cmake, kept between installs so that a second one builds only what changed."""

    def build_extension(self, ext: Extension) -> None:
        build_dir = ROOT / "build-python" / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir), "-G", "Ninja",
            "-DCMAKE_BUILD_TYPE=Release",
            "-DSTIFFMSA_BUILD_PYTHON=ON", "-DSTIFFMSA_BUILD_TESTS=OFF", "-DSTIFFMSA_BUILD_EXAMPLES=OFF",
            f"-DPython_EXECUTABLE={sys.executable}",
        ]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "stiffmsa_python", "--parallel", jobs],
                       check=True)
        built = sorted((build_dir / "python").glob("_core*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one built extension in {build_dir / 'python'}, found {built}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    version=cmake_version(),
    packages=["stiffmsa"],
    package_dir={"": "python"},
    package_data={"stiffmsa": ["py.typed", "*.pyi"]},
    ext_modules=[Extension("stiffmsa._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(Path("build-python") / "setuptools")}},
    zip_safe=False,
)
