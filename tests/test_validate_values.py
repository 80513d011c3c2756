"""``validate``'s checks (``analysis/validate*.py``) held to real numbers: the error each reports
on a fault of known size planted in a compiled function, the scale it divides by, and its
pass/fail threshold at the boundary; the pieces the checks are built from against independent
references:

- the error measure ``rel_err`` and the row rule on hand-made arrays (values worked out here);
- M from the energy by polarisation, and Lagrange's g, h, tau, against the compiled functions
  and against the pendulum written out by hand (I = izz + m l^2, g(q) = m g l cos q);
- a compiled output scaled by (1 + e): row (a) reports e (the SymPy model is exact), row (b)
  reports e (polarisation is exact up to rounding), (d) and the null-space row report e
  relative to the peak; a 1-DOF Jacobian shifted by d reports d over its physical scale
  (the sampled accelerations per unit rate or per radian), recomputed here from the states;
- faults just under and just over each tolerance (the README's table): pass, then FAIL;
- the smooth motion against its formula, the free motion's push, the table ``run_all`` builds
  (rows, order, what is shared between rows, a raising check as a FAIL row) and its refusals.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.analysis import validate
from planar_sym.analysis import validate_rows as rows
from planar_sym.analysis import validate_symbolic as symbolic
from planar_sym.errors import InputError, PlanarSymError

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"
# the pendulum test robot: m = 1.5 kg, cg at l = 0.25 m, izz = 0.02 kg*m^2, gravity 9.81 m/s^2
M_P, L_P, IZZ_P, G = 1.5, 0.25, 0.02, 9.81
I_P = IZZ_P + M_P * L_P**2  # about the pivot


@pytest.fixture(scope="module")
def robots():
    return {"serial_2dof": ps.load("serial_2dof"), "serial_3dof": ps.load("serial_3dof"),
            "five_bar": ps.load("five_bar_type1"), "geared": ps.load(GEARED),
            "pendulum": ps.load(TEST_ROBOTS / "pendulum.toml"),
            "horizontal": ps.load(TEST_ROBOTS / "horizontal_2dof.toml"),
            "cart_pole": ps.load(TEST_ROBOTS / "cart_pole.toml")}


class _Planted:
    """A compiled function whose output ``out`` is ``value * factor + shift``: a broken
    generation of known size."""

    def __init__(self, fn, out: str, factor: float = 1.0, shift: float = 0.0):
        self.fn, self.out, self.factor, self.shift, self.spec = fn, out, factor, shift, fn.spec

    def __call__(self, n, args):
        res = dict(self.fn(n, args))
        res[self.out] = np.asarray(res[self.out]) * self.factor + self.shift
        return res


def _plant(monkeypatch, robot, quantity: str, out: str, **fault) -> None:
    """The exact (CasADi) copy of ``quantity`` broken; validate builds its exact robot from
    ``library.functions``, so the fault reaches every exact path."""
    fns = dict(robot.library.functions)
    fns[quantity] = _Planted(fns[quantity], out, **fault)
    monkeypatch.setattr(robot.library, "functions", fns)


def _scaled_method(monkeypatch, robot, name: str, factor: float) -> None:
    """A method (a fast loop, an instance attribute) whose result is scaled by ``factor``."""
    real = getattr(robot, name)
    monkeypatch.setattr(robot, name, lambda *a: np.asarray(real(*a)) * factor, raising=False)


# -- the error measure and the row rule --------------------------------------------------------

def test_row_passes_at_its_tolerance_and_fails_one_ulp_above():
    r = rows.row("(x) check", 1e-7, 1e-7, "where")
    assert r == rows.Row("(x) check", 1e-7, 1e-7, "pass", "where")
    assert rows.row("x", np.nextafter(1e-7, 1.0), 1e-7).status == "FAIL"
    assert rows.row("x", 0.0, 0.0).status == "pass"
    for bad in (math.inf, -math.inf, math.nan):  # not finite: never a pass, whatever tol
        assert rows.row("x", bad, math.inf).status == "FAIL"
    assert rows.row("x", 1.0, 0.5).detail == ""


def test_rel_err_per_sample_and_against_the_peak():
    a = np.array([[1.0, 2.0], [3.0, 4.0]])
    b = np.array([[1.0, 1.0], [2.0, 4.0]])
    # per sample: |a0 - b0| = 1 over ||b0|| = 1, |a1 - b1| = 1 over ||b1|| = 4
    assert rows.rel_err(a, b) == 1.0
    assert rows.rel_err(a, b, peak=True) == 0.25  # both over the largest ||b_k|| = 4
    # (N, n, n) samples are flattened per sample: the worst entry over the largest entry
    a3 = np.array([[[1.0, 0.0], [0.0, 5.0]], [[2.0, 0.0], [0.0, 2.0]]])
    b3 = np.array([[[1.0, 0.0], [0.0, 4.0]], [[2.0, 0.0], [0.5, 2.0]]])
    assert rows.rel_err(a3, b3) == 0.25
    # (N,) samples: one value each
    assert rows.rel_err([1.0, 3.0], [2.0, 4.0]) == 0.5
    # a sign flip is an error of 2, not 0
    assert rows.rel_err([[-1.0]], [[1.0]]) == 2.0
    # each sample over its own size (0.5 / 1), not over the largest (0.5 / 10)
    assert rows.rel_err([[1.5, 0.0], [0.0, 10.5]], [[1.0, 0.0], [0.0, 10.0]]) == 0.5
    # small references keep their own size: no scale unless one is given
    assert rows.rel_err([[2e-3]], [[1e-3]]) == 1.0


def test_rel_err_of_a_zero_reference_is_absolute_or_over_the_scale():
    zero = np.zeros((2, 2))
    a = np.array([[3e-3, 0.0], [0.0, -5e-3]])
    assert rows.rel_err(a, zero) == 5e-3  # no size, no scale: absolute
    assert rows.rel_err(a, zero, scale=0.5) == 1e-2  # over the physical scale
    assert rows.rel_err(a, zero, peak=True) == 5e-3
    # a scale above the reference's own size is the floor of every denominator
    b = np.array([[0.1, 0.0], [0.0, 0.2]])
    assert rows.rel_err(b + 1e-3, b, scale=0.5) == pytest.approx(2e-3, rel=1e-12)
    assert rows.rel_err(b + 1e-3, b, scale=0.0) == pytest.approx(1e-2, rel=1e-12)
    # a scale below it changes nothing
    assert rows.rel_err(b + 1e-3, b, scale=0.01) == pytest.approx(1e-2, rel=1e-12)


def test_rel_err_floor_of_a_zero_sample():
    # a sample whose reference is exactly 0 is measured against 1e-12 of the largest one
    a = np.array([[1e-13], [1.0]])
    b = np.array([[0.0], [1.0]])
    assert rows.rel_err(a, b) == pytest.approx(0.1, rel=1e-12)
    # against the peak, 1e-13 over 1
    assert rows.rel_err(a, b, peak=True) == pytest.approx(1e-13, rel=1e-12)


def test_worst_key_counts_nan_as_the_worst():
    assert rows.worst_key({"a": 1.0, "b": 3.0, "c": 2.0}) == "b"
    assert rows.worst_key({"a": 1.0, "b": math.nan, "c": math.inf}) in ("b", "c")
    assert rows.worst_key({"a": 1.0, "b": math.nan, "c": 2.0}) == "b"
    assert rows.worst_key({"a": math.inf, "b": 1.0}) == "a"


def test_random_states_are_the_documented_draws(robots):
    robot = robots["serial_3dof"]
    q, qd, qdd, tau = rows.random_states(robot, 7, 5)
    rng = np.random.default_rng(5)  # drawn in this order: q, qd, qdd, tau
    assert np.array_equal(q, rng.uniform(-np.pi, np.pi, (7, 3)))
    for got in (qd, qdd, tau):
        assert np.array_equal(got, rng.uniform(-3, 3, (7, 3)))


def test_random_states_keep_coulomb_joints_away_from_rest(robots):
    """The geared arm's joint 1 has Coulomb friction (v_s = 0.01 rad/s): its rates are moved out
    by 20 v_s = 0.2 rad/s, keeping their sign; joint 2 (no Coulomb term) keeps the raw draw."""
    robot = robots["geared"]
    away = 20 * robot.drive_train.smoothing[0]
    assert away == pytest.approx(0.2, rel=1e-15)
    rng = np.random.default_rng(3)
    rng.uniform(-np.pi, np.pi, (400, 2))  # q first, then the raw qd
    raw = rng.uniform(-3, 3, (400, 2))
    _, qd, _, _ = rows.random_states(robot, 400, 3)
    assert np.array_equal(qd[:, 1], raw[:, 1])
    near = np.abs(raw[:, 0]) < away
    assert near.sum() >= 5  # 400 draws: about 27 land within 0.2 of rest
    assert np.array_equal(qd[~near, 0], raw[~near, 0])
    assert np.allclose(qd[near, 0], raw[near, 0] + np.sign(raw[near, 0]) * away, rtol=0,
                       atol=1e-15)
    assert np.min(np.abs(qd[:, 0])) >= away


# -- (b) Lagrange from the energy ----------------------------------------------------------------

def test_mass_from_energy_is_the_compiled_mass_matrix(robots):
    robot = robots["serial_3dof"]
    q, _, _, _ = rows.random_states(robot, 6, 0)
    M = validate.mass_from_energy(robot, q)
    assert M.shape == (6, 3, 3)
    assert rows.rel_err(M, robot.mass_matrix(q)) < 1e-13
    assert np.array_equal(M, M.transpose(0, 2, 1))


def test_lagrange_of_the_pendulum_by_hand(robots):
    robot = robots["pendulum"]
    q = np.array([[0.3], [-1.2], [2.5]])
    qd = np.array([[1.0], [-2.0], [0.5]])
    qdd = np.array([[0.7], [2.0], [-1.5]])
    ref = validate.lagrange_from_energy(robot, q, qd, qdd)
    g = M_P * G * L_P * np.cos(q)  # V = m g l sin q
    assert np.allclose(ref["M"][:, 0, 0], I_P, rtol=1e-13, atol=0)
    assert rows.rel_err(ref["g"], g) < 1e-10
    assert rows.rel_err(ref["h"], g) < 1e-10  # 1 DOF: no velocity term
    assert rows.rel_err(ref["tau"], I_P * qdd + g) < 1e-10


def test_lagrange_with_friction_is_the_compiled_dynamics(robots):
    robot = robots["geared"]
    q, qd, qdd, _ = rows.random_states(robot, 5, 4)
    ref = validate.lagrange_from_energy(robot, q, qd, qdd)
    assert rows.rel_err(ref["M"], robot.mass_matrix(q)) < 1e-13
    assert rows.rel_err(ref["g"], robot.gravity(q)) < 1e-9
    assert rows.rel_err(ref["h"], robot.bias(q, qd)) < 1e-9
    assert rows.rel_err(ref["tau"], robot.tree_inverse_dynamics(q, qd, qdd)) < 1e-9


def test_compiled_paths(robots):
    robot = robots["serial_2dof"].with_parameters(m_motor2=0.5)  # not the manifest's values
    assert not robot.exact
    (l0, exact), (l1, fast) = validate.compiled_paths(robot)
    assert (l0, l1) == ("", "fast ") and fast is robot
    assert exact.exact and exact.library is robot.library and np.array_equal(exact.p, robot.p)
    assert exact.parameters["m_motor2"] == 0.5
    assert validate.compiled_paths(exact) == [("", exact)]


def test_energy_route_reports_a_scaled_mass_matrix(robots, monkeypatch):
    robot = robots["serial_2dof"]
    _plant(monkeypatch, robot, "mass_matrix", "M", factor=1 + 1e-5)
    r = validate.check_energy_route(robot, samples=5)
    # polarisation gives M to rounding: the relative error is the factor's 1e-5
    assert r.worst == pytest.approx(1e-5, rel=1e-6)
    assert r.status == "FAIL" and r.tolerance == 1e-7
    assert r.check == "(b) Lagrange from the energy (finite differences), 5 states"
    assert r.detail == ("worst: mass_matrix.M; vs compiled M, g, h, tau, forward dynamics")


@pytest.mark.parametrize("e, status", [(0.9e-7, "pass"), (1.1e-7, "FAIL")])
def test_energy_route_threshold(robots, monkeypatch, e, status):
    robot = robots["serial_2dof"]
    _plant(monkeypatch, robot, "mass_matrix", "M", factor=1 + e)
    r = validate.check_energy_route(robot, samples=5)
    assert r.worst == pytest.approx(e, rel=1e-3) and r.status == status


@pytest.mark.parametrize("name, out", [("bias", "h"), ("gravity", "g"),
                                       ("tree_inverse_dynamics", "tau")])
def test_energy_route_sees_each_fast_loop(robots, monkeypatch, name, out):
    robot = robots["serial_2dof"]
    _scaled_method(monkeypatch, robot, name, 1 + 1e-4)
    r = validate.check_energy_route(robot, samples=5)
    quantity = {"tree_inverse_dynamics": "inverse_dynamics",
                "tree_forward_dynamics": "forward_dynamics"}.get(name, name)
    assert r.detail.startswith(f"worst: fast {quantity}.{out};"), r
    assert r.worst == pytest.approx(1e-4, rel=1e-4) and r.status == "FAIL"


def test_energy_route_sees_the_fast_forward_dynamics_as_torques(robots, monkeypatch):
    """The fast forward dynamics shifted by d (1e-4 rad/s^2 at each joint; a shift leaves
    the differences its Jacobian is checked with unchanged) is reported as the torque it
    implies: max_k ||M_k d||_inf / ||tau_k||_inf, M and tau of exactly the states drawn."""
    robot = robots["serial_2dof"]
    real = robot.tree_forward_dynamics
    monkeypatch.setattr(robot, "tree_forward_dynamics", lambda *a: np.asarray(real(*a)) + 1e-4,
                        raising=False)
    r = validate.check_energy_route(robot, samples=5)
    assert r.detail.startswith("worst: fast forward_dynamics.qdd;"), r
    q, qd, qdd, _ = rows.random_states(robot, 5, 2)
    m_d = robot.mass_matrix(q) @ np.full(2, 1e-4)
    tau = robot.tree_inverse_dynamics(q, qd, qdd)
    expected = np.max(np.max(np.abs(m_d), 1) / np.max(np.abs(tau), 1))
    assert r.worst == pytest.approx(expected, rel=1e-6) and r.status == "FAIL"


def test_energy_route_default_states(robots, monkeypatch):
    """20 states drawn with seed 2: an additive shift d of the pendulum's dqdd/dqd (zero at
    every state) is reported as d over max|qdd| / max|qd| of exactly those states."""
    robot = robots["pendulum"]
    _plant(monkeypatch, robot, "forward_dynamics_jacobian", "dqdd_dqd", shift=1e-4)
    r = validate.check_energy_route(robot)
    _, qd, qdd, _ = rows.random_states(robot, 20, 2)
    assert r.check.endswith(", 20 states")
    assert r.worst == pytest.approx(1e-4 * np.max(np.abs(qd)) / np.max(np.abs(qdd)), rel=1e-9)
    assert "forward_dynamics_jacobian.dqdd_dqd" in r.detail


def test_energy_route_scale_of_the_position_jacobian(robots, monkeypatch):
    """dqdd/dq of the pendulum is m g l sin q / I (qdd = (tau - m g l cos q) / I); shifted by d,
    each state's error is d over the larger of that and max|qdd| / pi (rad)."""
    robot = robots["pendulum"]
    d = 1e-3
    _plant(monkeypatch, robot, "forward_dynamics_jacobian", "dqdd_dq", shift=d)
    r = validate.check_energy_route(robot, samples=20, seed=7)
    q, _, qdd, _ = rows.random_states(robot, 20, 7)
    exact = np.abs(M_P * G * L_P * np.sin(q[:, 0]) / I_P)
    scale = np.max(np.abs(qdd)) / np.pi
    assert np.min(exact) < scale < np.max(exact)  # both branches of the denominator occur
    assert r.worst == pytest.approx(np.max(d / np.maximum(exact, scale)), rel=1e-6)
    assert "forward_dynamics_jacobian.dqdd_dq;" in r.detail


