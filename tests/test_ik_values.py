"""Task-space inverse kinematics (``motion/ik.py``, ``motion/newton.py``) held to real numbers and
exact messages, against references independent of the solver:

- the 2-DOF arm (a1 = a2 = 0.1 m, seed Table 1) in closed form: elbow angle from the law of
  cosines, its forward kinematics x(q), Jacobian J and Jdot qd written out by hand;
- the closed chain (5-bar Type I): its loops Phi(q) = 0, Phi_q qd = 0, and the rates and
  accelerations against central differences of the positions and rates;
- the condition-number and residual limits at their exact edges (inputs built so that the
  compared value is exactly the limit), and every refusal's message word for word.
"""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError, WorkspaceError
from planar_sym.motion import ik, newton
from planar_sym.motion.failures import Failures
from planar_sym.motion.profiles import Trajectory

A = 0.1  # m: serial_2dof's two links (planar_sym/robots/serial_2dof.toml)
Q0 = np.array([0.5, 1.0])  # rad: elbow bent (q2 > 0), well conditioned
LIMIT = 1e6  # the condition-number limit documented in planar_sym/model/loops.py
SEEDS = "serial_2dof, serial_3dof, five_bar_type1, five_bar_type2, parallel_3rrr"


# -- the 2-DOF arm by hand ---------------------------------------------------------------------

def fk2(q):
    """Tip (m) of the 2-link arm, q (N, 2) rad."""
    s = q[:, 0] + q[:, 1]
    return A * np.column_stack([np.cos(q[:, 0]) + np.cos(s), np.sin(q[:, 0]) + np.sin(s)])


def ik2(x, elbow=1.0):
    """Closed form (rad): q2 = +-arccos((r^2 - a1^2 - a2^2) / (2 a1 a2)), law of cosines."""
    r2 = x[:, 0] ** 2 + x[:, 1] ** 2
    q2 = elbow * np.arccos((r2 - 2 * A**2) / (2 * A**2))
    q1 = np.arctan2(x[:, 1], x[:, 0]) - np.arctan2(A * np.sin(q2), A + A * np.cos(q2))
    return np.column_stack([q1, q2])


def jac2(q):
    s1, c1 = np.sin(q[:, 0]), np.cos(q[:, 0])
    s12, c12 = np.sin(q[:, 0] + q[:, 1]), np.cos(q[:, 0] + q[:, 1])
    return A * np.stack([np.stack([-s1 - s12, -s12], -1), np.stack([c1 + c12, c12], -1)], 1)


def jdot_qd2(q, qd):
    w1, w12 = qd[:, 0], qd[:, 0] + qd[:, 1]
    s1, c1 = np.sin(q[:, 0]), np.cos(q[:, 0])
    s12, c12 = np.sin(q[:, 0] + q[:, 1]), np.cos(q[:, 0] + q[:, 1])
    return -A * np.column_stack([c1 * w1**2 + c12 * w12**2, s1 * w1**2 + s12 * w12**2])


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


@pytest.fixture(scope="module")
def five():
    return ps.load("five_bar_type1")


def arm_move(n=41, dx=(-0.05, 0.03), T=2.0):
    x0 = fk2(Q0[None])[0]
    return ps.cubic(x0, list(dx), T, np.linspace(0.0, T, n))


@pytest.mark.parametrize("solver", ["newton", "seed"])
def test_two_link_against_closed_form(arm, solver):
    """Positions equal the law of cosines' elbow-down solution; x(q) is the target to 1e-12 m;
    J qd = xd and J qdd + Jdot qd = xdd with J and Jdot qd written out by hand."""
    traj = arm_move()
    jt = ik.inverse_kinematics(arm, traj, solver=solver,
                               q_start=Q0 if solver == "newton" else None)
    assert jt.solver == {"newton": "newton", "seed": "seed closed form"}[solver]
    assert jt.t_s.dtype == np.float64 and jt.t_s.shape == (41,)
    assert np.array_equal(jt.t_s, traj.t_s)
    assert jt.q.shape == jt.qd.shape == jt.qdd.shape == (41, 2)
    assert np.max(np.abs(jt.q - ik2(traj.x))) < 1e-12
    assert np.max(np.abs(fk2(jt.q) - traj.x)) < 1e-12
    J = jac2(jt.q)
    assert np.max(np.abs(np.einsum("kij,kj->ki", J, jt.qd) - traj.xd)) < 1e-14
    xdd = np.einsum("kij,kj->ki", J, jt.qdd) + jdot_qd2(jt.q, jt.qd)
    assert np.max(np.abs(xdd - traj.xdd)) < 1e-13
    # the rates are really moving (Jdot qd is not negligible: a dropped term would show)
    assert np.max(np.abs(jdot_qd2(jt.q, jt.qd))) > 1e-3
    # rates against central differences of the positions (dt = 0.05 s: O(dt^2) agreement)
    dt = traj.t_s[1] - traj.t_s[0]
    fd_qd = (jt.q[2:] - jt.q[:-2]) / (2 * dt)
    fd_qdd = (jt.qd[2:] - jt.qd[:-2]) / (2 * dt)
    assert np.max(np.abs(fd_qd - jt.qd[1:-1])) < 2e-3 * np.max(np.abs(jt.qd))
    assert np.max(np.abs(fd_qdd - jt.qdd[1:-1])) < 2e-2 * np.max(np.abs(jt.qdd))


