"""Inverse dynamics beyond one generated call: the actuation matrix of a closed chain and the
split of the actuated torques into their inertial, velocity, gravity, friction and rotor parts.

Sign convention, stated once and tested (tests/test_closed_chain.py):

.. code:: text

    M(q) qdd + h(q, qd) = S^T tau + Phi_q(q)^T lambda,
    Phi(q) = r(parent point) - r(child point)  at every cut joint,

so ``lambda`` (N, world x and y) is the force the cut joint's child body exerts on its parent
body; the child feels ``-lambda``. ``S`` selects the actuated coordinates; passive joints carry
no torque.
"""

from __future__ import annotations

import numpy as np

from ..model.robot import Robot
from ..motion.closure import partition


def actuation_matrix(robot: Robot, q: np.ndarray, t=None) -> np.ndarray:
    """``[S^T Phi_q^T]`` at each sample, shape (N, n, n); refuses a singular pose by time.

    The matrix is singular exactly when the passive-joint block ``Phi_p`` is (its actuated
    rows are identity rows), so that block's 1-norm condition number is the measure.
    """
    act, pas = partition(robot)
    n_s, n = len(q), robot.n
    jac = robot.constraint_jacobian(q).reshape(n_s, robot.n_constraints, n)
    robot.refuse_singular(np.linalg.cond(jac[:, :, pas], 1), t)
    a = np.zeros((n_s, n, n))
    a[:, act, np.arange(len(act))] = 1.0
    a[:, :, len(act):] = jac.transpose(0, 2, 1)
    return a


#: the parts of the torque split, in plotting order: name -> label in the plots; the drive
#: train's two (friction, rotor) are zero for a robot without actuator models
SPLIT_PARTS = {"inertial": "M qdd", "velocity": "C qd", "gravity": "g", "friction": "D(qd)",
               "rotor": "rotors"}


def torque_split(robot: Robot, q, qd, qdd, t=None) -> dict[str, np.ndarray]:
    """The actuated torques split into inertial, velocity-dependent, gravity, friction and
    rotor parts.

    .. code:: text

        tau = tau(M qdd) + tau(C qd) + tau(g) + tau(D(qd)) + tau(rotors)

    ``M``, ``C`` are the links' own (rotor inertias set to zero); ``D(qd) = b qd + c tanh(qd /
    v_s)`` the drive train's friction; the rotor part is everything the rotors' inertia adds
    (``N^2 J_m qdd`` and its coupling to the parent body, and their velocity terms): the full
    ``M qdd + h`` less the links' with the same friction. For a tree every joint is actuated and
    the parts are the terms themselves. For a closed chain the torques come from the linear
    solve ``[S^T Phi_q^T] [tau; lambda] = M qdd + h``, so each term is pushed through the same
    matrix and the parts still add up to tau.

    Parameters
    ----------
    robot : Robot
    q, qd, qdd : ndarray, shape (N, n)
        Every coordinate (rad, rad/s, rad/s^2), consistent with the loops for closed chains.
    t : ndarray, shape (N,), optional
        Times (s), only to name the sample of a singular pose.

    Returns
    -------
    dict
        ``SPLIT_PARTS`` keys -> ndarray (N, actuated), N*m.
    """
    q, qd, qdd = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (q, qd, qdd))
    n_s, n = q.shape
    # a closed chain's torques come through [S^T Phi_q^T] (refused by time where singular)
    a = actuation_matrix(robot, q, t) if robot.is_closed_chain else None
    drives = robot.drive_train
    links = robot.with_values(robot.parameters.replace(
        **{f"jm_{d.joint}": 0.0 for d in drives.drives if d.rotor_inertia})
    ) if drives.has_rotors else robot
    mass = links.mass_matrix(q).reshape(n_s, n, n)
    h = links.bias(q, qd).reshape(n_s, n)
    g = links.gravity(q).reshape(n_s, n)
    friction = drives.friction(qd)
    rotor = (robot.tree_inverse_dynamics(q, qd, qdd).reshape(n_s, n)
             - links.tree_inverse_dynamics(q, qd, qdd).reshape(n_s, n)
             if drives.has_rotors else np.zeros((n_s, n)))
    terms = np.stack([(mass @ qdd[..., None])[..., 0], h - g - friction, g, friction, rotor],
                     axis=-1)  # (N, n, parts)
    if a is not None:  # one solve for all parts: the multipliers' shares dropped, torques kept
        terms = np.linalg.solve(a, terms)[:, :len(robot.actuated), :]
    return {k: terms[:, :, i] for i, k in enumerate(SPLIT_PARTS)}


def split_along(robot: Robot, q, qd, tau, t=None) -> dict[str, np.ndarray]:
    """``torque_split`` of a simulated motion: the accelerations the robot's own dynamics give
    under the actuated torques ``tau`` (N, actuated; N*m or N) at states ``q``, ``qd`` (N, n;
    rad, rad/s), then the split of those torques, each part (N, actuated). A tree's passive
    joints get no torque and are left out of the parts (their rows of M qdd + h balance to 0).
    ``t`` (N,) in s names a refused sample."""
    act = list(robot.actuated)
    if robot.is_closed_chain:
        from .forward_closed import kkt_accelerations

        qdd = kkt_accelerations(robot, q, qd, tau)
    else:
        full = np.zeros(np.shape(q))
        full[:, act] = tau
        qdd = robot.forward_dynamics(q, qd, full)
    parts = torque_split(robot, q, qd, qdd, t=t)
    if robot.is_closed_chain or len(act) == robot.n:
        return parts
    return {k: v[:, act] for k, v in parts.items()}