def test_energy_route_of_a_closed_chain(robots, monkeypatch):
    robot = robots["five_bar"]
    _plant(monkeypatch, robot, "constrained_terms", "h", factor=1 + 1e-5)
    r = validate.check_energy_route(robot, samples=4)
    assert r.worst == pytest.approx(1e-5, rel=1e-3) and r.status == "FAIL"
    assert r.detail == "worst: constrained_terms.h; vs compiled M, g, h, tau"
    monkeypatch.undo()
    _plant(monkeypatch, robot, "constrained_terms", "M", factor=1 + 1e-5)
    r = validate.check_energy_route(robot, samples=4)
    assert r.worst == pytest.approx(1e-5, rel=1e-6)
    assert r.detail.startswith("worst: constrained_terms.M;")


# -- (d) power, (b) null space, (e) constraints along the smooth motion --------------------------

def test_motion_is_the_documented_sine(robots):
    robot = robots["serial_3dof"]
    traj = validate.motion(robot, 5, 0.3)
    assert sorted(traj) == [-2, -1, 0, 1, 2]
    t0 = np.linspace(0.0, 1.0, 5)
    for k, j in traj.items():
        t = t0 + k * 1e-3  # the difference step, s
        arg = 2 * np.pi * t[:, None] + np.array([0.0, np.pi / 3, 2 * np.pi / 3])
        assert np.allclose(j.t_s, t, rtol=0, atol=1e-15)
        assert np.allclose(j.q, robot.q_drawn + 0.3 * np.sin(arg), rtol=0, atol=1e-15)
        assert np.allclose(j.qd, 2 * np.pi * 0.3 * np.cos(arg), rtol=0, atol=1e-14)
        assert np.allclose(j.qdd, -(2 * np.pi) ** 2 * 0.3 * np.sin(arg), rtol=0, atol=1e-13)