def test_two_link_elbow_up_is_the_other_root(arm):
    traj = arm_move(n=9)
    jt = ik.inverse_kinematics(arm, traj, solver="newton", q_start=[Q0[0] + Q0[1], -Q0[1]])
    assert np.max(np.abs(jt.q - ik2(traj.x, elbow=-1.0))) < 1e-12


def test_integer_and_column_times_are_taken_as_floats(arm):
    """t_s given as integers, or as a column (N, 1): the result's times are float, shape (N,)."""
    x0 = fk2(Q0[None])[0]
    traj = ps.cubic(x0, [-0.02, 0.01], 4.0, [0, 1, 2, 3, 4])
    ints = Trajectory(np.array([0, 1, 2, 3, 4]), traj.x, traj.xd, traj.xdd)
    column = Trajectory(np.arange(5.0)[:, None], traj.x, traj.xd, traj.xdd)
    for solver in ("seed", "newton"):
        for given in (ints, column):
            jt = ik.inverse_kinematics(arm, given, solver=solver,
                                       q_start=Q0 if solver == "newton" else None)
            assert jt.t_s.dtype == np.float64 and jt.t_s.shape == (5,)
            assert np.array_equal(jt.t_s, [0.0, 1.0, 2.0, 3.0, 4.0])
            assert np.max(np.abs(jt.q - ik2(traj.x))) < 1e-12


@pytest.mark.parametrize("solver", ["newton", "seed"])
def test_five_bar_closes_its_loops(five, solver):
    """5-bar Type I: x(q) the target, Phi(q) = 0 and Phi_q qd = 0 to 1e-12; qd and qdd against
    central differences of q and qd (201 samples over 2 s: dt^2 = 1e-4)."""
    t = np.linspace(0.0, 2.0, 201)
    traj = ps.cubic([0.060852, 0.154665], [0.03, -0.02], 2.0, t)
    jt = ik.inverse_kinematics(five, traj, solver=solver,
                               q_start=five.q_drawn if solver == "newton" else None)
    x, J, jdq = five.task(jt.q, jt.qd)
    assert np.max(np.abs(x - traj.x)) < 1e-12
    assert np.max(np.abs(five.constraint(jt.q))) < 1e-12
    assert np.max(np.abs(np.einsum("kij,kj->ki", J, jt.qd) - traj.xd)) < 1e-12
    phiq = five.constraint_jacobian(jt.q).reshape(len(t), -1, 4)
    assert np.max(np.abs(np.einsum("kij,kj->ki", phiq, jt.qd))) < 1e-12
    assert np.max(np.abs(np.einsum("kij,kj->ki", J, jt.qdd) + jdq - traj.xdd)) < 1e-12
    dt = t[1] - t[0]
    fd_qd = (jt.q[2:] - jt.q[:-2]) / (2 * dt)
    fd_qdd = (jt.qd[2:] - jt.qd[:-2]) / (2 * dt)
    assert np.max(np.abs(fd_qd - jt.qd[1:-1])) < 1e-4 * np.max(np.abs(jt.qd))
    assert np.max(np.abs(fd_qdd - jt.qdd[1:-1])) < 1e-3 * np.max(np.abs(jt.qdd))
    # the passive joints' accelerations are not those of an open chain (gamma matters)
    assert np.max(np.abs(jt.qdd[:, [1, 3]])) > 1e-2


# -- refusals, word for word -------------------------------------------------------------------

def test_refuses_what_is_not_a_trajectory(arm):
    with pytest.raises(InputError) as exc:
        ik.inverse_kinematics(arm, {"t_s": [0.0]})
    assert str(exc.value) == ("inverse_kinematics needs a Trajectory of the task (planar_sym.cubic "
                              "and the motion profiles make one), got dict")


