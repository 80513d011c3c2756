"""Point-to-point cubic trajectories, exactly the seed's ``coeff_3rd`` with analytic derivatives.

.. code:: text

    c0 = x0,  c1 = v0,  c2 = (3 dx - (2 v0 + v1) T) / T^2,  c3 = (-2 dx + (v0 + v1) T) / T^3
    x(t) = c0 + c1 t + c2 t^2 + c3 t^3,  xd = c1 + 2 c2 t + 3 c3 t^2,  xdd = 2 c2 + 6 c3 t

with zero end velocities (v0 = v1 = 0) as in every seed scenario. The seed differentiated x(t)
numerically with Simulink Derivative blocks; here xd and xdd are exact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError


@dataclass(frozen=True)
class Trajectory:
    """Samples of a trajectory: ``x``, ``xd``, ``xdd`` of shape (N, channels) at times ``t_s``.

    Units are the channels' own, SI: a task trajectory holds x, y in m (phi in rad), their
    rates in m/s (rad/s) and accelerations in m/s^2 (rad/s^2); ``t_s`` (N,) is in s.
    """

    t_s: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray


@dataclass(frozen=True)
class JointTrajectory:
    """Joint motion at times ``t_s`` (N,) in s: ``q`` (rad), ``qd`` (rad/s), ``qdd``
    (rad/s^2), each (N, n), every coordinate (passive ones too; m, m/s, m/s^2 at a slider).

    ``solver`` names the inverse kinematics that produced it ("seed closed form", "newton"),
    empty where none ran (joint-space motion)."""

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    solver: str = ""



def coeff_3rd(sp, sv, ep, ev, tsec: float) -> np.ndarray:
    """The seed's cubic coefficients, shape (channels, 4): c0 + c1 t + c2 t^2 + c3 t^3.

    ``sp``, ``ep`` are the start and end values, ``sv``, ``ev`` the start and end rates (one
    per channel, its own SI unit u and u/s), ``tsec`` the duration (s); the coefficients are in
    u, u/s, u/s^2, u/s^3.
    """
    if isinstance(tsec, bool) or not isinstance(tsec, (int, float, np.number)) \
            or not np.isfinite(tsec) or tsec <= 0:
        raise InputError(f"trajectory duration must be a positive number of seconds (got {tsec!r})")
    sp, sv, ep, ev = (_floats(name, v) for name, v in (("start", sp), ("start velocity", sv),
                                                        ("end", ep), ("end velocity", ev)))
    for name, v in (("start", sp), ("start velocity", sv), ("end", ep), ("end velocity", ev)):
        if not np.all(np.isfinite(v)):
            raise InputError(f"trajectory {name} must be finite (got {v.tolist()})")
    c = np.empty((sp.size, 4))
    c[:, 0] = sp
    c[:, 1] = sv
    c[:, 2] = (3.0 * (ep - sp) - (2.0 * sv + ev) * tsec) / (tsec * tsec)
    c[:, 3] = (-2.0 * (ep - sp) + (sv + ev) * tsec) / (tsec * tsec * tsec)
    return c


def _floats(name: str, v) -> np.ndarray:
    """``v`` as a flat float array; anything that is not numbers is an InputError."""
    try:
        return np.asarray(v, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InputError(f"trajectory {name} must be numbers (got {v!r:.60}: {exc})") from None


def cubic(x0, dx, duration_s: float, t_s) -> Trajectory:
    """Cubic from ``x0`` to ``x0 + dx`` over ``duration_s`` with zero end velocities, at ``t_s``.

    Parameters
    ----------
    x0, dx : array_like, shape (channels,)
        Start and displacement per channel, SI: a task motion's x, y in m (phi in rad), or
        joint coordinates in rad (m at a slider).
    duration_s : float
        Duration of the move (s), > 0.
    t_s : array_like, shape (N,)
        Sample times (s), each within ``[0, duration_s]``.

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` (N, channels) in the channels' units, /s and /s^2.
    """
    x0, dx = _floats("start", x0), _floats("displacement", dx)
    if x0.shape != dx.shape:
        raise InputError(f"x0 and dx must have the same length (got {x0.size} and {dx.size})")
    c = coeff_3rd(x0, np.zeros_like(x0), x0 + dx, np.zeros_like(x0), duration_s)
    if np.ndim(t_s) > 1:
        raise InputError(f"trajectory times must be a 1-D array (got shape {np.shape(t_s)})")
    t = _floats("times", t_s)
    if not np.all(np.isfinite(t)):
        raise InputError("trajectory times must be finite")
    outside = (t < 0) | (t > duration_s)
    if outside.any():
        k = int(np.argmax(outside))
        raise InputError(f"time t = {t[k]} s (sample {k}) is outside the trajectory "
                         f"[0, {duration_s}] s")
    tt = t[:, None]
    x = c[:, 0] + c[:, 1] * tt + c[:, 2] * tt**2 + c[:, 3] * tt**3
    xd = c[:, 1] + 2 * c[:, 2] * tt + 3 * c[:, 3] * tt**2
    xdd = 2 * c[:, 2] + 6 * c[:, 3] * tt
    return Trajectory(t, x, xd, xdd)
