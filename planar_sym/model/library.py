"""Compiled generated code: find it, check it, build it once per input hash, call it in batches.

Build policy (documented in the README): the committed C in ``generated/<robot>/`` is compiled on
first use with ``cc -O3 -fPIC -shared`` into a cache folder keyed by the manifest's input hash
(``$PLANAR_SYM_CACHE``, else the user cache folder of ``platformdirs``: ``~/.cache/planar_sym``
or ``$XDG_CACHE_HOME/planar_sym`` on Linux, ``~/Library/Caches/planar_sym`` on macOS,
``%LOCALAPPDATA%\\planar_sym\\Cache`` on Windows). The build holds a file lock (``filelock``) and renames the finished library into place, so concurrent
processes neither corrupt nor half-read it. ``make build`` does the same ahead of time.
"""

from __future__ import annotations

import ctypes
import hashlib
import json
import os
import platform
import shutil
import subprocess
import tempfile
import threading
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from filelock import FileLock

from ..errors import InputError, LibraryError
from .batch import FunctionSpec, shaped

CFLAGS = ("-O3", "-fPIC", "-shared", "-std=c99")
#: past this many operations in ``<robot>.c`` (a robot of about 10 links: the forward dynamics'
#: Jacobian is O(n^3)), -O1: gcc's -O2/-O3 passes cost it 2.5x the time (7.4 s against 2.9 s at
#: 12 links) on straight-line code they barely speed up (see BENCHMARKS.md, growth)
BIG_OPS = 20000
BIG_CFLAGS = ("-O1", "-fPIC", "-shared", "-std=c99")
#: compilers running at once, across threads (the exact library and the loops' units)
_JOBS = threading.BoundedSemaphore(max(1, os.cpu_count() or 1))
_DIR = Path(__file__).resolve().parent  # planar_sym/model: _fastcall.c
_PKG = _DIR.parent  # planar_sym: generated/ ships inside it


def builtin_generated_dirs() -> list[Path]:
    """The built-in robots' generated folders: inside the installed package, or the checkout's."""
    return [(_PKG / "generated").resolve(), (_PKG.parent / "generated").resolve()]


def generated_dirs() -> list[Path]:
    """Where generated robots are looked for, first match wins."""
    dirs = [Path(d) for d in os.environ.get("PLANAR_SYM_GENERATED", "").split(os.pathsep) if d]
    return dirs + builtin_generated_dirs()


def find_generated(robot: str) -> Path:
    for d in generated_dirs():
        if (d / robot / "manifest.json").is_file():
            return d / robot
    raise LibraryError(
        f"no generated code for robot {robot!r} (looked in "
        f"{', '.join(str(d) for d in generated_dirs())}): run `make derive`")


def cache_dir() -> Path:
    """Where compiled libraries are kept: ``$PLANAR_SYM_CACHE``, else the user cache folder."""
    if os.environ.get("PLANAR_SYM_CACHE"):
        return Path(os.environ["PLANAR_SYM_CACHE"])
    from platformdirs import user_cache_dir

    return Path(user_cache_dir("planar_sym", appauthor=False))


