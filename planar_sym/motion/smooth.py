"""Point-to-point profiles beyond the seed's cubic: quintic (rest to rest, zero accelerations at
both ends) and trapezoidal speed (limits on speed and acceleration), with exact derivatives.

.. code:: text

    quintic:   x(t) = x0 + dx s(tau),  s = 10 tau^3 - 15 tau^4 + 6 tau^5,  tau = t / T
    trapezoid: x(t) = x0 + dx s(t), s(t) a path parameter from 0 to 1 with
               |sd| <= v, |sdd| <= a (v, a the tightest of v_max_i / |dx_i|, a_max_i / |dx_i|):
               accelerate for ta = v / a, cruise, decelerate; T = 1 / v + v / a
               (triangular, peak speed sqrt(a), when 1 / v + v / a would need ta > T / 2)
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .profiles import Trajectory, _floats


def _times(t_s, duration_s: float) -> np.ndarray:
    if np.ndim(t_s) > 1:
        raise InputError(f"trajectory times must be a 1-D array (got shape {np.shape(t_s)})")
    t = _floats("times", t_s)
    bad = ~np.isfinite(t) | (t < 0) | (t > duration_s)
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError(f"time t = {t[k]} s (sample {k}) is outside the trajectory "
                         f"[0, {duration_s:.6g}] s")
    return t


def _duration(duration_s) -> float:
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not np.isfinite(duration_s) or duration_s <= 0:
        raise InputError(f"trajectory duration must be a positive number of seconds "
                         f"(got {duration_s!r})")
    return float(duration_s)


def _start_and_step(x0, dx) -> tuple[np.ndarray, np.ndarray]:
    x0, dx = _floats("start", x0), _floats("displacement", dx)
    if x0.shape != dx.shape:
        raise InputError(f"x0 and dx must have the same length (got {x0.size} and {dx.size})")
    if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(dx))):
        raise InputError("trajectory start and displacement must be finite")
    return x0, dx


def _along(x0: np.ndarray, dx: np.ndarray, t: np.ndarray, s, sd, sdd) -> Trajectory:
    return Trajectory(t, x0 + s[:, None] * dx, sd[:, None] * dx, sdd[:, None] * dx)


def quintic(x0, dx, duration_s: float, t_s) -> Trajectory:
    """From ``x0`` to ``x0 + dx`` in ``duration_s`` s, at rest with zero acceleration at both
    ends; positions, rates and accelerations at ``t_s`` (s), each (N, channels)."""
    x0, dx = _start_and_step(x0, dx)
    T = _duration(duration_s)
    t = _times(t_s, T)
    u = t / T
    s = u**3 * (10 - 15 * u + 6 * u**2)
    sd = 30 * u**2 * (1 - u) ** 2 / T
    sdd = 60 * u * (1 - u) * (1 - 2 * u) / T**2
    return _along(x0, dx, t, s, sd, sdd)


def _path_limits(dx: np.ndarray, v_max, a_max) -> tuple[float, float]:
    """Speed and acceleration limits of the path parameter s (1/s, 1/s^2): the tightest channel."""
    v_max, a_max = _floats("v_max", v_max), _floats("a_max", a_max)
    for name, lim in (("v_max", v_max), ("a_max", a_max)):
        if lim.size not in (1, dx.size):
            raise InputError(f"{name} needs 1 or {dx.size} values (got {lim.size})")
        if not np.all(np.isfinite(lim)) or np.any(lim <= 0):
            raise InputError(f"{name} must be positive and finite (got {lim.tolist()})")
    moving = np.abs(dx) > 0
    if not moving.any():
        raise InputError("a trapezoid needs a displacement: dx is zero in every channel")
    v = float(np.min(np.broadcast_to(v_max, dx.shape)[moving] / np.abs(dx[moving])))
    a = float(np.min(np.broadcast_to(a_max, dx.shape)[moving] / np.abs(dx[moving])))
    return v, a


def trapezoid_duration(dx, v_max, a_max) -> float:
    """Shortest time (s) of the straight move ``dx`` under the speed and acceleration limits."""
    v, a = _path_limits(_floats("displacement", dx), v_max, a_max)
    return 1.0 / v + v / a if v * v / a < 1.0 else 2.0 / np.sqrt(a)


def trapezoid(x0, dx, t_s, *, v_max, a_max, duration_s: float | None = None) -> Trajectory:
    """Straight move from ``x0`` by ``dx`` with a trapezoidal speed profile.

    Every channel moves along the same path parameter s(t) in [0, 1], so they start and end
    together; ``v_max``, ``a_max`` (per channel, units per s and per s^2, or one for all) limit
    each channel's speed and acceleration, the tightest one deciding. Without ``duration_s``
    the move takes the shortest time (``trapezoid_duration``); with it, the cruise speed is
    the one that takes exactly that long at the largest allowed acceleration, and a duration
    shorter than the minimum is refused.
    """
    x0, dx = _start_and_step(x0, dx)
    v, a = _path_limits(dx, v_max, a_max)
    shortest = trapezoid_duration(dx, v_max, a_max)
    T = shortest if duration_s is None else _duration(duration_s)
    if T < shortest * (1 - 1e-12):
        raise InputError(f"a trapezoid of {T:.6g} s is shorter than the {shortest:.6g} s the "
                         "speed and acceleration limits allow")
    # cruise speed for duration T at acceleration a: vc (T - vc / a) = 1
    disc = max(a * a * T * T - 4 * a, 0.0)
    vc = min((a * T - np.sqrt(disc)) / 2, v)
    ta = vc / a
    t = _times(t_s, T)
    rise, fall = t < ta, t > T - ta
    cruise = ~(rise | fall)
    s, sd, sdd = np.empty_like(t), np.empty_like(t), np.empty_like(t)
    s[rise], sd[rise], sdd[rise] = 0.5 * a * t[rise] ** 2, a * t[rise], a
    tc = t[cruise]
    s[cruise], sd[cruise], sdd[cruise] = 0.5 * vc * ta + vc * (tc - ta), vc, 0.0
    r = T - t[fall]
    s[fall], sd[fall], sdd[fall] = 1.0 - 0.5 * a * r**2, a * r, -a
    return _along(x0, dx, t, s, sd, sdd)
