"""Motions through given points: via points with times (a C2 spline at rest at both ends), and
tables of times and positions (a C2 spline through every row), with exact derivatives: the
rates and accelerations are the spline's own, never finite differences.

SciPy's ``CubicSpline`` does the work, imported on first use (``import planar_sym`` stays
light).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from . import _checks
from .profiles import Trajectory, _floats


def _knots(times_s, points, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Times (K,) and points (K, channels), checked: K >= 2, finite, strictly increasing."""
    if np.ndim(times_s) > 1:
        raise InputError(f"{what} times must be a 1-D array (got shape {np.shape(times_s)})")
    times = _floats(f"{what} times", times_s)
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what} points must be numbers, (K, channels) ({exc})") from None
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or len(pts) != len(times) or pts.shape[1] == 0:
        raise InputError(f"{what}: {len(times)} times need {len(times)} points (rows of "
                         f"(K, channels)), got shape {np.shape(points)}")
    if len(times) < 2:
        raise InputError(f"{what} needs at least 2 points (got {len(times)})")
    for k in range(len(times)):
        if not (np.isfinite(times[k]) and np.all(np.isfinite(pts[k]))):
            raise InputError(f"{what} point {k} must be finite (t = {times[k]} s, "
                             f"{pts[k].tolist()})")
    step = np.diff(times)
    if np.any(step <= 0):
        k = int(np.argmax(step <= 0)) + 1
        how = "repeats" if step[k - 1] == 0 else "comes before"
        raise InputError(f"{what} times must increase strictly: t[{k}] = {times[k]:g} s "
                         f"{how} t[{k - 1}] = {times[k - 1]:g} s")
    return times, pts


def _evaluate(spline, times: np.ndarray, t_s, what: str) -> Trajectory:
    t = _checks.times(t_s, float(times[0]), float(times[-1]), what)
    return Trajectory(t, spline(t), spline(t, 1), spline(t, 2))


def via(times_s, points, t_s) -> Trajectory:
    """A C2 curve through via points at given times, at rest at the first and the last.

    .. code:: text

        x(t) = cubic on each [t_k, t_k+1], x(t_k) = x_k exactly,
               x, xd, xdd continuous at every inner t_k (C2),
               xd(t_0) = xd(t_K-1) = 0 ("clamped"): scipy CubicSpline(bc_type="clamped")
        xd, xdd: the spline's derivatives (exact, piecewise quadratic and linear)

    The end accelerations are not zero: for zero end accelerations too, use ``quintic``
    between two points.

    Parameters
    ----------
    times_s : array_like, shape (K,)
        Via times (s), strictly increasing, K >= 2; the motion spans [times_s[0], times_s[-1]].
    points : array_like, shape (K, channels) or (K,)
        The via points, SI (m or rad); (K,) means one channel.
    t_s : array_like, shape (N,)
        Evaluation times (s) inside the span; a time outside is refused, naming it.

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` of shape (N, channels).
    """
    from scipy.interpolate import CubicSpline

    times, pts = _knots(times_s, points, "via")
    return _evaluate(CubicSpline(times, pts, bc_type="clamped", axis=0), times, t_s,
                     "via points' span")


def table(times_s, positions, t_s) -> Trajectory:
    """Positions from a table; rates and accelerations from the C2 spline through its rows.

    .. code:: text

        x(t) = cubic on each [t_k, t_k+1] through every row (x(t_k) = x_k exactly),
               C2 at inner rows, "not-a-knot" ends (the third derivative is continuous
               at the second and the second-last row: the table says nothing about the
               rates at its ends); 2 rows: a straight line, 3 rows: a parabola
        xd, xdd: the spline's derivatives (exact for the spline, never finite differences)
        error for a smooth motion with row spacing h: x ~ h^4, xd ~ h^3, xdd ~ h^2
        (measured: a quintic 0 -> 1 in 1 s, 101 rows: 1.0e-7, 6.3e-5, 2.5e-2)

    Parameters
    ----------
    times_s : array_like, shape (K,)
        Row times (s), strictly increasing, K >= 2 (e.g. from ``read_table``).
    positions : array_like, shape (K, channels) or (K,)
        Positions, SI (m or rad).
    t_s : array_like, shape (N,)
        Evaluation times (s) inside [times_s[0], times_s[-1]]; a time outside is refused.

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` of shape (N, channels).
    """
    from scipy.interpolate import CubicSpline

    times, pts = _knots(times_s, positions, "table")
    return _evaluate(CubicSpline(times, pts, bc_type="not-a-knot", axis=0), times, t_s,
                     "table's span")
