"""A robot's compiled functions, checked against its manifest and called in batches.

``Library`` finds the generated folder (``folders``), builds or loads the exact library and the
vectorised loops (``compile``), and wraps each generated function as a ``BatchFunction`` (N
samples, one C call); ``SingleCall`` is one sample with bound buffers, for integrator callbacks.
"""

from __future__ import annotations

import ctypes
import os
import threading
import warnings
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import InputError, LibraryError
from ..progress import announce
from .batch import FunctionSpec, shaped
from .compile import NoCompiler, _compiler, _fresh_name, build, build_simd, groups, is_built
from .folders import builtin_generated_dirs, find_generated, read_manifest

__all__ = ["BatchFunction", "CorruptLibrary", "Library", "SingleCall", "builtin_generated_dirs",
           "find_generated", "read_manifest"]


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


def _try_build_simd(folder: Path, manifest: dict,
                    group: int = 0) -> tuple[Path | None, LibraryError | None]:
    """``build_simd``'s library, or the error that stopped it (the caller warns: a robot
    without its loops still works, on the exact path)."""
    try:
        return build_simd(folder, manifest, group=group), None
    except LibraryError as exc:
        return None, exc


class _Functions(Mapping):
    """A library's functions by quantity, each group compiled when one of its functions is
    first asked for (a robot of one group is compiled when the library is made)."""

    def __init__(self, library: Library):
        self._library = library

    def __getitem__(self, quantity: str) -> BatchFunction:
        return self._library.function(quantity)

    def __contains__(self, quantity) -> bool:  # without compiling
        return quantity in self._library.manifest["functions"]

    def __iter__(self):
        return iter(self._library.manifest["functions"])

    def __len__(self) -> int:
        return len(self._library.manifest["functions"])


