"""The optimal-motion modules (planar_sym/optimal/) against independent references where the
mutation runs found gaps (issue 30): closed forms on a pure inertia (a 1-DOF link in a
horizontal plane, J = 0.02 + 1.5 * 0.25^2 = 0.11375 kg*m^2: the bang-bang time 2 sqrt(theta J /
tau_max), the trapezoid of a speed limit, the discrete least-effort move's exact cost), linear
programs (HiGHS) for the controllable sets and the fastest timing, a quadratic program (SLSQP)
for the least effort under a speed limit, the constraint residuals of the solutions (loops,
passive joints), the limits read from the description through the gears, the fallbacks'
sequence of solves (IPOPT stood in for) and every refusal word for word."""

from __future__ import annotations

import importlib
import re
import time
import warnings

import numpy as np
import pytest
from conftest import ROOT
from scipy.optimize import linprog
from scipy.sparse import coo_matrix

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.motion.profiles import JointTrajectory

TOPP = importlib.import_module("planar_sym.optimal.time_optimal")
P2P = importlib.import_module("planar_sym.optimal.point_to_point")
LIMITS = importlib.import_module("planar_sym.optimal.limits")

J_WHEEL = 0.02 + 1.5 * 0.25**2  # kg*m^2 about the pivot (tests/robots/pendulum.toml)

GANTRY = """name = "optimal_gantry"
title = "An x-y gantry: two sliders, a diagonal mass matrix"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
acceleration = "m/s^2"
[ground]
points = { rail = [0.0, 0.0] }
[[bodies]]
name = "carriage"
mass = 2.0
mass_at = "C"
points = { C = [0.0, 0.0] }
[[bodies]]
name = "head"
mass = 1.0
mass_at = "H"
points = { H = [0.0, 0.0] }
[[joints]]
name = "x"
type = "prismatic"
parent = "ground.rail"
child = "carriage.C"
actuated = true
axis = [1.0, 0.0]
[[joints]]
name = "y"
type = "prismatic"
parent = "carriage.C"
child = "head.H"
actuated = true
axis = [0.0, 1.0]
"""


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    """tests/robots/pendulum.toml in a horizontal plane: a pure inertia J_WHEEL."""
    text = (ROOT / "tests" / "robots" / "pendulum.toml").read_text()
    text = text.replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]")
    text = text.replace('name = "pendulum"', 'name = "optimal_wheel"')
    path = tmp_path_factory.mktemp("wheel") / "optimal_wheel.toml"
    path.write_text(text)
    return ps.load(path)


@pytest.fixture(scope="module")
def gantry(tmp_path_factory):
    path = tmp_path_factory.mktemp("gantry") / "optimal_gantry.toml"
    path.write_text(GANTRY)
    return ps.load(path)


def _line(q0, q1, samples, solver=""):
    """A straight joint-space path through ``samples`` points (uneven times: only their order
    matters to the timing)."""
    q0, q1 = np.atleast_1d(np.asarray(q0, float)), np.atleast_1d(np.asarray(q1, float))
    s = np.linspace(0.0, 1.0, samples)
    t = s + 0.3 * s**2
    return JointTrajectory(t, q0 + s[:, None] * (q1 - q0), np.tile(q1 - q0, (samples, 1)),
                           np.zeros((samples, len(q0))), solver)


# --- time_optimal ------------------------------------------------------------------------------

