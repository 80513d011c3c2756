"""Survivors of the mutation run of ``dynamics/reactions.py`` (issue 30): each figure against
every body's free-body balance (``tests/test_reactions.py::free_body_residuals``: gravity, the
reported joint loads, the accelerations and the rotors' spin on the bodies carrying them)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from test_reactions import free_body_residuals

import planar_sym as ps
from planar_sym.dynamics.reactions import joint_loads

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"


@pytest.mark.filterwarnings("ignore:.*a slip:RuntimeWarning")  # a huge rotor, on purpose
@pytest.mark.parametrize("inertia", [1.0, 0.25])
def test_a_rotor_of_exactly_one_kg_m2_is_in_its_bodys_balance(inertia):
    """Catches the rotors kept in reactions._structure chosen by ``rotor_inertia != 1.0``
    instead of ``!= 0.0`` (a rotor of exactly 1 kg*m^2 left out of the moment balance of the
    body carrying its stator): the geared 2-dof arm (examples/serial_2dof_geared.toml) with
    its elbow rotor, carried by link1, set to 1.0 and to 0.25 kg*m^2 (jm_joint2, SI) at a
    gear ratio of 50: every body balances to 1e-12 of its largest force and moment term at
    random states, the rotor's N J (alpha_link1 + N qdd_2), 2500 kg*m^2 times the
    accelerations, included."""
    robot = ps.load(GEARED).with_parameters(jm_joint2=inertia)
    assert robot.parameters["gear_joint2"] == 50.0
    rng = np.random.default_rng(5)
    q = robot.q_drawn + rng.uniform(-0.5, 0.5, (6, robot.n))
    qd, qdd = rng.uniform(-2, 2, (6, robot.n)), rng.uniform(-4, 4, (6, robot.n))
    res_f, res_m = free_body_residuals(robot, q, qd, qdd, joint_loads(robot, q, qd, qdd))
    assert res_f < 1e-12 and res_m < 1e-12, (res_f, res_m)
