"""The extension module `lava._lava`, built by the project's own CMake (pyproject.toml has
the rest). The build directory of README's commands (build/) is reused when it belongs to
this checkout, so that `pip install .` after them compiles nothing (LAVA_BUILD_DIR names
another); otherwise build-python/ is configured. The extension links the library statically: the package needs no
LD_LIBRARY_PATH or rpath, only the system's Vulkan loader."""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent


def cmake_build_dir():
    if os.environ.get("LAVA_BUILD_DIR"):  # a configured build of this checkout, named
        return pathlib.Path(os.environ["LAVA_BUILD_DIR"])
    build = ROOT / "build"
    cache = build / "CMakeCache.txt"
    if cache.exists() and f"CMAKE_HOME_DIRECTORY:INTERNAL={ROOT}\n" in cache.read_text():
        return build
    build = ROOT / "build-python"
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                    "-DLAVA_BUILD_PYTHON=ON"], check=True)
    return build


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = cmake_build_dir()
        jobs = str(max(1, len(os.sched_getaffinity(0))))
        subprocess.run(["cmake", "--build", str(build), "--target", "lava_python", "-j", jobs],
                       check=True)
        suffix = pathlib.Path(self.get_ext_filename(ext.name)).name
        built = build / "python" / "lava" / suffix
        if not built.exists():
            sys.exit(f"lava: CMake built no {built} (a python3 other than Debian's?)")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


class BuildPy(build_py):
    """The package's Python files, and the presets (scenes/*.toml, scenes/modules/*.toml)
    into lava/scenes: lava.Scene("volcano") finds them from any folder."""

    def run(self):
        super().run()
        target = pathlib.Path(self.build_lib) / "lava" / "scenes"
        for scene in list((ROOT / "scenes").glob("*.toml")) + list((ROOT / "scenes").glob("modules/*.toml")):
            destination = target / scene.relative_to(ROOT / "scenes")
            destination.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(scene, destination)


def requirements():
    """numpy, unless this python3 has none: another python3 of Debian's version (pyenv's,
    say), whose package then uses Debian's python3-numpy (lava/__init__.py)."""
    try:
        import numpy  # noqa: F401
        return ["numpy"]
    except ImportError:
        return []


def wheel_command():
    """setuptools' bdist_wheel, from Debian's python3-wheel where this python3 has none."""
    try:
        from wheel.bdist_wheel import bdist_wheel
    except ImportError:
        sys.path.append("/usr/lib/python3/dist-packages")
        from wheel.bdist_wheel import bdist_wheel
    return bdist_wheel


setup(ext_modules=[Extension("lava._lava", sources=[])],
      install_requires=requirements(),
      cmdclass={"build_ext": CMakeBuild, "build_py": BuildPy, "bdist_wheel": wheel_command()},
      # setuptools' own build tree, apart from CMake's files in build/.
      options={"build": {"build_base": "build/python-package"}})