def test_motion_of_a_closed_chain_moves_the_actuated_joints(robots):
    robot = robots["five_bar"]
    traj = validate.motion(robot, 9, 0.05)
    act = list(robot.actuated)
    arg = 2 * np.pi * np.linspace(0.0, 1.0, 9)[:, None] + np.array([0.0, np.pi / 2])
    j = traj[0]
    assert np.allclose(j.q[:, act], robot.q_drawn[act] + 0.05 * np.sin(arg), atol=1e-15)
    assert np.max(np.abs(robot.constraint(j.q))) < 1e-12  # the passive joints are solved
    assert np.allclose(traj[2].t_s - traj[-1].t_s, 3e-3, rtol=0, atol=1e-15)


def test_power_balance_reports_scaled_torques(robots, monkeypatch):
    robot = robots["serial_2dof"]
    traj = validate.motion(robot, 41, 0.3)
    power = np.sum(robot.tree_inverse_dynamics(traj[0].q, traj[0].qd, traj[0].qdd)
                   * traj[0].qd, axis=1)
    _scaled_method(monkeypatch, robot, "tree_inverse_dynamics", 1 + 1e-4)
    r = validate.check_power(robot, traj)
    # dE/dt equals the true power to ~1e-10 of the peak: the error is 1e-4 of the peak
    assert r.worst == pytest.approx(1e-4, rel=1e-5)
    assert r.status == "FAIL" and r.tolerance == 1e-6
    assert r.check == "(d) power balance sum tau qd = dE/dt, 41 samples"
    assert r.detail == f"relative to peak power {np.max(np.abs(power)):.3g} W"


