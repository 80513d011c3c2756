"""Closed chains at the motion layer: passive joints from the loop constraints (Newton,
continued sample to sample so the assembly mode is kept) and their exact rates.

The loop-closure equations are ``Phi(q) = 0`` with ``Phi = r(parent point) - r(child point)``
at every cut joint; rates follow exactly from ``Phi_q qd = 0`` and ``Phi_q qdd = gamma``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, WorkspaceError, warn_caller
from ..model.arrays import as_sample_set, as_samples, as_times, as_vector
from ..model.loops import COND_LIMIT, refuse_singular_matrices
from ..model.robot import Robot
from .continuation import NEWTON_TOL_M, Loops, Pose, follow, warn_between_samples
from .profiles import JointTrajectory


def partition(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the actuated and passive coordinates; checks the chain is fully actuated.

    Returns two integer arrays, shapes (actuated,) and (n - actuated,); InputError unless the
    actuated joints and the loop equations together fix every coordinate.
    """
    act, pas = np.array(robot.actuated, dtype=int), np.array(robot.passive, dtype=int)
    if len(act) + robot.n_constraints != robot.n:
        raise InputError(f"{robot.name}: {len(act)} actuated joints and {robot.n_constraints} "
                         f"loop equations for {robot.n} coordinates: the chain is not exactly "
                         "actuated, so torques are not unique")
    return act, pas


def solve_passive(robot: Robot, q_act, q_guess=None, t=None) -> np.ndarray:
    """Full coordinates from actuated ones, Newton on Phi(q) = 0 for the passive joints.

    The first sample is reached from the drawn configuration along the loops (as the others
    from it), so it is in the drawn assembly mode wherever it lies, or from ``q_guess`` by
    Newton, which then picks the mode; the others follow it along the motion, whatever the
    sampling (``follow``): from each solved pose to the next sample's actuated coordinates in
    steps of at most ``MAX_STEP`` in any coordinate (and shorter near a singular pose), each
    predicted along the loops' tangent and corrected by Newton; refused where the motion meets a
    singular pose (Phi_p's 1-norm condition number above COND_LIMIT), where the sign of det
    Phi_p changes (one crossed between two steps: another assembly mode), or where Newton cannot
    close the loops.

    ``q_act`` (N, actuated) holds the actuated coordinates (rad; m at a slider), ``q_guess``
    (n,) a start pose, ``t`` (N,) the times (s) to name in an error (checked here: finite, one
    per sample). Returns every coordinate,
    shape (N, n), in rad (m). Raises WorkspaceError where the loops cannot be closed or the
    motion would leave its assembly mode.
    """
    act, pas = partition(robot)
    loops = Loops(robot, act, pas)
    if t is not None:  # the times an error names: checked here, with the samples
        t = as_times(t, len(np.atleast_2d(q_act)), "q_act")
    q_act = as_samples("q_act", q_act, len(act), times=t)
    if q_guess is not None:  # checked here, once: _first is also entered again without one
        q_guess = as_vector("q_guess", q_guess, robot.n)
    pose = _first(loops, q_act[0], q_guess, t)
    out = np.empty((len(q_act), robot.n))
    out[0] = pose.q
    cond, passed = np.empty(len(q_act)), np.empty(len(q_act))
    cond[0] = passed[0] = pose.cond
    for k in range(1, len(q_act)):
        pose = follow(loops, pose, q_act[k], t, k)
        out[k], cond[k], passed[k] = pose.q, pose.cond, pose.passed
    warn_between_samples(robot.name, cond, passed, t)
    return out


