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
    #: (bodies, 3): every body's cg acceleration x, y (m/s^2) and angular acceleration (rad/s^2),
    #: exact: J qdd + (J qd)_q qd of the cg position and the frame angle
    body_accelerations: sp.Matrix
    #: (bodies, 2): every body's cg position (m)
    cg_positions: sp.Matrix
    #: (joints + cuts + prismatic joints, 2): where every joint's child point is (tree joints,
    #: then cuts; m), then every cut's parent point (m), then every prismatic joint's slide
    #: axis in world axes (a unit vector)
    joint_points: sp.Matrix


def build(desc: Description) -> Model:
    s = make_symbols(desc)
    fr = kinematics.frames(desc, s)
    lag = lagrange.derive(desc, s, fr)
    con = constraints.derive(desc, s, fr)
    x = kinematics.task(desc, s, fr).applyfunc(sp.expand)
    qd = sp.Matrix(s.qd)
    if x.shape[0]:
        jac = x.jacobian(s.q).applyfunc(sp.expand)
        jdot_qd = ((jac * qd).jacobian(s.q) * qd).applyfunc(sp.expand)
    else:  # no [task]: no tool point
        jac, jdot_qd = sp.zeros(0, len(s.q)), sp.zeros(0, 1)
    names = tuple(b for b in desc.bodies if b != GROUND)
    rows = []
    for b in names:
        o = fr[b].origin.position()
        rows.append([sp.expand(o[0]), sp.expand(o[1]), fr[b].angle])
    cgs = [fr[b].point(kinematics.body_vec(desc, s, b, None)).position() for b in names]
    return Model(desc, s, lag, con, x, jac, jdot_qd, sp.Matrix(rows), names,
                 _accelerations(s, fr, names, cgs),
                 sp.Matrix([[sp.expand(c[0]), sp.expand(c[1])] for c in cgs]),
                 _joint_points(desc, s, fr))


def _joint_points(desc: Description, s, fr) -> sp.Matrix:
    """Where the joint loads act, beside the accelerations what Newton-Euler needs: every joint's
    child point (tree joints, then cuts), every cut's parent point (m), every prismatic joint's
    slide axis turned into world axes."""
    def at(body: str, point: str) -> list[sp.Expr]:
        r = fr[body].point(kinematics.body_vec(desc, s, body, point)).position()
        return [sp.expand(r[0]), sp.expand(r[1])]

    joints = (*desc.tree_joints, *desc.loop_joints)
    rows = [at(j.child, j.child_point) for j in joints]
    rows += [at(j.parent, j.parent_point) for j in desc.loop_joints]
    for j in desc.tree_joints:
        if j.type == "prismatic":
            th = fr[j.parent].angle
            ux, uy = (sp.Integer(int(c)) if c in (0.0, 1.0, -1.0) else sp.Float(c)
                      for c in j.axis)
            rows.append([ux * sp.cos(th) - uy * sp.sin(th), ux * sp.sin(th) + uy * sp.cos(th)])
    return sp.Matrix(rows)


def _accelerations(s, fr, names, cgs) -> sp.Matrix:
    """Each body's cg acceleration and angular acceleration, ``d/dt (J qd) = J qdd + (J qd)_q qd``
    with ``J`` the Jacobian of (cg x, cg y, frame angle): the inputs of Newton-Euler."""
    q, qd, qdd = sp.Matrix(s.q), sp.Matrix(s.qd), sp.Matrix(s.qdd)
    rows = []
    for b, cg in zip(names, cgs):
        pose = cg.col_join(sp.Matrix([fr[b].angle]))
        jac = pose.jacobian(q)
        acc = jac * qdd + (jac * qd).jacobian(q) * qd
        rows.append([sp.expand(a) for a in acc])
    return sp.Matrix(rows)
