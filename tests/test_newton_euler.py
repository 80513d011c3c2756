"""The generated inverse dynamics by Newton-Euler (``derive/newton_euler.py``) against the
Lagrangian it replaced: ``tau = dp/dq qd + dp/dqd qdd - dT/dq + dV/dq + D(qd)``, differentiated
by CasADi from the energies of the same recursive kinematics (forward over reverse, as the
numeric route did), on the spanning tree of every built-in robot, test robot and example
(sliders with turned axes, welds, rotors on moving bodies, friction, several loops), a branched,
welded, geared tree and a 20-link chain, at random states with random positive parameters (so a
rotor's inertia, its gear ratio and gravity all count), to 1e-12 relative; ``h`` (at qdd = 0)
likewise; and what it buys: under 55% of the operations at every size from 6 links.
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from conftest import ROBOTS_DIR
from test_articulated import EXTRA, _written

from benchmarks.chains import write_chain
from derive import ad_dynamics
from derive.quantities import Generated
from planar_sym.model import description


def _lagrangian(d):
    """tau and h from the energies: forward sweeps over the reverse one."""
    s = d.sym
    dT_dq = ca.gradient(d.kinetic, s.q)
    rest = -dT_dq + d.gravity + ad_dynamics._friction(d.desc, s)
    tau = ca.jtimes(d.momentum, ca.vertcat(s.q, s.qd), ca.vertcat(s.qd, s.qdd)) + rest
    return tau, ca.jtimes(d.momentum, s.q, s.qd) + rest


@pytest.mark.parametrize(
    "source", sorted(ROBOTS_DIR.glob("*.toml")) + EXTRA + ["branched_geared", "chain_20"],
    ids=lambda p: getattr(p, "stem", p))
def test_newton_euler_is_the_lagrangian(source, tmp_path):
    path = source if isinstance(source, Path) else _written(tmp_path, source)
    desc = description.load(path)
    d = ad_dynamics.derive(desc)
    s = d.sym
    tau, h = _lagrangian(d)
    ins = [s.q, s.qd, s.qdd, s.p]
    both = ca.Function("both", ins, [d.inverse_dynamics, tau, d.bias, h])
    rng = np.random.default_rng(12)
    n, n_p = s.q.shape[0], len(desc.parameters())
    for _ in range(5):
        q, qd, qdd = (rng.uniform(-3, 3, n) for _ in range(3))
        ne, lag, ne_h, lag_h = (np.array(v).ravel() for v in both(q, qd, qdd,
                                                                   rng.uniform(0.2, 3, n_p)))
        assert np.max(np.abs(ne - lag)) <= 1e-12 * np.max(np.abs(lag)), path.stem
        assert np.max(np.abs(ne_h - lag_h)) <= 1e-12 * np.max(np.abs(lag_h)), path.stem


@pytest.mark.parametrize("n", [6, 20])
def test_half_the_operations(n, tmp_path):
    d = ad_dynamics.derive(description.load(write_chain(n, tmp_path)))
    s = d.sym
    tau, _ = _lagrangian(d)
    ins = [s.q, s.qd, s.qdd, s.p]
    ne, lag = (Generated("inverse_dynamics", ca.Function("f", ins, [e], {"cse": True}), "")
               for e in (d.inverse_dynamics, tau))
    assert ne.operations < 0.55 * lag.operations, (ne.operations, lag.operations)
