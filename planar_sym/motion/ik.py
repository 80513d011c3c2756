"""Inverse kinematics: joint motion (every coordinate, passive ones too) along a task motion.

Positions come from the textbook's closed form for a built-in robot (``seed_ik``) or from the
generic Newton solver for any robot (``newton``); rates, for either, exactly from the task
Jacobian stacked on the constraint Jacobian:

.. code:: text

    [Phi_q; J] qd = [0; xd],    [Phi_q; J] qdd = [gamma; xdd - Jdot qd]

never finite differences.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model.arrays import as_samples
from ..model.kinematics import stacked_jacobian
from ..model.loops import COND_LIMIT
from ..model.robot import Robot
from . import newton
from .failures import Failures
from .profiles import JointTrajectory, Trajectory

SOLVERS = ("auto", "newton", "seed")
SEED_NAME = "seed closed form"
NEWTON_NAME = "newton"


def solve_rates(robot: Robot, t: np.ndarray, x: np.ndarray, J: np.ndarray, rhs: np.ndarray,
                cond: np.ndarray | None = None):
    """Solve J y = rhs per sample, refusing a singular pose by name and time.

    J (N, n, n), rhs (N, n); ``cond``, the 2-norm condition numbers of J, if already known.
    ``t`` (N,) are the times (s) and ``x`` (N, n_task) the targets (m, rad) an error names.
    Returns y, shape (N, n), in the units of rhs per unit of J.
    """
    fails = Failures(robot, t, x)
    _add_singular(fails, np.linalg.cond(J) if cond is None else cond)
    fails.raise_earliest()
    return np.linalg.solve(J, rhs[..., None])[..., 0]


def _add_singular(fails: Failures, cond: np.ndarray) -> np.ndarray:
    """Record singular samples (condition number above COND_LIMIT, or not finite); returns them."""
    bad = ~(cond <= COND_LIMIT)
    fails.add(bad, lambda k: f"is at a singular pose (Jacobian condition number {cond[k]:.3g} > "
                             f"{COND_LIMIT:g})")
    return bad


def _add_mode_change(fails: Failures, robot: Robot, A: np.ndarray, ok: np.ndarray) -> None:
    """Record a step across a singular pose of a closed chain's passive joints: det Phi_p
    changes sign between two samples (A (N, n, n) is [Phi_q; J], ``ok`` (N,) the samples to
    trust). [Phi_q; J] stays regular there, so the task is followed, but the mechanism driven
    at its actuated joints passes a Type II singularity (unbounded torques) into another
    assembly mode: refused, as ``motion.closure.solve_passive`` refuses it for joint motions."""
    if not robot.is_closed_chain:
        return
    m = robot.n_constraints
    pas = [i for i in range(robot.n) if i not in robot.actuated]
    if len(pas) != m:  # Phi_p not square: no assembly mode to keep
        return
    sign = np.sign(np.linalg.det(A[:, :m][:, :, pas]))
    flip = (sign[1:] != sign[:-1]) & ok[1:] & ok[:-1]
    t = fails.t
    fails.add(np.concatenate([[False], flip]), lambda k: (
        f"is reached across a singular pose of the passive joints from sample {k - 1} "
        f"(t = {t[k - 1]:.6g} s): det Phi_p changes sign, so the mechanism driven at its "
        "actuated joints would pass a Type II singularity (unbounded torques) into another "
        "assembly mode; keep the move on one side of the singular curve (planar-sym atlas "
        "draws it)"))


def choose_solver(robot: Robot, solver: str, q_start) -> str:
    """``"seed"`` or ``"newton"`` for a request of ``auto``, ``newton`` or ``seed``.

    The closed forms are the built-in robots' only (``robot.is_builtin``): a robot of the user's
    that is named like one gets Newton. ``auto`` picks the closed form where there is one,
    unless a start pose is given (only Newton can start from it).
    """
    from .seed_ik import SEED_SOLVERS

    if solver not in SOLVERS:
        raise InputError(f"unknown inverse-kinematics solver {solver!r}: use one of "
                         f"{', '.join(SOLVERS)}")
    has_seed = robot.is_builtin and robot.name in SEED_SOLVERS
    if solver == "seed":
        if not has_seed:
            where = "" if robot.is_builtin else f" (from {robot.library.folder})"
            raise InputError(f"{robot.name}{where}: solver 'seed' is the textbook's closed form "
                             f"of the built-in robots ({', '.join(SEED_SOLVERS)}), and this robot"
                             " is not one of them: use solver 'newton' or 'auto'")
        if q_start is not None:
            raise InputError(f"{robot.name}: the seed's closed form has fixed working modes and "
                             "cannot start from q_start: use solver 'newton' (or 'auto')")
        return "seed"
    if solver == "auto" and has_seed and q_start is None:
        return "seed"
    return "newton"


def inverse_kinematics(robot: Robot, traj: Trajectory, *, solver: str = "auto",
                       q_start=None) -> JointTrajectory:
    """Joint motion (every coordinate, passive ones too) following a task trajectory.

    Parameters
    ----------
    robot : Robot
    traj : Trajectory
        ``t_s`` (N,) s; ``x``, ``xd``, ``xdd`` (N, n_task) in m, m/s, m/s^2 (rad for phi).
    solver : {"auto", "newton", "seed"}
        "seed": the textbook's closed form (built-in robots only); "newton": the generic
        solver, continued from ``q_start``; "auto": the closed form where there is one and no
        ``q_start`` is given, else Newton.
    q_start : array_like, shape (n,), optional
        Newton's start pose (rad), default the drawn configuration: the working and assembly
        modes of the result are its.

    Returns
    -------
    JointTrajectory
        q (rad), qd (rad/s), qdd (rad/s^2), each (N, n), and ``solver``, the one that ran.

    Raises
    ------
    WorkspaceError
        A target out of reach, a singular pose, a step onto another branch (each naming the
        time, sample and target), or a robot whose task does not fix its coordinates.
    """
    if not isinstance(traj, Trajectory):
        raise InputError(f"inverse_kinematics needs a Trajectory of the task (planar_sym.cubic "
                         f"and the motion profiles make one), got {type(traj).__name__}")
    which = choose_solver(robot, solver, q_start)
    newton.check_square(robot)
    t = np.asarray(traj.t_s, dtype=float).reshape(-1)
    if not np.all(np.isfinite(t)):
        k = int(np.argmax(~np.isfinite(t)))
        raise InputError(f"trajectory: t_s[{k}] is {t[k]}: times must be finite (s)")
    nt = len(robot.task_names)
    x, xd, xdd = (as_samples(k, v, nt, times=t) for k, v in (("x", traj.x), ("xd", traj.xd),
                                                              ("xdd", traj.xdd)))
    if not len(x) == len(xd) == len(xdd) == len(t):
        raise InputError(f"trajectory: t_s ({len(t)} times) and x, xd, xdd ({len(x)}, "
                         f"{len(xd)}, {len(xdd)} samples) must match")
    fails = Failures(robot, t, x)
    if which == "seed":
        from .seed_ik import SEED_SOLVERS

        q, run = SEED_SOLVERS[robot.name](robot, t, x), None
    else:
        run = newton.solve(robot, t, x, q_start)
        newton.report_failure(fails, robot, run)
        q = run.q
    solved = len(q) if run is None or run.failed is None else run.failed
    N, zeros = len(t), np.zeros((len(t), robot.n_constraints))
    A = np.tile(np.eye(robot.n), (N, 1, 1))
    A[:solved], x_of_q, _ = stacked_jacobian(robot, q[:solved])
    if run is not None:
        newton.verify(fails, robot, q[:solved], x_of_q, x[:solved])
    cond = np.full(N, np.inf)
    cond[:solved] = np.linalg.cond(A[:solved])
    singular = _add_singular(fails, cond[:solved])
    ok = np.zeros(N, dtype=bool)
    ok[:solved] = ~singular
    A[~ok] = np.eye(robot.n)  # placeholders: those samples are reported, never returned
    qd = np.linalg.solve(A, np.concatenate([zeros, xd], axis=1)[..., None])[..., 0]
    if run is not None:
        newton.branch_check(fails, t, q, qd, ok)
    _add_mode_change(fails, robot, A, ok)
    fails.raise_earliest()
    _, _, jdot_qd = robot.task(q, qd)
    gamma = robot.constraint_bias(q, qd).reshape(N, -1) if robot.is_closed_chain else zeros
    qdd = np.linalg.solve(A, np.concatenate([gamma, xdd - jdot_qd], axis=1)[..., None])[..., 0]
    return JointTrajectory(t, q, qd, qdd, SEED_NAME if which == "seed" else NEWTON_NAME)
