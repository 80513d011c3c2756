"""Compiling C: the generated code once per input hash into the cache (file lock, rename into
place), the vectorised loops for this machine, the robot-independent helpers (integrator,
Newton) and the fast-call extension; prebuilt libraries where the install made them.

Build policy (documented in the README): the committed C in ``generated/<robot>/`` is compiled on
first use with ``cc -O3 -fPIC -shared`` into a cache folder keyed by the manifest's input hash
(``folders.cache_dir``). The build holds a file lock (``filelock``) and renames the finished
library into place, so concurrent processes neither corrupt nor half-read it. ``make build``
does the same ahead of time.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
import threading
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from filelock import FileLock

from ..environment import flag
from ..errors import LibraryError
from .folders import _DIR, builtin_generated_dirs, cache_dir

CFLAGS = ("-O3", "-fPIC", "-shared", "-std=c99")
#: past this many operations in ``<robot>.c`` (a robot of about 10 links: the forward dynamics'
#: Jacobian is O(n^3)), -O1: gcc's -O2/-O3 passes cost it 2.5x the time (7.4 s against 2.9 s at
#: 12 links) on straight-line code they barely speed up (see BENCHMARKS.md, growth)
BIG_OPS = 20000
BIG_CFLAGS = ("-O1", "-fPIC", "-shared", "-std=c99")
#: compilers running at once, across threads (the exact library and the loops' units)
_JOBS = threading.BoundedSemaphore(max(1, os.cpu_count() or 1))


class NoCompiler(LibraryError):
    """No C compiler to run: the runtime falls back to CasADi's evaluator (``evaluator``)."""


def _compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        raise NoCompiler("no C compiler found (set CC, or install gcc): the generated code "
                         "is compiled on first use")
    return cc


#: the sample loops (derive/simd.py) are compiled for this machine's vector units with fast
#: math, which lets gcc call glibc's vector sin/cos. Linking happens without -ffast-math: gcc 12
#: would otherwise link crtfastmath.o into the library and switch the whole process to
#: flush-to-zero on load.
SIMD_CFLAGS = ("-O3", "-march=native", "-ffast-math", "-fPIC", "-std=c99")
#: with gcc (``simd_flags``): its RTL combiner takes three quarters of a big unit's time when
#: it tries 3- and 4-instruction combinations over a 1,500-statement loop body (a 30-link
#: chain's mass matrix unit: 59 s of CPU, 46 of them combining; a user trial met 109 s past 20
#: links); 2-instruction combinations take 25 s there, and the loops run as fast (2 links'
#: inverse dynamics 8.4 ns a sample either way, 20 links' mass matrix within the noise)
GCC_SIMD_FLAGS = ("--param", "max-combine-insns=2")


@functools.lru_cache(maxsize=4)
def _is_gcc(cc: str) -> bool:
    """Whether ``cc`` is gcc (clang calls itself cc too, and knows no such --param)."""
    try:
        out = subprocess.run([cc, "--version"], capture_output=True, text=True, timeout=30,
                             check=False).stdout
    except (OSError, subprocess.SubprocessError):
        return False
    return "Free Software Foundation" in out and "clang" not in out


def simd_flags() -> tuple[str, ...]:
    """The sample loops' flags for this machine's compiler (``SIMD_CFLAGS``, and with gcc
    ``GCC_SIMD_FLAGS``)."""
    try:
        gcc = _is_gcc(_compiler())
    except NoCompiler:
        gcc = False
    return SIMD_CFLAGS + (GCC_SIMD_FLAGS if gcc else ())


def _machine_key() -> str:
    """Identifies the CPU a -march=native build is for (a shared cache may see several)."""
    try:
        info = Path("/proc/cpuinfo").read_text()
        lines = [ln for ln in info.splitlines() if ln.startswith(("model name", "flags"))][:2]
    except OSError:
        lines = []
    return hashlib.sha256("\n".join([platform.machine(), *lines]).encode()).hexdigest()[:8]


def groups(manifest: dict) -> list[dict]:
    """The libraries a robot compiles into (derive/groups.py): each ``{"functions": [...],
    "units": [...]}``, its functions and its loops' compile units. A folder derived before
    groups is one group of everything."""
    functions = manifest.get("functions", {})
    if manifest.get("groups"):  # (a function a hand-edited manifest dropped is no member)
        return [{**g, "functions": [q for q in g["functions"] if q in functions]}
                for g in manifest["groups"]]
    units = manifest.get("compile_units", {}).get("simd", [0])
    return [{"functions": list(functions), "units": list(range(len(units)))}]


def exact_flags(manifest: dict, group: int = 0) -> tuple[str, ...]:
    """Flags of ``<robot>.c`` (of one group's functions) by size: -O3, or -O1 past ``BIG_OPS``
    operations."""
    functions = manifest.get("functions", {})  # groups() keeps only functions listed here
    ops = sum(functions[q].get("operations", 0) for q in groups(manifest)[group]["functions"])
    return BIG_CFLAGS if ops > BIG_OPS else CFLAGS


