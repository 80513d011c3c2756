"""Time-optimal timing of a path (issue 27, item 1), against independent references: the same
discretised problem as one linear program (SciPy's HiGHS: maximise the sum of sdot^2, whose
optimum is the pointwise largest feasible profile, the time-optimal one), and toppra on the
same spline and grid with our reduced dynamics as its inverse-dynamics callable. toppra 0.6
fails on the S3 path (a NaN controllable set where a torque row vanishes): there the linear
program is the reference."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.sparse import coo_matrix

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.motion.closure import from_actuated
from planar_sym.optimal.time_optimal import arc_length_path

ROOT_ROBOTS = Path(__file__).resolve().parent / "robots"


def _s3():
    arm = ps.load("serial_2dof")
    t = np.linspace(0.0, 5.0, 201)
    return arm, ps.inverse_kinematics(arm, ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t))


def _s5():
    fb = ps.load("five_bar_type1")
    t = np.linspace(0.0, 2.0, 201)
    return fb, ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))


def _torques(robot, q, qd, qdd):
    """The actuated torques (N, actuated) at these states, straight from the robot."""
    if robot.is_closed_chain:
        return robot.closed_chain_inverse_dynamics(q, qd, qdd)[0]
    return robot.inverse_dynamics(q, qd, qdd)


def _lp(robot, path, lim):
    """The time-optimal sdot by one LP over (x_0..x_N, u_0..u_{N-1}), x = sdot^2."""
    s, q, q_s, q_ss = arc_length_path(robot, path)
    z = np.zeros_like(q)
    c = _torques(robot, q, z, z)
    a, b = _torques(robot, q, z, q_s) - c, _torques(robot, q, q_s, q_ss) - c
    n_pts, na, ds = len(s), a.shape[1], np.diff(s)
    rows, cols, vals, rhs = [], [], [], []
    r = 0
    for i in range(n_pts - 1):
        for k in range(na):
            for sign in (1.0, -1.0):  # sign (a u + b x + c) <= lim
                rows += [r, r]
                cols += [i, n_pts + i]
                vals += [sign * b[i, k], sign * a[i, k]]
                rhs.append(lim[k] - sign * c[i, k])
                r += 1
    a_ub = coo_matrix((vals, (rows, cols)), shape=(r, 2 * n_pts - 1)).tocsr()
    i = np.arange(n_pts - 1)
    a_eq = coo_matrix((np.concatenate([np.ones(n_pts - 1), -np.ones(n_pts - 1), -2 * ds]),
                       (np.tile(i, 3), np.concatenate([i + 1, i, n_pts + i]))),
                      shape=(n_pts - 1, 2 * n_pts - 1)).tocsr()
    bounds = [(0, 0)] + [(0, None)] * (n_pts - 2) + [(0, 0)] + [(None, None)] * (n_pts - 1)
    res = linprog(np.concatenate([-np.ones(n_pts), np.zeros(n_pts - 1)]), A_ub=a_ub,
                  b_ub=np.array(rhs), A_eq=a_eq, b_eq=np.zeros(n_pts - 1), bounds=bounds,
                  method="highs")
    assert res.status == 0, res.message
    return np.sqrt(np.maximum(res.x[:n_pts], 0.0)), s


def test_s3_is_the_linear_programs_optimum_and_bang_bang():
    arm, path = _s3()
    lim = np.array([0.5, 0.1])
    res = ps.time_optimal(arm, path, lim)
    sdot, s = _lp(arm, path, lim)
    assert np.abs(res.sdot - sdot).max() <= 1e-9 * sdot.max()
    t_lp = np.sum(2 * np.diff(s) / (sdot[:-1] + sdot[1:]))
    assert res.duration_s == pytest.approx(t_lp, rel=1e-9)
    assert 0.3 < res.duration_s < 0.4  # seen: 0.33514 s (the cubic move took 5 s)
    # bang-bang: a torque on its limit at every sample but the switching ones
    assert np.count_nonzero(~res.on_limit[1:-1]) <= 2
    # the timed motion through the inverse dynamics stays within the limits
    jt = res.trajectory
    tau = arm.inverse_dynamics(jt.q, jt.qd, jt.qdd)
    assert np.abs(tau - res.tau).max() <= 1e-12 * lim.max()
    assert np.all(np.abs(tau) <= lim * (1 + 1e-6))
    assert jt.t_s[0] == 0.0 and jt.t_s[-1] == res.duration_s and np.all(np.diff(jt.t_s) > 0)
    assert np.abs(jt.qd[[0, -1]]).max() == 0.0  # rest to rest


def test_s5_closed_chain_equals_toppra_on_the_same_grid():
    toppra = pytest.importorskip("toppra")
    from toppra import algorithm, constraint

    fb, path = _s5()
    lim = np.array([0.1, 0.1])
    res = ps.time_optimal(fb, path, lim)
    s, *_ = arc_length_path(fb, path)
    act = list(fb.actuated)

    def reduced(qa, va, aa):  # toppra's callable: the actuated torques of the closed chain
        jt = from_actuated(fb, np.zeros(1), np.atleast_2d(qa), np.atleast_2d(va),
                           np.atleast_2d(aa), q_guess=path.q[0])
        return fb.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)[0][0]

    torque = constraint.JointTorqueConstraint(
        reduced, np.column_stack([-lim, lim]), np.zeros(2),
        discretization_scheme=constraint.DiscretizationType.Collocation)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        theirs = algorithm.TOPPRA([torque], toppra.SplineInterpolator(s, path.q[:, act]),
                                  gridpoints=s, solver_wrapper="seidel").compute_trajectory(0, 0)
    assert theirs is not None
    assert res.duration_s == pytest.approx(theirs.duration, rel=1e-6)  # seen: 2e-8
    jt = res.trajectory
    assert np.abs(fb.constraint(jt.q)).max() < 1e-9
    tau, _ = fb.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    assert np.all(np.abs(tau) <= lim * (1 + 1e-6))
    assert np.count_nonzero(~res.on_limit[1:-1]) <= 2


def test_speed_limit_is_held():
    arm, path = _s3()
    free = ps.time_optimal(arm, path, [0.5, 0.1])
    slow = ps.time_optimal(arm, path, [0.5, 0.1], speed_limit=[2.0, 2.0])
    assert np.abs(free.trajectory.qd).max() > 2.0
    assert np.abs(slow.trajectory.qd).max() <= 2.0 * (1 + 1e-9)
    assert slow.duration_s > free.duration_s
    # where the speed bound binds is reported (a trial's run summary named only the torques:
    # "on its limit at 46 of 201 samples", where the speed held the other 154): by hand
    assert free.speed_limits is None and free.on_speed_limit is None
    assert np.array_equal(slow.speed_limits, [2.0, 2.0])
    bound = np.any(np.abs(slow.trajectory.qd) >= 2.0 * (1 - 1e-6), axis=1)
    assert np.array_equal(slow.on_speed_limit, bound) and 0 < bound.sum() < len(bound)
    from planar_sym.study.spec import parse

    st = parse({"robot": "serial_2dof", "kind": "inverse", "units": {"length": "mm"},
                "motion": {"space": "task", "profile": "cubic", "start": [100.0, 100.0],
                           "by": [-200.0, 0.0], "duration": 5.0, "samples": 201},
                "optimise": {"torque_limit": [0.5, 0.1], "speed_limit": [2.0, 2.0]}}, "s")
    assert f"a speed on its limit (|qd| <= 2, 2 (rad/s, rad/s)) at {bound.sum()}" in (
        ps.run_study(st).note)


def test_refusals_name_the_mistake():
    arm, path = _s3()
    with pytest.raises(InputError, match="torque_limit is needed"):
        ps.time_optimal(arm, path)
    with pytest.raises(InputError, match="torque_limit must be positive"):
        ps.time_optimal(arm, path, [0.5, -0.1])
    with pytest.raises(InputError, match=r"cannot be followed within the limits at sample"):
        ps.time_optimal(arm, path, [0.01, 0.001])  # below the gravity torque
    with pytest.raises(InputError, match="friction"):
        ps.time_optimal(ps.load("examples/serial_2dof_geared.toml"), path, [0.5, 0.1])
    cart = ps.load("tests/robots/cart_pole.toml")
    with pytest.raises(InputError, match="underactuated"):
        ps.time_optimal(cart, path, [1.0])
    still = type(path)(path.t_s, np.repeat(path.q[:1], len(path.t_s), axis=0),
                       np.zeros_like(path.q), np.zeros_like(path.q))
    with pytest.raises(InputError, match="stands still between samples 0 and 1"):
        ps.time_optimal(arm, still, [0.5, 0.1])


def test_builtin_studies_time_their_paths_as_the_api_does():
    """`[optimise]` in an inverse study: the CSV's times and torques are time_optimal's on the
    study's path, the torques recomputed by the study's own inverse dynamics."""
    arm, path = _s3()
    api = ps.time_optimal(arm, path, [0.5, 0.1])
    res = ps.run_study("serial_2dof_cartesian_fastest")
    assert np.abs(res.get("t").values - api.trajectory.t_s).max() <= 1e-12
    tau = np.column_stack([res.get("tau", k).values for k in range(2)])
    assert np.abs(tau - api.tau).max() <= 1e-12
    assert res.timing.startswith("time-optimal: 0.3351 s (the motion as given: 5 s)")
    five = ps.run_study("five_bar_type1_move_x_fastest")
    assert five.get("t").values[-1] == pytest.approx(0.234678, rel=1e-5)
    assert np.abs(np.column_stack([s.values for s in five.series("tau")])).max() <= 0.1 * (
        1 + 1e-6)


def test_optimise_table_is_checked_with_the_study(tmp_path):
    from planar_sym.study.run import motion_and_reference
    from planar_sym.study.spec import parse

    base = {"robot": "serial_2dof", "kind": "inverse", "units": {"length": "mm"},
            "motion": {"space": "task", "profile": "cubic", "start": [100.0, 100.0],
                       "by": [-200.0, 0.0], "duration": 5.0, "samples": 51}}
    with pytest.raises(InputError, match=r"optimise.torque_limit: must be positive"):
        parse({**base, "optimise": {"torque_limit": [0.5, -0.1]}}, "s")
    with pytest.raises(InputError, match=r"optimise.speed: unknown key"):
        parse({**base, "optimise": {"speed": [1.0, 1.0]}}, "s")
    with pytest.raises(InputError, match=r"optimise: only for kind = \"inverse\""):
        parse({"robot": "serial_2dof", "kind": "forward", "optimise": {},
               "simulation": {"q0": [0.0, 0.0], "duration": 1.0}}, "s")
    st = parse({**base, "optimise": {"torque_limit": [0.5, 0.1, 0.2]}}, "s")
    with pytest.raises(InputError, match=r"needs 2 values, one per motor \(got 3\)"):
        ps.run_study(st)
    # pictures of a timed study: evenly spaced frames over the time reached
    st = parse({**base, "optimise": {"torque_limit": [0.5, 0.1]}}, "s")
    _, t, q, _ = motion_and_reference(st, 12)
    assert len(t) == 12 and np.allclose(np.diff(t), t[-1] / 11) and t[-1] < 0.4
    assert q[0] == pytest.approx([0.0, np.pi / 2]) and q.shape == (12, 2)


def test_timing_is_consistent_sample_to_sample():
    """sdot^2 grows by 2 ds sddot over each step, sddot read back from the returned motion
    (qdd = q_s sddot + q_ss sdot^2 on the arc-length path), to the last sample."""
    for robot, path, lim in ((*_s3(), [0.5, 0.1]), (*_s5(), [0.1, 0.1])):
        res = ps.time_optimal(robot, path, lim)
        s, _, q_s, q_ss = arc_length_path(robot, path)
        x = res.sdot**2
        jt = res.trajectory
        u = np.array([np.linalg.lstsq(q_s[i][:, None], jt.qdd[i] - q_ss[i] * x[i],
                                      rcond=None)[0][0] for i in range(len(s))])
        steps = x[1:] - x[:-1] - 2 * np.diff(s) * u[:-1]
        assert np.abs(steps).max() <= 1e-9 * x.max()
        assert u[-2] < 0 and res.on_limit[-2]  # braking into rest at the end, on a limit


def test_a_limit_of_the_wrong_length_is_named():
    """A student's three limits for two motors: InputError naming the option, not NumPy's
    broadcast message (the same rule for time_optimal and optimal_move)."""
    arm, path = _s3()
    with pytest.raises(InputError, match=r"torque_limit must be one number or 2, one per "
                                         r"actuated joint \(got \[0.5, 0.1, 0.2\]\)"):
        ps.time_optimal(arm, path, [0.5, 0.1, 0.2])
    with pytest.raises(InputError, match=r"speed_limit must be one number or 2, one per "
                                         "coordinate"):
        ps.optimal_move(arm, [0, 0], [1, 1], objective="time", torque_limit=1.0,
                        speed_limit=[1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="torque_limit must be one number or 2"):
        ps.time_optimal(arm, path, "half a newton metre")


def test_a_sweep_times_each_design_anew():
    """A sweep of a time-optimal study used the study's motion as given (the cubic, 5 s) for
    every design: peak tau1 0.30 N*m where the timed motion reaches its 0.5 N*m limit. Each
    design now runs the study, its path timed with that design's dynamics."""
    import dataclasses

    from planar_sym.study.run import load_study

    res = ps.sweep("serial_2dof_cartesian_fastest", {"m_motor2": (0.2, 0.4, 3)})
    assert res.route == "per design"
    assert res.columns["peak_tau1_n_m"] == pytest.approx([0.5, 0.5, 0.5], rel=1e-6)
    st = load_study("serial_2dof_cartesian_fastest")
    for k, m in enumerate((0.2, 0.3, 0.4)):  # each design as its own study run
        one = ps.run_study(dataclasses.replace(st, parameters={"m_motor2": (m, "kg")}))
        peak = np.abs(one.get("tau", 1).values).max()
        assert res.columns["peak_tau2_n_m"][k] == pytest.approx(peak, rel=1e-12)
    # the heaviest elbow motor: joint 1 binds all along, joint 2 stays off its 0.1 N*m
    assert res.columns["peak_tau2_n_m"][2] < 0.05