def test_refuses_mismatched_or_bad_samples(arm):
    """Lengths that differ, a time that is not finite, and a non-finite sample named by its
    array, index and time."""
    traj = arm_move(n=9)
    t, x, xd, xdd = traj.t_s, traj.x, traj.xd, traj.xdd
    cases = [
        (Trajectory(t, x, xd[:5], xdd),
         "trajectory: t_s (9 times) and x, xd, xdd (9, 5, 9 samples) must match"),
        (Trajectory(t[:8], x[:8], xd[:8], xdd),
         "trajectory: t_s (8 times) and x, xd, xdd (8, 8, 9 samples) must match"),
        (Trajectory(np.r_[t[:8], np.nan], x, xd, xdd),
         "trajectory: t_s[8] is nan: times must be finite (s)"),
        (Trajectory(t, x, xd[:, :1], xdd), "xd must have shape (N, 2) or (2,), got (9, 1)"),
        (Trajectory(t, x[:, :1], xd, xdd), "x must have shape (N, 2) or (2,), got (9, 1)"),
        (Trajectory(t, x, xd, xdd[:, :1]), "xdd must have shape (N, 2) or (2,), got (9, 1)"),
        (Trajectory(t, np.where(np.arange(9)[:, None] == 3, np.nan, x), xd, xdd),
         "x[3, 0] is nan at sample 3 (t = 0.75 s): inputs must be finite"),
        (Trajectory(t, x, np.where(np.arange(9)[:, None] == 2, np.nan, xd), xdd),
         "xd[2, 0] is nan at sample 2 (t = 0.5 s): inputs must be finite"),
        (Trajectory(t, x, xd, np.where(np.arange(9)[:, None] == 4, np.inf, xdd)),
         "xdd[4, 0] is inf at sample 4 (t = 1 s): inputs must be finite"),
    ]
    for traj_, msg in cases:
        for solver in ("newton", "seed"):
            with pytest.raises(InputError) as exc:
                ik.inverse_kinematics(arm, traj_, solver=solver,
                                      q_start=Q0 if solver == "newton" else None)
            assert str(exc.value) == msg


def test_choose_solver(arm, five):
    assert ik.choose_solver(arm, "newton", None) == "newton"
    assert ik.choose_solver(arm, "auto", None) == "seed"
    assert ik.choose_solver(arm, "auto", Q0) == "newton"
    assert ik.choose_solver(arm, "seed", None) == "seed"
    assert ik.choose_solver(five, "newton", five.q_drawn) == "newton"
    with pytest.raises(InputError) as exc:
        ik.choose_solver(arm, "closed", None)
    assert str(exc.value) == ("unknown inverse-kinematics solver 'closed': use one of auto, "
                              "newton, seed")
    with pytest.raises(InputError) as exc:
        ik.choose_solver(arm, "seed", Q0)
    assert str(exc.value) == ("serial_2dof: the seed's closed form has fixed working modes and "
                              "cannot start from q_start: use solver 'newton' (or 'auto')")
    rpr = ps.load("serial_rpr")  # built in, but no closed form in the seed
    assert ik.choose_solver(rpr, "auto", None) == "newton"
    with pytest.raises(InputError) as exc:
        ik.choose_solver(rpr, "seed", None)
    assert str(exc.value) == (f"serial_rpr: solver 'seed' is the textbook's closed form of the "
                              f"built-in robots ({SEEDS}), and this robot is not one of them: "
                              "use solver 'newton' or 'auto'")


def test_unreachable_target_message(arm):
    """Tip from (100, 100) mm by +300 mm in x: beyond 200 mm from sample 3 (t = 0.75 s, x =
    100 + 300 (3 s^2 - 2 s^3) mm at s = 3/8: 194.922 mm). The closest pose reported reaches the
    fraction ``reached`` of the straight line from sample 2, and |F| is its distance to the
    target; the message is checked word for word with those numbers."""
    t = np.linspace(0.0, 2.0, 9)
    traj = ps.cubic([0.1, 0.1], [0.3, 0.0], 2.0, t)
    run = newton.solve(arm, t, traj.x, Q0)
    assert (run.failed, run.code) == (3, 5)
    assert np.all(np.isfinite(run.q[:3])) and np.all(np.isnan(run.q[3:]))
    assert np.max(np.abs(fk2(run.q[:3]) - traj.x[:3])) < 1e-12
    assert 0.0 < run.reached < 1.0
    partial = traj.x[2] + run.reached * (traj.x[3] - traj.x[2])
    tip = fk2(run.closest[None])[0]
    assert np.max(np.abs(tip - partial)) < 1e-12
    assert run.residual == pytest.approx(np.max(np.abs(tip - traj.x[3])), abs=1e-12)
    assert np.hypot(*tip) <= 2 * A and np.hypot(*traj.x[3]) > 2 * A
    assert run.iterations > 0 and run.evaluations > run.iterations and run.halvings > 0
    # the step from sample 2 is bisected down to 2^-20 of it: ``reached`` is a multiple of
    # 2^-20, within 2^-19 short of where the straight line leaves the disc of radius 0.2 m
    d = traj.x[3] - traj.x[2]
    a, b, c = d @ d, 2 * traj.x[2] @ d, traj.x[2] @ traj.x[2] - (2 * A) ** 2
    edge = (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)
    assert run.reached * 2**20 == int(run.reached * 2**20)
    assert 0.0 <= edge - run.reached <= 2.0**-19
    with pytest.raises(WorkspaceError) as exc:
        ik.inverse_kinematics(arm, traj, solver="newton", q_start=Q0)
    assert str(exc.value) == (
        "serial_2dof: target (x = 194.922 mm, y = 100 mm) at t = 0.75 s (sample 3) is "
        "unreachable (outside the workspace, or beyond a singular pose on the way from sample "
        f"2): Newton does not converge (|F| reached {run.residual:.3g} m at the closest pose "
        f"found, {run.reached:.0%} of the way from sample 2; a step further crosses a singular "
        "pose, where det [Phi_q; J] changes sign)")