@pytest.mark.parametrize("e, status", [(0.9e-6, "pass"), (1.1e-6, "FAIL")])
def test_power_balance_threshold(robots, monkeypatch, e, status):
    robot = robots["serial_2dof"]
    traj = validate.motion(robot, 41, 0.3)
    _scaled_method(monkeypatch, robot, "tree_inverse_dynamics", 1 + e)
    r = validate.check_power(robot, traj)
    assert r.worst == pytest.approx(e, rel=1e-3) and r.status == status


def test_power_balance_labels(robots):
    r = validate.check_power(robots["geared"], validate.motion(robots["geared"], 21, 0.3))
    assert r.check == "(d) power balance sum tau qd = dE/dt + friction, 21 samples"
    assert r.status == "pass" and "passive" not in r.detail
    r = validate.check_power(robots["cart_pole"], validate.motion(robots["cart_pole"], 21, 0.3))
    assert r.detail.endswith("; tree torques at every joint, passive ones included")
    assert r.status == "pass"


def test_power_balance_of_a_closed_chain(robots, monkeypatch):
    robot = robots["five_bar"]
    traj = validate.motion(robot, 21, 0.05)
    assert validate.check_power(robot, traj).worst < 1e-8
    real = robot.closed_chain_inverse_dynamics
    monkeypatch.setattr(robot, "closed_chain_inverse_dynamics",
                        lambda *a: (real(*a)[0] * (1 + 1e-4), real(*a)[1]), raising=False)
    assert validate.check_power(robot, traj).worst == pytest.approx(1e-4, rel=1e-3)


