"""The C of the runtime, built when the package is installed.

Everything else is declared in pyproject.toml.

* ``_fastcall`` is a CPython extension; ``_integrate`` and ``_newton`` are plain C loaded with
  ctypes, built as (empty) extension modules so that the wheel carries them. Each records the
  hash of the source it was built from: the runtime loads it only while the shipped ``.c``
  still has that hash (an edited checkout compiles into the cache instead).
* The built-in robots' generated C, compiled as the runtime would (same compiler, flags and
  file names, see ``planar_sym/model/compile.py``) into ``planar_sym/model/prebuilt/``: a fresh
  install answers its first torque without compiling. The vectorised loops are built for this
  machine's CPU and named by it, so a wheel taken to another CPU compiles them on first use.

Without a C compiler the build skips all of it with a note; the runtime then runs on CasADi's
evaluator and says what that costs.
"""

import hashlib
import json
import os
import platform
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent

#: as planar_sym/model/compile.py compiles robots (CFLAGS, SIMD_CFLAGS); a library's file name
#: carries a hash of these and of its source (tests/test_install.py checks the two agree)
CFLAGS = ("-O3", "-fPIC", "-shared", "-std=c99")
SIMD_CFLAGS = ("-O3", "-march=native", "-ffast-math", "-fPIC", "-std=c99")
#: compile.GCC_SIMD_FLAGS, with gcc only
GCC_SIMD_FLAGS = ("--param", "max-combine-insns=2")


def _is_gcc(cc: str) -> bool:
    """compile._is_gcc: whether ``cc`` is gcc (clang calls itself cc too)."""
    try:
        out = subprocess.run([cc, "--version"], capture_output=True, text=True, timeout=30,
                             check=False).stdout
    except (OSError, subprocess.SubprocessError):
        return False
    return "Free Software Foundation" in out and "clang" not in out


def _extension(module: str, source: str) -> Extension:
    digest = hashlib.sha256((ROOT / source).read_bytes()).hexdigest()[:16]
    macros = [("PLANAR_SYM_EXTENSION", "1"), ("PLANAR_SYM_SOURCE_HASH", f'"{digest}"')]
    # no fast math: the finiteness checks must see NaN
    return Extension(module, [source], define_macros=macros,
                     extra_compile_args=["-O3", "-std=c99"], optional=True)


def _machine_key() -> str:
    """compile._machine_key: the CPU a -march=native build is for."""
    try:
        info = Path("/proc/cpuinfo").read_text()
        lines = [ln for ln in info.splitlines() if ln.startswith(("model name", "flags"))][:2]
    except OSError:
        lines = []
    return hashlib.sha256("\n".join([platform.machine(), *lines]).encode()).hexdigest()[:8]


def _robot_builds(folder: Path, gcc: bool = False) -> list[tuple[Path, tuple, str]]:
    """(source, flags, file name) of one generated robot's libraries, named as
    compile.library_path names them: the exact functions, and the vectorised loops."""
    manifest = json.loads((folder / "manifest.json").read_text())
    robot, files = manifest["robot"], manifest["files"]
    builds = []
    if len(manifest.get("groups") or [0]) > 1:  # a big robot: its groups compile on first use
        return builds
    simd = SIMD_CFLAGS + (GCC_SIMD_FLAGS if gcc else ())
    for flavour, flags, keyed in (("exact", CFLAGS, CFLAGS),
                                  ("simd", simd, simd + (_machine_key(),))):
        source = f"{robot}.c" if flavour == "exact" else f"{robot}_{flavour}.c"
        if source in files:
            key = hashlib.sha256(" ".join([*keyed, files[source]]).encode()).hexdigest()[:8]
            suffix = "" if flavour == "exact" else f"-{flavour}"
            builds.append((folder / source, flags,
                           f"{robot}-{manifest['input_hash'][:16]}-{key}{suffix}.so"))
    return builds