def test_unreachable_from_the_start(arm):
    t = np.linspace(0.0, 2.0, 9)
    traj = ps.cubic([0.3, 0.1], [0.01, 0.0], 2.0, t)
    run = newton.solve(arm, t, traj.x, Q0)
    assert run.failed == 0 and np.all(np.isnan(run.q))
    partial = fk2(Q0[None])[0] + run.reached * (traj.x[0] - fk2(Q0[None])[0])
    assert np.max(np.abs(fk2(run.closest[None])[0] - partial)) < 1e-12
    with pytest.raises(WorkspaceError) as exc:
        ik.inverse_kinematics(arm, traj, solver="newton", q_start=Q0)
    assert str(exc.value) == (
        "serial_2dof: target (x = 300 mm, y = 100 mm) at t = 0 s (sample 0) is unreachable "
        "(outside the workspace, or beyond a singular pose on the way from the start pose): "
        f"Newton does not converge (|F| reached {run.residual:.3g} m at the closest pose found, "
        f"{run.reached:.0%} of the way from the start pose; a step further crosses a singular "
        "pose, where det [Phi_q; J] changes sign)")


def _run(q, failed, code, closest, residual=0.25, reached=0.375):
    return newton.NewtonRun(q, failed, code, closest, residual, reached, 1, 2, 3)


def test_report_failure_texts(arm):
    """Each code's reason, the origin (the start pose or the sample before), the units of a task
    with an orientation, and the edge of the workspace where the closest pose is singular
    (q2 = 0 with q1 = 0: J has a zero row, condition number inf)."""
    t = np.array([0.0, 0.5, 1.0])
    x = np.array([[0.1, 0.05], [0.12, 0.0], [0.3, 0.0]])
    q = np.full((3, 2), np.nan)
    reasons = {1: "the corrections did not converge", 2: "[Phi_q; J] is exactly singular there",
               5: "a step further crosses a singular pose, where det [Phi_q; J] changes sign"}
    for code, reason in reasons.items():
        for k, origin, where in ((2, "sample 1", "x = 300 mm, y = 0 mm) at t = 1 s (sample 2)"),
                                 (0, "the start pose", ("x = 100 mm, y = 50 mm) at t = 0 s "
                                                       "(sample 0)"))):
            for closest, edge in ((Q0, ""), (np.zeros(2), (
                    ", a singular pose ([Phi_q; J] condition number inf > 1e+06): the target "
                    "is at or beyond the edge of the workspace"))):
                fails = Failures(arm, t, x)
                newton.report_failure(fails, arm, _run(q, k, code, closest))
                assert [f[0] for f in fails.found] == [k]
                with pytest.raises(WorkspaceError) as exc:
                    fails.raise_earliest()
                assert str(exc.value) == (
                    f"serial_2dof: target ({where} is unreachable (outside the workspace, or "
                    f"beyond a singular pose on the way from {origin}): Newton does not "
                    f"converge (|F| reached 0.25 m at the closest pose found, 38% of the way "
                    f"from {origin}{edge}; {reason})")
    fails = Failures(arm, t, x)
    newton.report_failure(fails, arm, _run(q, None, 0, None))
    assert fails.found == []
    r3 = ps.load("serial_3dof")
    x3 = np.array([[0.1, 0.05, 0.25]])
    fails = Failures(r3, t[:1], x3)
    newton.report_failure(fails, r3, _run(np.full((1, 3), np.nan), 0, 1, np.array([0.5, 1.0, 0.2]),
                                          residual=0.0123, reached=0.5))
    assert fails.found == [(0, (
        "is unreachable (outside the workspace, or beyond a singular pose on the way from the "
        "start pose): Newton does not converge (|F| reached 0.0123 m, rad at the closest pose "
        "found, 50% of the way from the start pose; the corrections did not converge)"))]


