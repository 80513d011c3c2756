"""Inverse kinematics: joint motion (every coordinate, passive ones too) along a task motion,
with exact joint rates from the task Jacobian stacked on the constraint Jacobian:

.. code:: text

    [Phi_q; J] qd = [0; xd],    [Phi_q; J] qdd = [gamma; xdd - Jdot qd]

never finite differences.
"""

from __future__ import annotations

import numpy as np

from ..errors import WorkspaceError
from ..model.robot import COND_LIMIT, Robot
from .failures import Failures
from .profiles import JointTrajectory, Trajectory


def solve_rates(robot: Robot, t: np.ndarray, x: np.ndarray, J: np.ndarray, rhs: np.ndarray):
    """Solve J y = rhs per sample, refusing a singular pose by name and time."""
    cond = np.linalg.cond(J)
    fails = Failures(robot, t, x)
    fails.add(~np.isfinite(cond) | (cond > COND_LIMIT),
              lambda k: f"is at a singular pose (Jacobian condition number {cond[k]:.3g} > "
                        f"{COND_LIMIT:g})")
    fails.raise_earliest()
    return np.linalg.solve(J, rhs[..., None])[..., 0]


def inverse_kinematics(robot: Robot, traj: Trajectory) -> JointTrajectory:
    """Joint motion (every coordinate, passive ones too) following a task trajectory.

    traj.x in m (and rad for phi). Rates come from the task Jacobian stacked, for a closed
    chain, on the constraint Jacobian:

    .. code:: text

        [Phi_q; J] qd = [0; xd],    [Phi_q; J] qdd = [gamma; xdd - Jdot qd]
    """
    from .seed_ik import SEED_SOLVERS

    solver = SEED_SOLVERS.get(robot.name)
    if solver is None:
        raise WorkspaceError(f"no closed-form inverse kinematics for {robot.name}; built in for "
                             f"{', '.join(SEED_SOLVERS)}")
    t, x = traj.t_s, traj.x
    q = solver(robot, t, x)
    N = len(t)
    _, J, _ = robot.task(q)
    J = J.reshape(N, len(robot.task_names), robot.n)
    zeros = np.zeros((N, robot.n_constraints))
    if robot.is_closed_chain:
        J = np.concatenate([robot.constraint_jacobian(q).reshape(N, -1, robot.n), J], axis=1)
    qd = solve_rates(robot, t, x, J, np.concatenate([zeros, traj.xd], axis=1))
    _, _, jdot_qd = robot.task(q, qd)
    gamma = robot.constraint_bias(q, qd).reshape(N, -1) if robot.is_closed_chain else zeros
    qdd = solve_rates(robot, t, x, J, np.concatenate([gamma, traj.xdd - jdot_qd], axis=1))
    return JointTrajectory(t, q, qd, qdd)