def test_null_space_reports_scaled_torques(robots, monkeypatch):
    robot = robots["five_bar"]
    traj = {0: validate.motion(robot, 21, 0.05)[0]}  # the motion's own samples (k = 0) only
    r = validate.check_null_space(robot, traj)
    assert r.status == "pass" and r.worst < 1e-9
    assert r.detail == "M qdd + h from the energy route, along the motion of (d)"
    real = robot.closed_chain_inverse_dynamics
    for e, status in ((1e-4, "FAIL"), (0.9e-7, "pass"), (1.1e-7, "FAIL")):
        monkeypatch.setattr(robot, "closed_chain_inverse_dynamics",
                            lambda *a, e=e: (real(*a)[0] * (1 + e), real(*a)[1]), raising=False)
        r = validate.check_null_space(robot, traj)
        assert r.worst == pytest.approx(e, rel=1e-3) and r.status == status
    assert r.check == "(b) closed chain: multipliers vs null space G^T (M qdd + h)"
    assert r.tolerance == 1e-7
    # a torque offset of 1e-4 of the peak torque: 1e-4 against the peak, not against the
    # smallest sample (where the torques pass near zero)
    j = traj[0]
    peak = np.max(np.abs(real(j.q, j.qd, j.qdd)[0]))
    monkeypatch.setattr(robot, "closed_chain_inverse_dynamics",
                        lambda *a: (real(*a)[0] + 1e-4 * peak, real(*a)[1]), raising=False)
    assert validate.check_null_space(robot, traj).worst == pytest.approx(1e-4, rel=1e-6)


def test_constraint_rows_report_planted_errors(robots, monkeypatch):
    robot = robots["five_bar"]
    traj = validate.motion(robot, 21, 0.05)
    phi, rates = validate.check_constraints(robot, traj)
    assert (phi.status, rates.status) == ("pass", "pass")
    assert phi.tolerance == 1e-9 and rates.tolerance == 1e-6
    assert phi.check == "(e) loop residual max |Phi| (m)"
    assert phi.detail == "worst along the motion of (d)"
    # the free motion's drift counts when larger
    phi, _ = validate.check_constraints(robot, traj, SimpleNamespace(constraint_drift_m=1e-9))
    assert (phi.worst, phi.status, phi.detail) == (1e-9, "pass", "worst in the free motion of (c)")
    phi, _ = validate.check_constraints(robot, traj, SimpleNamespace(
        constraint_drift_m=np.nextafter(1e-9, 1.0)))
    assert phi.status == "FAIL"
    phi, _ = validate.check_constraints(robot, traj, SimpleNamespace(constraint_drift_m=0.0))
    assert phi.detail == "worst along the motion of (d)" and phi.worst < 1e-12
    along = float(np.max(np.abs(robot.constraint(traj[0].q))))
    assert along > 0.0  # rounding: the drift equal to it does not replace it
    phi, _ = validate.check_constraints(robot, traj, SimpleNamespace(constraint_drift_m=along))
    assert (phi.worst, phi.detail) == (along, "worst along the motion of (d)")
    assert rates.check == "(e) passive qd, qdd vs differences of q(t)"
    assert rates.detail == "checks Phi_q and gamma against the Newton-solved positions"
    # passive rates off by 1e-5 of the peak rate
    j = traj[0]
    peak_qd, peak_qdd = np.max(np.abs(j.qd)), np.max(np.abs(j.qdd))
    pas = robot.passive[0]
    bumped = dict(traj)
    qd = j.qd.copy()
    qd[:, pas] += 1e-5 * peak_qd
    bumped[0] = dataclasses.replace(j, qd=qd)
    _, rates = validate.check_constraints(robot, bumped)
    assert rates.worst == pytest.approx(1e-5, rel=1e-3) and rates.status == "FAIL"
    qdd = j.qdd.copy()
    qdd[:, pas] += 1e-5 * peak_qdd
    bumped[0] = dataclasses.replace(j, qdd=qdd)
    _, rates = validate.check_constraints(robot, bumped)
    assert rates.worst == pytest.approx(1e-5, rel=1e-3)
    # a loop residual of 1e-6 m planted in the constraint function
    real = robot.constraint
    monkeypatch.setattr(robot, "constraint", lambda q: real(q) - 1e-6, raising=False)
    phi, _ = validate.check_constraints(robot, traj)
    assert phi.worst == pytest.approx(1e-6, rel=1e-9) and phi.status == "FAIL"


# -- (c) free motion ------------------------------------------------------------------------------

def test_free_motion_falls_from_rest_or_is_pushed(robots):
    sim = validate.free_motion(robots["serial_2dof"], 0.1)
    assert np.array_equal(sim.t_s, np.linspace(0.0, 0.1, 201))
    assert np.array_equal(sim.qd[0], [0.0, 0.0]) and sim.kinetic_j[-1] > 1e-3
    # no gravity: the drawn pose does not move by itself; the actuated joints start at 1 rad/s
    sim = validate.free_motion(robots["horizontal"])  # 1 s by default
    assert np.array_equal(sim.t_s, np.linspace(0.0, 1.0, 201))
    assert np.array_equal(sim.qd[0], [1.0, 1.0])
    assert sim.energy_drift < 1e-8


def test_free_motion_with_friction_integrates_its_work(robots):
    sim = validate.free_motion(robots["geared"], 0.2)
    assert len(sim.t_s) == 201 and sim.t_s[-1] == 0.2
    assert sim.friction_j is not None and sim.friction_j[-1] > 0
    assert sim.balance_residual < 1e-9
    # the tolerances the balance is held to (TOL_ENERGY 1e-8 assumes rtol 1e-11)
    assert (sim.rtol, sim.atol) == (1e-11, 1e-12)
    # without gravity the geared arm rests at its drawn pose: pushed at 1 rad/s, and friction
    # takes energy from that start
    sim = validate.free_motion(robots["geared"].with_parameters(g=0.0), 0.2)
    assert np.array_equal(sim.qd[0], [1.0, 1.0])
    assert sim.friction_j[-1] > 0 and sim.balance_residual < 1e-9