def test_singular_start_pose_messages(arm):
    tail = ("so it does not choose a working mode: give a start pose in the mode you want "
            "(q_start, or a study's motion.start_pose), e.g. with the elbow bent")
    with pytest.raises(WorkspaceError) as exc:
        newton.start_pose(arm, None)
    assert str(exc.value) == ("serial_2dof: the drawn configuration q = [0.0, 0.0] rad is "
                              "singular ([Phi_q; J] condition number inf > 1e+06), " + tail)
    with pytest.raises(WorkspaceError) as exc:
        ik.inverse_kinematics(arm, arm_move(n=3), solver="newton")
    assert str(exc.value).startswith("serial_2dof: the drawn configuration q = [0.0, 0.0] rad")
    with pytest.raises(WorkspaceError) as exc:
        newton.start_pose(arm, [0.0, 0.0])
    assert str(exc.value) == ("serial_2dof: the start pose q = [0.0, 0.0] rad is singular "
                              "([Phi_q; J] condition number inf > 1e+06), " + tail)
    # nearly stretched: q2 = 1.23456789e-7 rad, shown rounded to 6 decimals; its condition
    # number from the hand-written Jacobian (about 5 / q2 = 4.05e7, well above the limit)
    q = np.array([0.0, 1.23456789e-7])
    cond = np.linalg.cond(jac2(q[None])[0])
    assert cond == pytest.approx(5 / q[1], rel=1e-6)
    with pytest.raises(WorkspaceError) as exc:
        ik.inverse_kinematics(arm, arm_move(n=3), solver="newton", q_start=q)
    assert str(exc.value) == (f"serial_2dof: the start pose q = [0.0, 0.0] rad is singular "
                              f"([Phi_q; J] condition number {cond:.3g} > 1e+06), " + tail)
    assert np.array_equal(newton.start_pose(arm, [0.5, 1.0]), Q0)
    assert np.array_equal(newton.start_pose(ps.load("five_bar_type1"), None),
                          ps.load("five_bar_type1").q_drawn)


def _linear_robot(scale, name="gantry"):
    """A stand-in with the linear task x = diag(scale, 1) q: its [Phi_q; J] has condition number
    exactly scale (a diagonal matrix's singular values are its entries)."""
    def task(q, qd=None):
        q = np.atleast_2d(q)
        J = np.tile(np.diag([scale, 1.0]), (len(q), 1, 1))
        return np.einsum("kij,kj->ki", J, q), J, np.zeros((len(q), 2))
    return SimpleNamespace(name=name, n=2, n_constraints=0, task_names=("x", "y"),
                           is_closed_chain=False, q_drawn=np.array([0.25, 0.5]), task=task)


def test_condition_limit_edges():
    """At exactly the limit a pose is accepted; one ulp above, refused (start pose, the closest
    pose of a failure, the singular samples)."""
    at, above = _linear_robot(LIMIT), _linear_robot(np.nextafter(LIMIT, np.inf))
    assert np.linalg.cond(np.diag([LIMIT, 1.0])) == LIMIT
    assert np.array_equal(newton.start_pose(at, None), [0.25, 0.5])
    with pytest.raises(WorkspaceError, match=r"drawn configuration q = \[0.25, 0.5\] rad is "
                                             r"singular \(\[Phi_q; J\] condition number 1e\+06 "
                                             r"> 1e\+06\)"):
        newton.start_pose(above, None)
    t, x = np.array([0.0]), np.array([[0.0, 0.0]])
    for robot, edge in ((at, ""), (above, ", a singular pose")):
        fails = Failures(robot, t, x)
        newton.report_failure(fails, robot, _run(np.full((1, 2), np.nan), 0, 1, np.ones(2)))
        assert (", a singular pose" in fails.found[0][1]) == bool(edge)
    # the singular samples of the rates: NaN and anything above the limit
    fails = Failures(at, np.arange(4.0), np.zeros((4, 2)))
    cond = np.array([1.0, LIMIT, np.nextafter(LIMIT, np.inf), np.nan])
    bad = ik._add_singular(fails, cond)
    assert bad.tolist() == [False, False, True, True]
    assert fails.found == [(2, "is at a singular pose (Jacobian condition number 1e+06 > 1e+06)")]
    fails = Failures(at, np.arange(2.0), np.zeros((2, 2)))
    assert ik._add_singular(fails, np.array([LIMIT, np.nan])).tolist() == [False, True]
    assert fails.found == [(1, "is at a singular pose (Jacobian condition number nan > 1e+06)")]


def test_solve_rates(arm):
    """J y = rhs per sample, refused at the first singular sample by time and target."""
    t, x = np.array([0.0, 1.0, 2.0]), np.array([[0.1, 0.0], [0.2, 0.0], [0.0, 0.15]])
    J = np.array([[[2.0, 0.0], [0.0, 4.0]], [[1.0, 1.0], [0.0, 1.0]], [[0.0, 1.0], [1.0, 0.0]]])
    rhs = np.array([[1.0, 1.0], [3.0, 2.0], [5.0, 7.0]])
    y = ik.solve_rates(arm, t, x, J, rhs)
    assert y.shape == (3, 2)
    assert np.array_equal(y, [[0.5, 0.25], [1.0, 2.0], [7.0, 5.0]])
    assert np.array_equal(ik.solve_rates(arm, t, x, J, rhs, cond=np.ones(3)), y)
    # the condition numbers given are the ones judged
    with pytest.raises(WorkspaceError) as exc:
        ik.solve_rates(arm, t, x, J, rhs, cond=np.array([1.0, 2e6, 3e6]))
    assert str(exc.value) == ("serial_2dof: target (x = 200 mm, y = 0 mm) at t = 1 s (sample 1) "
                              "is at a singular pose (Jacobian condition number 2e+06 > 1e+06)")
    Js = J.copy()
    Js[2] = [[1.0, 2.0], [2.0, 4.0]]  # rank 1
    with pytest.raises(WorkspaceError) as exc:
        ik.solve_rates(arm, t, x, Js, rhs)
    assert str(exc.value).startswith("serial_2dof: target (x = 0 mm, y = 150 mm) at t = 2 s "
                                     "(sample 2) is at a singular pose (Jacobian condition "
                                     "number ")


