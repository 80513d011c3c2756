"""Closed-chain part of the report: Phi(q), Phi_q, gamma and the multiplier equation.

The sign convention is the one of planar_sym/dynamics/inverse.py, stated per cut joint: with
Phi = r(parent point) - r(child point), lambda is the force the cut joint's child body exerts on
its parent body (N, world x and y); the child feels -lambda.
"""

from __future__ import annotations

from .model import Model
from .notation import Notation
from .report_parts import Eq, Section, m


def sections(model: Model, nt: Notation) -> list[Section]:
    desc, con, s = model.desc, model.constraints, model.sym
    n, k = len(s.q), con.count
    trig, rate = nt.is_kind("trig"), nt.is_kind("rate")
    phi = Section(("Loop closure ", m("Phi(q) = 0", r"\Phi(q) = 0"),
                   " (m): parent point minus child point at each cut joint, x then y"))
    phi.eqs = [Eq(m(f"Phi{i + 1}", rf"\Phi_{{{i + 1}}}"),
                  nt.grouped(nt.compact(con.phi[i]), trig)) for i in range(k)]
    for c, j in enumerate(desc.loop_joints):
        a, b = 2 * c + 1, 2 * c + 2
        phi.notes.append((m(f"Phi{a}, Phi{b}", rf"\Phi_{{{a}}}, \Phi_{{{b}}}"),
                          (f": cut joint {j.name}, point {j.parent_point} of {j.parent} minus "
                           f"point {j.child_point} of {j.child}.")))
    jac = Section(("Constraint Jacobian ",
                   m("Phi_q = dPhi/dq", r"\Phi_q = \partial \Phi/\partial q"),
                   " (entries not shown are zero)"))
    jac.eqs = [Eq(m(f"Phi_q[{i + 1},{j + 1}]", rf"(\Phi_q)_{{{i + 1},{j + 1}}}"),
                  nt.grouped(nt.compact(con.jacobian[i, j]), trig))
               for i in range(k) for j in range(n) if con.jacobian[i, j] != 0]
    gam = Section(("Acceleration term ",
                   m("gamma = -(Phi_q qd)_q qd", r"\gamma = -(\Phi_q \dot q)_q \dot q"),
                   ", so that ", m("Phi_q qdd = gamma", r"\Phi_q \ddot q = \gamma")))
    gam.eqs = [Eq(m(f"gamma{i + 1}", rf"\gamma_{{{i + 1}}}"),
                  nt.grouped(nt.compact(con.accel_bias[i]), trig, rate)) for i in range(k)]
    return [phi, jac, gam, _multipliers(model)]


def _multipliers(model: Model) -> Section:
    desc = model.desc
    act = ", ".join(model.sym.q[i].name for i in desc.actuated)
    mult = Section(("Multiplier equation (loop reaction forces)",))
    # a LaTeX line break mid-line is eaten by GitHub's Markdown: each "\\" ends a source line
    mult.eqs = [
        Eq(m("M(q) qdd + C(q, qd) qd + g(q)", r"M(q) \ddot q + C(q, \dot q) \dot q + g(q)"),
           m("S^T tau + Phi_q^T lambda", r"S^\top \tau + \Phi_q^\top \lambda")),
        Eq(m("Phi_q qdd", r"\Phi_q \ddot q"), m("gamma", r"\gamma")),
        Eq(m("[M, -Phi_q^T; Phi_q, 0] [qdd; lambda]",
             "\\begin{bmatrix} M & -\\Phi_q^\\top \\\\\n\\Phi_q & 0 \\end{bmatrix}"
             "\\begin{bmatrix} \\ddot q \\\\\n\\lambda \\end{bmatrix}"),
           m("[S^T tau - C qd - g; gamma]",
             "\\begin{bmatrix} S^\\top \\tau - C \\dot q - g \\\\\n\\gamma \\end{bmatrix}")),
    ]
    mult.notes.append((
        m("S^T tau", r"S^\top \tau"), " has the torque ", m("tau_i", r"\tau_i"),
        (f" of each actuated joint in row i (actuated: {act}) and zero in the rows of the "
         "passive joints; "),
        m("(Phi_q^T lambda)_i = sum_k (Phi_q)_ki lambda_k",
          r"(\Phi_q^\top\lambda)_i = \sum_k (\Phi_q)_{ki}\lambda_k"), "."))
    for c, j in enumerate(desc.loop_joints):
        a, b = 2 * c + 1, 2 * c + 2
        mult.notes.append((
            m(f"lambda{a}, lambda{b}", rf"\lambda_{{{a}}}, \lambda_{{{b}}}"),
            (f" (N, world x and y): the force that body {j.child} (child of cut joint {j.name}) "
             f"exerts on body {j.parent} (its parent); {j.child} feels "),
            m(f"-(lambda{a}, lambda{b})", rf"-(\lambda_{{{a}}}, \lambda_{{{b}}})"),
            ". This follows from ",
            m("Phi = r(parent point) - r(child point)",
              r"\Phi = r_\mathrm{parent} - r_\mathrm{child}"), "."))
    return mult
