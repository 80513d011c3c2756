"""The fastest timing of a path: time-optimal path parametrisation by reachability analysis
(TOPP-RA, Pham and Pham 2018), on the compiled inverse dynamics, for trees and closed chains.

Along a path ``q(s)``, ``s`` in [0, 1] its arc length in the actuated coordinates, with ``x = sdot^2`` and ``u = sddot`` the torques are
affine in (u, x) at every sample ``i`` (``q_s``, ``q_ss``: the path's derivatives):

.. code:: text

    tau_i = a_i u + b_i x + c_i,   a_i = ID(q, 0, q_s) - c_i,   b_i = ID(q, q_s, q_ss) - c_i,
    c_i = ID(q, 0, 0)                                   (a closed chain: its actuated torques)
    x_{i+1} = x_i + 2 (s_{i+1} - s_i) u_i               (constant sddot between samples)

A backward pass finds each sample's controllable interval of x (the x from which the end is
reached at rest within the limits: two linear programs in (x, u) per sample, solved exactly
by their vertices), a forward pass takes the largest u that stays controllable. The limits are
held at the samples (toppra's collocation). Friction (not affine in x) is refused.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from .limits import description_speed_limits, speed_limits, torque_limits

#: slack on a constraint at a vertex of a linear program (relative to its right-hand side)
TOL = 1e-9


@dataclass(frozen=True)
class TimeOptimal:
    """The fastest timing: ``trajectory`` (the path's samples at times ``trajectory.t_s``, s;
    q, qd, qdd of every coordinate), ``tau`` (N, actuated) N*m (N at a slider) there,
    ``sdot`` (N,) the path speed (1/s, s in [0, 1]), ``duration_s``, ``on_limit`` (N,) whether
    a torque is on its limit (to 1e-6 relative) at each sample, ``limits`` (actuated,) the
    torque limits used; ``speed_limits`` (n,) rad/s (m/s at a slider) where speeds were
    limited (else None) and ``on_speed_limit`` (N,) whether a speed is on its limit there."""

    trajectory: JointTrajectory
    tau: np.ndarray
    sdot: np.ndarray
    duration_s: float
    on_limit: np.ndarray
    limits: np.ndarray
    speed_limits: np.ndarray | None = None
    on_speed_limit: np.ndarray | None = None


def time_optimal(robot: Robot, path: JointTrajectory, torque_limit=None,
                 speed_limit=None) -> TimeOptimal:
    """The fastest rest-to-rest timing of ``path`` (its samples, in order; any timing, e.g.
    ``ps.inverse_kinematics`` of a task move) under ``|tau_k| <= torque_limit[k]`` (N*m, N at
    a slider; one per actuated joint, default the description's ``torque_limit``) and
    ``|qd_j| <= speed_limit[j]`` (rad/s, m/s; one per coordinate; default the description's
    motor speed limits through the gears, if any: ``optimal.limits``).

    Raises InputError when a limit is missing or not positive, the robot has friction, or the
    path cannot be followed within the limits (naming the first sample).
    """
    if not isinstance(path, JointTrajectory):
        raise InputError("path must be a JointTrajectory (ps.inverse_kinematics, "
                         f"ps.from_actuated), got {type(path).__name__}")
    if robot.has_friction:
        raise InputError(f"{robot.name}: friction makes the torques non-affine in the path "
                         "speed squared: time_optimal takes robots without friction")
    na, n = len(robot.actuated), robot.n
    if not robot.is_closed_chain and na != n:
        raise InputError(f"{robot.name}: a passive joint of a tree does not follow a path "
                         "(underactuated): time_optimal takes fully actuated trees and "
                         "closed chains")
    lim = torque_limits(robot, torque_limit, (
        f"{robot.name}: torque_limit is needed (the description gives no torque_limit for "
        "every actuator): one per actuated joint, N*m"))
    s, q, q_s, q_ss = arc_length_path(robot, path)
    # the actuated torques (N, actuated) at rest, under q_s sddot and under q_s sdot^2 + q_ss
    # sdot^2: tau = a sddot + b sdot^2 + c
    zero = np.zeros_like(q)
    rates = ((zero, zero), (zero, q_s), (q_s, q_ss))
    if robot.is_closed_chain:
        c, a, b = (robot.closed_chain_inverse_dynamics(q, qd, qdd)[0] for qd, qdd in rates)
    else:
        c, a, b = (robot.inverse_dynamics(q, qd, qdd) for qd, qdd in rates)
    a, b = a - c, b - c
    x_max = np.full(len(s), np.inf)
    v = (description_speed_limits(robot) if speed_limit is None
         else speed_limits(robot, speed_limit))
    if v is not None:
        with np.errstate(divide="ignore"):
            x_max = np.min((v / np.abs(q_s)) ** 2, axis=1)
    ds = np.diff(s)
    lo, hi = _controllable(robot, a, b, c, lim, x_max, ds)
    x, u = np.zeros(len(s)), np.zeros(len(s))
    for i in range(len(s) - 1):  # forward: the largest u that stays controllable
        u_lo, u_hi = _u_range(a[i], b[i] * x[i] + c[i], lim, (lo[i + 1] - x[i]) / (2 * ds[i]),
                              (hi[i + 1] - x[i]) / (2 * ds[i]))
        if u_lo > u_hi + TOL * max(abs(u_hi), 1.0):
            raise InputError(f"{robot.name}: the forward pass left the controllable set at "
                             f"sample {i} (rounding?)")
        u[i] = u_hi
        x[i + 1] = max(min(x[i] + 2 * ds[i] * u[i], hi[i + 1]), lo[i + 1], 0.0)
    # the last sample has no interval ahead: the previous one's u, held within what its own
    # torque limits allow there (held as it was, a trial saw 1.000138 times the limit there)
    u_lo, u_hi = _u_range(a[-1], b[-1] * x[-1] + c[-1], lim, -np.inf, np.inf)
    u[-1] = min(max(u[-2], u_lo), u_hi) if u_lo <= u_hi else u[-2]
    sdot = np.sqrt(x)
    dt = 2 * ds / (sdot[:-1] + sdot[1:])
    times = np.concatenate([[0.0], np.cumsum(dt)])
    qd = q_s * sdot[:, None]
    qdd = q_s * u[:, None] + q_ss * x[:, None]
    tau = a * u[:, None] + b * x[:, None] + c
    on = np.any(np.abs(tau) >= lim * (1 - 1e-6), axis=1)
    on_speed = (None if v is None else
                np.any(np.abs(qd) >= np.asarray(v, dtype=float) * (1 - 1e-6), axis=1))
    return TimeOptimal(JointTrajectory(times, q, qd, qdd, path.solver), tau, sdot,
                       float(times[-1]), on, lim,
                       None if v is None else np.asarray(v, dtype=float), on_speed)


def arc_length_path(robot: Robot, path: JointTrajectory):
    """The path by its arc length in the actuated coordinates, s in [0, 1] at its samples:
    (s (N,), q, q_s, q_ss each (N, n)), q_s and q_ss from a cubic spline (not-a-knot, as
    toppra's ``SplineInterpolator``) through the actuated samples; a closed chain's passive
    coordinates follow from the loops (``from_actuated``), so every sample is on them.

    Timing a path needs a parameter whose rate never vanishes: a rest-to-rest motion's own
    time has q_s = 0 at its ends, where the torques do not depend on sddot."""
    from scipy.interpolate import CubicSpline

    t = np.asarray(path.t_s, dtype=float)
    if len(t) < 3 or np.any(np.diff(t) <= 0):
        raise InputError("path.t_s must hold 3 or more increasing times")
    act = list(robot.actuated)
    qa = path.q[:, act]
    step = np.linalg.norm(np.diff(qa, axis=0), axis=1)
    if np.any(step <= 1e-12 * max(step.max(), 1e-300)):
        k = int(np.argmax(step <= 1e-12 * max(step.max(), 1e-300)))
        raise InputError(f"{robot.name}: the path stands still between samples {k} and "
                         f"{k + 1} (the actuated joints do not move): give a path that moves")
    s = np.concatenate([[0.0], np.cumsum(step)]) / step.sum()
    spline = CubicSpline(s, qa)
    qa_s, qa_ss = spline(s, 1), spline(s, 2)
    if robot.is_closed_chain:
        from ..motion.closure import from_actuated

        full = from_actuated(robot, s, qa, qa_s, qa_ss, q_guess=path.q[0])
        return s, full.q, full.qd, full.qdd
    return s, qa.copy(), qa_s, qa_ss


def _controllable(robot, a, b, c, lim, x_max, ds) -> tuple[np.ndarray, np.ndarray]:
    """The controllable interval [lo_i, hi_i] of x at every sample, from the end at rest."""
    N = len(a)
    lo, hi = np.zeros(N), np.zeros(N)
    for i in range(N - 2, -1, -1):
        # rows of A [x, u] <= r: the torque limits, 0 <= x <= x_max, and x + 2 ds u in K_{i+1}
        rows = [np.column_stack([b[i], a[i]]), np.column_stack([-b[i], -a[i]]),
                [[-1.0, 0.0]], [[1.0, 2 * ds[i]]], [[-1.0, -2 * ds[i]]]]
        r = [lim - c[i], lim + c[i], [0.0], [hi[i + 1]], [-lo[i + 1]]]
        if np.isfinite(x_max[i]):
            rows.append([[1.0, 0.0]])
            r.append([x_max[i]])
        found = _lp_x_range(np.vstack(rows), np.concatenate(r))
        if found is None:
            raise InputError(f"{robot.name}: the path cannot be followed within the limits at "
                             f"sample {i} (of {N}): no path speed there reaches the end at "
                             "rest (raise torque_limit, or the gravity torque alone exceeds "
                             "it)")
        lo[i], hi[i] = found
    return lo, hi


def _lp_x_range(A: np.ndarray, r: np.ndarray) -> tuple[float, float] | None:
    """min and max of x over {A [x, u] <= r} (bounded in x), from the polygon's vertices:
    every pair of rows' intersection that satisfies all rows."""
    i, j = np.triu_indices(len(A), 1)
    det = A[i, 0] * A[j, 1] - A[i, 1] * A[j, 0]
    ok = np.abs(det) > 1e-300
    i, j, det = i[ok], j[ok], det[ok]
    x = (r[i] * A[j, 1] - A[i, 1] * r[j]) / det
    u = (A[i, 0] * r[j] - r[i] * A[j, 0]) / det
    slack = A @ np.vstack([x, u]) - r[:, None]
    feasible = np.all(slack <= TOL * (np.abs(r)[:, None] + np.abs(A) @ np.abs(np.vstack(
        [x, u])) + 1e-12), axis=0)
    if not feasible.any():
        return None
    return float(max(x[feasible].min(), 0.0)), float(x[feasible].max())


def _u_range(a, d, lim, u_lo, u_hi) -> tuple[float, float]:
    """The interval of u with |a_k u + d_k| <= lim_k for every k, within [u_lo, u_hi]."""
    for ak, dk, lk in zip(a, d, lim):
        if ak > 0:
            u_lo, u_hi = max(u_lo, (-lk - dk) / ak), min(u_hi, (lk - dk) / ak)
        elif ak < 0:
            u_lo, u_hi = max(u_lo, (lk - dk) / ak), min(u_hi, (-lk - dk) / ak)
    return u_lo, u_hi
