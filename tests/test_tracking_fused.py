"""The compiled loop's fused controller and plant (``derive/tracking.py``, ``engine_c.FUSED``)
against the two-call path it replaces (the controller's generated function, then the plant's
forward dynamics): the same run to the integrator's rounding, on the cases where the two could
part: a model error (the controller's parameters are not the plant's), saturation at the
actuator limits with friction in the plant, a passive joint with an input torque table, and
computed torque. The generated function itself is checked against SymPy in
``test_codegen_vs_sympy.py::test_tracking_functions``; the whole loop against SciPy and a
Python controller in ``test_control.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.control import controller, simulate_controlled
from planar_sym.dynamics import engine_c
from planar_sym.motion.signals import from_table

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"


def _runs(monkeypatch, robot, ctl, reference, **kw):
    out = []
    for fused in (True, False):
        monkeypatch.setattr(engine_c, "FUSED", fused)
        out.append(simulate_controlled(robot, ctl, (0.0, 1.5), reference=reference,
                                       t_eval=np.linspace(0, 1.5, 61), **kw))
    return out


def _reference(a, b):
    t = np.linspace(0.0, 1.5, 7)
    s = 0.5 - 0.5 * np.cos(np.pi * t / 1.5)
    return from_table(t, np.outer(1 - s, a) + np.outer(s, b), "cubic")


def _agree(fused, two, scale_q: float, scale_tau: float):
    assert np.max(np.abs(fused.q - two.q)) < 1e-9 * scale_q
    assert np.max(np.abs(fused.tau - two.tau)) < 1e-8 * scale_tau
    assert np.max(np.abs(fused.work_j - two.work_j)) < 1e-8 * max(np.max(np.abs(two.work_j)), 1)
    assert [e.name for e in fused.events] == [e.name for e in two.events]


@pytest.mark.parametrize("law", ["pd", "computed_torque"])
def test_a_model_error_is_the_plants_not_the_controllers(monkeypatch, law):
    """The 2-DOF arm with its elbow link 30 % heavier than the controller believes, and a
    constant input torque: the fused function must use the plant's parameters for the motion
    and the model's for the law, and add the input to the law's torque."""
    model = ps.load("serial_2dof")
    plant = model.with_parameters(m_link2=model.parameters["m_link2"] * 1.3)
    kp, kd = (20.0, 2.0) if law == "pd" else (400.0, 40.0)
    ref = _reference([0.3, 0.8], [1.2, -0.4])
    fused, two = _runs(monkeypatch, model, controller(law, kp, kd), ref, plant=plant,
                       torque=[0.05, -0.02])  # a constant input torque added to the law's
    _agree(fused, two, 1.0, np.max(np.abs(two.tau)))
    assert np.max(np.abs(fused.q_ref - fused.q[:, :2])) > 1e-4  # the model error shows


def test_saturation_with_friction(monkeypatch):
    """The geared arm (motor limits 0.01 N*m through 50:1 gears, Coulomb friction at the
    shoulder) asked to jump to a pose 1 rad away: the applied torques sit on their limits
    for part of the run, in both paths alike."""
    robot = ps.load(GEARED)
    ref = from_table([0.0, 1.5], [[1.0, 0.5], [1.0, 0.5]])
    fused, two = _runs(monkeypatch, robot, controller("computed_torque", 900.0, 60.0), ref,
                       q0=[0.0, 0.0], qd0=[0.0, 0.0])
    _agree(fused, two, 1.0, 0.5)
    limit = 0.5  # N*m at the joint: 0.01 at the motor times the gear
    held = np.isclose(np.abs(fused.tau), limit, rtol=1e-12)
    assert held.sum() > 5 and np.all(np.abs(fused.tau) <= limit * (1 + 1e-12))
    assert np.max(np.abs(fused.tau_cmd)) > 2 * limit


def test_a_passive_joint_and_an_input_table(monkeypatch):
    """The cart-pole: PD on the cart (the pole is passive: no torque, no reference), plus a
    tabled push added to the controller's force."""
    robot = ps.load(TEST_ROBOTS / "cart_pole.toml")
    assert len(robot.actuated) == 1 and robot.n == 2
    ref = from_table([0.0, 1.5], [[0.0], [0.3]])
    push = from_table([0.0, 0.5, 1.5], [[0.0], [0.4], [0.0]])
    fused, two = _runs(monkeypatch, robot, controller("pd", 30.0, 8.0), ref,
                       q0=[0.0, 0.1], qd0=[0.0, 0.0], torque=push)
    _agree(fused, two, 1.0, np.max(np.abs(two.tau)))


def test_the_fused_path_is_taken_where_the_robot_has_one(monkeypatch):
    """Trees up to TRACKING_MAX_N coordinates with a tracking law get the fused function;
    open loop, closed chains and FUSED = False do not."""
    from planar_sym.dynamics.engine_c import _Setup

    def address(robot, ctl):
        ref = from_table([0.0, 1.0], np.zeros((2, len(robot.actuated))))
        return _Setup(robot, robot, ctl, ref, None, [], np.full(len(robot.actuated),
                                                               np.inf)).c.tracking

    arm, five = ps.load("serial_2dof"), ps.load("five_bar_type1")
    lib = arm.library
    assert address(arm, controller("pd", 1.0, 1.0)) == lib.address("tracking_pd")
    assert address(arm, controller("computed_torque", 1.0, 1.0)) == lib.address("tracking_ct")
    assert address(arm, controller("none")) is None
    assert address(five, controller("pd", 1.0, 1.0)) is None
    monkeypatch.setattr(engine_c, "FUSED", False)
    assert address(arm, controller("pd", 1.0, 1.0)) is None
