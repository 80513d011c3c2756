"""The square Jacobian of a robot whose task and loops fix every coordinate: the loops'
constraint Jacobian stacked on the task Jacobian, K = [Phi_q; J] (J alone for a tree). The
generic inverse kinematics solves with it, and the pose measures (atlas, envelope) read their
conditioning from it."""

from __future__ import annotations

import numpy as np


def stacked_jacobian(robot, q: np.ndarray, qd=None
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """K = [Phi_q; J] (N, n, n), the task coordinates x(q) (N, n_task) and Jdot qd (N, n_task)
    at the poses ``q`` (N, n) in rad (m at a slider), with rates ``qd`` (N, n), default zero;
    N may be 0 (nothing solved)."""
    n, nt = robot.n, len(robot.task_names)
    if len(q) == 0:
        return np.zeros((0, n, n)), np.zeros((0, nt)), np.zeros((0, nt))
    q = np.atleast_2d(q)  # (the robot's functions answer 2-D samples in their own shapes)
    x, J, jdq = robot.task(q, qd)
    if robot.is_closed_chain:
        J = np.concatenate([robot.constraint_jacobian(q), J], axis=1)
    return J, x, jdq