def _first(loops: Loops, qa: np.ndarray, q_guess, t) -> Pose:
    """The first sample's pose: continued from the drawn pose, whose assembly mode it keeps,
    or from ``q_guess`` by Newton, which then picks the mode. Newton from the drawn passive
    angles straight at a crank 240 degrees away closed the slider-crank in its other mode (the
    slider on the far side of the pivot, 7% off in torque) without a word, so a guess whose
    passive coordinates are the drawn ones (``simulate(project=True)`` from ``q_drawn`` with
    the crank turned) is no guess. A drawn pose that is itself singular is left to Newton.
    ``q_guess`` (n,) is checked already (``solve_passive``)."""
    robot, act, pas = loops.robot, loops.act, loops.pas
    if q_guess is not None and np.array_equal(q_guess[pas], robot.q_drawn[pas]):
        q_guess = None
    if q_guess is not None:
        return _guessed(loops, qa, np.array(q_guess, dtype=float), t)
    q = np.array(robot.q_drawn, dtype=float)
    drawn, residual = loops.newton(q)
    pose = Pose(loops, drawn) if residual < NEWTON_TOL_M else None
    if pose is not None and pose.cond <= COND_LIMIT:
        try:
            return follow(loops, pose, qa, t, 0, origin="the drawn pose")
        except WorkspaceError:
            # a target the loops close at in no mode is outside, whatever lies between
            q[act] = qa
            residual = loops.newton(q)[1]
            if residual < NEWTON_TOL_M:
                raise
            loops.refuse_outside(qa, residual, t, 0)  # (not a second Newton, in close)
    q[act] = qa
    return Pose(loops, loops.close(q, qa, t, 0))


#: a guess whose passive coordinates Newton moves by more than this (rad; m at a slider) was
#: far from the loops: the pose it closes is compared with the drawn mode's, and a difference
#: is said
FAR_GUESS = 0.5


def _guessed(loops: Loops, qa: np.ndarray, guess: np.ndarray, t) -> Pose:
    """Newton from ``guess`` with the actuated coordinates ``qa``; its passive angles in the
    turn nearest the guess (Newton from far away wandered to q2 = 493 rad on a four-bar).
    Where Newton cannot close the loops from the guess the drawn mode is continued there; where
    a far guess closes another pose than the drawn mode's, a warning names both."""
    robot, pas = loops.robot, loops.pas
    q = guess.copy()
    q[loops.act] = qa
    closed, residual = loops.newton(q)
    if not residual < NEWTON_TOL_M:
        try:
            return _first(loops, qa, None, t)
        except WorkspaceError:
            loops.refuse_outside(qa, residual, t, 0)
    turns = np.array([robot.coordinate_units[i] == "rad" for i in pas])
    shift = np.where(turns, 2 * np.pi * np.round((closed[pas] - guess[pas]) / (2 * np.pi)), 0)
    closed[pas] -= shift
    if np.max(np.abs(closed[pas] - guess[pas])) > FAR_GUESS:
        try:
            drawn = _first(loops, qa, None, t).q
        except WorkspaceError:
            drawn = None
        if drawn is not None and not _same_pose(drawn, closed, pas, turns):
            warn_caller(
                f"{robot.name}: the start's passive coordinates {_listed(guess, pas)} are far "
                f"from the loops; Newton from them closes them at {_listed(closed, pas)}, "
                f"another pose than the drawn assembly mode's {_listed(drawn, pas)} at these "
                "actuated coordinates; the first was taken: give a start on the loops "
                "(planar_sym.from_actuated) to choose")
    return Pose(loops, closed)


def _same_pose(a: np.ndarray, b: np.ndarray, pas: np.ndarray, turns: np.ndarray) -> bool:
    d = a[pas] - b[pas]
    d = np.where(turns, (d + np.pi) % (2 * np.pi) - np.pi, d)
    return bool(np.max(np.abs(d)) < 1e-6)


def _listed(q: np.ndarray, idx: np.ndarray) -> list[float]:
    return np.round(q[idx], 4).tolist()