def test_free_motion_push_rule(robots, monkeypatch):
    """Pushed when the run from rest has a kinetic energy of at most 1e-12 of the largest
    |E| (or none at all where E is 0): a fake simulate returns the energies."""
    from planar_sym.dynamics import forward

    calls = []

    def fake(kinetic, energy):
        def simulate(robot, q0, qd0, t_span, t_eval=None, **kw):
            calls.append(np.zeros(robot.n) if qd0 is None else np.asarray(qd0))  # None: at rest
            return SimpleNamespace(kinetic_j=np.array([0.0, kinetic]),
                                   energy_j=np.array([energy, energy]))
        return simulate

    robot = robots["serial_2dof"]
    for kinetic, energy, pushed in ((0.5e-12, 0.5, True),  # exactly 1e-12 of |E|
                                    (np.nextafter(0.5e-12, 1.0), 0.5, False),
                                    (1e-13, 1e-3, False),  # 1e-10 of a small |E|: it moves
                                    (0.0, 0.0, True)):  # nothing at all
        calls.clear()
        monkeypatch.setattr(forward, "simulate", fake(kinetic, energy))
        validate.free_motion(robot, 0.1)
        assert np.array_equal(calls[0], [0.0, 0.0])
        assert len(calls) == (2 if pushed else 1), (kinetic, energy)
        if pushed:
            assert np.array_equal(calls[1], [1.0, 1.0])


def test_energy_row_labels():
    sim = SimpleNamespace(t_s=np.array([0.0, 0.2, 0.5]), kinetic_j=np.array([0.0, 2.5, 1.0]),
                          energy_j=np.full(3, 3.0), energy_drift=1e-8, friction_j=None,
                          balance_residual=None)
    assert validate.check_energy(sim) == rows.Row(
        "(c) energy drift, free motion 0.5 s", 1e-8, 1e-8, "pass",
        "relative; peak kinetic energy 2.5 J")
    sim.energy_drift = np.nextafter(1e-8, 1.0)
    assert validate.check_energy(sim).status == "FAIL"
    sim = SimpleNamespace(t_s=np.array([0.0, 1.0, 2.0]), kinetic_j=np.array([0.0, 2.5, 1.0]),
                          energy_j=np.array([3.0, 2.9, 2.8]), energy_drift=1.0,
                          friction_j=np.array([0.0, 0.0625, 0.125]), balance_residual=2e-8)
    assert validate.check_energy(sim) == rows.Row(
        "(c) energy balance with friction, free motion 2 s", 2e-8, 1e-8, "FAIL",
        "relative; peak kinetic energy 2.5 J, friction work 0.125 J")


# -- (a) against SymPy ------------------------------------------------------------------------------

def test_symbolic_row_reports_a_scaled_output(robots, monkeypatch):
    robot = robots["serial_2dof"]
    _plant(monkeypatch, robot, "mass_matrix", "M", factor=1 + 1e-9)
    r = symbolic.check_symbolic(robot, samples=3)
    # the SymPy model is exact: the error is the factor's, to rounding
    assert r.worst == pytest.approx(1e-9, rel=1e-5)
    assert r.status == "FAIL" and r.tolerance == 1e-11
    assert r.check == "(a) compiled vs SymPy, 3 random states"
    assert r.detail == f"worst: mass_matrix.M; from {robot.description_file}"


@pytest.mark.parametrize("fn, out", [("tracking_pd", "qdd"), ("tracking_pd", "tau_cmd"),
                                     ("tracking_ct", "tau_app")])
def test_symbolic_row_sees_the_fused_tracking_functions(robots, monkeypatch, fn, out):
    """The fused controller and plant of a tree (derive/tracking.py) are rows of (a) too: a
    fresh clone's `planar-sym validate` raised KeyError 'q_ref' on every tree once they were
    generated, its inputs unknown to the row. Each output, scaled by 1 + 1e-9, is named."""
    robot = robots["serial_2dof"]
    assert symbolic.check_symbolic(robot, samples=3).status == "pass"
    _plant(monkeypatch, robot, fn, out, factor=1 + 1e-9)
    r = symbolic.check_symbolic(robot, samples=3)
    assert r.status == "FAIL" and r.detail.startswith(f"worst: {fn}.{out};"), r
    assert r.worst == pytest.approx(1e-9, rel=1e-3)


@pytest.mark.parametrize("e, status", [(0.8e-11, "pass"), (1.2e-11, "FAIL")])
def test_symbolic_threshold(robots, monkeypatch, e, status):
    robot = robots["serial_2dof"]
    _plant(monkeypatch, robot, "inverse_dynamics", "tau", factor=1 + e)
    r = symbolic.check_symbolic(robot, samples=3)
    assert r.worst == pytest.approx(e, rel=1e-3) and r.status == status
    assert "inverse_dynamics.tau" in r.detail


@pytest.mark.parametrize("name, label", [("mass_matrix", "mass_matrix.M"), ("gravity", "gravity.g"),
                                         ("bias", "bias.h"),
                                         ("tree_inverse_dynamics", "inverse_dynamics.tau"),
                                         ("tree_forward_dynamics", "forward_dynamics.qdd")])
def test_symbolic_row_sees_each_fast_loop(robots, monkeypatch, name, label):
    robot = robots["serial_2dof"]
    _scaled_method(monkeypatch, robot, name, 1 + 1e-8)
    r = symbolic.check_symbolic(robot, samples=3)
    assert r.detail.startswith(f"worst: fast {label};")
    assert r.worst == pytest.approx(1e-8, rel=1e-4)


