"""The symbolic model of one robot: symbols, frames, Lagrangian, constraints, task kinematics."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.model.description import GROUND, Description

from . import constraints, kinematics, lagrange
from .symbols import Symbols, make_symbols


@dataclass(frozen=True)
class Model:
    desc: Description
    sym: Symbols
    lagrangian: lagrange.Lagrangian
    constraints: constraints.Constraints
    task: sp.Matrix  # task coordinates x(q)
    task_jacobian: sp.Matrix  # J = dx/dq
    task_jdot_qd: sp.Matrix  # Jdot qd = (J qd)_q qd
    frames: sp.Matrix  # (bodies, 3): origin x, origin y, angle of every body but ground
    body_names: tuple[str, ...]


def build(desc: Description) -> Model:
    s = make_symbols(desc)
    fr = kinematics.frames(desc, s)
    lag = lagrange.derive(desc, s, fr)
    con = constraints.derive(desc, s, fr)
    x = kinematics.task(desc, s, fr).applyfunc(sp.expand)
    jac = x.jacobian(s.q).applyfunc(sp.expand)
    qd = sp.Matrix(s.qd)
    jdot_qd = ((jac * qd).jacobian(s.q) * qd).applyfunc(sp.expand)
    names = tuple(b for b in desc.bodies if b != GROUND)
    rows = []
    for b in names:
        o = fr[b].origin.position()
        rows.append([sp.expand(o[0]), sp.expand(o[1]), fr[b].angle])
    return Model(desc, s, lag, con, x, jac, jdot_qd, sp.Matrix(rows), names)