def read_manifest(folder: Path) -> dict:
    """The manifest, after checking every generated file against the hashes it lists."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError) as exc:
        raise LibraryError(f"{folder / 'manifest.json'} is unreadable ({exc}): "
                           "run `make derive`") from None
    for name, digest in manifest.get("files", {}).items():
        path = folder / name
        if not path.is_file():
            raise LibraryError(f"{path} is missing: run `make derive`")
        if hashlib.sha256(path.read_bytes()).hexdigest() != digest:
            raise LibraryError(f"{path} does not match {folder / 'manifest.json'} (edited by "
                               "hand or half-written): run `make derive`")
    return manifest


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


def _machine_key() -> str:
    """Identifies the CPU a -march=native build is for (a shared cache may see several)."""
    try:
        info = Path("/proc/cpuinfo").read_text()
        lines = [ln for ln in info.splitlines() if ln.startswith(("model name", "flags"))][:2]
    except OSError:
        lines = []
    return hashlib.sha256("\n".join([platform.machine(), *lines]).encode()).hexdigest()[:8]


def exact_flags(manifest: dict) -> tuple[str, ...]:
    """Flags of ``<robot>.c`` by its size: -O3, or -O1 past ``BIG_OPS`` operations."""
    ops = sum(f.get("operations", 0) for f in manifest.get("functions", {}).values())
    return BIG_CFLAGS if ops > BIG_OPS else CFLAGS


def library_path(folder: Path, manifest: dict, flavour: str = "exact") -> Path:
    """Cache path keyed by robot, input hash, the C source's own hash and the flags.

    The source hash matters for hand-made folders: C edited (and re-hashed in the manifest)
    under an unchanged input hash must not reuse the library built from the old C.
    """
    robot = manifest["robot"]
    source = f"{robot}.c" if flavour == "exact" else f"{robot}_{flavour}.c"
    flags = exact_flags(manifest) if flavour == "exact" else SIMD_CFLAGS + (_machine_key(),)
    key = hashlib.sha256(" ".join([*flags, manifest.get("files", {}).get(source, "")])
                         .encode()).hexdigest()[:8]
    suffix = "" if flavour == "exact" else f"-{flavour}"
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
    if (os.environ.get("PLANAR_SYM_PREBUILT") == "0"  # compile into the cache regardless
            or folder.resolve().parent not in builtin_generated_dirs()):
        return None
    pre = PREBUILT / path.name
    return pre if _intact(pre) else None


def build(folder: Path, manifest: dict, force: bool = False) -> Path:
    """Compile ``<robot>.c`` (exact: -O3, no fast math) unless this hash is built already (at
    install, or in the cache)."""
    path = library_path(folder, manifest)
    if not force and (pre := _prebuilt(folder, path)):
        return pre
    return compile_shared([folder / f"{manifest['robot']}.c"], path, exact_flags(manifest),
                          force=force)


def build_simd(folder: Path, manifest: dict, force: bool = False) -> Path | None:
    """Compile ``<robot>_simd.c`` (the vectorised sample loops), if the robot has one."""
    src = folder / f"{manifest['robot']}_simd.c"
    if not src.exists():
        return None
    path = library_path(folder, manifest, "simd")
    if not force and (pre := _prebuilt(folder, path)):
        return pre
    units = manifest.get("compile_units", {}).get("simd", [0])
    return compile_shared([src], path, SIMD_CFLAGS, force=force,
                          units=[(f"-DPLANAR_SYM_UNIT={k}",) for k in range(len(units))]
                          if len(units) > 1 else None)


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


class CorruptLibrary(LibraryError):
    """A cached library that cannot be loaded at all (the loader rebuilds it once)."""

    def __init__(self, message: str, reason: str):
        super().__init__(message)
        self.reason = reason


class BatchFunction:
    """One generated function over N samples: per-sample arrays in, arrays out, one C call."""

    def __init__(self, lib: ctypes.CDLL, spec: FunctionSpec):
        self.spec = spec
        self._fn = getattr(lib, spec.symbol + "_batch")
        self._fn.restype = ctypes.c_int
        self._fn.argtypes = [ctypes.c_longlong] + [ctypes.c_void_p] * (
            len(spec.inputs) + len(spec.outputs))

    def __call__(self, n: int, args: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``args`` maps input names to C-contiguous float64 arrays: (n, size), or (size,) for p."""
        ptrs = []
        for name, size in self.spec.inputs:
            a = args[name]
            expected = (size,) if name == "p" else (n, size)
            if a.shape != expected or a.dtype != np.float64 or not a.flags.c_contiguous:
                raise LibraryError(f"internal: {self.spec.symbol} input {name} is {a.shape} "
                                   f"{a.dtype}, expected {expected} float64 contiguous")
            ptrs.append(a.ctypes.data)
        outs = {}
        for name, rows, cols, _ in self.spec.outputs:
            try:
                outs[name] = np.empty((n, rows * cols))
            except MemoryError:
                raise InputError(f"not enough memory for the output of {n} samples "
                                 f"({8e-9 * n * rows * cols:.3g} GB): evaluate them in smaller "
                                 "batches") from None
            ptrs.append(outs[name].ctypes.data)
        status = self._fn(n, *ptrs)
        if status:
            raise LibraryError(f"{self.spec.symbol} failed at sample {status - 1}")
        return shaped(self.spec, n, list(outs.values()))


def _try_build_simd(folder: Path, manifest: dict) -> tuple[Path | None, LibraryError | None]:
    """``build_simd``'s library, or the error that stopped it (the caller warns: a robot
    without its loops still works, on the exact path)."""
    try:
        return build_simd(folder, manifest), None
    except LibraryError as exc:
        return None, exc


