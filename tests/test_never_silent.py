"""Inputs that used to give a number without a word: each now gets a clear error naming what is
wrong (a passive joint in a tree, a second initial state, a NaN or 2-D time vector)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError

ROBOTS = Path(ps.__file__).resolve().parent / "robots"


@pytest.fixture(scope="module")
def passive_elbow(tmp_path_factory) -> ps.Robot:
    """serial_2dof with its elbow joint unactuated (a description file, derived on first use)."""
    text = (ROBOTS / "serial_2dof.toml").read_text()
    name, elbow = 'name = "serial_2dof"', 'name = "joint2"'
    assert name in text and elbow in text
    text = text.replace(name, 'name = "passive_elbow"')
    head, tail = text.split(elbow)
    tail = tail.replace("actuated = true", "actuated = false", 1)
    path = tmp_path_factory.mktemp("robots") / "passive_elbow.toml"
    path.write_text(head + elbow + tail)
    return ps.load(path)


def test_inverse_dynamics_refuses_a_passive_joint_of_a_tree(passive_elbow):
    assert passive_elbow.actuated == (0,)
    q = np.zeros((3, 2))
    with pytest.raises(InputError, match=r"passive_elbow: joint joint2 has no motor"):
        passive_elbow.inverse_dynamics(q, q, q)


def test_the_passive_tree_still_simulates(passive_elbow):
    """Forward dynamics is defined: zero torque at the passive joint, the same motion as the
    fully actuated arm under zero torque (both start at rest below the horizontal)."""
    arm = ps.load("serial_2dof")
    a = ps.simulate(passive_elbow, np.radians([-60.0, 10.0]), [0.0, 0.0], (0.0, 0.5))
    b = ps.simulate(arm, np.radians([-60.0, 10.0]), [0.0, 0.0], (0.0, 0.5))
    assert np.max(np.abs(a.q - b.q)) < 1e-12


def test_more_than_one_initial_state_is_an_error():
    arm = ps.load("serial_2dof")
    with pytest.raises(InputError, match=r"q0 must be one vector of 2 values, got 2 rows"):
        ps.simulate(arm, np.zeros((2, 2)), [0.0, 0.0], (0.0, 1.0))
    with pytest.raises(InputError, match=r"qd0 must be one vector of 2 values, got 3 rows"):
        ps.simulate(arm, [0.0, 0.0], np.zeros((3, 2)), (0.0, 1.0))
    five = ps.load("five_bar_type2")
    with pytest.raises(InputError, match=r"q0 must be one vector of 4 values, got 2 rows"):
        ps.simulate(five, np.tile(five.q_drawn, (2, 1)), np.zeros(4), (0.0, 1.0))


@pytest.mark.parametrize("t_eval, message", [
    ([0.0, np.nan, 1.0], r"t_eval\[1\] is nan: times must be finite"),
    ([[0.0, 0.5, 1.0]], r"t_eval must be a 1-D array of times, got shape \(1, 3\)"),
    ([0.0, 0.7, 0.5], r"t_eval must be at least 2 increasing times"),
    (["a", "b"], r"t_eval must be an array of times"),
])
def test_bad_time_vectors(t_eval, message):
    with pytest.raises(InputError, match=message):
        ps.simulate(ps.load("serial_2dof"), [0.0, 0.0], [0.0, 0.0], (0.0, 1.0), t_eval=t_eval)


def test_a_passive_joint_takes_no_torque_in_a_simulation(passive_elbow):
    """One torque per actuated joint: a constant shoulder torque equals the full arm's with a
    zero elbow torque; two values are refused."""
    arm = ps.load("serial_2dof")
    a = ps.simulate(passive_elbow, [0.0, 0.5], [0.0, 0.0], (0.0, 0.3), torque=[0.2])
    b = ps.simulate(arm, [0.0, 0.5], [0.0, 0.0], (0.0, 0.3), torque=[0.2, 0.0])
    assert np.max(np.abs(a.q - b.q)) < 1e-12
    with pytest.raises(InputError, match="torque"):
        ps.simulate(passive_elbow, [0.0, 0.5], [0.0, 0.0], (0.0, 0.3), torque=[0.2, 0.1])


ARM = "serial_2dof"


@pytest.mark.parametrize("call, message", [
    (lambda: ps.load(3), r"a robot is a built-in name, a description file or a generated folder"),
    (lambda: ps.equations(None), r"a robot is a built-in name"),
    (lambda: ps.Robot(3), r"Robot\(name\): a robot name \(str\), got int"),
    (lambda: ps.simulate(ps.load(ARM), [0, 0], [0, 0], 5), r"time span must be two numbers"),
    (lambda: ps.simulate(ps.load(ARM), [0, 0], [0, 0], ("a", "b")), r"time span must be two"),
    (lambda: ps.simulate(ps.load(ARM), [0, 0], [0, 0], (0, 1), rtol="x"),
     r"rtol must be a positive number \(got 'x'\)"),
    (lambda: ps.simulate(ps.load(ARM), [0, 0], [0, 0], (0, 1), torque=lambda t: "x"),
     r"torque function returned something that is not numbers at t = 0 s"),
    (lambda: ps.simulate("serial_2dof", [0, 0], [0, 0], (0, 1)), r"simulate needs a Robot"),
    (lambda: ps.cubic("a", [1.0], 1.0, [0.0]), r"trajectory start must be numbers"),
    (lambda: ps.cubic([0.0], [1.0], "x", [0.0]), r"duration must be a positive number"),
    (lambda: ps.cubic([0.0], [1.0], 1.0, [[0.0, 0.5]]), r"times must be a 1-D array"),
    (lambda: ps.from_actuated(ps.load("five_bar_type1"), "x", [[0, 0]], [[0, 0]], [[0, 0]]),
     r"t must be an array of numbers"),
    (lambda: ps.from_actuated(ps.load("five_bar_type1"), [0, 1], [[2.07, 1.07]], [[0, 0]],
                              [[0, 0]]), r"t has 2 times for 1 samples of q_act"),
    (lambda: ps.plot(None), r"plot takes a study Result"),
    (lambda: ps.validate(None), r"validate needs a Robot"),
    (lambda: ps.inverse_kinematics(ps.load(ARM), None), r"inverse_kinematics needs a Trajectory"),
])
def test_the_python_api_raises_its_own_errors(call, message):
    with pytest.raises(ps.PlanarSymError, match=message):
        call()
