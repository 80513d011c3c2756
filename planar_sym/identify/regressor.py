"""The regressor Y(q, qd, qdd): the torques as a linear map of the standard parameters,
``tau = Y pi`` (``standard.py``), one compiled call for N samples.

For a tree the rows are every coordinate's ``M qdd + h`` (a passive joint's row is an
equation too: its torque is zero). For a closed chain they are the actuated torques, pushed
through ``[S^T Phi_q^T]`` as ``closed_chain_inverse_dynamics`` does, and the cut-joint forces'
regressor comes with them; a state off the loops or at a singular pose is refused as there.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..model.arrays import as_samples
from ..model.fast_paths import loop_caller
from ..model.robot import Robot
from .standard import columns


@dataclass(frozen=True)
class Regressors:
    """``y`` (N, rows, columns): the torque rows (every coordinate of a tree, the actuated
    ones of a closed chain, their coordinates in ``rows``; N*m, N at a slider, per unit of
    each column); ``y_lambda`` (N, 2 * loops, columns) the cut-joint forces' (N) of a closed
    chain, else None."""

    y: np.ndarray
    rows: tuple[int, ...]
    y_lambda: np.ndarray | None


def regressor(robot: Robot, q, qd, qdd, t=None) -> Regressors:
    """``Y`` at N states (q rad, qd rad/s, qdd rad/s^2; m, m/s, m/s^2 at a slider), each
    (N, n) or (n,); ``t`` (N,) in s only names a refused sample.

    ``Y @ standard_parameters(robot).values`` equals the inverse dynamics (to rounding).
    """
    columns(robot)  # LibraryError for code generated before the regressors
    if not robot.is_closed_chain and t is None and _batches(robot, q, qd, qdd):
        # the compiled caller checks shapes and finiteness itself, naming the sample as
        # as_samples does: the Python checks would cost more than the loop (1000 2-DOF samples)
        return Regressors(_LOOPS[robot]["regressor"](q, qd, qdd), tuple(range(robot.n)), None)
    q, qd, qdd = (as_samples(k, a, robot.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                   ("qdd", qdd)))
    if not robot.is_closed_chain:
        return Regressors(_call(robot, "regressor", q, qd, qdd)[0], tuple(range(robot.n)), None)
    robot.closed_chain_inverse_dynamics(q, qd, qdd, t)  # its refusals: off the loops, singular
    y, y_lambda = _call(robot, "closed_regressor", q, qd, qdd)
    return Regressors(y, tuple(robot.actuated), y_lambda)


#: each robot's C-level callers of the regressor loops, made once (``model.fast_paths``)
_LOOPS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _batches(robot: Robot, *arrays) -> bool:
    """True when every input is already a (N, n) float64 C-contiguous batch and the tree's
    regressor loop is compiled: then the loop's own caller takes them as they are."""
    callers = _LOOPS.setdefault(robot, {})
    if "regressor" not in callers:
        callers["regressor"] = loop_caller(robot, "regressor")
    return callers["regressor"] is not None and all(
        type(a) is np.ndarray and a.ndim == 2 and a.dtype == np.float64
        and a.flags.c_contiguous for a in arrays)


def _call(robot: Robot, quantity: str, q, qd, qdd) -> tuple[np.ndarray, ...]:
    """The generated ``quantity``'s outputs over the samples: its vectorised loop where the
    library has one (about 1.5 to 10 times faster), else the exact per-sample function."""
    callers = _LOOPS.setdefault(robot, {})
    if quantity not in callers:
        callers[quantity] = loop_caller(robot, quantity)
    fast = callers[quantity]
    if fast is not None:
        out = fast(q, qd, qdd)
        return out if isinstance(out, tuple) else (out,)
    spec = robot.library.manifest["functions"][quantity]
    r = robot.library.functions[quantity](len(q), {"q": q, "qd": qd, "qdd": qdd, "p": robot.p})
    return tuple(r[name] for name, *_ in spec["outputs"])
