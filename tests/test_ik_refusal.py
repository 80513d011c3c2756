"""The generic inverse kinematics refuses a solution that Newton accepted on a small step while
its residual is still above the limit (``newton.verify``, the check after the C loop), rather
than returning the pose.

The C loop (planar_sym/motion/_newton.c) stops when a correction is below STEP_TOL = 1e-9 rad
without evaluating the residual again; the caller then checks |[Phi; x(q) - x*]|_inf against
VERIFY_TOL (1 + |x*|_inf) = 1e-12 (1 + |x*|). The residual stays above that where x(q) cannot
be evaluated to 1e-12 m: here the 2-DOF arm (a1 = a2 = 0.1 m, seed Table 1) whose shoulder has
turned 159155 times (q1 ~ 1e6 rad, e.g. a joint turning continuously for hours): doubles are
1.16e-10 rad apart there, so x(q) = a1 (cos q1, sin q1) + a2 (cos(q1 + q2), sin(q1 + q2))
moves in steps of ~1e-11 m. The reference is independent of the solver: the exact solution in
closed form (law of cosines), and every pose made of the doubles within 6 spacings of it
evaluated by that formula in numpy: none meets the limit, so no solver could have. The same
motion from the same pose with the turns taken off is solved, to the closed form.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import newton

A = 0.1  # m: serial_2dof's two links (planar_sym/robots/serial_2dof.toml)
TURNS = 159155  # 2 pi TURNS = 1.000001e6 rad
Q0 = np.array([0.5, 1.0])  # rad: elbow bent (q2 > 0), a well-conditioned pose
T = 2.0
TIMES = np.linspace(0.0, T, 9)
LIMIT_REL = 1e-12  # newton.VERIFY_TOL, as documented there


def tip(q1, s):
    """The 2-link arm's tip (m) for shoulder angle q1 and absolute elbow angle s = q1 + q2."""
    return A * np.stack([np.cos(q1) + np.cos(s), np.sin(q1) + np.sin(s)], axis=-1)


def closed_form(x):
    """Elbow-down (q2 > 0) solution (rad) for targets x (N, 2), law of cosines."""
    r = np.hypot(x[:, 0], x[:, 1])
    q2 = np.arccos((r**2 - 2 * A**2) / (2 * A**2))
    return np.column_stack([np.arctan2(x[:, 1], x[:, 0]) - q2 / 2, q2])


def best_double_residual(x):
    """The smallest |tip(q1, s) - x|_inf over the doubles q1, s within 6 spacings of the exact
    solution turned by TURNS (the task function rounds s = q1 + q2 to a double too)."""
    q = closed_form(x[None])[0]
    q1 = q[0] + 2 * np.pi * TURNS
    s = q1 + q[1]
    grid = np.arange(-6, 7) * np.spacing(q1)
    Q1, S = np.meshgrid(q1 + grid, s + grid)
    return float(np.min(np.max(np.abs(tip(Q1, S) - x), axis=-1)))


@pytest.fixture(scope="module")
def move():
    x0 = tip(Q0[0], Q0[0] + Q0[1])
    return ps.cubic(x0, [-0.05, 0.0], T, TIMES)


def test_a_stalled_newton_is_refused(move):
    """From q_start = (0.5 + 2 pi 159155, 1.0) rad: the C loop accepts every sample (it stops on
    small corrections), yet no pose of doubles near the solution meets the limit (best over the
    neighbouring doubles >= 2 x the limit at every sample, from the closed form): refused at
    sample 0, naming the residual and the limit, instead of returning the poses."""
    robot = ps.load("serial_2dof")
    start = Q0 + [2 * np.pi * TURNS, 0.0]
    limits = LIMIT_REL * (1 + np.max(np.abs(move.x), axis=1))
    best = np.array([best_double_residual(x) for x in move.x])
    assert np.all(best > 2 * limits), best / limits
    run = newton.solve(robot, TIMES, move.x, start)  # the stall: the C loop reports success
    assert run.failed is None and run.code == 0
    with pytest.raises(WorkspaceError, match=r"is missed by the solution found \(\|F\| = "
                                             r"[0-9.e+-]+ after Newton, limit [0-9.e+-]+\): the "
                                             r"pose is too ill-conditioned to solve "
                                             r"accurately") as exc:
        ps.inverse_kinematics(robot, move, solver="newton", q_start=start)
    msg = str(exc.value)
    assert "serial_2dof: target (x = " in msg and "at t = 0 s (sample 0)" in msg, msg
    found = re.search(r"\|F\| = ([0-9.e+-]+) after Newton, limit ([0-9.e+-]+)\)", msg)
    residual, limit = float(found.group(1)), float(found.group(2))
    assert limit == pytest.approx(limits[0], rel=1e-2)
    # what Newton reached is no better than the best pose there is, and rounding-sized
    assert best[0] * (1 - 1e-2) <= residual < 1e-10
    print(f"\nq1 ~ {start[0]:.7g} rad: |F| = {residual:.3g} m at sample 0 (limit {limit:.3g} m; "
          f"best over neighbouring doubles {best[0]:.3g} m, at every sample >= "
          f"{np.min(best / limits):.2f} x the limit)")


def test_the_same_move_without_the_turns_is_solved(move):
    """Control: the same poses with q1 near 0.5 rad are solved, equal to the closed form to
    1e-12 rad, so the refusal above is the angles' rounding, not the motion."""
    robot = ps.load("serial_2dof")
    jt = ps.inverse_kinematics(robot, move, solver="newton", q_start=Q0)
    assert jt.solver == "newton"
    assert np.max(np.abs(jt.q - closed_form(move.x))) < 1e-12