def test_the_last_sample_holds_its_limits():
    """The last sample has no interval ahead: it kept the previous interval's sdot-dot, whose
    torque there passed the limit (a trial's five-bar with unequal links: 1.000138 times it on
    a 51-sample task line). Now held within its own sample's limits: every sample, every joint
    within 1e-12 of the limit, by the robot's own closed-chain inverse dynamics."""
    fb = ps.load(ROOT_ROBOTS / "five_bar_unequal.toml")
    lim = np.array([0.5, 0.6])
    start = fb.task(fb.q_drawn)[0]
    for n in (51, 201):
        t = np.linspace(0.0, 2.0, n)
        path = ps.inverse_kinematics(fb, ps.cubic(start, [0.06, -0.03], 2.0, t))
        res = ps.time_optimal(fb, path, torque_limit=lim)
        jt = res.trajectory
        tau, _ = fb.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
        assert np.max(np.abs(tau) / lim) <= 1 + 1e-12, (n, np.max(np.abs(tau[-1]) / lim))


def test_a_joint_space_move_of_an_arm_is_timed_through_from_actuated():
    """A trial had no public way to time a joint-space path of an arm: ps.from_actuated on a
    tree raised KeyError: 'constraint', and JointTrajectory was not exported. Now the fully
    actuated tree's motion comes back as given (exactly), is timed as the linear program says,
    and a tree with a passive joint is refused for that reason."""
    arm = ps.load("serial_3dof")
    t = np.linspace(0.0, 2.0, 121)
    c = ps.cubic([0.0, 0.5, -0.3], [1.2, -0.9, 0.9], 2.0, t)
    path = ps.from_actuated(arm, t, c.x, c.xd, c.xdd)
    assert isinstance(path, ps.JointTrajectory)
    assert all(np.array_equal(a, b) for a, b in ((path.q, c.x), (path.qd, c.xd),
                                                   (path.qdd, c.xdd)))
    lim = np.array([5.0, 3.0, 1.0])
    res = ps.time_optimal(arm, path, lim)
    sdot, _ = _lp(arm, path, lim)
    assert np.abs(res.sdot - sdot).max() <= 1e-9 * sdot.max()
    with pytest.raises(InputError, match="cart_pole: hinge passive in a tree"):
        ps.from_actuated(ps.load("cart_pole"), t, c.x[:, :1], c.xd[:, :1], c.xdd[:, :1])
