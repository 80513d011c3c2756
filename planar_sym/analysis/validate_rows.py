"""The validation table (``planar-sym validate``): its rows, tolerances and the error measures
every check shares (see ``analysis.validate`` for the checks)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.robot import Robot

TOL_SYMBOLIC = 1e-11  # same expressions, different evaluation order: rounding only
TOL_ROUTE = 1e-7  # finite differences of the energy: ~1e-10 measured, kept well above
TOL_ENERGY = 1e-8  # relative energy drift over the free motion (integrator rtol 1e-11)
TOL_POWER = 1e-6  # finite differences in time of E along a smooth motion
TOL_PHI_M = 1e-9  # loop residual, m (Newton stops at 1e-13 m)
TOL_RATES = 1e-6  # passive qd, qdd against differences of the Newton-solved q(t)


@dataclass(frozen=True)
class Row:
    """One line of the validation table (``planar-sym validate``, ``planar_sym.validate``).

    Attributes
    ----------
    check : str
        What was checked, e.g. "(c) energy drift, free motion 1 s".
    worst : float or None
        The worst figure found (a relative error, or the loop residual in m); None when the
        check was skipped, inf when it raised.
    tolerance : float or None
        What ``worst`` must not exceed to pass (same unit).
    status : str
        ``"pass"``, ``"FAIL"`` or ``"skipped"``.
    detail : str
        Where the worst figure was, or why the check was skipped or failed.
    """

    check: str
    worst: float | None  # the worst figure; None when skipped
    tolerance: float | None
    status: str  # "pass", "FAIL" or "skipped"
    detail: str = ""


def row(check: str, worst: float, tol: float, detail: str = "") -> Row:
    """A Row that passes when ``worst`` is finite and at most ``tol``, else fails."""
    ok = math.isfinite(worst) and worst <= tol
    return Row(check, worst, tol, "pass" if ok else "FAIL", detail)


def rel_err(a, b, peak: bool = False, scale: float = 0.0) -> float:
    """Worst per-sample ``||a_k - b_k|| / ||b_k||`` (random states), or relative to the largest
    ``||b_k||`` (``peak``: along a motion, where every rate passes through zero together).

    ``scale`` (same unit as ``b``): the quantity's physical size, the floor of every sample's
    denominator, for a quantity that may vanish everywhere; 0 keeps the reference's own size.
    """
    a = np.asarray(a, dtype=float).reshape(len(a), -1)
    b = np.asarray(b, dtype=float).reshape(len(b), -1)
    diff, size = np.max(np.abs(a - b), axis=1), np.max(np.abs(b), axis=1)
    if size.max() == 0.0 and scale == 0.0:  # an all-zero reference, no scale: absolute
        return float(diff.max())
    floor = 1.0 if peak else 1e-12  # a (near) zero sample is measured against the largest
    return float(np.max(diff / np.maximum(size, max(floor * size.max(), scale))))


def random_states(robot: Robot, samples: int, seed: int):
    """Random states drawn with ``seed``, each of shape (samples, n): q uniform in [-pi, pi]
    (rad); qd (rad/s), qdd (rad/s^2) and tau (N*m) uniform in [-3, 3].

    A joint with Coulomb friction gets |qd| >= 20 v_s: its tanh(qd / v_s) turns over within a
    few v_s of rest (0.01 rad/s by default), too sharply for differences with a 1e-3 step;
    beyond 20 v_s its slope is below 1e-16 of c / v_s.
    """
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (samples, robot.n))
    qd, qdd, tau = (rng.uniform(-3, 3, (samples, robot.n)) for _ in range(3))
    drives = robot.drive_train
    away = np.where(drives.coulomb != 0.0, 20.0 * drives.smoothing, 0.0)
    qd = np.where(np.abs(qd) < away, np.copysign(away, qd) + qd, qd)
    return q, qd, qdd, tau


def worst_key(errs: dict[str, float]) -> str:
    """The key of the largest error, NaN counting as the largest."""
    return max(errs, key=lambda k: errs[k] if errs[k] == errs[k] else math.inf)
