"""An exciting motion: a periodic Fourier series per actuated joint whose stacked base regressor
is as well conditioned as the robot's limits allow.

.. code:: text

    min  log10 cond(W_b)                  W_b: the base regressor at evenly spaced samples of
                                          one period, each column scaled to unit norm
    s.t. q within its range,  |qd| <= speed,  |qdd| <= acceleration   (each actuated joint)
         |tau| <= the joint's torque limit, |tau / N| <= the motor's, |N qd| <= the motor's
         speed (where the description gives them; the nominal model's torques)
         a closed chain on its loops in the drawn assembly mode, cond(Phi_p) at most
         COND_FACTOR times its value at the drawn pose

SciPy's SLSQP from a few random starts (the problem is not convex), each scaled into the
limits first; the best is kept. Default limits (a range of +-1 rad about the drawn pose, 2 rad/s,
10 rad/s^2; a slider's the same per 10 cm) are there to be replaced with the machine's own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, WorkspaceError, warn_caller
from ..model.robot import Robot
from ..motion.closure import complete_rates, from_actuated
from ..motion.continuation import NEWTON_MAX_ITER, NEWTON_TOL_M
from ..motion.profiles import JointTrajectory
from .base import BaseParameters, base_parameters
from .fourier import FourierMotion, basis
from .regressor import regressor

#: a closed chain's passive-joint Jacobian stays within this factor of its condition number at
#: the drawn pose. Absolute bounds fail: the seed's 5-bar starts at 18, and at 80 along a
#: designed motion a tracking error of 0.01 rad at the motors already carried the passive
#: joints 0.13 rad, across the singular pose (a computed-torque run on a 30 % heavier robot
#: lost its loops there)
COND_FACTOR = 2.0
#: default limits per actuated joint: revolute (rad, rad/s, rad/s^2), and a slider's (m ...)
DEFAULT_REVOLUTE = (1.0, 2.0, 10.0)
DEFAULT_SLIDER = (0.1, 0.2, 1.0)
#: the kinematic limits are checked on this many times the regressor's samples: between two
#: points of that grid a position can pass its limit by at most dt^2 / 8 |qdd|max (dt the
#: grid's step; 5e-5 rad for 100 samples of a 6 s period at 6 rad/s^2)
DENSE = 8
#: halvings of a random start that leaves the limits
SHRINKS = 6
#: the torques kept this far (relative) inside their limits on the fine grid: the table that
#: ``write_excitation`` writes is read back through a spline, whose accelerations differ from
#: the series' by about 1e-5 relative at 200 Hz (a run found 1.2000169 N*m under 1.2)
TABLE_MARGIN = 1e-3


@dataclass(frozen=True)
class Limits:
    """Per actuated joint, each shape (actuated,) in SI: the position range ``low``, ``high``
    (rad; m at a slider), the largest ``speed`` (rad/s) and ``acceleration`` (rad/s^2);
    torques are limited by the description's actuators."""

    low: np.ndarray
    high: np.ndarray
    speed: np.ndarray
    acceleration: np.ndarray


@dataclass(frozen=True)
class Excitation:
    """The designed motion: ``fourier`` (actuated joints), ``trajectory`` (every coordinate,
    (N, n) at the samples of one period), the stacked base regressor's ``condition`` number
    (column-scaled, dimensionless) and ``start_condition``, the best start's it improved on,
    and the peaks reached, each shape (actuated,): ``peak_speed`` (rad/s; m/s at a slider),
    ``peak_acceleration`` (rad/s^2) and ``peak_torque`` (N*m; N at a slider)."""

    fourier: FourierMotion
    trajectory: JointTrajectory
    condition: float
    start_condition: float
    peak_speed: np.ndarray
    peak_acceleration: np.ndarray
    peak_torque: np.ndarray