def _compile(cc: str, source: Path, flags: tuple, name: str, target: Path) -> bool:
    """Compile and link as library.compile_shared does, then rename into place with the
    stamp (sha256) the runtime checks before loading."""
    cflags = [f for f in flags if f != "-shared"]
    with tempfile.TemporaryDirectory() as tmp:
        obj, lib = Path(tmp) / "f.o", Path(tmp) / name
        for cmd in ([cc, *cflags, "-c", "-o", str(obj), str(source)],
                    [cc, "-shared", "-o", str(lib), str(obj), "-lm"]):
            if subprocess.run(cmd, capture_output=True, check=False).returncode:
                print(f"planar-sym: could not compile {source.name}; it is compiled on first use")
                return False
        (target / (name + ".sha256")).write_text(hashlib.sha256(lib.read_bytes()).hexdigest())
        shutil.move(str(lib), target / name)
    return True


class BuildExt(build_ext):
    """numpy's headers are looked up only when building (numpy is a build requirement); MSVC
    takes its own flags; then the robots are compiled (in parallel)."""

    def build_extensions(self):
        import numpy

        for ext in self.extensions:
            if ext.name.endswith("_fastcall"):
                ext.include_dirs.append(numpy.get_include())
            if self.compiler.compiler_type == "msvc":
                ext.extra_compile_args = ["/O2"]
        super().build_extensions()

    def run(self):
        super().run()
        if self.compiler.compiler_type == "unix":
            self._prebuild_robots()

    def _prebuild_robots(self):
        cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
        if not cc:
            print("planar-sym: no C compiler: the robots' C is compiled on first use instead")
            return
        target = (ROOT if self.inplace else Path(self.build_lib)) / "planar_sym/model/prebuilt"
        if target.is_dir():  # only this build's libraries: old ones would ship too
            shutil.rmtree(target)
        target.mkdir(parents=True)
        jobs = [job for d in sorted((ROOT / "generated").iterdir())
                if (d / "manifest.json").is_file() for job in _robot_builds(d, _is_gcc(cc))]
        with ThreadPoolExecutor(os.cpu_count() or 1) as pool:
            done = sum(pool.map(lambda job: _compile(cc, *job, target), jobs))
        print(f"planar-sym: compiled {done} of {len(jobs)} robot libraries")


def _packages() -> tuple[list[str], dict[str, list[str]]]:
    """Every folder of planar_sym with Python modules, the derivation (as ``planar_sym._derive``,
    never a top-level ``derive``) and each built-in robot's generated folder with its files."""
    runtime = sorted(".".join(d.relative_to(ROOT).parts) for d in (ROOT / "planar_sym").rglob("*")
                     if d.is_dir() and any(d.glob("*.py")) and "__pycache__" not in d.parts)
    robots = sorted(d.name for d in (ROOT / "generated").iterdir()
                    if (d / "manifest.json").is_file())
    packages = ["planar_sym", *runtime, "planar_sym._derive", "planar_sym.generated",
                *[f"planar_sym.generated.{r}" for r in robots]]
    data = {"planar_sym": ["py.typed"], "planar_sym.model": ["*.c", "*.pyi"],
            "planar_sym.dynamics": ["*.c"], "planar_sym.motion": ["*.c"],
            "planar_sym.robots": ["*.toml"], "planar_sym.studies": ["*.toml"],
            "planar_sym.schemas": ["*.json"]}
    data.update({f"planar_sym.generated.{r}": ["*.c", "*.h", "*.json", "*.txt", "*.tex", "*.md",
                                               "*.casadi"] for r in robots})
    return packages, data


if __name__ == "__main__":  # the build backend runs this file as __main__; tests import it
    PACKAGES, PACKAGE_DATA = _packages()
    setup(
        packages=PACKAGES,
        # the committed generated C ships inside the package (compiled at install, or on first
        # use, or evaluated by CasADi from its saved functions); derive/ too, for a user's robots
        package_dir={"planar_sym.generated": "generated", "planar_sym._derive": "derive"},
        package_data=PACKAGE_DATA,
        ext_modules=[
            _extension("planar_sym.model._fastcall", "planar_sym/model/_fastcall.c"),
            _extension("planar_sym.dynamics._integrate", "planar_sym/dynamics/_integrate.c"),
            _extension("planar_sym.motion._newton", "planar_sym/motion/_newton.c"),
        ],
        cmdclass={"build_ext": BuildExt},
    )
