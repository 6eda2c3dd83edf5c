"""Build the geosep Python package: the extension geosep._geosep, compiled from
the binding (python/src) and the library's own C sources (../src,
../include) with the flags and libraries of the CMake build (C11, OpenMP,
METIS, CHOLMOD, libpng).

Install (no network needed; Debian: python3-dev python3-numpy python3-venv and
the library's own build dependencies, tools/install-deps.sh):
    python3 -m venv --system-site-packages VENV
    VENV/bin/python -m pip install --no-build-isolation ./python
"""
import glob
import os
import re
from concurrent.futures import ThreadPoolExecutor

import numpy
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def project_version():
    """The one project version: CMakeLists.txt's project(geosep VERSION x.y.z)."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(\s*geosep\s+VERSION\s+([0-9]+\.[0-9]+\.[0-9]+)", f.read())
    if not m:
        raise RuntimeError("CMakeLists.txt: no project(geosep VERSION x.y.z)")
    return m.group(1)


def cholmod_include():
    for d in ("/usr/include/suitesparse", "/usr/local/include/suitesparse"):
        if os.path.exists(os.path.join(d, "cholmod.h")):
            return [d]
    return []  # cholmod.h on the default include path


def write_version_header(folder):
    """include/geosep_version.h.in configured as CMake's configure_file does
    (@PROJECT_VERSION_MAJOR@ ...) into folder; False if the tree has none."""
    template = os.path.join(ROOT, "include", "geosep_version.h.in")
    if not os.path.exists(template):
        return False
    major, minor, patch = project_version().split(".")
    with open(template, encoding="utf-8") as f:
        text = f.read()
    for key, value in (("MAJOR", major), ("MINOR", minor), ("PATCH", patch)):
        text = text.replace(f"@PROJECT_VERSION_{key}@", value)
    if "@" in text:
        raise RuntimeError(f"{template}: a variable setup.py does not know: {text[text.index('@'):][:40]}")
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "geosep_version.h")
    old = open(path, encoding="utf-8").read() if os.path.exists(path) else None
    if old != text:  # unchanged: keep its time stamp
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
    return True


class BuildExt(build_ext):
    """build_ext that generates the version header and compiles the sources
    in parallel (one job per core, or GEOSEP_BUILD_JOBS): the library has a
    few dozen files."""

    def build_extensions(self):
        generated = os.path.join(os.path.abspath(self.build_temp), "generated")
        if write_version_header(generated):
            for ext in self.extensions:
                ext.include_dirs.insert(0, generated)
        compile_serial = self.compiler.compile
        jobs = int(os.environ.get("GEOSEP_BUILD_JOBS", "0")) or os.cpu_count() or 1

        def compile_parallel(sources, *args, **kwargs):
            with ThreadPoolExecutor(max_workers=jobs) as pool:
                parts = pool.map(lambda s: compile_serial([s], *args, **kwargs), sources)
                return [obj for objs in parts for obj in objs]

        self.compiler.compile = compile_parallel
        super().build_extensions()


library_sources = sorted(glob.glob(os.path.join(ROOT, "src", "*", "*.c")))
binding_sources = sorted(glob.glob(os.path.join(HERE, "src", "*.c")))
if not library_sources:
    raise RuntimeError(f"no library sources under {ROOT}/src: build from a geosep source tree")

# Headers, so that a change to one rebuilds the extension (setuptools
# compares only these and the sources with the built module).
headers = sorted(glob.glob(os.path.join(ROOT, "include", "*.h*")) + glob.glob(os.path.join(ROOT, "src", "*", "*.h"))
                 + glob.glob(os.path.join(HERE, "src", "*.h")) + [os.path.join(ROOT, "CMakeLists.txt")])

extension = Extension(
    "geosep._geosep",
    sources=binding_sources + library_sources,
    depends=headers,
    include_dirs=[os.path.join(ROOT, "include"), numpy.get_include()] + cholmod_include(),
    define_macros=[("_POSIX_C_SOURCE", "200809L")],
    libraries=["metis", "cholmod", "png", "m"],
    # as the CMake build: hidden visibility (the module exports PyInit__geosep
    # and the library's GS_API functions only)
    extra_compile_args=["-std=c11", "-fopenmp", "-fvisibility=hidden", "-Wall", "-Wextra"],
    extra_link_args=["-fopenmp"],
)

setup(
    name="geosep",
    version=project_version(),
    description="Fast geodesic distance queries on triangle meshes (Gotsman & Hormann 2022)",
    license="MIT",
    python_requires=">=3.9",
    install_requires=["numpy"],
    packages=["geosep"],
    ext_modules=[extension],
    cmdclass={"build_ext": BuildExt},
    zip_safe=False,
)