def default_limits(robot: Robot, range_=None, speed=None, acceleration=None) -> Limits:
    """``Limits`` about the drawn pose, each given value (one per actuated joint, or one for
    all) replacing the defaults."""
    act = list(robot.actuated)
    slide = np.array([robot.coordinate_units[i] == "m" for i in act])
    defaults = np.where(slide[:, None], DEFAULT_SLIDER, DEFAULT_REVOLUTE)  # (na, 3)

    def given(v, k, name):
        if v is None:
            return defaults[:, k]
        a = np.atleast_1d(np.asarray(v, dtype=float))
        if a.ndim != 1 or len(a) not in (1, len(act)):
            raise InputError(f"excitation {name} needs {len(act)} value"
                             f"{'s' * (len(act) > 1)}, one per actuated joint (or 1 for all) "
                             f"(got {a.size})")
        a = np.broadcast_to(a, (len(act),)).copy()
        if not np.all(np.isfinite(a) & (a > 0)):
            raise InputError(f"excitation {name} must be positive numbers (one per actuated "
                             f"joint or one for all), got {v}")
        return a

    half, sp, acc = given(range_, 0, "range"), given(speed, 1, "speed"), \
        given(acceleration, 2, "acceleration")
    turns = [robot.coordinates[i] for i, h, s in zip(act, half, slide) if not s and h > 2 * np.pi]
    if turns:  # (--range 400 was taken as 400 rad each way: a trial)
        warn_caller(f"{robot.name}: the excitation range of {', '.join(turns)} is more than a "
                    f"turn each way ({max(half[~slide]):.4g} rad): degrees typed as radians? "
                    "(the range is in rad at a revolute joint)")
    q0 = np.asarray(robot.q_drawn, dtype=float)[act]
    return Limits(q0 - half, q0 + half, sp, acc)