def library_path(folder: Path, manifest: dict, flavour: str = "exact", group: int = 0) -> Path:
    """Cache path keyed by robot, input hash, the C source's own hash and the flags (and the
    group, for a robot of several).

    The source hash matters for hand-made folders: C edited (and re-hashed in the manifest)
    under an unchanged input hash must not reuse the library built from the old C.
    """
    robot = manifest["robot"]
    source = f"{robot}.c" if flavour == "exact" else f"{robot}_{flavour}.c"
    flags = (exact_flags(manifest, group) if flavour == "exact"
             else simd_flags() + (_machine_key(),))
    key = hashlib.sha256(" ".join([*flags, manifest.get("files", {}).get(source, "")])
                         .encode()).hexdigest()[:8]
    suffix = "" if flavour == "exact" else f"-{flavour}"
    if len(groups(manifest)) > 1:
        suffix = f"-g{group}{suffix}"
    return cache_dir() / f"{robot}-{manifest['input_hash'][:16]}-{key}{suffix}.so"


def compile_shared(sources: list[Path], target: Path, cflags, extra: tuple = (),
                   link_flags: tuple = ("-lm",), force: bool = False,
                   units: list[tuple[str, ...]] | None = None) -> Path:
    """Compile ``sources`` into the shared library ``target``: locked, renamed into place.

    ``units``: compile each source once per entry with those extra flags (``-DPLANAR_SYM_UNIT=k``
    of a generated file split into units), the objects in parallel. Concurrent builders of
    the same target wait on the lock and then reuse the result, so no process ever loads a
    half-written library.
    """
    if _intact(target) and not force:
        return target
    if target.exists() and not force:  # there, but not what was built: truncated or replaced
        warnings.warn(f"compiled library {target} does not match the hash recorded when it was "
                      "built (truncated or replaced): rebuilding it", RuntimeWarning, stacklevel=3)
    target.parent.mkdir(parents=True, exist_ok=True)
    with FileLock(target.with_suffix(".lock")):
        if _intact(target) and not force:
            return target
        with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
            cc = _compiler()
            jobs = [(src, unit, Path(tmp) / f"{src.stem}.{k}.o")
                    for src in sources for k, unit in enumerate(units or [()])]

            def one(job):
                src, unit, obj = job
                with _JOBS:
                    _run([cc, *[f for f in cflags if f != "-shared"], *extra, *unit, "-c",
                          "-o", str(obj), str(src)], src)

            with ThreadPoolExecutor(max(1, min(len(jobs), os.cpu_count() or 1))) as pool:
                list(pool.map(one, jobs))  # re-raises the first failure
            objs = [str(obj) for _, _, obj in jobs]
            out = Path(tmp) / target.name
            _run([_compiler(), "-shared", "-o", str(out), *objs, *link_flags], sources[0])
            stamp = Path(tmp) / "stamp"
            stamp.write_text(hashlib.sha256(out.read_bytes()).hexdigest())
            os.replace(stamp, _stamp(target))  # stamp first: a crash between leaves a mismatch
            os.replace(out, target)
    return target


def _stamp(target: Path) -> Path:
    return target.with_name(target.name + ".sha256")


def _intact(target: Path) -> bool:
    """The library exists and matches the hash written when it was built. Checked before
    dlopen: loading a truncated shared library kills the process with SIGBUS."""
    try:
        return (hashlib.sha256(target.read_bytes()).hexdigest()
                == _stamp(target).read_text().strip())
    except OSError:
        return False


def _run(cmd: list[str], src: Path) -> None:
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    except OSError as exc:
        raise NoCompiler(f"cannot run the C compiler {cmd[0]!r} ({exc.strerror}): install "
                         "gcc, or set CC to a C compiler") from None
    if proc.returncode != 0:
        raise LibraryError(f"compiling {src} failed ({' '.join(cmd)}):\n{proc.stderr}")


#: the built-in robots' libraries, compiled when the package was installed (setup.py), named
#: as library_path names them
PREBUILT = _DIR / "prebuilt"


def _prebuilt(folder: Path, path: Path) -> Path | None:
    """The library of that name built at install for a built-in robot, if there and intact
    (a copied or user folder compiles into the cache, where its own problems show)."""
    if (flag("PLANAR_SYM_PREBUILT") is False  # compile into the cache regardless
            or folder.resolve().parent not in builtin_generated_dirs()):
        return None
    pre = PREBUILT / path.name
    return pre if _intact(pre) else None


def is_built(folder: Path, manifest: dict, group: int = 0) -> bool:
    """Whether a group's exact library is built already (at install, or in the cache)."""
    path = library_path(folder, manifest, group=group)
    return _prebuilt(folder, path) is not None or _intact(path)


