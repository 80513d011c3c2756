"""The expanded SymPy closed forms as CasADi SX: one of the two routes ``codegen`` chooses from.

The same expressions the equation report prints, translated term by term (``to_casadi.py``).
For small robots they are often the cheaper code: the terms are collected by parameter, so
``m2 l1 lc2 cos(q2)`` costs a few products where differentiating the energies costs sweeps.
"""

from __future__ import annotations

import casadi as ca
import sympy as sp

from .model import Model
from .quantities import CLOSED, Quantities
from .recursion import Symbols
from .to_casadi import Translator


def quantities(model: Model, sym: Symbols) -> Quantities:
    """The SymPy model's expressions in ``sym``'s CasADi inputs."""
    s, lag, con = model.sym, model.lagrangian, model.constraints
    mapping = {a: var[i] for syms, var in ((s.q, sym.q), (s.qd, sym.qd), (s.qdd, sym.qdd),
                                           (s.tau, sym.tau), (s.p, sym.p))
               for i, a in enumerate(syms)}
    tr = Translator(mapping)
    M, h = tr.matrix(lag.mass_matrix), tr.matrix(lag.bias)
    return Quantities(
        CLOSED, model.desc, sym, M, h, tr.matrix(lag.gravity), ca.mtimes(M, sym.qdd) + h,
        tr(lag.kinetic), tr(lag.potential), tr.matrix(model.frames),
        tr.matrix(model.body_accelerations.T), tr.matrix(model.cg_positions.T),
        tr.matrix(model.joint_points.T), tr.matrix(model.task), tr.matrix(model.task_jacobian),
        tr.matrix(model.task_jdot_qd), tr.matrix(con.phi),
        tr.matrix(con.jacobian if con.count else sp.zeros(0, len(s.q))),
        tr.matrix(con.accel_bias))