class Library:
    """A robot's compiled functions, checked against its manifest."""

    def __init__(self, robot: str, folder: Path | None = None):
        self.folder = folder or find_generated(robot)
        self.manifest = read_manifest(self.folder)
        if self.manifest.get("robot") != robot:
            raise LibraryError(f"{self.folder / 'manifest.json'} is for robot "
                               f"{self.manifest.get('robot')!r}, not {robot!r}: run `make derive`")
        specs = {q: FunctionSpec(f["symbol"], tuple(map(tuple, f["inputs"])),
                                 tuple(map(tuple, f["outputs"])))
                 for q, f in self.manifest["functions"].items()}
        # the loops compile beside the exact library: two compilers at once on a first use
        with ThreadPoolExecutor(1) as pool:
            simd_job = pool.submit(_try_build_simd, self.folder, self.manifest)
            try:
                self.path = build(self.folder, self.manifest)
            except NoCompiler as exc:
                if not all("casadi" in f for f in self.manifest["functions"].values()):
                    raise  # a folder derived before the saved functions: nothing to fall back on
                from .evaluator import CasadiFunction, no_compiler_warning

                no_compiler_warning(robot, str(exc).split(" (")[0])
                self.path, self.lib, self.simd = None, None, None
                self.functions = {q: CasadiFunction(self.folder / self.manifest["functions"][q]
                                                    ["casadi"], spec)
                                  for q, spec in specs.items()}
                return
            finally:
                simd_path, simd_error = simd_job.result()
        try:
            self.lib = self._load(self.path)
        except CorruptLibrary as exc:  # truncated or overwritten cache file: build it anew
            warnings.warn(f"compiled library {self.path} could not be loaded ({exc.reason}): "
                          "rebuilding it", RuntimeWarning, stacklevel=2)
            self.path = build(self.folder, self.manifest, force=True)
            self.lib = self._load(_fresh_name(self.path), private_copy=True)
        self.simd = None  # the vectorised sample loops, where this machine can build them
        if simd_error is not None:
            warnings.warn(f"{robot}: vectorised loops not built, using the exact path: "
                          f"{simd_error}", RuntimeWarning, stacklevel=2)
        if simd_path is not None:
            try:
                self.simd = self._load(simd_path, f"{robot}_simd_input_hash")
            except CorruptLibrary as exc:
                warnings.warn(f"compiled library {simd_path} could not be loaded "
                              f"({exc.reason}): rebuilding it", RuntimeWarning, stacklevel=2)
                simd_path = build_simd(self.folder, self.manifest, force=True)
                self.simd = self._load(_fresh_name(simd_path), f"{robot}_simd_input_hash",
                                       private_copy=True)
        self.functions = {q: BatchFunction(self.lib, spec) for q, spec in specs.items()}

    @property
    def compiled(self) -> bool:
        """False where no C compiler was at hand: CasADi's evaluator runs the functions."""
        return self.lib is not None

    def address(self, quantity: str) -> int:
        """Address of ``<robot>_<quantity>_batch`` in the exact library (for C callers); with
        CasADi's evaluator, a callback of the same signature."""
        if self.lib is None:
            return self.functions[quantity].address
        symbol = self.manifest["functions"][quantity]["symbol"] + "_batch"
        return ctypes.cast(getattr(self.lib, symbol), ctypes.c_void_p).value

    def loop_address(self, quantity: str) -> int | None:
        """Address of ``<robot>_<quantity>_loop`` (vectorised), or None without the library."""
        spec = self.manifest["functions"][quantity]
        if self.simd is None or "loop" not in spec:
            return None
        return ctypes.cast(getattr(self.simd, spec["loop"]), ctypes.c_void_p).value

    def _load(self, path: Path, hash_symbol: str | None = None,
              private_copy: bool = False) -> ctypes.CDLL:
        robot, want = self.manifest["robot"], self.manifest["input_hash"]
        try:
            lib = ctypes.CDLL(str(path))
            if private_copy:  # mapped now: the file is not needed on disk
                path.unlink()
            get = getattr(lib, hash_symbol or f"{robot}_input_hash")
        except (OSError, AttributeError) as exc:
            raise CorruptLibrary(f"compiled library {path} is corrupt or not for {robot} "
                                 f"({exc}): delete it and run `make build`", str(exc)) from None
        get.restype = ctypes.c_char_p
        have = get().decode()
        if have != want:
            raise LibraryError(
                f"compiled library {path} was built from input hash {have[:16]}..., but "
                f"{self.folder / 'manifest.json'} says {want[:16]}...: delete it and run "
                "`make build` (or `make derive` if the generated sources are stale)")
        return lib


class SingleCall:
    """One sample through a batch function with pre-bound buffers: for integrator callbacks.

    Outputs are views into reused buffers: copy them if you keep them.
    """

    def __init__(self, fn: BatchFunction, p: np.ndarray):
        self._fn = fn._fn
        self._ins = {name: (p.copy() if name == "p" else np.zeros(size))
                     for name, size in fn.spec.inputs}
        self._outs = [np.zeros(rows * cols) for _, rows, cols, _ in fn.spec.outputs]
        self._names = [name for name, _ in fn.spec.inputs if name != "p"]
        self._args = (1, *[a.ctypes.data for a in self._ins.values()],
                      *[o.ctypes.data for o in self._outs])

    def __call__(self, *arrays: np.ndarray) -> list[np.ndarray]:
        for name, a in zip(self._names, arrays):
            self._ins[name][:] = a
        if self._fn(*self._args):
            raise LibraryError("generated function failed")
        return self._outs


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