@pytest.mark.parametrize("lim", [0.3, 1e-12])
def test_pure_inertia_is_timed_bang_bang_in_the_closed_form_time(wheel, lim):
    """theta = 0.8 rad, |tau| <= 0.3 N*m (or a feeble 1e-12 N*m: the timing scales, no
    tolerance of the vertices' test is absolute): T = 2 sqrt(theta J / tau_max) exactly
    (constant sddot per step is exact here, and the switch falls on the middle sample);
    sdot^2 = 2 u s with u = tau_max / (J theta) (s in [0, 1]); the torque +tau_max then
    -tau_max at every sample, the last one braking as the last step does."""
    theta = 0.8
    res = ps.time_optimal(wheel, _line(0.2, 0.2 + theta, 21, "newton"), [lim])
    assert res.duration_s == pytest.approx(2 * np.sqrt(theta * J_WHEEL / lim), rel=1e-12)
    s = np.linspace(0.0, 1.0, 21)
    u = lim / (J_WHEEL * theta)
    assert res.sdot == pytest.approx(np.sqrt(2 * u * np.minimum(s, 1 - s)), rel=1e-9,
                                     abs=1e-9 * np.sqrt(u))
    assert res.tau[:10, 0] == pytest.approx(np.full(10, lim), rel=1e-12)
    assert res.tau[10:, 0] == pytest.approx(np.full(11, -lim), rel=1e-12)
    assert res.on_limit.all() and res.limits.tolist() == [lim]
    jt = res.trajectory
    assert jt.solver == "newton"
    assert jt.qdd[:, 0] == pytest.approx(np.where(s < 0.5, 1, -1) * lim / J_WHEEL, rel=1e-12)
    t_closed = np.where(s <= 0.5, np.sqrt(2 * s / u), 2 / np.sqrt(u) - np.sqrt(2 * (1 - s) / u))
    assert jt.t_s == pytest.approx(t_closed, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("v", [1.0, 1e-6])
def test_a_speed_limit_makes_the_trapezoid_and_cruises_off_the_torque_limit(wheel, v):
    """1 rad with |tau| <= 2 v^2 J and |qd| <= v (1 rad/s, or a creeping 1e-6 rad/s: nothing
    absolute in the vertices' tolerance): accelerate over a quarter (1 / (2 v) s), cruise at v
    over half, brake over the last quarter: 1.5 / v s, the speed limit met with equality and
    the torque off its limit (zero) while cruising."""
    lim = 2 * J_WHEEL * v**2
    res = ps.time_optimal(wheel, _line(0.0, 1.0, 21), [lim], speed_limit=v)
    assert res.duration_s == pytest.approx(1.5 / v, rel=1e-12)
    assert np.abs(res.trajectory.qd).max() == pytest.approx(v, rel=1e-12)
    on = np.r_[np.ones(5, bool), np.zeros(10, bool), np.ones(6, bool)]
    assert res.on_limit.tolist() == on.tolist()
    assert np.abs(res.tau[5:15]).max() < 1e-12 * lim


def _controllable_lp(a, b, c, lim, x_max, ds, i):
    """min and max of x_i over every timing from sample i to the end at rest within the limits
    (one linear program each: x_i..x_{N-1}, u_i..u_{N-2}), or None where there is none."""
    n_pts, na = len(a), a.shape[1]
    m = n_pts - i  # x_i..x_{N-1}, then u_i..u_{N-2}
    rows, cols, vals, rhs = [], [], [], []
    r = 0
    for j in range(i, n_pts - 1):
        for k in range(na):
            for sign in (1.0, -1.0):
                rows += [r, r]
                cols += [j - i, m + j - i]
                vals += [sign * b[j, k], sign * a[j, k]]
                rhs.append(lim[k] - sign * c[j, k])
                r += 1
    a_ub = coo_matrix((vals, (rows, cols)), shape=(r, 2 * m - 1)).tocsr()
    e = np.arange(m - 1)
    a_eq = coo_matrix((np.concatenate([np.ones(m - 1), -np.ones(m - 1), -2 * ds[i:]]),
                       (np.tile(e, 3), np.concatenate([e + 1, e, m + e]))),
                      shape=(m - 1, 2 * m - 1)).tocsr()
    bounds = [(0, None if not np.isfinite(x_max[j]) else x_max[j]) for j in range(i, n_pts - 1)]
    bounds += [(0, 0)] + [(None, None)] * (m - 1)
    out = []
    for sign in (1.0, -1.0):
        res = linprog(np.r_[sign, np.zeros(2 * m - 2)], A_ub=a_ub, b_ub=np.array(rhs),
                      A_eq=a_eq, b_eq=np.zeros(m - 1), bounds=bounds, method="highs")
        if res.status == 2:
            return None
        assert res.status == 0, res.message
        out.append(res.x[0])
    return out


def _fastest_lp(a, b, c, lim, x_max, ds):
    """The fastest timing's x = sdot^2 at every sample: the largest sum of x (the pointwise
    largest feasible profile) from rest to rest."""
    n_pts = len(a)
    lp = _controllable_lp(a, b, c, lim, x_max, ds, 0)  # feasibility, same rows
    assert lp is not None
    # the same program, maximising the sum of x, with x_0 = 0
    na, m = a.shape[1], n_pts
    rows, cols, vals, rhs = [], [], [], []
    r = 0
    for j in range(n_pts - 1):
        for k in range(na):
            for sign in (1.0, -1.0):
                rows += [r, r]
                cols += [j, m + j]
                vals += [sign * b[j, k], sign * a[j, k]]
                rhs.append(lim[k] - sign * c[j, k])
                r += 1
    a_ub = coo_matrix((vals, (rows, cols)), shape=(r, 2 * m - 1)).tocsr()
    e = np.arange(m - 1)
    a_eq = coo_matrix((np.concatenate([np.ones(m - 1), -np.ones(m - 1), -2 * ds]),
                       (np.tile(e, 3), np.concatenate([e + 1, e, m + e]))),
                      shape=(m - 1, 2 * m - 1)).tocsr()
    bounds = [(0, 0)] + [(0, None if not np.isfinite(x_max[j]) else x_max[j])
                         for j in range(1, n_pts - 1)] + [(0, 0)] + [(None, None)] * (m - 1)
    res = linprog(np.r_[-np.ones(m), np.zeros(m - 1)], A_ub=a_ub, b_ub=np.array(rhs),
                  A_eq=a_eq, b_eq=np.zeros(m - 1), bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return np.maximum(res.x[:m], 0.0)


def _coefficients(robot, path):
    s, q, q_s, q_ss = TOPP.arc_length_path(robot, path)
    zero = np.zeros_like(q)
    c = robot.inverse_dynamics(q, zero, zero)
    return s, q_s, robot.inverse_dynamics(q, zero, q_s) - c, \
        robot.inverse_dynamics(q, q_s, q_ss) - c, c


@pytest.mark.parametrize("forward", [True, False])
def test_over_the_top_the_controllable_sets_and_the_timing_are_the_linear_programs(forward):
    """The pendulum with 1.5 N*m (m g l = 3.68 N*m) from 0.35 rad past the top, down, round
    and up to 0.35 rad short of it (or back): it climbs the last half only on the speed gained,
    so the controllable sets have a lower bound above zero there (x = sdot^2 up to 1.84). Each
    sample's [lo, hi] is the min and max of x_i over all timings to the end at rest (one LP
    each); with a speed limit too; the timing is the LP's largest profile, at rest at the end."""
    rod = ps.load("tests/robots/pendulum.toml")
    q0, q1 = np.pi / 2 + 0.35, 5 * np.pi / 2 - 0.35
    path = _line(q0, q1, 25) if forward else _line(q1, q0, 25)
    s, q_s, a, b, c = _coefficients(rod, path)
    lim, ds = np.array([1.5]), np.diff(s)
    for speed in (None, 12.0):
        x_max = np.full(len(s), np.inf) if speed is None else (speed / np.abs(q_s[:, 0])) ** 2
        lo, hi = TOPP._controllable(rod, a, b, c, lim, x_max, ds)
        ref = np.array([_controllable_lp(a, b, c, lim, x_max, ds, i) for i in range(24)])
        scale = ref.max()
        assert np.abs(lo[:-1] - ref[:, 0]).max() <= 1e-9 * scale
        assert np.abs(hi[:-1] - ref[:, 1]).max() <= 1e-9 * scale
        assert lo[-1] == hi[-1] == 0.0 and lo.max() > 0.2 * scale
        res = ps.time_optimal(rod, path, lim, speed_limit=speed)
        x = _fastest_lp(a, b, c, lim, x_max, ds)
        assert np.abs(res.sdot**2 - x).max() <= 1e-9 * x.max()
        assert res.sdot[0] == res.sdot[-1] == 0.0
        # the last sample brakes as the last step does, sddot = (0 - x_{N-2}) / (2 ds), held
        # within what its own torque limit allows at rest there (|a u + c| <= lim, by hand):
        # as the last step alone, its torque passed the limit
        u_step = -res.sdot[-2] ** 2 / (2 * ds[-1])
        bounds = sorted(((-lim[0] - c[-1, 0]) / a[-1, 0], (lim[0] - c[-1, 0]) / a[-1, 0]))
        u_last = min(max(u_step, bounds[0]), bounds[1])
        assert res.trajectory.qdd[-1, 0] == pytest.approx(q_s[-1, 0] * u_last, rel=1e-9)
        assert abs(res.tau[-1, 0]) <= lim[0] * (1 + 1e-12)
        if speed is not None:  # the speed limit met with equality where it binds
            assert np.abs(res.trajectory.qd).max() == pytest.approx(speed, rel=1e-9)


def test_a_joint_whose_torque_does_not_depend_on_the_path_acceleration(gantry):
    """The gantry moved along x only: the y slider's force is the head's weight m g = 9.81 N at
    every sample, whatever the path speed (its row of a is exactly 0), so the x force alone
    times the move, bang-bang: T = 2 sqrt(d (m_c + m_h) / F) = 2 sqrt(0.6 * 3 / 4.5) s, with no
    division by that zero (no RuntimeWarning); below the weight no sample can be passed, the
    first one found (backward) the last but one."""
    path = _line([0.1, 0.2], [0.7, 0.2], 21)
    with warnings.catch_warnings():  # nor by its zero rate along the path (speed limit / 0)
        warnings.simplefilter("error")
        res = ps.time_optimal(gantry, path, [4.5, 10.0], speed_limit=[5.0, 5.0])
    assert res.duration_s == pytest.approx(2 * np.sqrt(0.6 * 3.0 / 4.5), rel=1e-12)
    assert res.tau[:, 1] == pytest.approx(np.full(21, 9.81), rel=1e-12)
    assert np.abs(res.tau[:, 0]).tolist() == pytest.approx([4.5] * 21, rel=1e-12)
    with pytest.raises(InputError) as err:
        ps.time_optimal(gantry, path, [4.5, 9.0])
    assert str(err.value) == (
        "optimal_gantry: the path cannot be followed within the limits at sample 19 (of 21): "
        "no path speed there reaches the end at rest (raise torque_limit, or the gravity "
        "torque alone exceeds it)")


def test_time_optimal_refusals_word_for_word():
    arm = ps.load("serial_2dof")
    path = _line([0.0, 0.5], [0.5, 0.0], 11)
    with pytest.raises(InputError) as err:
        ps.time_optimal(arm, path.q, [0.5, 0.1])
    assert str(err.value) == ("path must be a JointTrajectory (ps.inverse_kinematics, "
                              "ps.from_actuated), got ndarray")
    geared = ps.load("examples/serial_2dof_geared.toml")
    with pytest.raises(InputError) as err:
        ps.time_optimal(geared, path, [0.5, 0.1])
    assert str(err.value) == ("serial_2dof_geared: friction makes the torques non-affine in the "
                              "path speed squared: time_optimal takes robots without friction")
    with pytest.raises(InputError) as err:
        ps.time_optimal(ps.load("tests/robots/cart_pole.toml"), path, [1.0])
    assert str(err.value) == ("cart_pole: a passive joint of a tree does not follow a path "
                              "(underactuated): time_optimal takes fully actuated trees and "
                              "closed chains")
    with pytest.raises(InputError) as err:
        ps.time_optimal(arm, path)
    assert str(err.value) == ("serial_2dof: torque_limit is needed (the description gives no "
                              "torque_limit for every actuator): one per actuated joint, N*m")
    short = JointTrajectory(path.t_s[:2], path.q[:2], path.qd[:2], path.qdd[:2])
    tied = JointTrajectory(np.r_[0.0, 1.0, 1.0, 2.0], path.q[:4], path.qd[:4], path.qdd[:4])
    for bad in (short, tied):
        with pytest.raises(InputError) as err:
            ps.time_optimal(arm, bad, [0.5, 0.1])
        assert str(err.value) == "path.t_s must hold 3 or more increasing times"
    # three samples are enough: the straight line timed (the spline through 3 points is it)
    three = ps.time_optimal(arm, JointTrajectory(path.t_s[:3], path.q[:3], path.qd[:3],
                                                 path.qdd[:3]), [0.5, 0.1])
    assert three.trajectory.t_s[0] == 0.0 and three.duration_s > 0 and len(three.sdot) == 3
    q = path.q.copy()
    q[3] = q[2]
    with pytest.raises(InputError) as err:
        ps.time_optimal(arm, JointTrajectory(path.t_s, q, path.qd, path.qdd), [0.5, 0.1])
    assert str(err.value) == ("serial_2dof: the path stands still between samples 2 and 3 (the "
                              "actuated joints do not move): give a path that moves")
    still = JointTrajectory(path.t_s, np.tile(path.q[4], (11, 1)), path.qd, path.qdd)
    with pytest.raises(InputError) as err:
        ps.time_optimal(arm, still, [0.5, 0.1])
    assert "stands still between samples 0 and 1" in str(err.value)
    # a step a 1e-13 of the longest is standing still (a 50 rad path and a 5e-12 rad step)
    far = JointTrajectory(np.arange(4.0), np.array([[0.0, 0.0], [25.0, 0.0], [50.0, 0.0],
                                                    [50.0 + 5e-12, 0.0]]),
                          np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(InputError, match="stands still between samples 2 and 3"):
        ps.time_optimal(arm, far, [0.5, 0.1])


def _widened_once(gap):
    """_u_range with the first step's lower end raised to ``gap`` above its upper one (``gap``
    of its upper end's magnitude, at least 1): an empty range as rounding would leave it."""
    real, calls = TOPP._u_range, []

    def widened(a, d, lims, u_lo, u_hi):
        lo_, hi_ = real(a, d, lims, u_lo, u_hi)
        calls.append(1)
        return (hi_ + gap(hi_), hi_) if len(calls) == 1 else (lo_, hi_)
    return widened


def test_the_forward_pass_tolerates_only_rounding(wheel, monkeypatch):
    """Each step's range of sddot may come out empty by rounding: a gap up to TOL relative to
    the largest sddot (absolute below 1) is taken as rounding, a larger one refused, naming the
    step. Forced here by widening the range's lower end at the first step: on the bang-bang
    move (u = 4.1 /s^2 there) and on a slow one (u = 0.44 /s^2)."""
    theta, lim = 0.8, 0.3
    path = _line(0.2, 0.2 + theta, 21)
    assert lim / (J_WHEEL * theta) > 1.0
    monkeypatch.setattr(TOPP, "_u_range", _widened_once(lambda u: 0.5 * TOPP.TOL * abs(u)))
    res = ps.time_optimal(wheel, path, [lim])
    assert res.duration_s == pytest.approx(2 * np.sqrt(theta * J_WHEEL / lim))
    monkeypatch.setattr(TOPP, "_u_range", _widened_once(lambda u: 1.5 * TOPP.TOL * abs(u)))
    with pytest.raises(InputError) as err:
        ps.time_optimal(wheel, path, [lim])
    assert str(err.value) == ("optimal_wheel: the forward pass left the controllable set at "
                              "sample 0 (rounding?)")
    slow = 0.4375 * J_WHEEL * theta
    assert slow / (J_WHEEL * theta) < 1.0
    monkeypatch.setattr(TOPP, "_u_range", _widened_once(lambda u: 0.9 * TOPP.TOL))
    ps.time_optimal(wheel, path, [slow])
    monkeypatch.setattr(TOPP, "_u_range", _widened_once(lambda u: 1.5 * TOPP.TOL))
    with pytest.raises(InputError, match="left the controllable set at sample 0"):
        ps.time_optimal(wheel, path, [slow])


def test_a_closed_chain_path_keeps_its_assembly_mode():
    """The five-bar's S5 move in its other assembly mode (the distal links mirrored, B = -2.62
    rad where the drawn pose has -1.52): timed on the same branch, every sample of it."""
    from planar_sym.motion.closure import from_actuated

    fb = ps.load("five_bar_type1")
    t = np.linspace(0.0, 2.0, 21)
    s5 = ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    act = list(fb.actuated)
    guess = s5.q[0].copy()
    guess[1], guess[3] = -2.6248, 2.6248
    other = from_actuated(fb, t, s5.q[:, act], s5.qd[:, act], s5.qdd[:, act], q_guess=guess)
    assert abs(other.q[0, 1] - s5.q[0, 1]) > 1.0
    res = ps.time_optimal(fb, other, [0.1, 0.1])
    assert np.abs(res.trajectory.q - other.q).max() < 1e-9
    tau, _ = fb.closed_chain_inverse_dynamics(res.trajectory.q, res.trajectory.qd,
                                              res.trajectory.qdd)
    # (the limits hold where the steps are timed: the last sample's sddot is the last step's)
    assert np.abs(tau - res.tau).max() < 1e-9 and np.all(np.abs(tau[:-1]) <= 0.1 * (1 + 1e-6))


# --- optimal_move -------------------------------------------------------------------------------

def _least_effort(theta, duration, intervals):
    """The discrete least-effort rest-to-rest move of a unit inertia on ``intervals`` constant
    accelerations: a_k = beta (N/2 - k - 1/2) (the Lagrange conditions of min sum a_k^2 under
    sum a_k = 0 and h^2 sum (N - k - 1/2) a_k = theta), beta = 12 theta / (h^2 N (N^2 - 1)); the
    cost h sum a_k^2 = 12 theta^2 / T^3 * N^2 / (N^2 - 1) (the cubic's 12 theta^2 / T^3 as
    N grows)."""
    N, h = intervals, duration / intervals
    beta = 12 * theta / (h**2 * N * (N**2 - 1))
    acc = beta * (N / 2 - np.arange(N) - 0.5)
    return acc, 12 * theta**2 / duration**3 * N**2 / (N**2 - 1)


def _motor_wheel(tmp_path_factory, rpm=300.0):
    """The wheel through a 50:1 gear, its motor 0.03 N*m/A and 2 ohm, speed limit ``rpm``
    (v = rpm 2 pi / 60 / 50 at the joint) and torque limit tau / 50 with tau = 2 J v^2 (the
    joint's own torque_limit, 1 N*m, is looser)."""
    v = rpm * 2 * np.pi / 60 / 50
    tau = 2 * J_WHEEL * v**2
    text = (ROOT / "tests" / "robots" / "pendulum.toml").read_text()
    text = text.replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]")
    text = text.replace('name = "pendulum"', 'name = "optimal_motor_wheel"')
    text = text.replace("actuated = true\n", "actuated = true\n[joints.actuator]\ngear_ratio = 50\n"
                        "torque_constant = 0.03\nwinding_resistance = 2.0\n"
                        f"motor_speed_limit_rpm = {rpm!r}\nmotor_torque_limit = {tau / 50!r}\n"
                        "torque_limit = 1.0\n")
    path = tmp_path_factory.mktemp("motor_wheel") / "optimal_motor_wheel.toml"
    path.write_text(text)
    return ps.load(path), v, tau


@pytest.fixture(scope="module")
def motor_wheel(tmp_path_factory):
    return _motor_wheel(tmp_path_factory)


@pytest.mark.parametrize("intervals", [2, 6])
def test_least_effort_of_a_pure_inertia_is_the_discrete_closed_form(wheel, intervals):
    """0.8 rad in 1 s: the cost, each node's torque (the interval's J a_k; the last node the
    last interval's), the nodes on the double integrator, and IPOPT's report."""
    theta, T, N = 0.8, 1.0, intervals
    acc, cost = _least_effort(theta, T, N)
    start = time.perf_counter()
    move = ps.optimal_move(wheel, [0.1], [0.1 + theta], objective="effort", duration_s=T,
                           intervals=np.int64(N))
    wall = time.perf_counter() - start
    assert move.objective == pytest.approx(J_WHEEL**2 * cost, rel=1e-8)
    assert move.tau[:, 0] == pytest.approx(J_WHEEL * np.r_[acc, acc[-1]], rel=1e-7, abs=1e-9)
    jt = move.trajectory
    h = T / N
    assert move.duration_s == T and jt.t_s == pytest.approx(np.linspace(0, T, N + 1), abs=0)
    assert jt.qdd[:, 0] == pytest.approx(np.r_[acc, acc[-1]], rel=1e-7, abs=1e-9)
    qd = np.r_[0.0, np.cumsum(h * acc)]
    q = 0.1 + np.r_[0.0, np.cumsum(h * qd[:-1] + h**2 / 2 * acc)]
    assert jt.qd[:, 0] == pytest.approx(qd, abs=1e-9) and jt.q[:, 0] == pytest.approx(q,
                                                                                       abs=1e-9)
    assert jt.solver == "optimal (IPOPT)"
    report = move.solver
    assert sorted(report) == ["constraint_violation", "iterations", "solve_time_s", "status",
                              "total_time_s"]
    assert report["status"] == "Solve_Succeeded" and isinstance(report["iterations"], int)
    assert 1 <= report["iterations"] < 100
    # the largest violation of any constraint is at least the integrator's residual here
    resid = np.abs(jt.q[1:, 0] - jt.q[:-1, 0] - h * jt.qd[:-1, 0] - h**2 / 2 * acc).max()
    assert resid <= report["constraint_violation"] + 1e-15 and report["constraint_violation"] < 1e-6
    assert 0 < report["solve_time_s"] < wall


def test_least_energy_of_a_pure_inertia_is_the_copper_loss_of_the_least_effort(motor_wheel):
    """No gravity, rest to rest: the work done returns exactly (h/2 sum tau_k (qd_k + qd_k+1) =
    J (qd_N^2 - qd_0^2) / 2 = 0), so the least energy is R / (N k_t)^2 times the least effort
    (1 rad in 4 s on 6 intervals, within the description's limits)."""
    rod, _, _ = motor_wheel
    acc, cost = _least_effort(1.0, 4.0, 6)
    move = ps.optimal_move(rod, [0.0], [1.0], objective="energy", duration_s=4.0, intervals=6)
    assert move.objective == pytest.approx(2.0 / (50 * 0.03) ** 2 * J_WHEEL**2 * cost, rel=1e-8)
    assert move.tau[:, 0] == pytest.approx(J_WHEEL * np.r_[acc, acc[-1]], rel=1e-7)


def test_the_fastest_move_within_the_motors_limits_is_the_trapezoid(motor_wheel):
    """1 rad within the motor's speed (v at the joint) and torque (tau = 2 J v^2 at the joint)
    through the gear: accelerate for 1 / (2 v), cruise as long, brake as long: T = 1.5 / v, on
    6 intervals exactly (the continuous optimum is on the grid); the speed and torque limits met
    with equality, the torque zero while cruising. A looser speed limit given (2 v) overrides
    the description's: bang-bang, T = 2 sqrt(theta J / tau) = sqrt(2) / v."""
    rod, v, tau = motor_wheel
    move = ps.optimal_move(rod, [0.0], [1.0], objective="time", intervals=6)
    assert move.duration_s == pytest.approx(1.5 / v, rel=1e-6)
    assert move.tau[:, 0] / tau == pytest.approx([1, 1, 0, 0, -1, -1, -1], abs=1e-6)
    assert move.trajectory.qd[:, 0] / v == pytest.approx([0, 0.5, 1, 1, 1, 0.5, 0], abs=1e-6)
    assert move.objective == pytest.approx(move.duration_s, rel=1e-12)
    fast = ps.optimal_move(rod, [0.0], [1.0], objective="time", intervals=6, speed_limit=2 * v)
    assert fast.duration_s == pytest.approx(np.sqrt(2) / v, rel=1e-6)
    assert np.abs(fast.tau[:, 0]) / tau == pytest.approx(np.ones(7), abs=1e-6)
    assert fast.solver["constraint_violation"] < 1e-6


def test_a_passive_joint_of_a_tree_is_free_on_average_over_each_interval():
    """The cart-pole's cart moved 0.3 m in 1.5 s with the least effort (the pole on its free
    hinge): on each interval the hinge's torque at the start and at the end, from the
    generated inverse dynamics on the solution, cancel; the cart's force is the returned one;
    the objective is the trapezoid of the force squared."""
    cart = ps.load("tests/robots/cart_pole.toml")
    move = ps.optimal_move(cart, [0.0, -np.pi / 2], [0.3, -np.pi / 2], objective="effort",
                           duration_s=1.5, intervals=10)
    jt = move.trajectory
    start = cart.tree_inverse_dynamics(jt.q[:-1], jt.qd[:-1], jt.qdd[:-1])
    end = cart.tree_inverse_dynamics(jt.q[1:], jt.qd[1:], jt.qdd[:-1])
    assert np.abs(start[:, 1] + end[:, 1]).max() <= 1e-9
    assert np.abs(start[:, 1]).max() > 1e-3  # not zero at each end: free on average
    assert np.abs(start[:, 0] - move.tau[:-1, 0]).max() <= 1e-9
    assert end[-1, 0] == pytest.approx(move.tau[-1, 0], abs=1e-9)
    h = 1.5 / 10
    assert move.objective == pytest.approx(h / 2 * (np.sum(start[:, 0] ** 2)
                                                    + np.sum(end[:, 0] ** 2)), rel=1e-9)
    assert np.abs(jt.q[:, 1] + np.pi / 2).max() > 0.01  # the pole swings


def test_a_closed_chain_move_stays_on_its_loops_at_both_ends_of_every_interval():
    """The five-bar's least-effort move (its actuated coordinates given): every node on the
    loops with its rates and accelerations (the passive ones completed from the loops by
    from_actuated, an independent solver), each node's torque the closed-chain inverse
    dynamics there, and the effort the trapezoid of the torques at both ends of each interval
    (the ends' passive accelerations again from the loops)."""
    from planar_sym.motion.closure import from_actuated

    fb = ps.load("five_bar_type1")
    act = list(fb.actuated)
    q0 = fb.q_drawn
    t = np.linspace(0.0, 2.0, 21)
    s5 = ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    N, T = 8, 0.5
    move = ps.optimal_move(fb, s5.q[0], s5.q[-1, act], objective="effort", duration_s=T,
                           intervals=N)
    jt = move.trajectory
    assert np.abs(fb.constraint(jt.q)).max() < 1e-9
    full = from_actuated(fb, jt.t_s, jt.q[:, act], jt.qd[:, act], jt.qdd[:, act],
                         q_guess=s5.q[0])
    assert np.abs(full.q - jt.q).max() < 1e-9 and np.abs(full.qd - jt.qd).max() < 1e-9
    assert np.abs(full.qdd - jt.qdd).max() < 1e-7
    tau, _ = fb.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    assert np.abs(tau - move.tau).max() <= 1e-9
    ends = from_actuated(fb, jt.t_s[1:], jt.q[1:, act], jt.qd[1:, act], jt.qdd[:-1, act],
                         q_guess=s5.q[0])
    tau_end, _ = fb.closed_chain_inverse_dynamics(ends.q, ends.qd, ends.qdd)
    h = T / N
    assert move.objective == pytest.approx(h / 2 * (np.sum(tau[:-1] ** 2)
                                                    + np.sum(tau_end ** 2)), rel=1e-7)
    assert jt.q[0] == pytest.approx(s5.q[0], abs=1e-9) and q0.shape == (4,)


def test_optimal_move_refusals_word_for_word(wheel, motor_wheel, monkeypatch):
    arm = ps.load("serial_2dof")
    cases = [
        ({"objective": "fastest"},
         "objective must be one of time, effort, energy (got 'fastest')"),
        ({"duration_s": 1.0, "intervals": 1},
         "intervals must be an integer from 2 to 10000 (got 1)"),
        ({"duration_s": 1.0, "intervals": 10_001},
         "intervals must be an integer from 2 to 10000 (got 10001)"),
        ({"duration_s": 1.0, "intervals": 8.0},
         "intervals must be an integer from 2 to 10000 (got 8.0)"),
        ({"objective": "time"},
         ("serial_2dof: objective \"time\" needs torque_limit (the description gives none "
          "for every actuator): one per actuated joint, N*m")),
        ({"duration_s": 0.0}, "objective 'effort' needs duration_s > 0 (s)"),
        ({"objective": "energy", "duration_s": -1.0},
         "objective 'energy' needs duration_s > 0 (s)"),
        ({"objective": "time", "torque_limit": [0.5, 0.0]},
         "torque_limit must be positive and finite, got [0.5, 0.0]"),
        ({"objective": "time", "torque_limit": [0.5, 0.1], "duration_s": 1.0},
         ("objective 'time' finds the duration: leave duration_s out (got 1.0), or minimise "
          "'effort' or 'energy' in it")),
        ({"duration_s": 1.0, "speed_limit": [1.0, 0.0]},
         "speed_limit must be positive, got [1.0, 0.0]"),
    ]
    for kwargs, message in cases:
        with pytest.raises(InputError) as err:
            ps.optimal_move(arm, [0.0, 0.0], [0.5, 0.5], **kwargs)
        assert str(err.value) == message, kwargs
    with pytest.raises(InputError) as err:
        ps.optimal_move(arm, [0.0, 0.0], [0.5, 0.5, 0.5], duration_s=1.0)
    assert str(err.value) == ("q_end must be 2 finite values for serial_2dof (one per "
                              "coordinate), got [0.5, 0.5, 0.5]")
    with pytest.raises(InputError) as err:
        ps.optimal_move(arm, [0.0, np.nan], [0.5, 0.5], duration_s=1.0)
    assert str(err.value).startswith("q_start must be 2 finite values")
    fb = ps.load("five_bar_type1")
    with pytest.raises(InputError) as err:
        ps.optimal_move(fb, [0.1, 0.2, 0.3], [0.0, 0.0], duration_s=1.0)
    assert str(err.value) == ("q_start must be 2 finite values for five_bar_type1 (its "
                              "actuated coordinates, or 4 for a pose on its loops), got "
                              "[0.1, 0.2, 0.3]")
    off = np.zeros(4)
    with pytest.raises(InputError) as err:
        ps.optimal_move(fb, fb.q_drawn, off, duration_s=1.0)
    assert str(err.value) == (
        f"q_end is off five_bar_type1's loops (|Phi| = {np.abs(fb.constraint(off)).max():.3g} "
        "m): give the actuated coordinates, or a pose on the loops")
    # the energy needs every motor's electrical figures: one joint lacks them, or two
    with pytest.raises(InputError) as err:
        ps.optimal_move(wheel, [0.0], [1.0], objective="energy", duration_s=1.0)
    assert str(err.value) == ("optimal_wheel: objective \"energy\" needs each motor's "
                              "torque_constant (N*m/A) and winding_resistance (ohm) in its "
                              "[joints.actuator]; pivot has none")
    with pytest.raises(InputError) as err:  # before the ends are read
        ps.optimal_move(arm, [0.0, 0.0], [0.5], objective="energy", duration_s=1.0)
    assert str(err.value).endswith("[joints.actuator]; joint1, joint2 have none")
    # IPOPT finding nothing: 1 rad in 2 s needs more than the motor's torque
    rod, _, _ = motor_wheel
    with pytest.raises(ps.SimulationError) as err:
        ps.optimal_move(rod, [0.0], [1.0], objective="energy", duration_s=2.0, intervals=6)
    assert re.fullmatch(r"optimal_motor_wheel: IPOPT found no optimal move \((Infeasible_"
                        r"Problem_Detected|Restoration_Failed|Local_Infeasibility), [1-9]\d* "
                        r"iterations\): loosen the limits, lengthen duration_s, or change the "
                        r"end points", str(err.value)), str(err.value)
    # the largest grid is accepted (and handed on as an int), as are NumPy integers
    seen = []
    monkeypatch.setattr(P2P, "_within_limits",
                        lambda *args, **kw: seen.append(args[-1]) or "solved")
    monkeypatch.setattr(P2P, "_timed", lambda move, started: move)  # (the stand-in's text)
    assert ps.optimal_move(arm, [0.0, 0.0], [0.5, 0.5], duration_s=1.0,
                           intervals=np.int16(10_000)) == "solved"
    assert seen == [10_000] and type(seen[0]) is int


# --- limits -------------------------------------------------------------------------------------

def test_the_description_limits_through_the_gears():
    """tests/robots/actuated_2dof.toml: joint1's own 0.8 N*m is tighter than its motor's 0.02
    N*m through 50:1 (1 N*m), joint2 has no limit; joint1's motor turns at 3000 rpm, 3000 * 2 pi
    / 60 / 50 = 6.2832 rad/s at the joint, joint2's has none (inf)."""
    arm = ps.load("tests/robots/actuated_2dof.toml")
    assert LIMITS.description_torque_limits(arm) == [0.8, None]
    assert LIMITS.description_speed_limits(arm).tolist() == pytest.approx([2 * np.pi, np.inf])
    assert LIMITS.torque_limits(arm, None, None) is None  # a limit missing: none at all
    with pytest.raises(InputError) as err:
        LIMITS.torque_limits(arm, None, "which limit?")
    assert str(err.value) == "which limit?"
    plain = ps.load("serial_2dof")
    assert LIMITS.description_torque_limits(plain) == [None, None]
    assert LIMITS.description_speed_limits(plain) is None


def test_the_motor_limit_is_the_tighter_one(motor_wheel):
    """The motor wheel: its motor's tau / 50 through 50:1 is tighter than the joint's 1 N*m;
    300 rpm is 300 * 2 pi / 60 / 50 rad/s at the joint."""
    rod, v, tau = motor_wheel
    assert LIMITS.description_torque_limits(rod) == [pytest.approx(tau, rel=1e-12)]
    assert LIMITS.torque_limits(rod, None, "unused").tolist() == [pytest.approx(tau, rel=1e-12)]
    assert LIMITS.description_speed_limits(rod).tolist() == [pytest.approx(v, rel=1e-12)]


def test_given_limits_are_checked_and_copied():
    arm = ps.load("serial_2dof")
    given = np.array([0.5, 0.25])
    lim = LIMITS.torque_limits(arm, given, None)
    given[0] = 7.0  # the caller's array changed afterwards: the limits taken stay
    assert lim.tolist() == [0.5, 0.25] and lim.dtype == float and lim.flags.writeable
    assert LIMITS.torque_limits(arm, 2, None).tolist() == [2.0, 2.0]
    assert LIMITS.torque_limits(arm, [1, 3], "unused").dtype == float
    for bad in ([0.5, np.inf], [np.nan, 0.5], [0.5, 0.0], -1.0):
        with pytest.raises(InputError) as err:
            LIMITS.torque_limits(arm, bad, None)
        shown = np.broadcast_to(np.asarray(bad, float), (2,)).tolist()
        assert str(err.value) == f"torque_limit must be positive and finite, got {shown}"
    with pytest.raises(InputError) as err:
        LIMITS.torque_limits(arm, [1.0, 2.0, 3.0], None)
    assert str(err.value) == ("torque_limit must be one number or 2, one per actuated joint "
                              "(got [1.0, 2.0, 3.0])")
    assert LIMITS.speed_limits(arm, 0.5).tolist() == [0.5, 0.5]  # below 1 rad/s is a limit
    speeds = np.array([0.25, 3.0])
    v = LIMITS.speed_limits(arm, speeds)
    speeds[1] = -1.0
    assert v.tolist() == [0.25, 3.0] and v.flags.writeable
    for bad in ([0.5, 0.0], [-1.0, 1.0], [np.nan, 1.0]):
        with pytest.raises(InputError) as err:
            LIMITS.speed_limits(arm, bad)
        assert str(err.value) == f"speed_limit must be positive, got {np.asarray(bad).tolist()}"
    with pytest.raises(InputError) as err:
        LIMITS.speed_limits(arm, "fast")
    assert str(err.value) == "speed_limit must be one number or 2, one per coordinate (got 'fast')"


class _Recorder:
    """Stands in for CasADi's Opti where only the starting point is asked for: records
    set_initial(variable, value) by the variable's name."""

    def __init__(self):
        self.initial = {}

    def set_initial(self, var, value):
        assert var not in self.initial, var
        self.initial[var] = np.array(value, dtype=float)


def test_initial_guess_is_the_cubic_rest_to_rest_move():
    """From [0.2, -1] to [1.4, 0.5] in 2 s on 4 intervals: q = a0 + (3 s^2 - 2 s^3) d, qd =
    6 (s - s^2) d / T, and each interval's acceleration the cubic's at its midpoint, 6 (1 - 2
    s_mid) d / T^2, with s = t / T."""
    a0, a1, T = np.array([0.2, -1.0]), np.array([1.4, 0.5]), 2.0
    t, q, qd, qdd = P2P.initial_guess(a0, a1, 4, T)
    d = a1 - a0
    s = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    assert t.tolist() == (s * T).tolist()
    assert q == pytest.approx(a0 + (3 * s**2 - 2 * s**3)[:, None] * d, abs=1e-15)
    assert qd == pytest.approx((6 * (s - s**2) / T)[:, None] * d, abs=1e-15)
    mid = np.array([0.125, 0.375, 0.625, 0.875])
    assert qdd == pytest.approx((6 * (1 - 2 * mid) / T**2)[:, None] * d, abs=1e-15)
    assert q[[0, -1]] == pytest.approx(np.vstack([a0, a1]), abs=1e-15)
    assert qd.shape == (5, 2) and qdd.shape == (4, 2)


def test_ipopt_starts_from_the_cubic_or_from_the_move_given():
    """The starting point handed to IPOPT: the cubic over the duration (1 s when the time is
    free, which then starts at 1 s) for the integrated coordinates, a closed chain's passive
    ones completed from its loops; or another move's nodes, its passive accelerations for both
    ends of each interval, and its duration."""
    from planar_sym.motion.closure import from_actuated

    arm = ps.load("serial_2dof")
    a0, a1 = np.array([0.0, 0.5]), np.array([0.5, 0.0])
    for duration, T in ((2.5, 2.5), (None, "T")):
        rec = _Recorder()
        P2P._guess(arm, rec, [0, 1], [], False, a0, a1, 4, "Qi", "Vi", "Ai", None, None,
                   (None, None), T, duration)
        _, q, qd, qdd = P2P.initial_guess(a0, a1, 4, 2.5 if duration else 1.0)
        assert sorted(rec.initial) == (["Ai", "Qi", "Vi"] if duration else ["Ai", "Qi", "T", "Vi"])
        assert rec.initial["Qi"] == pytest.approx(q.T) and rec.initial["Vi"] == pytest.approx(qd.T)
        assert rec.initial["Ai"] == pytest.approx(qdd.T)
        if duration is None:
            assert rec.initial["T"] == 1.0
    fb = ps.load("five_bar_type1")
    act, pas = list(fb.actuated), list(fb.passive)
    t = np.linspace(0.0, 2.0, 21)
    s5 = ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    b0, b1 = s5.q[0, act], s5.q[-1, act]
    rec = _Recorder()
    P2P._guess(fb, rec, act, pas, True, b0, b1, 5, "Qi", "Vi", "Ai", "Qp", "Vp", ("Ap", "Ae"),
               0.8, 0.8)
    tt, q, qd, qdd = P2P.initial_guess(b0, b1, 5, 0.8)
    full = from_actuated(fb, tt, q, qd, np.vstack([qdd, qdd[-1:]]))
    assert sorted(rec.initial) == ["Ae", "Ai", "Ap", "Qi", "Qp", "Vi", "Vp"]
    assert rec.initial["Qp"] == pytest.approx(full.q[:, pas].T)
    assert rec.initial["Vp"] == pytest.approx(full.qd[:, pas].T)
    assert rec.initial["Ap"] == pytest.approx(full.qdd[:-1, pas].T)
    assert rec.initial["Ae"] == pytest.approx(full.qdd[:-1, pas].T)
    # from another move
    rng = np.random.default_rng(3)
    jt = JointTrajectory(np.linspace(0, 1, 6), rng.normal(size=(6, 4)), rng.normal(size=(6, 4)),
                         rng.normal(size=(6, 4)))
    warm = P2P.OptimalMove(jt, np.zeros((6, 2)), 1.7, 1.7, {})
    for closed, T in ((True, "T"), (False, 0.9)):
        rec = _Recorder()
        P2P._warm(rec, warm, act, pas, closed, "Qi", "Vi", "Ai", "Qp", "Vp", ("Ap", "Ae"), T)
        assert rec.initial["Qi"] == pytest.approx(jt.q[:, act].T)
        assert rec.initial["Vi"] == pytest.approx(jt.qd[:, act].T)
        assert rec.initial["Ai"] == pytest.approx(jt.qdd[:-1, act].T)
        if closed:
            assert rec.initial["Qp"] == pytest.approx(jt.q[:, pas].T)
            assert rec.initial["Vp"] == pytest.approx(jt.qd[:, pas].T)
            assert rec.initial["Ap"] == pytest.approx(jt.qdd[:-1, pas].T)
            assert rec.initial["Ae"] == pytest.approx(jt.qdd[:-1, pas].T)
            assert rec.initial["T"] == 1.7
        else:
            assert sorted(rec.initial) == ["Ai", "Qi", "Vi"]


def test_the_default_grid_and_a_silent_solver(wheel, capfd):
    """40 intervals unless told (41 nodes), and nothing printed by CasADi or IPOPT."""
    capfd.readouterr()
    move = ps.optimal_move(wheel, [0.0], [0.5], duration_s=1.0)
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    assert len(move.trajectory.t_s) == 41 and move.tau.shape == (41, 1)
    _, cost = _least_effort(0.5, 1.0, 40)
    assert move.objective == pytest.approx(J_WHEEL**2 * cost, rel=1e-8)


def test_controllable_sets_of_random_programs_are_the_linear_programs():
    """Two joints' torques affine in (u, x) with random coefficients (and gravity-like offsets
    up to 1.3 times the limits), random steps and speed bounds: each sample's [lo, hi] is the
    LP's min and max of x_i over every timing to the end at rest; where the LP has none, the
    backward pass refuses at the last such sample."""
    rng = np.random.default_rng(30)
    rod = ps.load("tests/robots/pendulum.toml")  # only its name is read
    refused = checked = 0
    for _ in range(12):
        N = 7
        a, b = rng.normal(size=(N, 2)), rng.normal(size=(N, 2))
        c = rng.uniform(-1.3, 1.3, size=(N, 2))
        lim = np.array([1.0, 1.0])
        ds = rng.uniform(0.5, 1.5, size=N - 1)
        ds /= ds.sum()
        x_max = np.where(rng.random(N) < 0.5, np.inf, rng.uniform(0.5, 5.0, N))
        ref = [_controllable_lp(a, b, c, lim, x_max, ds, i) for i in range(N - 1)]
        empty = [i for i, r in enumerate(ref) if r is None]
        if empty:
            with pytest.raises(InputError, match=f"within the limits at sample {max(empty)} "
                                                 f"\\(of {N}\\)"):
                TOPP._controllable(rod, a, b, c, lim, x_max, ds)
            refused += 1
            continue
        lo, hi = TOPP._controllable(rod, a, b, c, lim, x_max, ds)
        ref = np.array(ref)
        scale = max(ref.max(), 1.0)
        assert np.abs(lo[:-1] - ref[:, 0]).max() <= 1e-9 * scale
        assert np.abs(hi[:-1] - ref[:, 1]).max() <= 1e-9 * scale
        checked += 1
    assert refused >= 2 and checked >= 4, (refused, checked)


def test_a_path_cannot_turn_back_where_gravity_exceeds_the_limit():
    """The pendulum from 0.3 rad short of the top down to horizontal (q = 0, m g l = 3.68
    N*m) and back up: turning back there needs more than m g l whatever the speed (q_s = 0,
    tau = J q_ss sdot^2 + m g l), so the backward pass stops at that sample, 10 of 21."""
    rod = ps.load("tests/robots/pendulum.toml")
    top = np.pi / 2 - 0.3
    q = np.r_[np.linspace(top, 0.0, 11), np.linspace(0.0, top, 11)[1:]]
    path = JointTrajectory(np.arange(21.0), q[:, None], np.zeros((21, 1)), np.zeros((21, 1)))
    with pytest.raises(InputError) as err:
        ps.time_optimal(rod, path, [1.5])
    assert str(err.value).startswith("pendulum: the path cannot be followed within the limits "
                                     "at sample 10 (of 21): ")


def test_standing_still_is_relative_to_the_longest_step(wheel):
    """A step of at most 1e-12 of the longest is standing still, that bound included; a
    micro-move (2e-12 rad on 20 steps of 1e-13) is a move, timed as any other (bang-bang in
    2 sqrt(theta J / tau)), and its repeated sample is named."""
    def path(q):
        q = np.asarray(q, float)
        return JointTrajectory(np.arange(len(q), dtype=float), q[:, None],
                               np.zeros((len(q), 1)), np.zeros((len(q), 1)))

    for q, k in (([-1.0, 0.0, 1e-12], 1), ([-1.0, 0.0, 1e-12, 1e-12], 1)):
        with pytest.raises(InputError) as err:
            ps.time_optimal(wheel, path(q), [1.0])
        assert f"stands still between samples {k} and {k + 1} " in str(err.value)
    micro = np.linspace(0.0, 2e-12, 21)
    res = ps.time_optimal(wheel, path(micro), [1.0])
    assert res.duration_s == pytest.approx(2 * np.sqrt(2e-12 * J_WHEEL / 1.0), rel=1e-9)
    with pytest.raises(InputError) as err:
        ps.time_optimal(wheel, path(np.r_[micro[:8], micro[7:]]), [1.0])
    assert "stands still between samples 7 and 8 " in str(err.value)


def test_the_fastest_move_of_a_pure_inertia_is_bang_bang(wheel):
    """0.8 rad with |tau| <= 3 N*m: T = 2 sqrt(theta J / tau_max) = 0.348 s (well under the
    1 s IPOPT starts from), +3 N*m over the first half, -3 N*m over the second."""
    move = ps.optimal_move(wheel, [0.3], [1.1], objective="time", torque_limit=3.0,
                           intervals=4)
    assert move.duration_s == pytest.approx(2 * np.sqrt(0.8 * J_WHEEL / 3.0), rel=1e-7)
    assert move.objective == pytest.approx(move.duration_s, rel=1e-12)
    assert move.tau[:, 0] == pytest.approx([3, 3, -3, -3, -3], rel=1e-6)
    assert move.solver["status"] == "Solve_Succeeded"
    assert 0 <= move.solver["constraint_violation"] < 1e-6


class _Script:
    """Stands in for one IPOPT solve (``_solve``) or one move within the limits
    (``_within_limits``): records each call's arguments and plays its outcomes in turn (an
    exception is raised, anything else returned)."""

    def __init__(self, *outcomes):
        self.outcomes, self.calls = list(outcomes), []

    def __call__(self, robot, a0, a1, objective, duration, lim, v, N, warm=None, seed=None,
                 copper=None):
        self.calls.append((objective, duration, None if lim is None else tuple(lim),
                           None if v is None else tuple(v), N, warm))
        out = self.outcomes.pop(0)
        if isinstance(out, Exception):
            raise out
        return out


def test_a_move_within_the_limits_falls_back_on_the_same_move_without_them(monkeypatch):
    """From the cubic first; where IPOPT fails, the same objective without any limit, then
    with them from that move; the first failure is what is raised (without the later ones
    chained) when either fails, and at once when there were no limits to drop."""
    arm = ps.load("serial_2dof")
    a0, a1, lim, v = np.zeros(2), np.ones(2), np.array([0.5, 0.1]), np.array([2.0, 3.0])
    first, later = ps.SimulationError("first"), ps.SimulationError("later")
    for objective in ("effort", "energy"):
        for limits in ((lim, v), (None, v), (lim, None)):
            script = _Script(first, "free", "final")
            monkeypatch.setattr(P2P, "_solve", script)
            assert P2P._within_limits(arm, a0, a1, objective, 1.5, *limits, 7) == "final"
            shown = tuple(None if x is None else tuple(x) for x in limits)
            assert script.calls == [(objective, 1.5, *shown, 7, None),
                                    (objective, 1.5, None, None, 7, None),
                                    (objective, 1.5, *shown, 7, "free")]
    script = _Script("cubic")  # the cubic start found it: with every limit given
    monkeypatch.setattr(P2P, "_solve", script)
    assert P2P._within_limits(arm, a0, a1, "effort", 2.0, lim, v, 5) == "cubic"
    assert script.calls == [("effort", 2.0, (0.5, 0.1), (2.0, 3.0), 5, None)]
    for outcomes in ((first, later), (first, "free", later)):
        monkeypatch.setattr(P2P, "_solve", _Script(*outcomes))
        with pytest.raises(ps.SimulationError) as err:
            P2P._within_limits(arm, a0, a1, "effort", 1.5, lim, None, 7)
        assert err.value is first and err.value.__suppress_context__
    script = _Script(first, "never")
    monkeypatch.setattr(P2P, "_solve", script)
    with pytest.raises(ps.SimulationError) as err:
        P2P._within_limits(arm, a0, a1, "effort", 1.5, None, None, 7)
    assert err.value is first and len(script.calls) == 1


def test_the_fastest_move_falls_back_on_a_least_effort_move_of_doubling_duration(monkeypatch):
    """Where the fastest move is not found from the cubic: the least effort within the limits
    over 1 s, 2 s, 4 s, ... (WARM_TRIES = 6 durations, up to 32 s) until one is found, then the
    fastest from it; the first failure is raised when none is found, or when the fastest from
    the one found fails too."""
    arm = ps.load("serial_2dof")
    first, fail = ps.SimulationError("first"), ps.SimulationError("again")
    call = {"objective": "time", "torque_limit": [0.5, 0.1], "speed_limit": [2.0, 3.0],
            "intervals": np.int64(9)}

    def run(solve, within):
        monkeypatch.setattr(P2P, "_solve", solve)
        monkeypatch.setattr(P2P, "_within_limits", within)
        monkeypatch.setattr(P2P, "_timed", lambda move, started: move)  # (stand-ins' texts)
        return ps.optimal_move(arm, [0.0, 0.5], [0.5, 0.0], **call)

    solve, within = _Script(first, "fastest"), _Script(fail, fail, "warm")
    assert run(solve, within) == "fastest"
    assert [c[:2] for c in within.calls] == [("effort", 1.0), ("effort", 2.0), ("effort", 4.0)]
    assert all(c[2:4] == ((0.5, 0.1), (2.0, 3.0)) for c in within.calls)
    assert solve.calls[1] == ("time", None, (0.5, 0.1), (2.0, 3.0), 9, "warm")
    assert all(c[4] == 9 and type(c[4]) is int for c in solve.calls + within.calls)
    solve, within = _Script(first), _Script(*[fail] * 6)
    with pytest.raises(ps.SimulationError) as err:
        run(solve, within)
    assert err.value is first
    assert [c[1] for c in within.calls] == [1.0, 2.0, 4.0, 8.0, 16.0, 32.0]
    solve, within = _Script(first, fail), _Script("warm", "unused")
    with pytest.raises(ps.SimulationError) as err:
        run(solve, within)
    assert err.value is first and len(within.calls) == 1 and len(solve.calls) == 2
    solve, within = _Script("at once"), _Script()
    assert run(solve, within) == "at once" and solve.calls == [
        ("time", None, (0.5, 0.1), (2.0, 3.0), 9, None)]


def test_least_effort_under_a_speed_limit_is_the_quadratic_programs(wheel):
    """1 rad in 2 s with |qd| <= 0.6 rad/s (the unconstrained cubic peaks at 0.75): the same
    discrete problem as a quadratic program in the 8 accelerations (SciPy's SLSQP: min h J^2
    sum a_k^2, the end reached at rest, |h sum_{j<k} a_j| <= 0.6 at every node), the speed
    limit met with equality."""
    from scipy.optimize import minimize

    theta, T, N, v = 1.0, 2.0, 8, 0.6
    h = T / N
    move = ps.optimal_move(wheel, [0.0], [theta], objective="effort", duration_s=T,
                           speed_limit=v, intervals=N)
    lower = np.tril(np.ones((N, N)))  # node k + 1's rate: h times the sum of a_0..a_k
    res = minimize(lambda a: 1e3 * h * J_WHEEL**2 * a @ a, np.zeros(N), method="SLSQP",
                   jac=lambda a: 2e3 * h * J_WHEEL**2 * a,
                   constraints=[{"type": "eq", "fun": lambda a: [h * a.sum(),
                                 h**2 * (N - np.arange(N) - 0.5) @ a - theta]},
                                {"type": "ineq", "fun": lambda a: v - np.abs(h * lower @ a)}],
                   options={"ftol": 1e-14, "maxiter": 500})
    assert res.success, res.message
    assert move.objective == pytest.approx(res.fun / 1e3, rel=1e-6)
    assert np.abs(move.trajectory.qd).max() == pytest.approx(v, rel=1e-7)
    assert move.objective > J_WHEEL**2 * _least_effort(theta, T, N)[1] * 1.01


def _five_bar_other_mode():
    """The five-bar, its actuated coordinates, the S5 move in the drawn assembly mode and the
    same actuated motion in the other mode (passive joints started near -+2.6248 rad)."""
    from planar_sym.motion.closure import from_actuated

    fb = ps.load("five_bar_type1")
    act = list(fb.actuated)
    t = np.linspace(0.0, 2.0, 21)
    s5 = ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    guess = s5.q[0].copy()
    guess[1], guess[3] = -2.6248, 2.6248
    other = from_actuated(fb, t, s5.q[:, act], s5.qd[:, act], s5.qdd[:, act], q_guess=guess)
    return fb, act, s5, other


def test_a_closed_chain_move_starts_from_the_pose_given_in_its_assembly_mode():
    """The five-bar's start given as a pose on its loops in the other assembly mode (B =
    -2.62 rad, D = 2.62 where the drawn pose has -1.52, 1.52): the least-effort move starts at
    that very pose and stays in its mode to the end (the passive joints' first guess was the
    drawn mode's, whatever the pose given: the move started elsewhere). The actuated
    coordinates alone keep the drawn mode."""
    fb, act, s5, other = _five_bar_other_mode()
    move = ps.optimal_move(fb, other.q[0], other.q[-1], objective="effort", duration_s=0.5,
                           intervals=8)
    jt = move.trajectory
    assert np.abs(jt.q[0] - other.q[0]).max() < 1e-9
    assert np.abs(jt.q[-1] - other.q[-1]).max() < 1e-9
    assert np.abs(fb.constraint(jt.q)).max() < 1e-9
    drawn = ps.optimal_move(fb, other.q[0, act], other.q[-1, act], objective="effort",
                            duration_s=0.5, intervals=8)
    assert np.abs(drawn.trajectory.q[0] - s5.q[0]).max() < 1e-9
    assert drawn.objective != pytest.approx(move.objective, rel=1e-3)


def test_a_closed_chain_move_found_again_from_the_move_without_limits(monkeypatch):
    """The five-bar's least-effort move within 0.03 N*m, in its other assembly mode, when the
    start from the cubic fails (forced here): the same move without the limit, then with it
    from that one (every node, its passive joints too, handed on) gives the move the cubic
    gives, in the same mode."""
    fb, _, _, other = _five_bar_other_mode()
    ask = {"objective": "effort", "duration_s": 0.5, "intervals": 8, "torque_limit": 0.03}
    direct = ps.optimal_move(fb, other.q[0], other.q[-1], **ask)
    assert np.abs(direct.tau).max() == pytest.approx(0.03, rel=1e-6)  # the limit binds
    real, calls = P2P._solve, []

    def first_fails(*args, **kwargs):
        calls.append(args[5] is None)
        if len(calls) == 1:
            raise ps.SimulationError("forced")
        return real(*args, **kwargs)

    monkeypatch.setattr(P2P, "_solve", first_fails)
    again = ps.optimal_move(fb, other.q[0], other.q[-1], **ask)
    assert calls == [False, True, False]  # with the limit, without, with it from that one
    assert again.objective == pytest.approx(direct.objective, rel=1e-7)
    assert np.abs(again.trajectory.q - direct.trajectory.q).max() < 1e-6
    assert np.abs(fb.constraint(again.trajectory.q)).max() < 1e-9
