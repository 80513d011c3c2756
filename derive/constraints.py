"""Loop-closure equations of the cut joints and their derivatives.

.. code:: text

    Phi(q) = r_parent_point(q) - r_child_point(q) = 0      (2 rows per cut joint, m)
    Phi_q(q) qd = 0,    Phi_q(q) qdd = gamma(q, qd) = -(Phi_q qd)_q qd
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.model.description import Description

from .kinematics import Frame, body_vec
from .symbols import Symbols


@dataclass(frozen=True)
class Constraints:
    phi: sp.Matrix  # (2 * loops, 1)
    jacobian: sp.Matrix  # (2 * loops, n)
    accel_bias: sp.Matrix  # gamma = -(Phi_q qd)_q qd

    @property
    def count(self) -> int:
        return self.phi.shape[0]


def derive(desc: Description, s: Symbols, fr: dict[str, Frame]) -> Constraints:
    n = len(s.q)
    rows: list[sp.Expr] = []
    for j in desc.loop_joints:
        a = fr[j.parent].point(body_vec(desc, s, j.parent, j.parent_point)).position()
        b = fr[j.child].point(body_vec(desc, s, j.child, j.child_point)).position()
        rows += [sp.expand(a[0] - b[0]), sp.expand(a[1] - b[1])]
    phi = sp.Matrix(rows) if rows else sp.zeros(0, 1)
    jac = phi.jacobian(s.q) if rows else sp.zeros(0, n)
    qd = sp.Matrix(s.qd)
    gamma = (-(jac * qd).jacobian(s.q) * qd).applyfunc(sp.expand) if rows else sp.zeros(0, 1)
    return Constraints(phi, jac, gamma)
