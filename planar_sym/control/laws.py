"""Control laws and their gains: ``controller`` makes a checked ``Controller`` (the law the
simulation engine runs, ``dynamics.laws``, with the equations) from a law's name and its gains.

Units: PD gains are N*m/rad and N*m*s/rad (N/m and N*s/m at a slider); computed-torque gains
are 1/s^2 and 1/s (Kp = w^2 and Kd = 2 zeta w give a natural frequency w and damping zeta).
"""

from __future__ import annotations

import numpy as np

from ..dynamics.laws import KINDS, MODE, Controller
from ..errors import InputError

__all__ = ["KINDS", "MAX_GAIN", "MODE", "Controller", "bandwidth_gains", "controller",
           "effective_inertia"]

#: a gain above this cannot be meant (the step size it forces would stall the integrator)
MAX_GAIN = 1e9


def _gains(name: str, value, width: int | None) -> tuple[float, ...]:
    try:
        arr = np.asarray(value, dtype=float)
        arr = arr.reshape(-1) if width is None and arr.ndim <= 1 else \
            np.broadcast_to(arr, (width,))
    except (TypeError, ValueError):
        many = ("one number (one actuated joint)" if width == 1 else
                f"one number or {width or 'several'} numbers, one per actuated joint")
        raise InputError(f"{name} must be {many} (got {value!r})") from None
    for k, v in enumerate(arr):
        if not np.isfinite(v):
            raise InputError(f"{name}[{k}] is {v}: gains must be finite")
        if v < 0:
            raise InputError(f"{name}[{k}] is {v:g}: a negative gain pushes the joint away "
                             "from its reference (unstable); gains must be >= 0")
        if v > MAX_GAIN:
            raise InputError(f"{name}[{k}] is {v:g}: above {MAX_GAIN:g} (a unit slip?)")
    return tuple(float(v) for v in arr)


def controller(kind: str = "pd", kp=None, kd=None, *, width: int | None = None,
               saturate: bool = True) -> Controller:
    """A checked Controller for ``width`` actuated coordinates (None: as many as the robot it
    is used with has; one gain then serves every joint).

    ``kp``, ``kd``: one number (every joint) or one per actuated joint; required for "pd" and
    "computed_torque", not taken by "none". Negative, non-finite or absurd gains raise
    InputError; a computed-torque loop with Kp > 0 and Kd = 0 never settles (undamped), and
    is refused too.
    """
    if kind not in KINDS:
        raise InputError(f"controller must be one of {', '.join(KINDS)} (got {kind!r})")
    if kind == "lqr":
        raise InputError("an LQR law is designed from the robot's linearisation: "
                         "planar_sym.lqr(robot, q, q_weight=..., r_weight=...).controller()")
    if kind == "none":
        if kp is not None or kd is not None:
            raise InputError("controller \"none\" (open loop) takes no gains")
        return Controller(kind, saturate=saturate)
    if kp is None or kd is None:
        raise InputError(f"controller {kind!r} needs both gains kp and kd")
    kp_, kd_ = _gains("kp", kp, width), _gains("kd", kd, width)
    for k, (p, d) in enumerate(zip(kp_, kd_)):
        if p > 0 and d == 0 and kind == "computed_torque":
            raise InputError(f"kd[{k}] is 0 with kp[{k}] = {p:g}: the error would oscillate "
                             "for ever (e'' + Kp e = 0); give some damping, e.g. kd = "
                             f"2 sqrt(kp) = {2 * np.sqrt(p):.4g} 1/s for critical damping")
        if p == 0 and d == 0:
            raise InputError(f"kp[{k}] and kd[{k}] are both 0: that joint has no feedback "
                             "(use controller = \"none\" for an open-loop run)")
    return Controller(kind, kp_, kd_, bool(saturate))


def bandwidth_gains(robot, kind: str, q0: np.ndarray, natural_frequency_hz: float,
                    damping: float) -> tuple[np.ndarray, np.ndarray]:
    """(kp, kd), each shape (actuated,) in SI, from a natural frequency w = 2 pi f (f in Hz) and
    damping zeta: computed torque Kp = w^2 (1/s^2), Kd = 2 zeta w (1/s); PD the same times each
    actuated joint's effective inertia at ``q0`` (n,) (rad; m at a slider): N*m/rad and
    N*m*s/rad."""
    na = len(robot.actuated)
    w = 2.0 * np.pi * natural_frequency_hz
    kp, kd = np.full(na, w * w), np.full(na, 2.0 * damping * w)
    if kind == "pd":
        inertia = effective_inertia(robot, q0)
        kp, kd = kp * inertia, kd * inertia
    return kp, kd


def effective_inertia(robot, q: np.ndarray) -> np.ndarray:
    """Diagonal of the mass matrix seen at the actuated joints at pose ``q`` (n,), shape
    (actuated,) in kg*m^2 (kg at a slider): G^T M G with G (n, actuated) the map from actuated
    rates to every rate (the loops' for a closed chain)."""
    n, act = robot.n, list(robot.actuated)
    M = robot.mass_matrix(q).reshape(n, n)
    G = np.zeros((n, len(act)))
    G[act, range(len(act))] = 1.0
    if robot.is_closed_chain:
        J = robot.constraint_jacobian(q).reshape(robot.n_constraints, n)
        pas = list(robot.passive)
        G[pas] = -np.linalg.solve(J[:, pas], J[:, act])
    return np.diag(G.T @ M @ G).copy()
