"""The two routes to the generated code agree: algorithmic differentiation of the recursive
kinematics (``derive/ad_dynamics.py``, any size) against the expanded SymPy closed forms
(``derive/closed_route.py``, the teaching output), every function and every output, at random
states, to 1e-12 (normwise relative per sample).

``tests/test_codegen_vs_sympy.py`` checks the compiled code against SymPy, but ``codegen``
keeps per function the route with fewer operations, so on small robots much of the AD route
is never compiled; here both are evaluated in CasADi's virtual machine, route against route,
on every built-in robot, the test robots, the examples (several loops, motors with rotors and
friction, sliders), chains past the closed-form limit (against Pinocchio's RNEA instead), and
Hypothesis' random arms. The routes share nothing but the description and the final
``quantities.functions`` assembly (M^-1 by LDL^T, the closed chain's multipliers).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ALL_ROBOTS
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_hypothesis_runtime import serial_robots

from benchmarks.chains import write_chain
from derive import ad_dynamics, closed_route, model, quantities, size
from planar_sym.model import description

ROOT = Path(__file__).resolve().parent.parent
TOL = 1e-12
FLOOR = 1e-300
EXTRA = sorted((ROOT / "tests" / "robots").glob("*.toml")) + sorted(  # robots, not studies
    p for p in (ROOT / "examples").glob("*.toml") if "[[bodies]]" in p.read_text())


def _states(desc, rng, samples=12):
    n, n_p = len(desc.coordinates), len(desc.parameters())
    p = np.array(desc.parameter_values())
    assert p.shape == (n_p,)
    return [{"q": rng.uniform(-np.pi, np.pi, n), "qd": rng.uniform(-3, 3, n),
                 "qdd": rng.uniform(-3, 3, n), "tau": rng.uniform(-5, 5, n), "p": p}
            for _ in range(samples)]


def _input(state: dict, f, name: str, rng) -> np.ndarray:
    """The state's value of input ``name``, or one drawn for it once per state (the tracking
    functions' references, gains, input torques, limits and nominal parameters; the same for
    both routes)."""
    if name not in state:
        size = f.size1_in(name) * f.size2_in(name)
        state[name] = (state["p"] * rng.uniform(0.8, 1.2, size) if name == "p_nom"
                       else rng.uniform(-2, 2, size) * (1 if name in ("lo", "hi") else 3))
        if name == "lo":  # about half the torques clip, at either limit
            state[name] = -np.abs(state[name])
        elif name == "hi":
            state[name] = np.abs(state[name])
    return state[name]


def _worst(desc, a: list, b: list, rng) -> tuple[float, str]:
    """The largest relative difference over every output of every function pair.

    Normwise over a function's outputs and samples together: a block that is structurally
    zero in one route (dqdd/dqd of a single pendulum) is rounding in the other, and a torque
    that nearly cancels at one sample (inertia against tilted gravity) is judged by the size
    the function has elsewhere, not by its own small value.
    """
    states = _states(desc, rng)
    worst, where = 0.0, ""
    for fa, fb in zip(a, b):
        f, g = fa.function, fb.function
        assert (fa.quantity, f.name_in()) == (fb.quantity, g.name_in())
        pairs = [(f(**args), g(**args))
                 for args in ({k: _input(st, f, k, rng) for k in f.name_in()} for st in states)]
        scale = max(max(np.max(np.abs(np.array(rb[o])), initial=0.0)
                        for _, rb in pairs for o in f.name_out()), FLOOR)
        for ra, rb in pairs:
            for out in f.name_out():
                x, y = np.array(ra[out]).ravel(), np.array(rb[out]).ravel()
                err = np.max(np.abs(x - y), initial=0.0) / scale
                if err > worst:
                    worst, where = err, f"{fa.quantity}.{out}"
    return worst, where


def _both(desc):
    ad = ad_dynamics.quantities(desc)
    closed = closed_route.quantities(model.build(desc), ad.sym)
    return quantities.functions(ad), quantities.functions(closed)


@pytest.mark.parametrize("robot", [*ALL_ROBOTS, *EXTRA], ids=lambda r: Path(str(r)).stem)
def test_routes_agree(robot, rng):
    desc = description.load(robot)
    a, b = _both(desc)
    worst, where = _worst(desc, a, b, rng)
    assert worst < TOL, f"{desc.name}: {where} differs by {worst:.2e}"


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                   HealthCheck.function_scoped_fixture])
@given(robot=serial_robots(), seed=st.integers(0, 999))
def test_routes_agree_on_random_arms(tmp_path, robot, seed):
    text, _ = robot
    path = tmp_path / "arm.toml"
    path.write_text(text.replace("{name}", "random_arm"))
    desc = description.load(path)
    a, b = _both(desc)
    worst, where = _worst(desc, a, b, np.random.default_rng(seed))
    assert worst < TOL, f"{where} differs by {worst:.2e}\n{text}"


def test_route_choice_keeps_the_cheaper_code(tmp_path):
    """Within the closed-form limit each function keeps the route with fewer operations; past
    it every function is algorithmic differentiation, and the inverse dynamics grows linearly."""
    desc = description.load("serial_2dof")
    a, b = _both(desc)
    chosen = quantities.choose(b, a)
    for g, x, y in zip(chosen, b, a):
        assert g.operations == min(x.operations, y.operations)
    ops = {}
    for n in (6, 9, 12):
        d = description.load(write_chain(n, tmp_path))
        assert not size.measure(d).closed_forms_fit
        gens = {g.quantity: g for g in quantities.functions(ad_dynamics.quantities(d))}
        ops[n] = gens["inverse_dynamics"].operations
    # linear growth: equal steps in n add (nearly) equal operations
    assert abs((ops[12] - ops[9]) - (ops[9] - ops[6])) < 0.05 * (ops[12] - ops[6])


@pytest.mark.parametrize("n", [8, 12])
def test_long_chain_against_pinocchio(tmp_path, rng, n):
    """Past the closed-form limit: the AD route's inverse dynamics, mass matrix and gravity
    against Pinocchio's RNEA, CRBA and RNEA at rest on the same description."""
    import pinocchio as pin
    from pinocchio_model import pinocchio_model

    desc = description.load(write_chain(n, tmp_path))
    pm, _ = pinocchio_model(desc)
    data = pm.createData()
    gens = {g.quantity: g.function for g in quantities.functions(ad_dynamics.quantities(desc))}
    p = np.array(desc.parameter_values())
    for state in _states(desc, rng, 5):
        q, qd, qdd = state["q"], state["qd"], state["qdd"]
        tau = np.array(gens["inverse_dynamics"](q, qd, qdd, p)).ravel()
        ref = pin.rnea(pm, data, q, qd, qdd)
        assert np.max(np.abs(tau - ref)) / np.max(np.abs(ref)) < TOL
        M = np.array(gens["mass_matrix"](q, p))
        ref_m = pin.crba(pm, data, q)
        ref_m = np.triu(ref_m) + np.triu(ref_m, 1).T
        assert np.max(np.abs(M - ref_m)) / np.max(np.abs(ref_m)) < TOL
        qdd_fd = np.array(gens["forward_dynamics"](q, qd, ref, p)).ravel()
        assert np.max(np.abs(qdd_fd - qdd)) / np.max(np.abs(qdd)) < 1e-10
