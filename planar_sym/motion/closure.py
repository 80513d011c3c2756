"""Closed chains at the motion layer: passive joints from the loop constraints (Newton,
continued sample to sample so the assembly mode is kept) and their exact rates.

The loop-closure equations are ``Phi(q) = 0`` with ``Phi = r(parent point) - r(child point)``
at every cut joint; rates follow exactly from ``Phi_q qd = 0`` and ``Phi_q qdd = gamma``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, WorkspaceError
from ..model.arrays import as_sample_set, as_samples, when
from ..model.library import SingleCall
from ..model.loops import refuse_singular_matrices
from ..model.robot import Robot
from .profiles import JointTrajectory

#: Newton on Phi(q) = 0 stops below this residual (m); far under the 1e-9 m the tests demand.
NEWTON_TOL_M = 1e-13
NEWTON_MAX_ITER = 30


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

    Sample by sample, each started from the previous solution: continuation keeps the
    assembly mode (the first sample starts from ``q_guess``, default the drawn configuration).

    ``q_act`` (N, actuated) holds the actuated coordinates (rad; m at a slider), ``q_guess``
    (n,) a start pose, ``t`` (N,) the times (s) to name in an error. Returns every coordinate,
    shape (N, n), in rad (m). Raises WorkspaceError where the loops cannot be closed.
    """
    act, pas = partition(robot)
    q_act = as_samples("q_act", q_act, len(act), times=t)
    phi_f = SingleCall(robot.library.functions["constraint"], robot.p)
    jac_f = SingleCall(robot.library.functions["constraint_jacobian"], robot.p)
    q = np.array(robot.q_drawn if q_guess is None else q_guess, dtype=float)
    out = np.empty((len(q_act), robot.n))
    m = robot.n_constraints
    for k, qa in enumerate(q_act):
        q[act] = qa
        for _ in range(NEWTON_MAX_ITER):
            (phi,) = phi_f(q)
            if np.max(np.abs(phi)) < NEWTON_TOL_M:
                break
            (jac,) = jac_f(q)
            jp = jac.reshape(robot.n, m).T[:, pas]
            q[pas] -= np.linalg.solve(jp, phi)
        else:
            raise WorkspaceError(f"{robot.name}: the loops cannot be closed at {when(t, k)} "
                                 f"for actuated coordinates {np.round(qa, 9).tolist()} "
                                 f"({', '.join(robot.coordinate_units[i] for i in act)}) "
                                 f"(|Phi| = {np.max(np.abs(phi)):.3g} m): outside the workspace")
        out[k] = q
    return out


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
    """Full joint motion of a closed chain from its actuated joints' motion.

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
    t = as_samples("t", np.reshape(t, (-1, 1)) if np.ndim(t) == 1 else t, 1)[:, 0]
    if len(t) != len(np.atleast_2d(q_act)):
        raise InputError(f"t has {len(t)} times for {len(np.atleast_2d(q_act))} samples of q_act")
    q = solve_passive(robot, q_act, q_guess, t)
    qd, qdd = complete_rates(robot, q, qd_act, qdd_act, t)
    return JointTrajectory(np.asarray(t), q, qd, qdd)


def complete_state(robot: Robot, q_act, qd_act, q_guess=None) -> tuple[np.ndarray, np.ndarray]:
    """One state of a closed chain from its actuated joints: every coordinate (n,) on the loops
    (Newton from ``q_guess``, default the drawn configuration) and every rate (n,) from
    ``Phi_q qd = 0``; ``q_act``, ``qd_act`` (actuated,) in rad, rad/s (m, m/s at a slider)."""
    n_act = len(robot.actuated)
    jt = from_actuated(robot, np.zeros(1), np.reshape(q_act, (1, -1)),
                       np.reshape(qd_act, (1, -1)), np.zeros((1, n_act)), q_guess)
    return jt.q[0], jt.qd[0]
