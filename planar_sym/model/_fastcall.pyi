"""Types of the ``_fastcall`` extension (planar_sym/model/_fastcall.c)."""

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

#: sha256 prefix of the source this build came from (builds made at install only)
SOURCE_HASH: str

class Caller:
    """A generated sample loop called with C-level argument handling (one robot method).

    Called with the robot method's inputs, each (N, size) or (size,) for one sample, by
    position or by name; returns one array, or a tuple of them, per sample (N, ...).
    ``inspect.signature`` gives the input names.
    """

    def __call__(self, *arrays: npt.ArrayLike, **named: npt.ArrayLike) -> np.ndarray | tuple[np.ndarray, ...]: ...
    def designs(self, P: npt.ArrayLike, *arrays: npt.ArrayLike, reduce: bool = False,
                weights: npt.ArrayLike | None = None) -> np.ndarray | tuple[np.ndarray, ...]:
        """The loop once per parameter vector ``P[d]`` (D, n_p) over shared (N, size) or
        per-design (D, N, size) inputs; ``reduce``: min, max and mean square per design (the
        sum of ``weights[s] v[s]**2`` with ``weights`` (N,), else the plain mean)."""

def make(address: int, in_sizes: tuple[int, ...], p_slot: int,
         out_specs: tuple[tuple[int, int, int], ...], p: npt.ArrayLike, error: type[Exception],
         names: tuple[str, ...], doc: str | None) -> Caller:
    """A Caller for the sample loop at ``address`` (see ``Robot._bind_fast_paths``)."""

def closed_solve(b: np.ndarray, jac: np.ndarray, act: Sequence[int], tau_out: np.ndarray,
                 lam_out: np.ndarray, cond_out: np.ndarray) -> None:
    """Torques (N, n_act) and multipliers (N, m) of a closed chain from the passive rows, with
    the 1-norm condition number of Phi_p (N,) (infinite where exactly singular)."""