def excite(robot: Robot, duration_s: float, harmonics: int = 5, *, limits: Limits | None = None,
           samples: int = 100, starts: int = 2, seed: int = 0,
           base: BaseParameters | None = None) -> Excitation:
    """Design an exciting motion of period ``duration_s`` (s) with ``harmonics`` per joint.

    Raises InputError for bad settings, WorkspaceError when no start stays within the limits
    (a closed chain's drawn pose near a singular one, or limits too tight to move at all).
    """
    from scipy.optimize import minimize

    if not (np.isfinite(duration_s) and duration_s > 0):
        raise InputError(f"duration must be a positive number of seconds, got {duration_s}")
    if not (isinstance(harmonics, int) and 1 <= harmonics <= 20):
        raise InputError(f"harmonics must be an integer from 1 to 20, got {harmonics}")
    if not robot.is_closed_chain and len(robot.actuated) < robot.n:
        # the search found no motion and said "widen the limits" (a trial's cart-pole)
        passive = [robot.coordinates[i] for i in range(robot.n) if i not in robot.actuated]
        raise InputError(f"{robot.name}: {', '.join(passive)} {'is' if len(passive) == 1 else 'are'} "
                         "passive: an exciting motion is imposed on every joint of a tree, "
                         "and a passive joint moves as the dynamics take it. Run the robot "
                         "under input torques instead (a forward study with a torque table) "
                         "and identify from that run's CSV")
    limits = limits or default_limits(robot)
    base = base or base_parameters(robot)
    act = list(robot.actuated)
    na, t = len(act), np.linspace(0.0, duration_s, samples, endpoint=False)
    at = basis(t, duration_s, harmonics)
    wl = at[2]
    # the kinematic limits on a grid finer than the regressor's samples: a peak between two
    # samples must not pass unseen (the torques and a closed chain's loops: at the samples)
    dense = basis(np.linspace(0.0, duration_s, DENSE * samples, endpoint=False), duration_s,
                  harmonics)
    center = (limits.low + limits.high) / 2
    drives = robot.drive_train.drives
    # the actuators' limits at the joint: torque, the motor's torque through the gear, speed
    tau_max = np.array([min([x for x in (d.torque_limit, d.motor_torque_limit and
                                          d.motor_torque_limit * d.gear_ratio) if x] or [np.inf])
                        for d in drives])
    w_max = np.array([d.motor_speed_limit_rad_s / d.gear_ratio if d.motor_speed_limit_rad_s
                      else np.inf for d in drives])
    speed = np.minimum(limits.speed, w_max)
    cond_max = np.inf
    if robot.is_closed_chain:
        drawn = robot.constraint_jacobian(robot.q_drawn)[:, list(robot.passive)]
        cond_max = COND_FACTOR * float(np.linalg.cond(drawn, 1))

    def motion(x) -> FourierMotion:
        a, b = np.split(x, 2)
        a, b = a.reshape(na, harmonics), b.reshape(na, harmonics)
        # q0: the middle of the range at the mean (the series' mean is q0)
        return FourierMotion(center, a, b, duration_s)

    last = {}  # a closed chain's last solved poses: the next nearby motion starts from them

    def states(fm: FourierMotion):
        q, qd, qdd = fm.at(at)
        if not robot.is_closed_chain:
            return q, qd, qdd
        full = _near(robot, q, last.get("q"))
        if full is None:  # the first, or too far from the last: continuation from the drawn pose
            full = from_actuated(robot, t, q, qd, qdd, q_guess=robot.q_drawn).q
        last["q"] = full
        return (full, *complete_rates(robot, full, qd, qdd))

    def torques(q, qd, qdd):
        if robot.is_closed_chain:
            return robot.closed_chain_inverse_dynamics(q, qd, qdd)[0]
        return robot.tree_inverse_dynamics(q, qd, qdd)[:, act]

    memo: dict[bytes, tuple] = {}
    best = None  # (cost, x) of the best feasible motion evaluated

    def evaluate(x):
        nonlocal best
        key = x.tobytes()
        if key not in memo:
            fm = motion(x)
            qa, qda, qdda = fm.at(dense)
            margins = [(limits.high - qa) / (limits.high - limits.low),
                       (qa - limits.low) / (limits.high - limits.low),
                       1 - np.abs(qda) / speed, 1 - np.abs(qdda) / limits.acceleration]
            try:
                q, qd, qdd = states(fm)
                tau = torques(q, qd, qdd)
                margins.append(1 - np.abs(tau) / tau_max)
                if robot.is_closed_chain:
                    jac = robot.constraint_jacobian(q)[:, :, list(robot.passive)]
                    margins.append(1 - np.linalg.cond(jac, 1)[:, None] / cond_max)
                w = regressor(robot, q, qd, qdd).y[..., list(base.kept)].reshape(-1, len(base))
                w = w / np.maximum(np.linalg.norm(w, axis=0), 1e-300)
                sv = np.linalg.svd(w, compute_uv=False)
                cost = float(np.log10(sv[0] / sv[-1])) if sv[-1] > 0 else 20.0
            except (WorkspaceError, InputError):  # off the loops or singular: infeasible
                margins.append(np.full((1, 1), -1.0))
                cost = 20.0
            # each limit's worst sample per joint: a few constraints, not one per sample
            # (SLSQP's subproblem grows with their number)
            memo[key] = (min(cost, 20.0),
                         np.concatenate([np.min(np.reshape(m, (len(m), -1)), axis=0)
                                         for m in margins]))
            if np.all(memo[key][1] >= 0) and (best is None or memo[key][0] < best[0]):
                best = (memo[key][0], x.copy())  # every feasible point seen counts
        return memo[key]

    rng = np.random.default_rng(seed)
    first = None
    for _ in range(starts):
        x0 = _start(rng, na, harmonics, wl, limits, speed)
        for _ in range(SHRINKS):  # a start that leaves the limits (or the loops) is shrunk
            if np.all(evaluate(x0)[1] >= 0):
                break
            x0 = x0 / 2
        c0, _ = evaluate(x0)
        first = c0 if first is None else min(first, c0)
        # SLSQP may end off the loops or stall at a limit (the cost jumps where the loops
        # break): the best feasible point it evaluated on the way is kept (``evaluate``)
        minimize(lambda x: evaluate(x)[0], x0, method="SLSQP",
                 constraints=[{"type": "ineq", "fun": lambda x: evaluate(x)[1]}],
                 options={"maxiter": 60, "ftol": 1e-4})
    if best is None:
        raise WorkspaceError(f"{robot.name}: no exciting motion found within the limits "
                             "(ranges, speeds, accelerations, torques and, for a closed chain, "
                             f"the loops' conditioning within {COND_FACTOR:g} times the drawn "
                             "pose's): widen them, or lengthen the period")
    x, cost = best[1], best[0]
    if np.any(np.isfinite(tau_max)):
        # the torques were held at the samples; between them a peak passed its limit by 0.02 %
        # and the run of the table warned: shrunk about the centre until the fine grid holds
        t_fine = np.linspace(0.0, duration_s, DENSE * samples, endpoint=False)

        def peaks(x):
            qa, qda, qdda = motion(x).at(dense)
            if robot.is_closed_chain:
                full = from_actuated(robot, t_fine, qa, qda, qdda, q_guess=robot.q_drawn)
                qa, qda, qdda = full.q, full.qd, full.qdd
            return np.max(np.abs(torques(qa, qda, qdda)), axis=0)

        for _ in range(SHRINKS):
            over = float(np.max(peaks(x) / tau_max))
            if over <= 1.0 - TABLE_MARGIN:
                break
            x = x * (1.0 - 2.0 * (over - 1.0 + TABLE_MARGIN))
            cost = evaluate(x)[0]
        top = peaks(x)
        k = int(np.argmax(top / tau_max))
        if top[k] > tau_max[k]:  # shrinking leaves gravity's share: it can stay over
            d = drives[k]
            warn_caller(f"{robot.name}: the exciting motion's {d.joint} needs {top[k]:.4g} "
                        f"{d.unit}, over its limit {tau_max[k]:.4g} {d.unit} by "
                        f"{100 * (top[k] / tau_max[k] - 1):.2g} % (shrinking the motion about "
                        "its centre does not lower what gravity needs there): narrow --range "
                        "about a pose where gravity needs less, or raise the limit")
    fm = motion(x)
    q, qd, qdd = states(fm)
    tau = torques(q, qd, qdd)
    return Excitation(fm, JointTrajectory(t, q, qd, qdd), 10 ** cost, 10 ** first,
                      np.abs(qd[:, act]).max(axis=0), np.abs(qdd[:, act]).max(axis=0),
                      np.abs(tau).max(axis=0))