def complete_rates(robot: Robot, q, qd_act, qdd_act, t=None) -> tuple[np.ndarray, np.ndarray]:
    """Passive rates from the constraints, batched.

    .. code:: text

        Phi_p qd_p = -Phi_a qd_a,    Phi_p qdd_p = gamma - Phi_a qdd_a

    ``q`` (N, n) is on the loops (rad); ``qd_act``, ``qdd_act`` (N, actuated) are the actuated
    rates (rad/s) and accelerations (rad/s^2); ``t`` (N,) times (s) to name in an error.
    Returns ``qd``, ``qdd``, each (N, n), every coordinate. Raises WorkspaceError at a pose
    where Phi_p is singular.
    """
    act, pas = partition(robot)
    q, qd_act, qdd_act = as_sample_set({"q": robot.n, "qd_act": len(act), "qdd_act": len(act)},
                                       {"q": q, "qd_act": qd_act, "qdd_act": qdd_act}, times=t)
    jac = robot.constraint_jacobian(q)
    jac = jac if jac.ndim == 3 else jac[None]
    refuse_singular_matrices(robot.name, jac[:, :, pas],
                             "passive-joint constraint Jacobian Phi_p", t)
    qd = np.zeros_like(q)
    qd[:, act] = qd_act
    qd[:, pas] = np.linalg.solve(jac[:, :, pas], -(jac[:, :, act] @ qd[:, act, None]))[..., 0]
    gamma = robot.constraint_bias(q, qd).reshape(len(q), -1)
    qdd = np.zeros_like(q)
    qdd[:, act] = qdd_act
    qdd[:, pas] = np.linalg.solve(jac[:, :, pas],
                                  (gamma - (jac[:, :, act] @ qdd[:, act, None])[..., 0])[..., None]
                                  )[..., 0]
    return qd, qdd


def from_actuated(robot: Robot, t, q_act, qd_act, qdd_act, q_guess=None) -> JointTrajectory:
    """Full joint motion of a closed chain from its actuated joints' motion (of a fully
    actuated tree: the motion given, as a ``JointTrajectory``).

    Parameters
    ----------
    t : ndarray, shape (N,)
        Times (s), one per sample.
    q_act, qd_act, qdd_act : ndarray, shape (N, actuated)
        The actuated joints' angles (rad), rates (rad/s) and accelerations (rad/s^2).
    q_guess : ndarray, shape (n,), optional
        Where the first sample's Newton starts (default the drawn configuration): its assembly
        mode is kept.
    """
    if t is None:  # (None is solve_passive's "no times")
        raise InputError("t must be the samples' times (s), one per sample of q_act: got None")
    if robot.is_closed_chain:
        q = solve_passive(robot, q_act, q_guess, t)  # t checked there, with q_act
        t = np.asarray(t, dtype=float).reshape(-1)
        qd, qdd = complete_rates(robot, q, qd_act, qdd_act, t)
        return JointTrajectory(t, q, qd, qdd)
    t = as_times(t, len(np.atleast_2d(q_act)), "q_act")
    # a tree (a KeyError on the loop functions a tree has not, before)
    passive = [robot.coordinates[i] for i in range(robot.n) if i not in robot.actuated]
    if passive:
        raise InputError(f"{robot.name}: {', '.join(passive)} passive in a tree: a tree's "
                         "passive joints follow from its dynamics, not from the actuated "
                         "joints' motion (simulate it under their torques)")
    act = list(robot.actuated)
    full = [np.zeros((len(t), robot.n)) for _ in range(3)]
    for f, (k, a) in zip(full, (("q_act", q_act), ("qd_act", qd_act), ("qdd_act", qdd_act))):
        f[:, act] = as_samples(k, a, len(act), times=t)
    return JointTrajectory(t, *full)


def complete_state(robot: Robot, q_act, qd_act, q_guess=None) -> tuple[np.ndarray, np.ndarray]:
    """One state of a closed chain from its actuated joints: every coordinate (n,) on the loops
    (Newton from ``q_guess``, default the drawn configuration) and every rate (n,) from
    ``Phi_q qd = 0``; ``q_act``, ``qd_act`` (actuated,) in rad, rad/s (m, m/s at a slider)."""
    n_act = len(robot.actuated)
    jt = from_actuated(robot, np.zeros(1), np.reshape(q_act, (1, -1)),
                       np.reshape(qd_act, (1, -1)), np.zeros((1, n_act)), q_guess)
    return jt.q[0], jt.qd[0]