class Library:
    """A robot's compiled functions, checked against its manifest.

    The functions compile in groups (``compile.groups``, made by ``derive/groups.py``): a robot
    of one group (every built-in robot, a chain of up to five links) compiles when the library
    is made; a bigger one's groups (one function each) the first time a function is called.
    """

    def __init__(self, robot: str, folder: Path | None = None):
        self.folder = folder or find_generated(robot)
        self.manifest = read_manifest(self.folder)
        if self.manifest.get("robot") != robot:
            raise LibraryError(f"{self.folder / 'manifest.json'} is for robot "
                               f"{self.manifest.get('robot')!r}, not {robot!r}: run `make derive`")
        self._specs = {q: FunctionSpec(f["symbol"], tuple(map(tuple, f["inputs"])),
                                       tuple(map(tuple, f["outputs"])))
                       for q, f in self.manifest["functions"].items()}
        self.groups = groups(self.manifest)
        self._group_of = {q: k for k, g in enumerate(self.groups) for q in g["functions"]}
        self._built: dict[int, tuple] = {}  # group -> (exact path, exact lib, loops lib)
        self._batch: dict[str, BatchFunction] = {}
        self._locks = [threading.Lock() for _ in self.groups]  # one build of a group at once
        #: group 0's libraries (a one-group robot's only ones): None until built
        self.path, self.lib, self.simd = None, None, None
        self.compiled = True
        try:
            if len(self.groups) == 1:
                self._build(0)
            else:
                _compiler()  # a missing compiler shows now, not at a later first call
        except NoCompiler as exc:
            if not all("casadi" in f for f in self.manifest["functions"].values()):
                raise  # a folder derived before the saved functions: nothing to fall back on
            from .evaluator import CasadiFunction, no_compiler_warning

            no_compiler_warning(robot, str(exc).split(" (")[0])
            self.compiled = False
            self.functions = {q: CasadiFunction(self.folder / self.manifest["functions"][q]
                                                ["casadi"], spec)
                              for q, spec in self._specs.items()}
            return
        self.functions = _Functions(self)

    def function(self, quantity: str) -> BatchFunction:
        """One generated function over N samples, its group compiled if it is not yet."""
        if quantity not in self._batch:
            self._build(self._group_of[quantity])
        return self._batch[quantity]

    def exact_path(self, quantity: str) -> Path:
        """The exact library holding ``quantity`` (its group compiled if it is not yet)."""
        return self._build(self._group_of[quantity])[0]

    def is_built(self, quantity: str) -> bool:
        """Whether ``quantity``'s group is compiled and loaded (no compiling to find out)."""
        return self._group_of.get(quantity) in self._built

    @property
    def has_loops(self) -> bool:
        """Whether vectorised loops are there to call: a one-group robot's were built (or not)
        with it; a bigger robot's are built with each group (``loop_address`` says)."""
        return self.compiled and (self.simd is not None if len(self.groups) == 1 else True)

    def _build(self, group: int) -> tuple:
        """Compile (or find in the cache) and load one group's libraries: the exact functions
        and, beside them in parallel, the vectorised loops."""
        if group in self._built:
            return self._built[group]
        with self._locks[group]:
            if group in self._built:
                return self._built[group]
            robot = self.manifest["robot"]
            if not is_built(self.folder, self.manifest, group):
                announce(self._compiling(group))
            with ThreadPoolExecutor(1) as pool:
                simd_job = pool.submit(_try_build_simd, self.folder, self.manifest, group)
                try:
                    path = build(self.folder, self.manifest, group=group)
                finally:
                    simd_path, simd_error = simd_job.result()
            try:
                lib = self._load(path)
            except CorruptLibrary as exc:  # truncated or overwritten cache file: build anew
                warnings.warn(f"compiled library {path} could not be loaded ({exc.reason}): "
                              "rebuilding it", RuntimeWarning, stacklevel=3)
                path = build(self.folder, self.manifest, force=True, group=group)
                lib = self._load(_fresh_name(path), private_copy=True)
            simd = None  # the vectorised sample loops, where this machine can build them
            if simd_error is not None:
                warnings.warn(f"{robot}: vectorised loops not built, using the exact path: "
                              f"{simd_error}", RuntimeWarning, stacklevel=3)
            if simd_path is not None:
                try:
                    simd = self._load(simd_path, f"{robot}_simd_input_hash")
                except CorruptLibrary as exc:
                    warnings.warn(f"compiled library {simd_path} could not be loaded "
                                  f"({exc.reason}): rebuilding it", RuntimeWarning, stacklevel=3)
                    simd_path = build_simd(self.folder, self.manifest, force=True, group=group)
                    simd = self._load(_fresh_name(simd_path), f"{robot}_simd_input_hash",
                                      private_copy=True)
            for q in self.groups[group]["functions"]:
                self._batch[q] = BatchFunction(lib, self._specs[q])
            self._built[group] = (path, lib, simd)
            if group == 0:
                self.path, self.lib, self.simd = path, lib, simd
            return self._built[group]

    def _compiling(self, group: int) -> str:
        """What a group's first compile says: a big robot's takes seconds no caller expects."""
        names = self.groups[group]["functions"]
        ops = sum(self.manifest["functions"][q].get("operations", 0) for q in names)
        what = (f"{names[0]}" if len(names) == 1 else f"{len(names)} functions")
        return (f"{self.manifest['robot']}: compiling {what} ({ops:,} operations), once: "
                "kept in the cache")

    def build_all(self) -> None:
        """Compile every group now (``planar-sym build``, ``make build``): the groups side by
        side, the biggest first (``compile``'s semaphore holds the compilers to the cores)."""
        if not self.compiled:
            return
        functions = self.manifest["functions"]
        order = sorted(range(len(self.groups)), key=lambda k: -sum(
            functions[q].get("operations", 0) for q in self.groups[k]["functions"]))
        with ThreadPoolExecutor(max(1, min(len(order), os.cpu_count() or 1))) as pool:
            list(pool.map(self._build, order))  # re-raises the first failure

    @property
    def is_builtin(self) -> bool:
        """True for the package's own robots (their generated folders ship with it): a user's
        robot that shares a built-in name is not one, so it never gets a built-in's solver."""
        return self.folder.resolve().parent in builtin_generated_dirs()

    @property
    def description_file(self) -> Path | None:
        """The description the code was derived from, where it is at hand: a built-in robot's
        ``robots/<name>.toml``, or the ``description.toml`` copy in the generated folder."""
        if self.is_builtin:
            from .description import robots_dir

            return robots_dir() / f"{self.manifest['robot']}.toml"
        copy = self.folder / "description.toml"
        return copy if copy.is_file() else None

    @cached_property
    def length_unit(self) -> str:
        """The length unit its description is typed in ("m", "cm" or "mm"): the unit of the
        robot's pictures (drawing, animation, atlas maps); "m" without a description at hand."""
        from .length_unit import typed_length_unit

        return typed_length_unit(self.description_file)

    def casadi_function(self, quantity: str):
        """One of the robot's functions as a ``casadi.Function`` (saved at derive time with
        ``Function.save``), for ``casadi.Opti``, integrators or your own graphs: no SymPy and no
        compiler needed. Symbolic (``MX``/``SX``) or numeric inputs, one sample as columns.

        Parameters
        ----------
        quantity : str
            A key of ``manifest["functions"]``: ``"mass_matrix"`` (q, p) -> M (n, n),
            ``"bias"`` (q, qd, p) -> h (n,), ``"constraint"`` (q, p) -> Phi (m,) in m,
            ``"inverse_dynamics"``, ``"task"``, ... Inputs are q (n,) in rad or m, qd in rad/s
            or m/s, qdd in rad/s^2 or m/s^2, and p (n_p,) the parameter vector (SI,
            ``Robot.p``).

        Returns
        -------
        casadi.Function
        """
        import casadi as ca

        functions = self.manifest["functions"]
        if quantity not in functions:
            raise InputError(f"{self.manifest['robot']} has no function {quantity!r}; it has: "
                             f"{', '.join(functions)}")
        saved = functions[quantity].get("casadi")
        if saved is None:
            raise InputError(f"{self.folder} was derived before functions were saved "
                             "for CasADi: derive it again (`make derive`, or planar-sym derive)")
        return ca.Function.load(str(self.folder / saved))

    def address(self, quantity: str) -> int:
        """Address of ``<robot>_<quantity>_batch`` in the exact library (for C callers); with
        CasADi's evaluator, a callback of the same signature."""
        if not self.compiled:
            return self.functions[quantity].address
        _, lib, _ = self._build(self._group_of[quantity])
        symbol = self.manifest["functions"][quantity]["symbol"] + "_batch"
        return ctypes.cast(getattr(lib, symbol), ctypes.c_void_p).value

    def loop_address(self, quantity: str) -> int | None:
        """Address of ``<robot>_<quantity>_loop`` (vectorised), or None without the library."""
        spec = self.manifest["functions"][quantity]
        if not self.compiled or "loop" not in spec:
            return None
        _, _, simd = self._build(self._group_of[quantity])
        if simd is None:
            return None
        return ctypes.cast(getattr(simd, spec["loop"]), ctypes.c_void_p).value

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
