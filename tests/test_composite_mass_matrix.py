"""The numeric route's mass matrix by composite bodies (``derive/composite.py``) against the
momentum's Jacobian ``dp/dqd`` of the same recursive kinematics (what it replaced), on every
built-in robot, test robot and example (sliders, welds, rotors on moving links, friction, several
loops) and a 12-link chain, at random states with random positive parameters (so a rotor's
inertia, gear ratio and every mass count), to 1e-13 relative; and the reason for it: at 20
links it takes 27 % of the operations (34 % before distances within a body became parameter
sums and the revolute entries ``B_k - P_i . h_k``; a revert fails the bound).
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from conftest import ALL_ROBOTS, ROBOTS_DIR

from benchmarks.chains import write_chain
from derive import ad_dynamics
from derive.composite import mass_matrix
from planar_sym.model import description

ROOT = Path(__file__).resolve().parent.parent
EXTRA = sorted((ROOT / "tests" / "robots").glob("*.toml")) + sorted(
    p for p in (ROOT / "examples").glob("*.toml") if "[[bodies]]" in p.read_text())


def _pair(desc):
    """(composite M, dp/dqd) as CasADi functions of q and p."""
    d = ad_dynamics.derive(desc)
    s = d.sym
    by_momentum = ca.jacobian(d.momentum, s.qd)
    return (ca.Function("composite", [s.q, s.p], [mass_matrix(desc, d.tree)]),
            ca.Function("momentum", [s.q, s.p], [by_momentum]))


@pytest.mark.parametrize("path", [ROBOTS_DIR / f"{r}.toml" for r in ALL_ROBOTS] + EXTRA,
                         ids=lambda p: p.stem)
def test_composite_bodies_give_the_momentums_jacobian(path):
    desc = description.load(path)
    composite, momentum = _pair(desc)
    rng = np.random.default_rng(7)
    n, n_p = len(desc.coordinates), len(desc.parameters())
    for _ in range(6):
        q, p = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.2, 3.0, n_p)
        a, b = np.array(composite(q, p)), np.array(momentum(q, p))
        assert np.max(np.abs(a - b)) <= 1e-13 * np.max(np.abs(b)), (path.stem, a, b)
        assert np.array_equal(a, a.T)


def test_a_long_chain_agrees_and_costs_under_a_third(tmp_path):
    for n, most in ((12, 0.35), (20, 0.3)):
        desc = description.load(write_chain(n, tmp_path))
        composite, momentum = _pair(desc)
        rng = np.random.default_rng(n)
        q, p = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.2, 3.0, len(desc.parameters()))
        a, b = np.array(composite(q, p)), np.array(momentum(q, p))
        assert np.max(np.abs(a - b)) <= 1e-13 * np.max(np.abs(b))
        assert composite.n_instructions() < most * momentum.n_instructions(), n
