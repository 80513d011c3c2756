"""The fast paths (vectorised loops, -ffast-math, C-level calls) against the exact path.

Exact: CasADi's per-sample functions compiled with -O3 and no fast math. Fast: the same
CasADi algorithm printed as straight-line loops (derive/simd.py), -O3 -march=native
-ffast-math, called through planar_sym/model/_fastcall.c. Both must agree to 1e-12 relative;
measured ~1e-15.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ALL_ROBOTS

import planar_sym
from planar_sym.errors import InputError
from planar_sym.model.locate import load
from planar_sym.model.robot import Robot

TOL = 1e-12
FAST = ("mass_matrix", "bias", "gravity", "tree_inverse_dynamics", "energy")
TREE_ONLY = ("inverse_dynamics", "forward_dynamics")


def _pair(name):
    fast = load(name)
    return fast, Robot(name, fast.library, exact=True)


def _rel(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, (a.shape, b.shape)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_fast_equals_exact(name):
    fast, exact = _pair(name)
    assert not isinstance(fast.mass_matrix, type(exact.mass_matrix)), "fast path not bound"
    rng = np.random.default_rng(7)
    q, qd, qdd = (rng.uniform(-3, 3, (500, fast.n)) for _ in range(3))
    methods = FAST + (() if fast.is_closed_chain else TREE_ONLY)
    for m in methods:
        args = {"mass_matrix": (q,), "gravity": (q,), "bias": (q, qd), "energy": (q, qd)}.get(
            m, (q, qd, qdd))
        a, b = getattr(fast, m)(*args), getattr(exact, m)(*args)
        for x, y in zip(a if m == "energy" else [a], b if m == "energy" else [b]):
            assert _rel(x, y) < TOL, m
        # one sample: same numbers, sample axis dropped
        one = getattr(fast, m)(*(x[3] for x in args))
        ref = getattr(exact, m)(*(x[3] for x in args))
        for x, y in zip(one if m == "energy" else [one], ref if m == "energy" else [ref]):
            assert np.shape(x) == np.shape(y) and _rel(x, y) < TOL, m


def test_fast_path_checks_input_like_the_exact_one():
    fast, _ = _pair("serial_2dof")
    q = np.zeros((4, 2))
    q[2, 1] = np.inf
    with pytest.raises(InputError, match=r"q\[2, 1\] is inf at sample 2"):
        fast.inverse_dynamics(q, np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(InputError, match="shape"):
        fast.mass_matrix(np.zeros((4, 3)))
    with pytest.raises(InputError, match="samples"):
        fast.bias(np.zeros((4, 2)), np.zeros((5, 2)))
    # lists and integer arrays are converted, as numpy users expect
    assert np.allclose(fast.gravity([0, 0]), fast.gravity(np.zeros(2)))


def test_parameters_reach_the_fast_path():
    fast, _ = _pair("serial_2dof")
    heavy = fast.with_parameters(m_motor2=0.6)
    q = np.array([0.2, 0.9])
    # a point mass dm at the elbow adds dm g a1 cos(q1) to g1, nothing to g2
    extra = (0.6 - 0.292) * 9.81 * 0.1 * np.cos(0.2)
    assert _rel(heavy.gravity(q) - fast.gravity(q), [extra, 0.0]) < 1e-12
    assert heavy.exact is False and Robot("serial_2dof", fast.library, exact=True).exact


def test_exact_mode_from_the_environment(monkeypatch):
    monkeypatch.setenv("PLANAR_SYM_EXACT", "1")
    robot = planar_sym.load("serial_3dof")
    assert robot.exact and "inverse_dynamics" not in vars(robot)
