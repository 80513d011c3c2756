"""Point-to-point profiles beyond the seed's cubic: quintic (rest to rest, zero accelerations at
both ends) and trapezoidal speed (limits on speed and acceleration), with exact derivatives.

Both move every channel along one path parameter s(t) from 0 to 1, ``x = x0 + s dx``, so the
channels start and end together and the path is the straight line from ``x0`` to ``x0 + dx``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from . import _checks
from .profiles import Trajectory, _floats


def _along(x0: np.ndarray, dx: np.ndarray, t: np.ndarray, s, sd, sdd) -> Trajectory:
    return Trajectory(t, x0 + s[:, None] * dx, sd[:, None] * dx, sdd[:, None] * dx)


def quintic(x0, dx, duration_s: float, t_s) -> Trajectory:
    """Rest-to-rest quintic from ``x0`` to ``x0 + dx``: zero velocity and acceleration at both ends.

    .. code:: text

        u = t / T,  s(u) = 10 u^3 - 15 u^4 + 6 u^5
        x(t)   = x0 + dx s
        xd(t)  = dx 30 u^2 (1 - u)^2 / T
        xdd(t) = dx 60 u (1 - u) (1 - 2 u) / T^2

    Peak rate 1.875 dx / T at u = 1/2, peak acceleration 10 / sqrt(3) dx / T^2 = 5.7735 dx / T^2.

    Parameters
    ----------
    x0, dx : array_like, shape (channels,)
        Start and displacement, SI (m or rad).
    duration_s : float
        T, positive and finite (s).
    t_s : array_like, shape (N,)
        Evaluation times in [0, T] (s); a time outside is refused, naming it and its sample.

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` of shape (N, channels): m or rad, per s, per s^2.
    """
    x0, dx = _checks.start_and_step(x0, dx)
    T = _checks.duration(duration_s)
    t = _checks.times(t_s, 0.0, T)
    u = t / T
    s = u**3 * (10 - 15 * u + 6 * u**2)
    sd = 30 * u**2 * (1 - u) ** 2 / T
    sdd = 60 * u * (1 - u) * (1 - 2 * u) / T**2
    return _along(x0, dx, t, s, sd, sdd)


def _limit(name: str, lim, dx: np.ndarray) -> np.ndarray:
    lim = _floats(name, lim)
    if lim.size not in (1, dx.size):
        raise InputError(f"trapezoid: {name} needs 1 or {dx.size} values, one per channel "
                         f"(got {lim.size})")
    if not np.all(np.isfinite(lim)) or np.any(lim <= 0):
        raise InputError(f"trapezoid: {name} must be positive and finite (got {lim.tolist()})")
    return np.broadcast_to(lim, dx.shape)


def _path_limits(dx: np.ndarray, v_max, a_max) -> tuple[float, float, int, int]:
    """Speed and acceleration limits of s (1/s, 1/s^2), and the channels that set them."""
    if not np.all(np.isfinite(dx)):
        raise InputError(f"trajectory displacement must be finite (got {dx.tolist()})")
    v_max, a_max = _limit("v_max", v_max, dx), _limit("a_max", a_max, dx)
    moving = np.flatnonzero(np.abs(dx) > 0)
    if moving.size == 0:
        raise InputError("trapezoid: the displacement dx is zero in every channel: nothing "
                         "to move (a trapezoid's duration follows from its length)")
    v_path = v_max[moving] / np.abs(dx[moving])
    a_path = a_max[moving] / np.abs(dx[moving])
    kv, ka = int(np.argmin(v_path)), int(np.argmin(a_path))
    return float(v_path[kv]), float(a_path[ka]), int(moving[kv]), int(moving[ka])


def _minimum(v: float, a: float) -> tuple[float, float]:
    """Shortest duration (s) of s: 0 -> 1 and its peak speed (1/s)."""
    if v * v < a:  # the cruise speed is reached
        return 1.0 / v + v / a, v
    return 2.0 / np.sqrt(a), float(np.sqrt(a))  # triangular


def trapezoid_duration(dx, v_max, a_max) -> float:
    """Shortest duration (s) of the straight move ``dx`` under speed and acceleration limits.

    .. code:: text

        v = min_i v_max_i / |dx_i|,  a = min_i a_max_i / |dx_i|   (path-parameter limits)
        T = 1 / v + v / a      if v^2 < a   (trapezoid; per channel T = |dx|/v_max + v_max/a_max)
        T = 2 / sqrt(a)        otherwise    (triangle; per channel T = 2 sqrt(|dx| / a_max))

    Parameters
    ----------
    dx : array_like, shape (channels,)
        Displacement, SI (m or rad); at least one channel nonzero.
    v_max, a_max : float or array_like, shape (channels,)
        Speed (per s) and acceleration (per s^2) limits, one for all channels or one each.

    Returns
    -------
    float
        The duration (s) of ``trapezoid(..., duration_s=None)``.
    """
    v, a, _, _ = _path_limits(_floats("displacement", dx), v_max, a_max)
    return float(_minimum(v, a)[0])


def trapezoid(x0, dx, t_s, *, v_max, a_max, duration_s: float | None = None) -> Trajectory:
    """Straight move from ``x0`` by ``dx`` with a trapezoidal speed profile.

    .. code:: text

        x(t) = x0 + dx s(t),  xd = dx sd(t),  xdd = dx sdd(t)
        v, a: path limits, the tightest channel (see trapezoid_duration)
        vc = cruise speed of s, ta = vc / a (time to reach it), T the duration:
          0 <= t < ta:        s = a t^2 / 2,                sd = a t,   sdd =  a
          ta <= t <= T - ta:  s = vc ta / 2 + vc (t - ta),  sd = vc,    sdd =  0
          T - ta < t <= T:    s = 1 - a (T - t)^2 / 2,      sd = a (T - t), sdd = -a
        duration_s None:  T minimum, vc = v (or sqrt(a), triangular, when v^2 >= a)
        duration_s = T:   vc (T - vc / a) = 1, the slower root: vc = 2 / (T + sqrt(T^2 - 4 / a))

    Every channel follows the same s(t), so all start and end together. ``a_max`` is always
    used in full (the shortest ramps); with ``duration_s`` the cruise speed drops so the move
    takes exactly that long. A duration shorter than the minimum is refused, naming both and
    the channel whose limit binds.

    Parameters
    ----------
    x0, dx : array_like, shape (channels,)
        Start and displacement, SI (m or rad).
    t_s : array_like, shape (N,)
        Evaluation times in [0, T] (s); ``trapezoid_duration`` gives T when ``duration_s`` is
        None.
    v_max, a_max : float or array_like, shape (channels,)
        Each channel's speed (per s) and acceleration (per s^2) limit, or one for all.
    duration_s : float, optional
        T (s), at least the minimum duration; None: the minimum.

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` of shape (N, channels); piecewise: xdd jumps at ta and T - ta.
    """
    x0, dx = _checks.start_and_step(x0, dx)
    v, a, kv, ka = _path_limits(dx, v_max, a_max)
    shortest, vc = _minimum(v, a)
    if duration_s is None:
        T = shortest
    else:
        T = _checks.duration(duration_s, "trapezoid duration")
        if T < shortest * (1 - 1e-12):
            raise InputError(f"trapezoid: a duration of {T:.6g} s is shorter than the "
                             f"{shortest:.6g} s the speed and acceleration limits allow "
                             f"({_binding(dx, v_max, a_max, v, a, kv, ka)})")
        vc = 2.0 / (T + np.sqrt(max(T * T - 4.0 / a, 0.0)))
    ta = vc / a
    t = _checks.times(t_s, 0.0, T)
    rise, fall = t < ta, t > T - ta
    cruise = ~(rise | fall)
    s, sd, sdd = np.empty_like(t), np.empty_like(t), np.empty_like(t)
    s[rise], sd[rise], sdd[rise] = 0.5 * a * t[rise] ** 2, a * t[rise], a
    s[cruise], sd[cruise], sdd[cruise] = 0.5 * vc * ta + vc * (t[cruise] - ta), vc, 0.0
    r = T - t[fall]
    s[fall], sd[fall], sdd[fall] = 1.0 - 0.5 * a * r**2, a * r, -a
    return _along(x0, dx, t, s, sd, sdd)


def _binding(dx, v_max, a_max, v: float, a: float, kv: int, ka: int) -> str:
    """Which channel's limits set the minimum duration, with their figures."""
    n = dx.size
    acc = (f"channel {ka + 1} of {n}: |dx| = {abs(dx[ka]):.6g}, "
           f"a_max = {np.broadcast_to(_floats('a_max', a_max), dx.shape)[ka]:.6g} per s^2")
    if v * v >= a:
        return f"triangular, the speed limit is not reached; acceleration set by {acc}"
    vmax = np.broadcast_to(_floats("v_max", v_max), dx.shape)[kv]
    return (f"speed set by channel {kv + 1} of {n}: |dx| = {abs(dx[kv]):.6g}, v_max = "
            f"{vmax:.6g} per s; acceleration by {acc}")
