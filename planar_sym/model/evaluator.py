"""CasADi's own evaluator standing in for the compiled C, where no C compiler is at hand.

Every generated folder holds each function as ``Function.save`` wrote it (``<quantity>.casadi``).
Loaded with ``casadi.Function.load`` (no SymPy, no compiler), it gives the same numbers as the
compiled C (the same expression graph; tested to 1e-12), slower: about 20x per sample in
batches, and about 500x per step of a simulation or a Newton loop, which calls back into Python
once per step (``make bench``, section 3).

Batches evaluate through CasADi's column mapping (inputs with N columns). The C helpers that
take function pointers (the DOPRI5 integrator, the Newton loop) get a ctypes callback with the
generated ``<name>_batch`` signature, so every compiled loop keeps working, a Python call per
sample.
"""

from __future__ import annotations

import ctypes
import warnings
from pathlib import Path

import numpy as np

from ..errors import LibraryError
from .batch import shaped

#: measured by ``make bench`` (section 3): the evaluator against the compiled C, per sample in
#: batches (14-21x) and per right-hand side of a simulation (380-850x)
SLOWER_BATCH, SLOWER_STEP = 20, 500


def no_compiler_warning(robot: str, reason: str) -> None:
    """One line: what runs instead of the compiled C, what it costs, how to get it back."""
    warnings.warn(
        f"{robot}: {reason}; running on CasADi's own evaluator instead: the same numbers, about "
        f"{SLOWER_BATCH}x slower in batches and {SLOWER_STEP}x in simulations and inverse "
        "kinematics (install gcc, or set CC to a C compiler, for compiled speed)",
        RuntimeWarning, stacklevel=4)


class CasadiFunction:
    """One saved CasADi function with the compiled ``BatchFunction``'s interface.

    ``__call__(n, args)`` takes per-sample arrays (n, size) (``p``: (size,)) and returns
    (n, rows*cols) blocks shaped like the compiled path's; ``_fn`` is a C-callable pointer of
    the ``<name>_batch`` signature, for the C loops and ``SingleCall``.
    """

    def __init__(self, path: Path, spec):
        import casadi as ca

        self.spec = spec
        try:
            self.function = ca.Function.load(str(path))
        except RuntimeError as exc:
            raise LibraryError(f"{path} cannot be loaded by CasADi ({str(exc).splitlines()[-1]})"
                               ": run `make derive`") from None
        self._ins = [(name, size) for name, size in spec.inputs]
        self._outs = [rows * cols for _, rows, cols, _ in spec.outputs]
        proto = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_longlong,
                                 *[ctypes.c_void_p] * (len(self._ins) + len(self._outs)))
        self._fn = proto(self._c_call)  # kept here: ctypes frees a callback nobody holds
        self.error: BaseException | None = None

    @property
    def address(self) -> int:
        return ctypes.cast(self._fn, ctypes.c_void_p).value

    def _evaluate(self, n: int, inputs: list[np.ndarray]) -> list[np.ndarray]:
        """Inputs (n, size) or (size,) for p -> outputs (n, rows*cols), column-major blocks."""
        cols = [a if a.ndim == 1 else a.T for a in inputs]  # CasADi maps over N columns
        res = self.function.call(cols)
        outs = []
        for r, (_, rows, c, _) in zip(res, self.spec.outputs):
            a = np.asarray(r, dtype=float).reshape(rows, n, c)  # (rows, c * n): blocks side by side
            outs.append(a.transpose(1, 2, 0).reshape(n, rows * c))
        return outs

    def _c_call(self, n, *ptrs) -> int:
        """The ``<name>_batch`` signature: an exception becomes a failure status, never a
        silently unwritten output (ctypes would print it and return 0)."""
        try:
            ins = []
            for (name, size), ptr in zip(self._ins, ptrs):
                count = size if name == "p" else n * size
                a = np.ctypeslib.as_array((ctypes.c_double * count).from_address(ptr))
                ins.append(a if name == "p" else a.reshape(n, size))
            for out, size, ptr in zip(self._evaluate(n, ins), self._outs, ptrs[len(self._ins):]):
                np.ctypeslib.as_array((ctypes.c_double * (n * size)).from_address(ptr))[:] = \
                    out.ravel()
            return 0
        except BaseException as exc:  # noqa: BLE001 - reported by the caller, see above
            self.error = exc
            return 1

    def __call__(self, n: int, args: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Same contract as ``library.BatchFunction.__call__``."""
        return shaped(self.spec, n, self._evaluate(n, [args[name] for name, _ in self._ins]))
