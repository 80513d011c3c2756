"""``validate`` on the robots its checks used to fail although they are right, and still failing
on broken ones:

* a geared arm with rotors and friction (``examples/serial_2dof_geared.toml``): the energy route
  (b) adds the drive train's friction D(qd) = b qd + c tanh(qd / v_s), computed from the
  parameters in numpy (not the compiled code), to Lagrange's equations from the energy; (c) is
  the energy balance E(t) - E(0) + F(t) = 0 with the friction's work F integrated with the
  state; (d) the power balance sum tau qd = dE/dt + D . qd;
* a 1-DOF pendulum: its dqdd/dqd is zero at every state, measured against the sampled
  accelerations per unit rate instead of against its own rounding noise;
* a tree with a passive joint (the cart-pole): the power balance with the tree torques at every
  joint (the passive one's as an applied torque);

and fails when the compiled friction differs from the drive train's (a viscous coefficient 1 %
off in the compiled code only), when a 1-DOF robot's velocity Jacobian is off by 1e-4 of its
scale, and when a passive tree's compiled energy is off (1e-3 of the potential).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.analysis import validate, validate_rows
from planar_sym.model.drive import DriveTrain

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"
CASES = {"geared": GEARED, "pendulum": TEST_ROBOTS / "pendulum.toml",
         "cart_pole": TEST_ROBOTS / "cart_pole.toml",
         "point_pendulum": TEST_ROBOTS / "point_pendulum.toml"}


@pytest.fixture(scope="module")
def robots():
    return {k: ps.load(v) for k, v in CASES.items()}


@pytest.mark.parametrize("case", CASES)
def test_validate_passes(robots, case):
    rows = validate.run_all(robots[case])
    bad = [(r.check, r.worst, r.detail) for r in rows if r.status != "pass"]
    assert not bad, bad
    assert all(r.worst is not None and r.worst <= r.tolerance for r in rows)


def test_the_friction_is_the_parameters_own(robots):
    """D(qd) from the drive train against the closed form with the parameters read by name
    here, and against the compiled code: the bias with friction less the bias of the same
    robot with fv and fc set to 0 (same compiled function, other parameter vector)."""
    robot = robots["geared"]
    p = robot.parameters
    qd = np.array([[0.3, -0.7], [0.004, -2.0]])
    expected = np.column_stack([
        p["fv_joint1"] * qd[:, 0] + p["fc_joint1"] * np.tanh(qd[:, 0] / p["vs_joint1"]),
        np.zeros(2)])  # joint2 of this example has a rotor and no friction
    got = robot.drive_train.friction(qd)
    assert np.max(np.abs(got - expected)) <= 1e-15 * np.max(np.abs(expected))
    q = np.array([[0.2, 0.5], [1.0, -0.4]])
    frictionless = robot.with_parameters(fv_joint1=0.0, fc_joint1=0.0)
    compiled = robot.bias(q, qd) - frictionless.bias(q, qd)
    assert np.max(np.abs(compiled - got)) <= 1e-12 * np.max(np.abs(got))


def test_a_drive_train_that_differs_from_the_compiled_friction_fails(robots, monkeypatch):
    """The compiled code keeps its friction; the drive train (the model every check and
    consumer reads) says the viscous coefficient is 1 % larger: (b) and (d) see it, and so does
    (c), whose friction work is integrated from the drive train while the compiled dynamics
    dissipates with its own."""
    robot = robots["geared"]
    real = robot.drive_train
    drives = list(real.drives)
    drives[0] = type(drives[0])(**{**drives[0].__dict__, "viscous": drives[0].viscous * 1.01})
    monkeypatch.setattr(type(robot), "drive_train", property(
        lambda self: DriveTrain(tuple(drives), real.n)))
    rows = {r.check[:3]: r for r in validate.run_all(robot)}
    assert all(rows[k].status == "FAIL" for k in ("(b)", "(c)", "(d)")), rows


def test_an_ill_conditioned_mass_matrix_passes_and_a_wrong_solve_still_fails(robots,
                                                                             monkeypatch):
    """A trial: a rotor of 0.5 kg*m^2 (plausible, the description allows up to 1) behind
    the shoulder's 50:1 gear reflects 1250 kg*m^2 beside the elbow's 1.5e-3: cond(M) ~ 8e5.
    (b) compared the forward dynamics' accelerations themselves, which a right solve gets
    only to cond(M) times the torques' rounding (1.7e-7 > 1e-7: "FAILED" on a correct
    robot). As the torques they imply (M qdd + h) they agree to rounding; a solve 1e-6 off
    still fails (a shift of 1e-6 of its accelerations, which the Jacobian's differences
    do not see)."""
    robot = robots["geared"].with_parameters(jm_joint1=0.5)
    q, qd, qdd, _ = validate_rows.random_states(robot, 20, 2)
    assert np.linalg.cond(robot.mass_matrix(q)).max() > 1e5
    forward = validate.lagrange_from_energy(robot, q, qd, qdd)
    qdd_c = robot.tree_forward_dynamics(q, qd, forward["tau"])
    forward_error = np.max(np.max(np.abs(qdd_c - qdd), 1) / np.max(np.abs(qdd), 1))
    assert forward_error > 1e-7  # what the old measure reported: a false failure
    row = validate.check_energy_route(robot)
    assert row.status == "pass" and row.worst < 1e-7, row
    real = robot.tree_forward_dynamics
    monkeypatch.setattr(robot, "tree_forward_dynamics",
                        lambda *a: np.asarray(real(*a)) + 1e-6 * np.max(np.abs(qdd)),
                        raising=False)
    row = validate.check_energy_route(robot)
    assert row.status == "FAIL" and "forward_dynamics.qdd" in row.detail, row
    assert row.worst > 5e-7


class _Shifted:
    """A compiled function whose output ``out`` is shifted by ``by`` (a broken generation)."""

    def __init__(self, fn, out: str, by: float):
        self.fn, self.out, self.by, self.spec = fn, out, by, fn.spec

    def __call__(self, n, args):
        res = dict(self.fn(n, args))
        res[self.out] = np.asarray(res[self.out]) + self.by
        return res


def test_a_broken_velocity_jacobian_of_a_one_dof_robot_fails(monkeypatch):
    robot = ps.load(CASES["pendulum"])
    fns = dict(robot.library.functions)
    # 1e-4 1/s: the sampled accelerations per unit rate are about 1 1/s
    fns["forward_dynamics_jacobian"] = _Shifted(fns["forward_dynamics_jacobian"],
                                                "dqdd_dqd", 1e-4)
    monkeypatch.setattr(robot.library, "functions", fns)
    row = validate.check_energy_route(robot)
    assert row.status == "FAIL" and "dqdd_dqd" in row.detail, row
    assert 1e-5 < row.worst < 1e-3


def test_a_broken_energy_of_a_passive_tree_fails_the_power_balance(robots, monkeypatch):
    """The cart-pole's power balance uses its tree torques; an energy function off by a
    q-dependent 1e-3 of its potential must break it (the check is not vacuous)."""
    robot = robots["cart_pole"]
    real = type(robot).energy

    def energy(self, q, qd):
        kinetic, potential = real(self, q, qd)
        return kinetic, potential * (1 + 1e-3 * np.sin(np.asarray(q)[..., -1]))

    monkeypatch.setattr(robot, "energy", energy.__get__(robot))
    row = validate.check_power(robot, validate.motion(robot, 41, 0.3))
    assert row.status == "FAIL" and row.worst > 1e-5, row
