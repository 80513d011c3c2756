"""The base parameters in closed form (``derive/base_forms.py``, printed in the equation
report) against the runtime's numeric ones (``planar_sym.identify.base``: Gautier's method on
the compiled CasADi regressor, a second route): the same names, the same regrouping matrix at
the description's lengths, and SymPy's Y equal to the compiled regressor at random states."""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.identify.base import base_parameters
from planar_sym.identify.regressor import regressor
from planar_sym.model.description import load as read_description

sp = pytest.importorskip("sympy")
from derive.base_forms import base_forms
from derive.model import build

pytestmark = pytest.mark.slow

# revolute and prismatic, rotors and friction, no gravity, a point mass, a cart
TREES = ["serial_2dof", "serial_3dof", "serial_rpr", "examples/serial_2dof_geared.toml",
         "tests/robots/cart_pole.toml", "tests/robots/horizontal_2dof.toml",
         "tests/robots/point_pendulum.toml"]


def _forms(ref):
    path = ps.load(ref).description_file
    model = build(read_description(path))
    return model, base_forms(model)


@pytest.mark.parametrize("ref", TREES)
def test_closed_forms_are_the_numeric_base_parameters(ref):
    robot = ps.load(ref)
    model, forms = _forms(ref)
    base = base_parameters(robot)
    assert forms.names == base.names
    assert forms.unidentifiable == base.unidentifiable
    # the regrouping matrix at the description's values
    values = {p: v for p, v in zip(model.sym.p, robot.p)}
    symbols = [forms.standard[n] for n in base.standard.names]
    got = np.array([[float(sp.diff(e, s).xreplace(values)) for s in symbols]
                     for e in forms.expressions])
    assert np.abs(got - base.regrouping).max() <= 1e-9 * np.abs(base.regrouping).max()


@pytest.mark.parametrize("ref", TREES[:4])
def test_sympy_regressor_is_the_compiled_one(ref):
    robot = ps.load(ref)
    model, forms = _forms(ref)
    s = model.sym
    f = sp.lambdify([s.q, s.qd, s.qdd, s.p], forms.y, "numpy")
    rng = np.random.default_rng(7)
    q, qd, qdd = (rng.uniform(-2, 2, (5, robot.n)) for _ in range(3))
    ours = regressor(robot, q, qd, qdd).y
    for k in range(5):
        theirs = np.array(f(q[k], qd[k], qdd[k], robot.p), dtype=float)
        assert np.abs(theirs - ours[k]).max() <= 1e-10 * max(np.abs(ours[k]).max(), 1.0)


def test_report_shows_the_lumped_parameters_are_base_combinations():
    """Issue 26: for the 2-DOF arm the report's alpha, beta, delta and gravity coefficients
    are the base set (the committed report, as make derive writes it)."""
    text = (ps.load("serial_2dof").library.folder / "equations.txt").read_text()
    for line in ("alpha = izo_link1R + izo_link2", "beta = mcx_link2*a_1", "delta = izo_link2",
                 "g1 = mcx_link1R*g*c1 + mcx_link2*g*c12", "g2 = mcx_link2*g*c12",
                 "izo_link1R = izo_link1 + izo_motor2 + m_link2*a_1**2 + m_motor2*a_1**2",
                 "No effect on any torque (not identifiable): m_link1."):
        assert line in text


def test_closed_chain_and_inexact_angles_say_why_not():
    model = build(read_description(ps.load("five_bar_type1").description_file))
    assert "closed chain" in base_forms(model)
    model = build(read_description(ps.load("tests/robots/bent_arm.toml").description_file))
    assert "not exact" in base_forms(model)
