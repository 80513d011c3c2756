"""The robot's parameters as one immutable, checked value (issue 24, item 1): a change makes a new
robot on the same compiled code, whose fast callers read the new vector, never the old one.

Checked against independent values: the 2-DOF arm's gravity torque in closed form, the exact
(CasADi) path, a pickle round trip, and the rules' own column-wise form.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.model.parameter_set import Parameters
from planar_sym.model.robot import Robot


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


def _gravity_closed_form(p, q):
    """g(q) of the seed's 2-DOF arm, by hand: masses at their centres of gravity on the links."""
    g, m1, m2 = p["g"], p["m_link1"], p["m_link2"]
    c1, c2, l1 = p["cgx_link1"], p["cgx_link2"], p["px_link1_CS2"]
    mm = p.get("m_motor2", 0.0)  # the elbow motor sits at the end of link 1
    s1, s12 = np.cos(q[0]), np.cos(q[0] + q[1])
    g2 = m2 * g * c2 * s12
    g1 = (m1 * c1 + (m2 + mm) * l1) * g * s1 + g2
    return np.array([g1, g2])


def test_parameters_are_a_read_only_mapping(arm):
    p = arm.parameters
    assert isinstance(p, Parameters)
    assert dict(p) == {e.name: e.value for e in arm.parameter_list}  # as derived
    assert p == dict(p) and len(p) == len(arm.parameter_list)
    with pytest.raises(ValueError, match="read-only"):
        arm.p[0] = 1.0
    with pytest.raises(TypeError, match=r"read-only .* robot.with_parameters\(g=1.0\)"):
        p["g"] = 1.0  # type: ignore[index]
    with pytest.raises(InputError, match=r"parameter m_link1 must be a number in kg \(SI; "):
        arm.with_parameters(m_link1=[2.0])
    # a unit typed into the API is read as --set and a study read it
    assert arm.with_parameters(m_link1="2 kg").parameters["m_link1"] == 2.0
    with pytest.raises(InputError, match=r"parameter m_link1: \"heavy\": unknown name heavy"):
        arm.with_parameters(m_link1="heavy")


def test_a_changed_robot_computes_with_its_own_values(arm):
    """The fast callers of the new robot read its vector; the old robot keeps its values."""
    q = np.array([0.3, -0.7])
    if {"cgx_link1", "cgx_link2", "px_link1_CS2"} - set(arm.parameters):
        pytest.skip("the arm's parameter names changed")
    heavy = arm.with_parameters(m_link2=2.5, g=3.7)
    typed = {**arm.parameters, "m_link2": 2.5, "g": 3.7}  # what the user asked for
    for robot, values in ((arm, dict(arm.parameters)), (heavy, typed)):
        assert robot.gravity(q) == pytest.approx(_gravity_closed_form(values, q),
                                                 rel=1e-12, abs=1e-14)
    assert arm.parameters["m_link2"] != 2.5  # unchanged
    exact = Robot(heavy.name, heavy.library, heavy.parameters, exact=True)
    z = np.zeros(2)
    assert heavy.inverse_dynamics(q, z, z) == pytest.approx(exact.inverse_dynamics(q, z, z),
                                                            rel=1e-12)


def test_every_route_refuses_with_the_same_rule(arm):
    bad = {"m_link1": -1.0, "g": 1e4, "izz_link1": -0.1}
    for name, value in bad.items():
        k = [e.name for e in arm.parameter_list].index(name)
        vector = arm.p.copy()
        vector[k] = value
        messages = []
        routes = (lambda n=name, v=value: arm.with_parameters(**{n: v}),
                  lambda n=name, v=value: arm.parameters.replace(**{n: v}),
                  lambda p=vector: arm.parameters.with_vector(p),
                  lambda p=vector: Robot(arm.name, arm.library, p))
        for route in routes:
            with pytest.raises(InputError) as info:
                route()
            messages.append(str(info.value).split(": ", 1)[1])
        assert len(set(messages)) == 1, messages  # one rule, one message
        assert name in messages[0]


def test_a_design_vector_and_a_pickle_keep_the_values(arm):
    values = {"m_link1": 0.9, "izz_link1": 0.004}
    changed = arm.with_parameters(**values)
    design = arm.with_values(arm.parameters.with_vector(changed.p, checked=True))
    back = pickle.loads(pickle.dumps(changed))
    q, z = np.array([0.1, 0.2]), np.zeros(2)
    qdd = np.array([1.0, -2.0])
    want = changed.inverse_dynamics(q, z, qdd)
    for robot in (design, back):
        assert np.array_equal(robot.p, changed.p)
        assert np.array_equal(robot.inverse_dynamics(q, z, qdd), want)
    assert not np.array_equal(arm.inverse_dynamics(q, z, qdd), want)


def test_parameters_of_another_robot_are_refused(arm):
    other = ps.load("serial_3dof")
    with pytest.raises(InputError, match="another robot"):
        arm.with_values(other.parameters)
