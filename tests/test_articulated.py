"""``M^-1 B`` by articulated bodies (``derive/articulated.py``) and the forward dynamics built on it.

* On the spanning tree of every built-in robot, test robot and example (serial, branched like the
  3-RRR's three legs, sliders with turned axes, welds, rotors on moving bodies), on a branched,
  welded, geared tree written here and on a 20-link chain, at random states and random positive
  parameters (so every rotor inertia and gear ratio counts): ``M X`` gives ``B`` back, with ``M``
  from composite bodies (an independent recursion, itself checked against ``dp/dqd``), to 1e-13
  relative to ``|M| |X|``.
* The generated forward dynamics keeps, per robot, whichever of ``L D L^T`` and the articulated
  recursion has fewer operations: ``L D L^T`` on the 2-link arm, the recursion from 4 links of a
  chain, where it takes under a third of the operations at 20 links; and the chosen functions agree
  with Pinocchio's ``aba`` to 1e-12 (the Jacobian with central differences of ``aba`` to 1e-6).
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from conftest import ALL_ROBOTS, ROBOTS_DIR

from benchmarks.chains import write_chain
from derive import ad_dynamics, quantities
from derive.articulated import Articulated
from derive.factor import solve_spd
from planar_sym.model import description

ROOT = Path(__file__).resolve().parent.parent
EXTRA = sorted((ROOT / "tests" / "robots").glob("*.toml")) + sorted(
    p for p in (ROOT / "examples").glob("*.toml") if "[[bodies]]" in p.read_text())

BRANCHED = """
name = "branched_geared"
title = "A base with an arm and a slider carrying a welded bracket and a tip, all geared"
pose = "joints"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "rad"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "base"
mass = 3.0
izz = 0.06
cg = [0.2, 0.05]
points = { O = [0.0, 0.0], A = [0.4, 0.0], B = [0.2, 0.1] }
[[bodies]]
name = "arm"
mass = 1.0
izz = 0.008
cg = [0.15, 0.0]
points = { A = [0.0, 0.0], T = [0.3, 0.0] }
[[bodies]]
name = "sled"
mass = 0.8
izz = 0.003
cg = [0.1, 0.0]
points = { R = [0.0, 0.0], W = [0.2, 0.0] }
[[bodies]]
name = "bracket"
mass = 0.3
izz = 0.001
cg = [0.05, 0.05]
points = { W = [0.0, 0.0], C = [0.1, 0.1] }
[[bodies]]
name = "tip"
mass = 0.2
izz = 0.0004
cg = [0.07, 0.0]
points = { C = [0.0, 0.0], E = [0.15, 0.0] }
[[joints]]
name = "j0"
type = "revolute"
parent = "ground.O"
child = "base.O"
actuated = true
angle = 0.3
actuator = { gear_ratio = 30, rotor_inertia = 1e-4 }
[[joints]]
name = "j1"
type = "revolute"
parent = "base.A"
child = "arm.A"
actuated = true
angle = -0.5
actuator = { gear_ratio = 20, rotor_inertia = 5e-5, viscous_friction = 0.02 }
[[joints]]
name = "j2"
type = "prismatic"
parent = "base.B"
child = "sled.R"
axis = [0.6, 0.8]
actuated = true
displacement = 0.1
actuator = { gear_ratio = 1000, rotor_inertia = 1e-5 }
[[joints]]
name = "weld"
type = "weld"
parent = "sled.W"
child = "bracket.W"
[[joints]]
name = "j3"
type = "revolute"
parent = "bracket.C"
child = "tip.C"
actuated = true
angle = 0.7
actuator = { gear_ratio = 10, rotor_inertia = 2e-5, coulomb_friction = 0.05 }
"""


def _written(tmp_path: Path, name: str) -> Path:
    if name == "branched_geared":
        path = tmp_path / "branched_geared.toml"
        path.write_text(BRANCHED)
        return path
    return write_chain(int(name.split("_")[1]), tmp_path)


@pytest.mark.parametrize(
    "source", [ROBOTS_DIR / f"{r}.toml" for r in ALL_ROBOTS] + EXTRA
    + ["branched_geared", "chain_20"], ids=lambda p: getattr(p, "stem", p))
def test_articulated_bodies_invert_the_mass_matrix(source, tmp_path):
    path = source if isinstance(source, Path) else _written(tmp_path, source)
    desc = description.load(path)
    d = ad_dynamics.derive(desc)
    s = d.sym
    n = s.q.shape[0]
    b = ca.SX.sym("b", n, 3)
    solve = ca.Function("solve", [s.q, s.p, b], [Articulated(desc, d.tree).solve(b)])
    mass = ca.Function("mass", [s.q, s.p], [d.mass_matrix])
    rng = np.random.default_rng(11)
    for _ in range(5):
        q, p = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.2, 3.0, len(desc.parameters()))
        rhs = rng.normal(size=(n, 3))
        m, x = np.array(mass(q, p)), np.array(solve(q, p, rhs))
        assert np.max(np.abs(m @ x - rhs)) <= 1e-13 * np.max(np.abs(m)) * np.max(np.abs(x)), (
            path.stem, m @ x - rhs)


def _forward(desc):
    """{quantity: Generated} of the numeric route, forward dynamics included."""
    return {g.quantity: g for g in quantities.functions(ad_dynamics.quantities(desc))}


def test_the_cheaper_solve_is_kept(tmp_path):
    small = _forward(description.load(ROBOTS_DIR / "serial_2dof.toml"))
    assert "articulated" not in small["forward_dynamics"].route  # L D L^T of a 2 x 2
    # at 4 links L D L^T of the composite M is the cheaper since its entries cost 4
    # operations (e97269e), from 6 links the recursion
    four = _forward(description.load(write_chain(4, tmp_path)))
    assert "articulated" not in four["forward_dynamics"].route
    for n in (6, 12, 20):
        gens = _forward(description.load(write_chain(n, tmp_path)))
        assert gens["forward_dynamics"].route.endswith("M^-1 by articulated bodies"), n
        assert "articulated" not in gens["forward_dynamics_jacobian"].route  # compile cost
        if n == 20:  # against M by composite bodies and L D L^T: under a third
            d = ad_dynamics.derive(description.load(write_chain(n, tmp_path)))
            s = d.sym
            ldl = ca.Function("ldl", [s.q, s.qd, s.tau, s.p],
                              [solve_spd(d.mass_matrix, s.tau - d.bias)], {"cse": True})
            assert gens["forward_dynamics"].operations < quantities.Generated(
                "forward_dynamics", ldl, "").operations / 3


@pytest.mark.parametrize("n", [6, 12])
def test_forward_dynamics_against_pinocchio_aba(tmp_path, n):
    import pinocchio as pin
    from pinocchio_model import pinocchio_model

    desc = description.load(write_chain(n, tmp_path))
    pm, _ = pinocchio_model(desc)
    data = pm.createData()
    gens = _forward(desc)
    fd = gens["forward_dynamics"].function
    jac = gens["forward_dynamics_jacobian"].function
    p = np.array(desc.parameter_values())
    rng = np.random.default_rng(n)
    for _ in range(5):
        q, qd, tau = (rng.uniform(-3, 3, n) for _ in range(3))
        ref = pin.aba(pm, data, q, qd, tau)
        qdd = np.array(fd(q, qd, tau, p)).ravel()
        assert np.max(np.abs(qdd - ref)) <= 1e-12 * np.max(np.abs(ref))
        dq, dqd = (np.array(x) for x in jac(q, qd, tau, p))
        h = 1e-6
        for k in range(n):
            e = np.eye(n)[k] * h
            by_q = (pin.aba(pm, data, q + e, qd, tau) - pin.aba(pm, data, q - e, qd, tau)) / 2 / h
            by_qd = (pin.aba(pm, data, q, qd + e, tau) - pin.aba(pm, data, q, qd - e, tau)) / 2 / h
            assert np.max(np.abs(dq[:, k] - by_q)) <= 1e-6 * np.max(np.abs(dq)), k
            assert np.max(np.abs(dqd[:, k] - by_qd)) <= 1e-6 * np.max(np.abs(dqd)), k