def test_symbolic_row_sees_the_fast_kinetic_energy(robots, monkeypatch):
    robot = robots["serial_2dof"]
    real = robot.energy
    monkeypatch.setattr(robot, "energy", lambda q, qd: (real(q, qd)[0] * (1 + 1e-8),
                                                        real(q, qd)[1]), raising=False)
    r = symbolic.check_symbolic(robot, samples=3)
    assert r.detail.startswith("worst: fast energy.kinetic;")
    assert r.worst == pytest.approx(1e-8, rel=1e-4)


def test_symbolic_default_states(robots, monkeypatch):
    """20 states drawn with seed 1: a shift d of M is reported as d / min_k ||M_k||."""
    robot = robots["serial_2dof"]
    _plant(monkeypatch, robot, "mass_matrix", "M", shift=1e-8)
    r = symbolic.check_symbolic(robot)
    q, _, _, _ = rows.random_states(robot, 20, 1)
    size = np.max(np.abs(robot.mass_matrix(q)).reshape(20, -1), axis=1)
    assert r.check == "(a) compiled vs SymPy, 20 random states"
    assert r.worst == pytest.approx(1e-8 / np.min(size), rel=1e-6)


def test_symbolic_row_skips_and_refusals(robots, monkeypatch):
    robot = robots["serial_2dof"]
    with pytest.raises(InputError, match=r"^--description no_such\.toml: no such file$"):
        symbolic.check_symbolic(robot, "no_such.toml", samples=2)
    other = symbolic.check_symbolic(robot, TEST_ROBOTS / "pendulum.toml", samples=2)
    assert other == rows.Row("(a) compiled vs SymPy, 2 random states", math.inf, 1e-11, "FAIL",
                             f"{TEST_ROBOTS / 'pendulum.toml'}: parameter vector differs")
    monkeypatch.setitem(robot.library.manifest, "equations", "structure")
    assert symbolic.check_symbolic(robot, samples=2) == rows.Row(
        "(a) compiled vs SymPy, 2 random states", None, 1e-11, "skipped",
        "skipped: past the closed-form size (the report shows why); the expanded forms would "
        "take minutes, the other rows still check the compiled code")
    monkeypatch.undo()
    monkeypatch.setattr(type(robot), "description_file", property(lambda self: None))
    monkeypatch.setitem(robot.library.manifest, "input", "serial_2dof.toml")
    assert symbolic.check_symbolic(robot, samples=2) == rows.Row(
        "(a) compiled vs SymPy, 2 random states", None, 1e-11, "skipped",
        "skipped: no description file found (pass --description)")


def test_symbolic_row_without_sympy(robots, monkeypatch):
    monkeypatch.setitem(sys.modules, "sympy", None)  # import sympy now raises ImportError
    assert symbolic.check_symbolic(robots["serial_2dof"], samples=4) == rows.Row(
        "(a) compiled vs SymPy, 4 random states", None, 1e-11, "skipped",
        "skipped: needs SymPy")


def test_find_description(robots, monkeypatch, tmp_path):
    robot = robots["serial_2dof"]
    own = ROOT / "planar_sym" / "robots" / "serial_2dof.toml"
    assert symbolic.find_description(robot) == own
    given = tmp_path / "d.toml"
    given.write_text("")
    assert symbolic.find_description(robot, str(given)) == given
    with pytest.raises(InputError, match=r"^--description .*nothing\.toml: no such file$"):
        symbolic.find_description(robot, tmp_path / "nothing.toml")
    with pytest.raises(InputError):
        symbolic.find_description(robot, tmp_path)  # a folder is not a file
    # a copied folder without its description: the manifest's repo-relative input
    monkeypatch.setattr(type(robot), "description_file", property(lambda self: None))
    assert symbolic.find_description(robot) == own
    monkeypatch.setitem(robot.library.manifest, "input", "serial_2dof.toml")  # outside the repo
    assert symbolic.find_description(robot) is None
    monkeypatch.setitem(robot.library.manifest, "input", "planar_sym/robots/none.toml")
    assert symbolic.find_description(robot) is None
    monkeypatch.delitem(robot.library.manifest, "input")
    assert symbolic.find_description(robot) is None


# -- the table ------------------------------------------------------------------------------------

class _Progress:
    def __init__(self):
        self.total, self.steps = None, []

    def step(self, label):
        self.steps.append(label)


def _light(monkeypatch, calls):
    """run_all with the SymPy row and the free motion recorded instead of run (the slow parts)."""
    def sym(robot, description, samples):
        calls.append(("a", description, samples))
        return rows.Row("(a) stub", 0.0, 1e-11, "pass")

    sim = SimpleNamespace(t_s=np.array([0.0, 1.0]), kinetic_j=np.array([0.0, 1.0]),
                          energy_j=np.ones(2), energy_drift=0.0, friction_j=None,
                          constraint_drift_m=0.0)

    def free(robot, seconds):
        calls.append(("c", seconds))
        return sim

    real_motion = validate.motion

    def motion(robot, samples, amplitude):
        calls.append(("motion", samples, amplitude))
        return real_motion(robot, samples, amplitude)

    monkeypatch.setattr(validate, "check_symbolic", sym)
    monkeypatch.setattr(validate, "free_motion", free)
    monkeypatch.setattr(validate, "motion", motion)
    return sim


