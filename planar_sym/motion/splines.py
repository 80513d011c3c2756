"""Motions through given points: via points with times (a C2 spline at rest at both ends), and
tables of times and positions (a C2 spline through every row), with exact derivatives.

.. code:: text

    via:   cubic spline through (t_k, x_k), x'(t_0) = x'(t_K) = 0 ("clamped"): C2, at rest at
           both ends, passing exactly through every via point
    table: cubic spline through every row, "not-a-knot" ends (the table says nothing about
           the rates at its ends); rates and accelerations are the spline's own derivatives,
           so they converge as h^3 and h^2 with the row spacing h for a smooth motion

SciPy's ``CubicSpline`` does the work (imported on first use: ``import planar_sym`` stays light).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .profiles import Trajectory, _floats


def _knots(times_s, points, what: str) -> tuple[np.ndarray, np.ndarray]:
    times = _floats(f"{what} times", times_s)
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what} points must be numbers ({exc})") from None
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or len(pts) != len(times):
        raise InputError(f"{what}: {len(times)} times need {len(times)} points (rows), got "
                         f"shape {np.shape(points)}")
    if len(times) < 2:
        raise InputError(f"{what} needs at least 2 points (got {len(times)})")
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(pts))):
        raise InputError(f"{what} times and points must be finite")
    step = np.diff(times)
    if np.any(step <= 0):
        k = int(np.argmax(step <= 0)) + 1
        raise InputError(f"{what} times must increase: t[{k}] = {times[k]:g} s follows "
                         f"t[{k - 1}] = {times[k - 1]:g} s")
    return times, pts


def _evaluate(spline, times: np.ndarray, t_s, what: str) -> Trajectory:
    if np.ndim(t_s) > 1:
        raise InputError(f"trajectory times must be a 1-D array (got shape {np.shape(t_s)})")
    t = _floats("times", t_s)
    bad = ~np.isfinite(t) | (t < times[0]) | (t > times[-1])
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError(f"time t = {t[k]} s (sample {k}) is outside the {what} "
                         f"[{times[0]:g}, {times[-1]:g}] s")
    return Trajectory(t, spline(t), spline(t, 1), spline(t, 2))


def via(times_s, points, t_s) -> Trajectory:
    """Through ``points`` (K, channels) at ``times_s`` (K,), at rest at the first and last."""
    from scipy.interpolate import CubicSpline

    times, pts = _knots(times_s, points, "via")
    return _evaluate(CubicSpline(times, pts, bc_type="clamped", axis=0), times, t_s,
                     "via points' span")


def table(times_s, positions, t_s) -> Trajectory:
    """Through every row of a table: ``positions`` (K, channels) at ``times_s`` (K,)."""
    from scipy.interpolate import CubicSpline

    times, pts = _knots(times_s, positions, "table")
    bc = "not-a-knot" if len(times) > 3 else "natural"  # not-a-knot needs 4 rows
    return _evaluate(CubicSpline(times, pts, bc_type=bc, axis=0), times, t_s, "table's span")
