"""Generic inverse kinematics for any robot whose task and loops fix every coordinate: Newton on

.. code:: text

    F(q) = [Phi(q); x(q) - x*(t_k)] = 0,    dF/dq = [Phi_q; J]   (square: m + n_task = n)

continued sample to sample from a start pose (default the drawn configuration), so the working
and assembly modes are the start pose's. The loop over the samples runs in C (``_newton.c``)
on the robot's compiled ``task``, ``constraint`` and ``constraint_jacobian`` functions; between
samples it follows the straight line in task space, in shorter steps where Newton needs a large
correction or would change the sign of det [Phi_q; J] (which happens only across a singular
pose, where modes meet), so coarse sampling does not jump to another branch. After solving,
every step is checked against the exact joint rates (``branch_check``).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import WorkspaceError
from ..model.arrays import as_vector
from ..model.compile import load_helper
from ..model.kinematics import stacked_jacobian
from ..model.loops import COND_LIMIT
from ..model.robot import Robot
from .failures import Failures

#: converged when |F|_inf <= NEWTON_TOL * (1 + |x*|_inf) (m, rad): a few hundred times the
#: rounding of x(q) at these robots' sizes (~3e-17 m at 0.2 m), so the angles are exact to
#: ~1e-15 rad at a well-conditioned pose (measured against the closed forms, worst 3e-15 rad
#: where the closed form itself is accurate: tests/test_generic_ik.py)
NEWTON_TOL = 1e-14
#: ... or when a correction is below this (rad): the error left is then ~10 STEP_TOL^2 rad
#: (quadratic convergence), and every solution's residual is checked afterwards (``verify``)
STEP_TOL = 1e-9
#: a solution is accepted when its task and loop residual, evaluated afterwards in one batch,
#: is below this times (1 + |x*|_inf) (m, rad)
VERIFY_TOL = 1e-12
#: a Newton correction larger than this (rad) is not trusted: the step between targets is
#: halved. Away from singular poses the branches are much further apart (the 2-DOF elbow's
#: +-q2 are 1 rad apart at q2 = 30 deg); near one, the sign of det [Phi_q; J] keeps the branch
DQ_MAX = 0.1
#: corrections must shrink at least this fast (|dq_i| <= THETA |dq_i-1|) or the step is halved:
#: inside Newton's basin they shrink quadratically (ratios of 1e-3 and less)
THETA = 0.5
MAX_ITER = 12
#: the step between two targets is halved at most down to this fraction (2^-20)
MIN_FRACTION = 2.0**-20
#: branch check (``branch_check``): a joint's step may leave the interval its exact rates at the
#: two samples allow by this fraction of the step. On a smooth motion it leaves it only where
#: the rate has an extremum inside the step, by O(dt^2) of it (a cubic from rest sampled at
#: 4 times: 8 %); an elbow that flips to its mirror image misses by ~100 % of the step.
BRANCH_REL = 0.5
#: ... plus this absolute slack (rad): a robot at rest has steps of rounding size
BRANCH_ABS = 1e-9

#: why the last attempt at the failing step stopped (codes of _newton.c)
_CODES = {1: "the corrections did not converge",
          2: "[Phi_q; J] is exactly singular there",
          3: "a generated function failed", 4: "too many coordinates for the solver (32)",
          5: "a step further crosses a singular pose, where det [Phi_q; J] changes sign"}


def check_square(robot: Robot) -> None:
    """Refuse a robot whose task and loops do not fix every coordinate, or whose motors cannot
    give unique torques: task-space inverse kinematics needs n_task + n_constraints == n, and
    torques are unique only when n_actuated == n - n_constraints (the degrees of freedom)."""
    n, m, nt, na = robot.n, robot.n_constraints, len(robot.task_names), len(robot.actuated)
    dof = n - m
    counts = (f"{n} coordinate{'s' * (n != 1)}, {m} loop equation{'s' * (m != 1)} "
              f"({dof} degree{'s' * (dof != 1)} of freedom), a {nt}-coordinate task "
              f"({', '.join(robot.task_names) or 'none'}) and {na} actuated joint"
              f"{'s' * (na != 1)}")
    if nt != dof:
        fix = ("drive its actuated joint" + ("s" * (na != 1)) + " in joint space instead "
               "(a study's motion.space = \"joint\", or ps.from_actuated)"
               if nt > dof else "the task leaves joints free: add task coordinates (an "
               "orientation) or drive the joints in joint space")
        raise WorkspaceError(f"{robot.name}: no inverse kinematics in task space: it has "
                             f"{counts}; the task must fix the {dof} degree"
                             f"{'s' * (dof != 1)} of freedom, so {nt} != {dof}: {fix}")
    if na != dof:
        raise WorkspaceError(f"{robot.name}: it has {counts}: torques are unique only with one "
                             f"motor per degree of freedom ({na} != {dof})")


@dataclass(frozen=True)
class NewtonRun:
    """Positions of the solved samples and what the C loop reports.

    ``q`` (N, n) rad: rows from ``failed`` on are NaN; ``failed`` is the first sample not
    solved (None: all), ``code`` why (1 no convergence, 2 exactly singular, 5 a singular pose
    crossed: see ``_CODES``),
    ``closest`` (n,) the pose closest to it that was found, ``residual`` the |F|_inf (m, rad)
    there, ``reached`` the fraction of the last step solved; ``iterations`` (corrections),
    ``evaluations`` (of F) and ``halvings`` (of a step between targets): totals over the run.
    """

    q: np.ndarray
    failed: int | None
    code: int
    closest: np.ndarray | None
    residual: float
    reached: float
    iterations: int
    evaluations: int
    halvings: int


def verify(fails: Failures, robot: Robot, q: np.ndarray, x_of_q: np.ndarray,
           target: np.ndarray) -> None:
    """Record solutions whose residual |[Phi(q); x(q) - x*]|_inf exceeds VERIFY_TOL (1 + |x*|):
    the C loop stops on small corrections without evaluating the last one."""
    res = np.max(np.abs(x_of_q - target), axis=1) if len(q) else np.zeros(0)
    if robot.is_closed_chain and len(q):
        res = np.maximum(res, np.max(np.abs(robot.constraint(q).reshape(len(q), -1)), axis=1))
    limit = VERIFY_TOL * (1 + np.max(np.abs(target), axis=1)) if len(q) else res
    fails.add(~(res <= limit), lambda k: (
        f"is missed by the solution found (|F| = {res[k]:.3g} after Newton, limit "
        f"{limit[k]:.3g}): the pose is too ill-conditioned to solve accurately"))


def start_pose(robot: Robot, q_start) -> np.ndarray:
    """The start pose (rad), default the drawn configuration; refused where it is singular,
    as it then does not choose a working mode."""
    q0 = as_vector("q_start", robot.q_drawn if q_start is None else q_start, robot.n)
    cond = float(np.linalg.cond(stacked_jacobian(robot, q0[None])[0][0]))
    if not (cond <= COND_LIMIT):
        what = "drawn configuration" if q_start is None else "start pose"
        raise WorkspaceError(
            f"{robot.name}: the {what} q = {np.round(q0, 6).tolist()} rad is singular "
            f"([Phi_q; J] condition number {cond:.3g} > {COND_LIMIT:g}), so it does not choose "
            "a working mode: give a start pose in the mode you want (q_start, or a study's "
            "motion.start_pose), e.g. with the elbow bent")
    return q0


def solve(robot: Robot, t: np.ndarray, x: np.ndarray, q_start=None) -> NewtonRun:
    """Newton continued over the samples in C, on a robot whose task and loops fix every
    coordinate (``check_square``, which ``ik.inverse_kinematics`` asks once, at its entry).

    Parameters
    ----------
    t : ndarray, shape (N,)
        Times (s); only their ratios matter (the predictor's extrapolation).
    x : ndarray, shape (N, n_task)
        Targets (m; rad for phi).
    q_start : array_like, shape (n,), optional
        Start pose (rad), default ``robot.q_drawn``: its working and assembly modes are kept.
    """
    q0 = start_pose(robot, q_start)
    n, m, nt, N = robot.n, robot.n_constraints, len(robot.task_names), len(t)
    lib = robot.library
    t = np.ascontiguousarray(t, dtype=float)
    x = np.ascontiguousarray(x, dtype=float)
    opts = np.array([NEWTON_TOL, DQ_MAX, THETA, MAX_ITER, MIN_FRACTION, STEP_TOL])
    q = np.full((N, n), np.nan)
    info = np.zeros(5)
    k_fail = ctypes.c_longlong(-1)
    # one call for F and dF/dq where the robot was derived with it (shared sines: the 3-RRR's
    # Newton step costs about a third less), else task, Phi and Phi_q one by one
    fused = "ik_terms" in lib.manifest["functions"]
    rc = _newton()(n, m, nt, robot.p.ctypes.data, lib.address("task"),
                   lib.address("constraint") if m else None,
                   lib.address("constraint_jacobian") if m else None,
                   lib.address("ik_terms") if fused else None, N, t.ctypes.data,
                   x.ctypes.data, q0.ctypes.data, opts.ctypes.data, q.ctypes.data,
                   ctypes.byref(k_fail), info.ctypes.data)
    if rc not in (0, 1, 2, 5):
        raise WorkspaceError(f"{robot.name}: generic inverse kinematics failed at sample "
                             f"{k_fail.value}: {_CODES.get(rc, rc)}")
    failed = None if rc == 0 else int(k_fail.value)
    closest = None if failed is None else q[failed].copy()
    if failed is not None:
        q[failed:] = np.nan
    return NewtonRun(q, failed, rc, closest, float(info[0]), float(info[1]), int(info[2]),
                     int(info[3]), int(info[4]))


def report_failure(fails: Failures, robot: Robot, run: NewtonRun) -> None:
    """Record the sample Newton could not reach (if any) in ``fails``, with the residual it
    reached and, where the closest pose found is singular, that it is at the workspace's edge."""
    if run.failed is None:
        return
    k = run.failed
    bad = np.zeros(len(run.q), dtype=bool)
    bad[k] = True
    unit = "m, rad" if "phi" in robot.task_names else "m"
    origin = f"sample {k - 1}" if k else "the start pose"
    cond = float(np.linalg.cond(stacked_jacobian(robot, run.closest[None])[0][0]))
    edge = (f", a singular pose ([Phi_q; J] condition number {cond:.3g} > {COND_LIMIT:g}): the "
            "target is at or beyond the edge of the workspace" if not cond <= COND_LIMIT else "")
    fails.add(bad, lambda _: (
        f"is unreachable (outside the workspace, or beyond a singular pose on the way from "
        f"{origin}): Newton does not converge (|F| reached {run.residual:.3g} {unit} at the "
        f"closest pose found, {run.reached:.0%} of the way from {origin}{edge}; "
        f"{_CODES[run.code]})"))


def branch_check(fails: Failures, t: np.ndarray, q: np.ndarray, qd: np.ndarray,
                 ok: np.ndarray) -> None:
    """Record steps that the exact rates cannot account for: another branch, or too coarse.

    By the mean value theorem each joint's step is dt times its rate somewhere between the two
    samples, so it lies between dt qd_k and dt qd_k+1 wherever the rate is monotone over the
    step. A step is refused (named at sample k + 1) when a joint lands outside that interval by
    more than BRANCH_REL of the step's size, max(|q_k+1 - q_k|, dt |qd_k|, dt |qd_k+1|)_inf,
    plus BRANCH_ABS. ``ok`` (N,) marks samples whose q and qd can be trusted; steps touching
    others are skipped.
    """
    if len(q) < 2:
        return
    dt = np.diff(t)[:, None]
    step = np.diff(q, axis=0)
    lo = np.minimum(dt * qd[:-1], dt * qd[1:])
    hi = np.maximum(dt * qd[:-1], dt * qd[1:])
    with np.errstate(invalid="ignore"):
        out = np.maximum(lo - step, step - hi)  # > 0 outside [lo, hi]
        size = np.maximum(np.max(np.abs(step), axis=1), np.max(np.abs(hi), axis=1))
        size = np.maximum(size, np.max(np.abs(lo), axis=1))
        worst = np.argmax(np.where(np.isfinite(out), out, -np.inf), axis=1)
        miss = out[np.arange(len(out)), worst]
        bad = (miss > BRANCH_REL * size + BRANCH_ABS) & ok[1:] & ok[:-1]
    names = fails.robot.coordinates

    def why(k: int) -> str:
        j, i = worst[k - 1], k - 1
        return (f"is on another branch than sample {i}, or the samples are too coarse to follow "
                f"the motion: from sample {i} joint {names[j]} moves by {step[i, j]:.3g} rad, "
                f"but its exact rates at the two samples ({qd[i, j]:.3g} and {qd[k, j]:.3g} "
                f"rad/s over {dt[i, 0]:.3g} s) account for {lo[i, j]:.3g} to {hi[i, j]:.3g} "
                f"rad: use more samples")

    fails.add(np.concatenate([[False], bad]), why)


_NEWTON = None


def _newton():
    """``planar_sym_ik_newton`` from _newton.c (compiled once per source hash), via ctypes."""
    global _NEWTON
    if _NEWTON is None:
        fn = load_helper(Path(__file__).resolve().parent / "_newton.c").planar_sym_ik_newton
        i, ptr = ctypes.c_int, ctypes.c_void_p
        fn.argtypes = [i, i, i, ptr, ptr, ptr, ptr, ptr, ctypes.c_longlong, ptr, ptr, ptr, ptr,
                       ptr, ptr, ptr]
        fn.restype = i
        _NEWTON = fn
    return _NEWTON