def test_run_all_of_a_tree(robots, monkeypatch):
    calls = []
    _light(monkeypatch, calls)
    progress = _Progress()
    table = validate.run_all(robots["serial_2dof"], progress=progress)
    assert [r.check[:3] for r in table] == ["(a)", "(b)", "(c)", "(d)"]
    assert all(r.status == "pass" for r in table)
    # README: (b) 1e-7, (c) 1e-8, (d) 1e-6
    assert [r.tolerance for r in table[1:]] == [1e-7, 1e-8, 1e-6]
    assert table[1].check.endswith(", 20 states")
    assert calls == [("a", None, 20), ("c", 1.0), ("motion", 41, 0.3)]
    assert progress.total == 4
    assert progress.steps == ["serial_2dof: (a) compiled vs SymPy",
                              "serial_2dof: (b) Lagrange from the energy",
                              "serial_2dof: (c) free motion", "serial_2dof: (d) power balance"]


def test_run_all_of_a_closed_chain_shares_the_motion_and_the_free_run(robots, monkeypatch):
    calls, got = [], {}
    sim = _light(monkeypatch, calls)
    real = validate.check_constraints

    def constraints(robot, traj, s=None):
        got["sim"] = s
        return real(robot, traj, s)

    monkeypatch.setattr(validate, "check_constraints", constraints)
    progress = _Progress()
    table = validate.run_all(robots["five_bar"], "d.toml", samples=3, seconds=0.5,
                             progress=progress)
    assert progress.total == 6
    assert progress.steps == [f"five_bar_type1: {label}" for label in (
        "(a) compiled vs SymPy", "(b) Lagrange from the energy", "(b) null-space torques",
        "(c) free motion", "(d) power balance", "(e) constraints")]
    assert [r.check[:3] for r in table] == ["(a)", "(b)", "(b)", "(c)", "(d)", "(e)", "(e)"]
    assert table[2].check.startswith("(b) closed chain")
    assert all(r.status == "pass" for r in table), table
    # README: (e) 1e-9 m and 1e-6
    assert [r.tolerance for r in table[5:]] == [1e-9, 1e-6]
    assert table[1].check.endswith(", 3 states")
    # one motion (0.05 rad: inside the workspace) for (b), (d), (e); one free run for (c), (e)
    assert calls == [("a", "d.toml", 3), ("motion", 41, 0.05), ("c", 0.5)]
    assert got["sim"] is sim


def test_run_all_turns_a_raising_check_into_a_fail_row(robots, monkeypatch):
    calls = []
    _light(monkeypatch, calls)

    def broken(robot, seconds):
        raise PlanarSymError("no free motion")

    monkeypatch.setattr(validate, "free_motion", broken)
    got = {}
    real = validate.check_constraints

    def constraints(robot, traj, s=None):
        got["sim"] = s
        return real(robot, traj, s)

    monkeypatch.setattr(validate, "check_constraints", constraints)
    table = validate.run_all(robots["five_bar"], samples=3)
    assert table[3] == rows.Row("(c) free motion", math.inf, None, "FAIL",
                                "raised PlanarSymError: no free motion")
    assert got == {"sim": None}  # (e) does not run the failed free motion again
    assert len(table) == 7 and table[5].status == "pass"

    def singular(robot, traj):
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setattr(validate, "check_power", singular)
    table = validate.run_all(robots["serial_2dof"], samples=3)
    assert table[-1] == rows.Row("(d) power balance", math.inf, None, "FAIL",
                                 "raised LinAlgError: Singular matrix")


def test_run_all_refuses_what_is_not_a_robot():
    with pytest.raises(PlanarSymError, match=r"^validate needs a Robot \(planar_sym\.load\), "
                                             r"got str$"):
        validate.run_all("serial_2dof")


HANGING = """# A free 10 m pendulum drawn hanging at rest, no motor (a user trial's robot): its free
# motion from the drawn pose does not move unless pushed.
name = "hanging_pendulum"
title = "10 m pendulum, 5 kg bob on a 1 kg rod, no motor"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "deg"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "rod"
mass = 1.0
izz = "1.0*10^2/12"
cg = [0.0, -5.0]
cg_from = "O"
points = { O = [0.0, 0.0], tip = [0.0, -10.0] }
frame = ["O", "tip"]
[[bodies]]
name = "bob"
mass = 5.0
mass_at = "c"
points = { c = [0.0, -10.0] }
[[joints]]
name = "pivot"
type = "revolute"
parent = "ground.O"
child = "rod.O"
actuated = false
[[joints]]
name = "bob_weld"
type = "weld"
parent = "rod.tip"
child = "bob.c"
"""


def test_a_free_motion_that_does_not_move_is_pushed_or_skipped(tmp_path):
    """(c) on a motorless pendulum drawn hanging at rest passed with a drift of 0 and a peak
    kinetic energy of 1e-30 J (user trial): it is now pushed at every joint (a tree without
    actuators), and its drift is measured on a real swing, checked against the energy the
    push gave, 1/2 J w^2 with w = 1 rad/s about the pivot (J = 100/12 + 1 * 5^2 + 5 * 10^2)."""
    path = tmp_path / "hanging_pendulum.toml"  # (not in tests/robots: no actuated joint)
    path.write_text(HANGING)
    robot = ps.load(str(path))
    sim = validate.free_motion(robot)
    assert sim.kinetic_j[0] == pytest.approx(0.5 * (100 / 12 + 25 + 500), rel=1e-12)
    got = validate.check_energy(sim)
    assert got.status == "pass" and got.worst < 1e-8 and got.worst > 0.0
    quiet = SimpleNamespace(t_s=sim.t_s, kinetic_j=np.full(len(sim.t_s), 1e-30),
                            energy_j=np.full(len(sim.t_s), -531.4), friction_j=None,
                            energy_drift=0.0)
    skipped = validate.check_energy(quiet)
    assert skipped.status == "skipped" and skipped.worst is None
    assert skipped.detail == "the free motion does not move (peak kinetic energy 1e-30 J)"