def build(folder: Path, manifest: dict, force: bool = False, group: int = 0) -> Path:
    """Compile ``<robot>.c`` (exact: -O3, no fast math), or one group of its functions,
    unless this hash is built already (at install, or in the cache)."""
    path = library_path(folder, manifest, group=group)
    if not force and (pre := _prebuilt(folder, path)):
        return pre
    whole = len(groups(manifest)) == 1
    return compile_shared([folder / f"{manifest['robot']}.c"], path,
                          exact_flags(manifest, group), force=force,
                          extra=() if whole else (f"-DPLANAR_SYM_GROUP={group}",))


def build_simd(folder: Path, manifest: dict, force: bool = False,
               group: int = 0) -> Path | None:
    """Compile ``<robot>_simd.c`` (the vectorised sample loops) or one group's compile units,
    if the robot (the group) has loops. The first unit of each library defines
    ``PLANAR_SYM_HEAD``: it holds the library's input hash."""
    src = folder / f"{manifest['robot']}_simd.c"
    units = groups(manifest)[group]["units"]
    if not src.exists() or not units:
        return None
    path = library_path(folder, manifest, "simd", group)
    if not force and (pre := _prebuilt(folder, path)):
        return pre
    if len(groups(manifest)) == 1 and len(units) == 1:  # the whole file
        return compile_shared([src], path, simd_flags(), force=force)
    return compile_shared([src], path, simd_flags(), force=force,
                          units=[(f"-DPLANAR_SYM_UNIT={k}",) + (("-DPLANAR_SYM_HEAD",)
                                                                 if i == 0 else ())
                                 for i, k in enumerate(units)])


_FASTCALL = None


def fastcall():
    """The C extension that calls sample loops from Python (None where it cannot be built)."""
    global _FASTCALL
    if _FASTCALL is None:
        _FASTCALL = _build_fastcall() or False
    return _FASTCALL or None


def installed_extension(src: Path) -> Path | None:
    """The file setup.py built from ``src`` at install, if it is there (beside the source)."""
    import importlib.machinery

    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = src.with_name(src.stem + suffix)
        if path.is_file():
            return path
    return None


def source_hash(src: Path) -> str:
    """The hash setup.py records in what it builds from ``src``."""
    return hashlib.sha256(src.read_bytes()).hexdigest()[:16]


def _build_fastcall():
    import importlib.machinery
    import importlib.util
    import sysconfig

    src = _DIR / "_fastcall.c"
    built = installed_extension(src)
    if built is not None:
        try:
            from . import _fastcall

            if getattr(_fastcall, "SOURCE_HASH", None) == source_hash(src):
                return _fastcall
        except ImportError:  # built for another interpreter or numpy: compile it below
            pass
    try:
        import numpy

        tag = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
        key = hashlib.sha256(src.read_bytes() + numpy.__version__.encode()).hexdigest()[:12]
        target = cache_dir() / f"_fastcall-{key}{tag}"
        includes = ("-I" + sysconfig.get_paths()["include"], "-I" + numpy.get_include())
        # no fast math here: the finiteness check must see NaN
        compile_shared([src], target, ("-O3", "-fPIC", "-std=c99"), extra=includes,
                       link_flags=())
        spec = importlib.util.spec_from_file_location("planar_sym._fastcall", target)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    except (LibraryError, OSError, ImportError):
        return None  # no Python headers or compiler: the ctypes path still works


def _fresh_name(path: Path) -> Path:
    """A private copy of a just-rebuilt library: dlopen returns the handle it already holds
    for a path name (the bad file, opened a moment ago), not the file now at that path."""
    fd, tmp = tempfile.mkstemp(suffix=".so", dir=path.parent)
    os.close(fd)
    shutil.copyfile(path, tmp)
    return Path(tmp)


def load_helper(src: Path) -> ctypes.CDLL:
    """A robot-independent C helper (an integrator, a Newton loop): the one built at install
    (setup.py) while its source is unchanged, else compiled once per source hash into the cache
    and loaded; a corrupt cached copy is rebuilt and loaded privately."""
    built = installed_extension(src)
    if built is not None:
        try:
            lib = ctypes.CDLL(str(built))
            get = lib.planar_sym_source_hash
            get.restype = ctypes.c_char_p
            if get().decode() == source_hash(src):
                return lib
        except (OSError, AttributeError):  # not loadable here, or stale: compile it below
            pass
    key = hashlib.sha256(src.read_bytes() + " ".join(CFLAGS).encode()).hexdigest()[:12]
    target = cache_dir() / f"{src.stem}-{key}.so"
    try:
        return ctypes.CDLL(str(compile_shared([src], target, CFLAGS)))
    except OSError:  # built, yet unloadable: build it anew and load a private copy
        fresh = _fresh_name(compile_shared([src], target, CFLAGS, force=True))
        lib = ctypes.CDLL(str(fresh))
        fresh.unlink()
        return lib
