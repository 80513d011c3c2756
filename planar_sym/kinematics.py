"""The seed's closed-form inverse kinematics, with exact joint rates from the task Jacobian.

Positions follow the seed's listings (elbow choice, ``th1 += 2 pi`` wrap, 2-DOF joint limits),
but take every length from the robot's own parameter vector, so that forward kinematics of the
solution returns the target to rounding. Rates are exact, never finite differences:

.. code:: text

    qd = J^-1 xd,    qdd = J^-1 (xdd - Jdot qd)

Where the seed silently held its last solution outside the workspace, this raises
WorkspaceError naming the time and the target.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .dynamics import Robot
from .errors import WorkspaceError
from .trajectory import Trajectory

#: a joint angle within this of a limit (rad) counts as on it: the seed's start poses sit
#: exactly on q1 = 0, where atan2 returns +-1e-17 and the seed's own check would flicker.
ANGLE_TOL_RAD = 1e-9

#: a Jacobian whose condition number exceeds this is called singular. Near a singularity the
#: condition number grows like 1 / distance, and joint rates and torques with it: at 1e6 they
#: are already about a million times their size at a well-conditioned pose.
COND_LIMIT = 1e6


@dataclass(frozen=True)
class JointTrajectory:
    """Joint motion at times ``t_s``: q (rad), qd (rad/s), qdd (rad/s^2), each (N, n)."""

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


def _describe(robot: Robot, x: np.ndarray) -> str:
    parts = []
    for name, v in zip(robot.task_names, x):
        parts.append(f"{name} = {v:.6g} rad" if name == "phi" else f"{name} = {v * 1e3:.6g} mm")
    return "(" + ", ".join(parts) + ")"


class Failures:
    """Collects failing samples of every IK check, then reports the earliest of them all."""

    def __init__(self, robot: Robot, t: np.ndarray, x: np.ndarray):
        self.robot, self.t, self.x = robot, t, x
        self.found: list[tuple[int, str]] = []

    def add(self, bad: np.ndarray, why: Callable[[int], str]) -> None:
        if bad.any():
            k = int(np.argmax(bad))
            self.found.append((k, why(k)))

    def raise_earliest(self) -> None:
        if self.found:
            k, why = min(self.found, key=lambda f: f[0])
            raise WorkspaceError(f"{self.robot.name}: target {_describe(self.robot, self.x[k])} "
                                 f"at t = {self.t[k]:.6g} s (sample {k}) {why}")


def _two_link(fails: Failures, px, py, a1, a2, elbow: float, wrap: bool = True,
              what: str = ""):
    """Seed's 2-link solution: th2 = elbow * acos(kappa), th1 from atan2 (wrapped to
    [0, 2 pi) as the serial listings do when ``wrap``). Unreachable samples are recorded in
    ``fails`` and computed with kappa clipped (as the seed does) so later checks still run."""
    kappa = (px**2 + py**2 - a1**2 - a2**2) / (2 * a1 * a2)
    fails.add(np.abs(kappa) > 1, lambda k: f"is outside the workspace ({what + ': ' if what else ''}"
                                           f"cos of the elbow angle would be {kappa[k]:.6g}, "
                                           "beyond +-1)")
    th2 = elbow * np.arccos(np.clip(kappa, -1.0, 1.0))
    delta = a1**2 + a2**2 + 2 * a1 * a2 * np.cos(th2)
    c1 = (px * (a1 + a2 * np.cos(th2)) + py * a2 * np.sin(th2)) / delta
    s1 = (-px * a2 * np.sin(th2) + py * (a1 + a2 * np.cos(th2))) / delta
    th1 = np.arctan2(s1, c1)
    if wrap:
        th1 = np.where(th1 < -ANGLE_TOL_RAD, th1 + 2 * np.pi, th1)  # seed: 0 < th < 360
    return th1, th2


def _params(robot: Robot, *names: str) -> list[float]:
    p = robot.parameters
    return [p.get(n, 0.0) for n in names]


def _check_on_axis(robot: Robot, *names: str) -> None:
    off = [n for n in names if robot.parameters.get(n, 0.0) != 0.0]
    if off:
        raise WorkspaceError(f"{robot.name}: the seed's closed-form IK assumes joints and tool on "
                             f"the link axes, but {', '.join(off)} are non-zero")


def ik_serial_2dof(robot: Robot, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Seed listing: elbow down (th2 = +acos), joint limits 0 <= th1 <= pi, pi/6 <= th2 <= 5pi/6."""
    _check_on_axis(robot, "py_link1_CS2", "py_link2_CS2")
    a1, a2 = _params(robot, "px_link1_CS2", "px_link2_CS2")
    fails = Failures(robot, t, x)
    th1, th2 = _two_link(fails, x[:, 0], x[:, 1], a1, a2, +1.0)
    tol = ANGLE_TOL_RAD
    fails.add((th1 < -tol) | (th1 > np.pi + tol),
              lambda k: f"violates the joint limit 0 <= q1 <= 180 deg "
                        f"(q1 = {np.degrees(th1[k]):.6g} deg)")
    fails.add((th2 < np.pi / 6 - tol) | (th2 > 5 * np.pi / 6 + tol),
              lambda k: f"violates the joint limit 30 <= q2 <= 150 deg "
                        f"(q2 = {np.degrees(th2[k]):.6g} deg)")
    fails.raise_earliest()
    return np.column_stack([th1, th2])


def ik_serial_3dof(robot: Robot, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Seed listing: wrist p = x - a3 (cos phi, sin phi), elbow down, q3 = phi - q1 - q2.

    The seed's listing is cut off after q1; ``q3 = phi - q1 - q2`` completes it.
    """
    _check_on_axis(robot, "py_link1_CS2", "py_link2_CS2", "py_link3_CS2")
    a1, a2, a3 = _params(robot, "px_link1_CS2", "px_link2_CS2", "px_link3_CS2")
    phi = x[:, 2]
    px, py = x[:, 0] - a3 * np.cos(phi), x[:, 1] - a3 * np.sin(phi)
    fails = Failures(robot, t, x)
    th1, th2 = _two_link(fails, px, py, a1, a2, +1.0)
    fails.raise_earliest()
    return np.column_stack([th1, th2, phi - th1 - th2])


IK_SOLVERS: dict[str, Callable[[Robot, np.ndarray, np.ndarray], np.ndarray]] = {
    "serial_2dof": ik_serial_2dof,
    "serial_3dof": ik_serial_3dof,
}


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
    from .closed_ik import CLOSED_IK_SOLVERS

    solver = IK_SOLVERS.get(robot.name) or CLOSED_IK_SOLVERS.get(robot.name)
    if solver is None:
        raise WorkspaceError(f"no closed-form inverse kinematics for {robot.name}; built in for "
                             f"{', '.join([*IK_SOLVERS, *CLOSED_IK_SOLVERS])}")
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