# -- newton's parts --------------------------------------------------------------------------------

def _counts(n, m, task, na, name="toy"):
    return SimpleNamespace(name=name, n=n, n_constraints=m, task_names=task, actuated=tuple(range(na)))


def test_check_square_messages(five):
    newton.check_square(five)  # 4 coordinates, 2 loops, a 2-D task, 2 motors
    cases = [
        (_counts(1, 0, ("x", "y"), 1),
         ("toy: no inverse kinematics in task space: it has 1 coordinate, 0 loop equations (1 "
         "degree of freedom), a 2-coordinate task (x, y) and 1 actuated joint; the task must fix "
         "the 1 degree of freedom, so 2 != 1: drive its actuated joint in joint space instead (a "
         "study's motion.space = \"joint\", or ps.from_actuated)")),
        (_counts(4, 1, ("x", "y", "phi", "z"), 2),
         ("toy: no inverse kinematics in task space: it has 4 coordinates, 1 loop equation (3 "
         "degrees of freedom), a 4-coordinate task (x, y, phi, z) and 2 actuated joints; the task "
         "must fix the 3 degrees of freedom, so 4 != 3: drive its actuated joints in joint space "
         "instead (a study's motion.space = \"joint\", or ps.from_actuated)")),
        (_counts(3, 2, (), 1),
         ("toy: no inverse kinematics in task space: it has 3 coordinates, 2 loop equations (1 "
         "degree of freedom), a 0-coordinate task (none) and 1 actuated joint; the task must fix "
         "the 1 degree of freedom, so 0 != 1: the task leaves joints free: add task coordinates "
         "(an orientation) or drive the joints in joint space")),
        (_counts(3, 0, ("x", "y"), 3),
         ("toy: no inverse kinematics in task space: it has 3 coordinates, 0 loop equations (3 "
         "degrees of freedom), a 2-coordinate task (x, y) and 3 actuated joints; the task must "
         "fix the 3 degrees of freedom, so 2 != 3: the task leaves joints free: add task "
         "coordinates (an orientation) or drive the joints in joint space")),
        (_counts(2, 0, ("x", "y"), 1),
         ("toy: it has 2 coordinates, 0 loop equations (2 degrees of freedom), a 2-coordinate "
         "task (x, y) and 1 actuated joint: torques are unique only with one motor per degree "
         "of freedom (1 != 2)")),
        (_counts(3, 1, ("x", "y"), 3),
         ("toy: it has 3 coordinates, 1 loop equation (2 degrees of freedom), a 2-coordinate task "
         "(x, y) and 3 actuated joints: torques are unique only with one motor per degree of "
         "freedom (3 != 2)")),
    ]
    for robot, msg in cases:
        with pytest.raises(WorkspaceError) as exc:
            newton.check_square(robot)
        assert str(exc.value) == msg
    newton.check_square(_counts(3, 1, ("x", "y"), 2))
    newton.check_square(_counts(1, 0, ("x",), 1))
    with pytest.raises(WorkspaceError, match=r"slider_crank: no inverse kinematics .* 0 != 1"):
        ik.inverse_kinematics(ps.load("slider_crank"), ps.cubic([0.1], [0.01], 1.0, [0.0, 1.0]))


def test_stacked_jacobian(arm, five):
    """[Phi_q; J] for the closed chain: loop rows first, then the task rows; the 2-DOF arm's J
    by hand; nothing solved gives empty arrays of the right shapes; Jdot qd is the task's."""
    from planar_sym.model.kinematics import stacked_jacobian

    A0, x0, j0 = stacked_jacobian(five, np.zeros((0, 4)))
    assert A0.shape == (0, 4, 4) and x0.shape == (0, 2) and j0.shape == (0, 2)
    A0, x0, j0 = stacked_jacobian(arm, np.zeros((0, 2)))
    assert A0.shape == (0, 2, 2) and x0.shape == (0, 2) and j0.shape == (0, 2)
    q = five.q_drawn + np.array([[0.0, 0.0, 0.0, 0.0], [0.01, -0.02, 0.03, 0.04]])
    S, x, _ = stacked_jacobian(five, q)
    assert S.shape == (2, 4, 4) and x.shape == (2, 2)
    assert np.array_equal(S[:, :2], five.constraint_jacobian(q).reshape(2, 2, 4))
    assert np.array_equal(S[:, 2:], five.task(q)[1].reshape(2, 2, 4))
    assert np.array_equal(x, five.task(q)[0])
    assert np.max(np.abs(x[0] - [0.060852, 0.154665])) < 1e-9  # P drawn
    qa = np.array([[0.5, 1.0], [-0.3, 2.0], [1.0, -0.5]])
    S, x, jdq = stacked_jacobian(arm, qa, np.ones_like(qa))
    assert np.max(np.abs(S - jac2(qa))) < 1e-15 and np.max(np.abs(x - fk2(qa))) < 1e-15
    assert np.max(np.abs(jdq - jdot_qd2(qa, np.ones_like(qa)))) < 1e-14  # by hand


