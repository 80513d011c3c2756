"""The loop-closure Jacobian's inverse block by block (``derive/block_triangular.py``), as the
closed-chain inverse dynamics uses it: on every closed robot (built-in, test robot, example:
one loop, the 3-RRR's three coupled loops, the Watt six-bar's two and Jansen's leg's three), at
random states with random positive parameters, ``A A^-1 = A^-1 A = I`` to 1e-12 relative to
``|A| |A^-1|``, with ``A = Phi_p^T`` the matrix the runtime inverts; never more operations than
the whole inverse, and on Jansen's leg (block lower triangular, three 2 x 2 blocks) under a fifth;
a one-block matrix is inverted whole, so the one-loop robots' code is what it was.
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from conftest import ROBOTS_DIR

from derive import ad_dynamics, block_triangular
from derive.quantities import Generated
from planar_sym.model import description

ROOT = Path(__file__).resolve().parent.parent
PATHS = [p for folder in (ROBOTS_DIR, ROOT / "tests" / "robots", ROOT / "examples")
         for p in sorted(folder.glob("*.toml"))
         if "[[bodies]]" in p.read_text() and "closes_loop = true" in p.read_text()]


def _operations(fn: ca.Function) -> int:
    return Generated("x", fn, "").operations


@pytest.mark.parametrize("path", PATHS, ids=lambda p: p.stem)
def test_the_block_inverse_inverts(path):
    desc = description.load(path)
    qs = ad_dynamics.quantities(desc)
    s = qs.sym
    passive = [i for i in range(s.q.shape[0]) if i not in desc.actuated]
    a = qs.phi_q[:, passive].T
    inv = block_triangular.inverse(a)
    both = ca.Function("both", [s.q, s.p], [a, inv], {"cse": True})
    whole = ca.Function("whole", [s.q, s.p], [ca.inv(a)], {"cse": True})
    blocks = ca.Function("blocks", [s.q, s.p], [inv], {"cse": True})
    assert _operations(blocks) <= _operations(whole)
    if a.sparsity().btf()[0] == 1:
        assert _operations(blocks) == _operations(whole)
    if path.stem == "jansen_linkage":
        assert _operations(blocks) < _operations(whole) / 5
    rng = np.random.default_rng(4)
    n, eye = len(passive), np.eye(len(passive))
    for _ in range(5):
        q, p = rng.uniform(-np.pi, np.pi, s.q.shape[0]), rng.uniform(0.2, 3, len(desc.parameters()))
        m, x = (np.array(v) for v in both(q, p))
        scale = np.max(np.abs(m)) * np.max(np.abs(x)) * n
        assert np.max(np.abs(m @ x - eye)) <= 1e-12 * scale, path.stem
        assert np.max(np.abs(x @ m - eye)) <= 1e-12 * scale, path.stem