def _start(rng, na, harmonics, wl, limits: Limits, speed) -> np.ndarray:
    """Random coefficients scaled so that the motion uses about half of each limit."""
    a, b = rng.normal(size=(2, na, harmonics)) / np.arange(1, harmonics + 1)
    fm = FourierMotion(np.zeros(na), a, b, 2 * np.pi / wl[0])
    q, qd, qdd = fm(np.linspace(0, 2 * np.pi / wl[0], 400, endpoint=False))
    half = (limits.high - limits.low) / 2
    scale = 0.5 * np.min([half / np.abs(q).max(axis=0), speed / np.abs(qd).max(axis=0),
                          limits.acceleration / np.abs(qdd).max(axis=0)], axis=0)
    return np.concatenate([(a * scale[:, None]).ravel(), (b * scale[:, None]).ravel()])


def _near(robot: Robot, q_act: np.ndarray, previous: np.ndarray | None) -> np.ndarray | None:
    """Every sample's pose from the actuated coordinates ``q_act`` (N, actuated), by Newton on
    all samples at once from ``previous`` (N, n), the poses of a nearby motion; None unless
    each sample closes its loops in the same assembly mode (sign of det Phi_p) as before."""
    if previous is None:
        return None
    act, pas = list(robot.actuated), list(robot.passive)
    q = previous.copy()
    q[:, act] = q_act
    sign = np.sign(np.linalg.det(robot.constraint_jacobian(previous)[:, :, pas]))
    for _ in range(NEWTON_MAX_ITER):
        phi = robot.constraint(q)
        if np.max(np.abs(phi)) < NEWTON_TOL_M:
            jac = robot.constraint_jacobian(q)[:, :, pas]
            return q if np.all(np.sign(np.linalg.det(jac)) == sign) else None
        jac = robot.constraint_jacobian(q)[:, :, pas]
        try:
            q[:, pas] -= np.linalg.solve(jac, phi[..., None])[..., 0]
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(q)) or np.max(np.abs(q - previous)) > 0.5:
            return None  # wandered off: let the continuation decide
    return None