def test_verify_edges(arm, five):
    """|F|_inf against 1e-12 (1 + |x*|_inf): exactly at the limit accepted, above refused; the
    loops count for a closed chain."""
    t = np.array([0.0, 1.0, 2.0])
    target = np.array([[0.0, 0.0], [0.5, -2.0], [0.0, 0.0]])
    lim1 = 1e-12 * (1 + 2.0)
    ok = target + np.array([[1e-12, -1e-12], [-lim1, 0.0], [0.0, -1e-12]])
    fails = Failures(arm, t, target)
    newton.verify(fails, arm, np.zeros((3, 2)), ok, target)
    assert fails.found == []
    for k, off, shown in ((0, [2e-12, 0.0], ("2e-12", "1e-12")),
                          (1, [0.0, 2.5e-12 + lim1], ("5.5e-12", "3e-12")),
                          (2, [0.0, -1.5e-12], ("1.5e-12", "1e-12"))):
        miss = ok.copy()
        miss[k] = target[k] + off
        fails = Failures(arm, t, target)
        newton.verify(fails, arm, np.zeros((3, 2)), miss, target)
        assert fails.found == [(k, (f"is missed by the solution found (|F| = {shown[0]} after "
                                   f"Newton, limit {shown[1]}): the pose is too ill-conditioned "
                                   "to solve accurately"))]
    # |x*| is an absolute value: a target of (0.5, -2) allows 3e-12, not 1.5e-12
    fails = Failures(arm, t[1:2], target[1:2])
    newton.verify(fails, arm, np.zeros((1, 2)), target[1:2] + [2.5e-12, 0.0], target[1:2])
    assert fails.found == []
    # nothing solved: nothing to check
    fails = Failures(arm, t[:0], target[:0])
    newton.verify(fails, arm, np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 2)))
    newton.verify(fails, five, np.zeros((0, 4)), np.zeros((0, 2)), np.zeros((0, 2)))
    assert fails.found == []
    # the closed chain: the task met exactly, the loops open at the second pose
    q = np.vstack([five.q_drawn, five.q_drawn + 0.01])
    xq = five.task(q)[0]
    phi = np.max(np.abs(five.constraint(q)), axis=1)
    assert phi[0] < 1e-15 and phi[1] > 1e-4
    fails = Failures(five, t[:2], xq)
    newton.verify(fails, five, q, xq, xq)
    assert fails.found == [(1, (f"is missed by the solution found (|F| = {phi[1]:.3g} after "
                               f"Newton, limit {1e-12 * (1 + np.max(np.abs(xq[1]))):.3g}): the "
                               "pose is too ill-conditioned to solve accurately"))]


def _branch(t, q, qd, ok=None, robot=None):
    robot = robot or ps.load("serial_2dof")
    fails = Failures(robot, np.asarray(t, float), np.zeros((len(t), 2)))
    newton.branch_check(fails, np.asarray(t, float), np.asarray(q, float),
                        np.asarray(qd, float), np.ones(len(t), bool) if ok is None else ok)
    return fails.found


def test_branch_check_message_and_edges():
    """A step may leave [min, max] of dt qd at its two samples by 0.5 of its size (the largest
    of |step|, dt |qd_k|, dt |qd_k+1|) plus 1e-9 rad: exactly that is accepted, more refused.
    The values below are exact in binary, so the limit is met exactly."""
    found = _branch([0.0, 0.5], [[0.0, 0.0], [0.25, 2.0]], [[1.0, -2.0], [3.0, 0.0]])
    assert found == [(1, ("is on another branch than sample 0, or the samples are too coarse to "
                         "follow the motion: from sample 0 joint joint2 moves by 2 rad, but its "
                         "exact rates at the two samples (-2 and 0 rad/s over 0.5 s) account for "
                         "-1 to 0 rad: use more samples"))]
    # the size from the step: 2e-9 off an interval [0, 0] is 0.5 * 2e-9 + 1e-9
    assert _branch([0.0, 1.0], [[0.0, 0.0], [2e-9, 0.0]], np.zeros((2, 2))) == []
    assert len(_branch([0.0, 1.0], [[0.0, 0.0], [2.01e-9, 0.0]], np.zeros((2, 2)))) == 1
    # the size from dt qd_k+1 (joint1: [0, 4]) and from dt qd_k (joint1: [-4, 0]); joint2 is off
    # its interval [0, 0] by 0.5 * 4 + 1e-9
    edge = 0.5 * 4.0 + 1e-9
    for qd in ([[0.0, 0.0], [4.0, 0.0]], [[-4.0, 0.0], [0.0, 0.0]], [[4.0, 0.0], [0.0, 0.0]],
               [[0.0, 0.0], [-4.0, 0.0]]):
        assert _branch([0.0, 1.0], [[0.0, 0.0], [0.0, edge]], qd) == []
        assert _branch([0.0, 1.0], [[0.0, 0.0], [0.0, -edge]], qd) == []
        found = _branch([0.0, 1.0], [[0.0, 0.0], [0.0, edge + 1e-8]], qd)
        assert [k for k, _ in found] == [1] and "joint joint2 moves by 2 rad" in found[0][1]
    # dt scales the rates: over 2 s a rate of 1 rad/s accounts for 2 rad
    assert _branch([1.0, 3.0], [[0.0, 0.0], [2.0, -2.0]], [[1.0, -1.0], [1.0, -1.0]]) == []
    found = _branch([1.0, 3.0], [[0.0, 0.0], [2.0, -5.0]], [[1.0, -1.0], [1.0, -1.0]])
    assert found == [(1, ("is on another branch than sample 0, or the samples are too coarse to "
                         "follow the motion: from sample 0 joint joint2 moves by -5 rad, but its "
                         "exact rates at the two samples (-1 and -1 rad/s over 2 s) account for "
                         "-2 to -2 rad: use more samples"))]
    # a step below its interval, and the earliest of several, at the later sample's index
    found = _branch([0.0, 1.0, 2.0, 3.0], [[0.0, 0.0], [1.0, 0.0], [1.25, 0.0], [0.0, 0.0]],
                    [[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    assert [k for k, _ in found] == [2]
    assert "from sample 1 joint joint1 moves by 0.25 rad" in found[0][1]
    assert "(1 and 1 rad/s over 1 s) account for 1 to 1 rad" in found[0][1]
    # steps touching an untrusted sample are skipped
    ok = np.array([True, True, False, True])
    found = _branch([0.0, 1.0, 2.0, 3.0], [[0.0, 0.0], [1.0, 0.0], [1.25, 0.0], [0.0, 0.0]],
                    [[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0]], ok)
    assert found == []
    ok = np.array([True, True, True, False])
    found = _branch([0.0, 1.0, 2.0, 3.0], [[0.0, 0.0], [1.0, 0.0], [1.25, 0.0], [0.0, 0.0]],
                    [[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0]], ok)
    assert [k for k, _ in found] == [2]
    # one sample, or a stretch of rest: nothing to refuse
    assert _branch([0.0], [[0.3, 0.4]], [[5.0, 5.0]]) == []
    assert _branch([0.0, 1.0], [[0.3, 0.4], [0.3, 0.4]], np.zeros((2, 2))) == []


def test_branch_change_refused_word_for_word(arm):
    """S3 sampled at its ends only (rest at both): the shoulder turns pi/2 between samples,
    which rates of zero cannot account for."""
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, [0.0, 5.0])
    with pytest.raises(WorkspaceError) as exc:
        ik.inverse_kinematics(arm, traj, solver="newton", q_start=Q0)
    msg = str(exc.value)
    head = ("serial_2dof: target (x = -100 mm, y = 100 mm) at t = 5 s (sample 1) is on another "
            "branch than sample 0, or the samples are too coarse to follow the motion: from "
            "sample 0 joint joint1 moves by 1.57 rad, but its exact rates at the two samples (")
    assert msg.startswith(head) and msg.endswith(" rad: use more samples")
    rates = re.fullmatch(r"(\S+) and (\S+) rad/s over 5 s\) account for (\S+) to (\S+)",
                         msg[len(head):-len(" rad: use more samples")])
    assert rates and all(abs(float(v)) < 1e-14 for v in rates.groups())


def test_a_large_correction_halves_the_step(arm):
    """One target, the start pose turned about the base by 0.5 rad: Newton's first correction
    (about sin 0.5 = 0.48 rad) is more than the 0.1 rad trusted, so the step is halved, at
    least to 1/8 (0.0625 rad); a turn of 0.09 rad is taken in one step."""
    for turn, halved in ((0.5, True), (0.09, False)):
        q = (Q0 + [turn, 0.0])[None]
        run = newton.solve(arm, np.array([1.0]), fk2(q), Q0)
        assert run.failed is None and run.code == 0 and run.closest is None
        assert np.max(np.abs(run.q - q)) < 1e-12
        assert (run.halvings >= 3) if halved else (run.halvings == 0)
        assert 0 < run.iterations < run.evaluations
        assert run.reached == 1.0
