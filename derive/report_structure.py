"""The equation report of a robot too big for expanded closed forms: the structure instead.

Past ``size.py``'s limits the expanded equations run to pages of trigonometry (182 kB for an
8-link chain) and the numbers come from algorithmic differentiation of the energies of a
recursive kinematics (``recursion.py``, ``ad_dynamics.py``). This report prints what that code
computes, in the look of the closed-form report (``report_format``: text headings ending in
``:``, ``  label = rhs`` lines in SymPy syntax, a complete LaTeX document, Markdown with
``$$`` blocks):

- why the structure and how to get the closed forms anyway;
- the kinematic recursion body by body, parents first, with named intermediate terms
  (``theta_B``, frame origin ``xo_B, yo_B``, joint point ``xj_J, yj_J``, prismatic travel
  ``s_J``, centre of gravity ``xc_B, yc_B``), mirroring ``recursion.walk``;
- the energies as sums over the bodies, the Lagrange equations and how each is evaluated;
- for closed chains the loop closure, its Jacobian and gamma;
- the generated functions with their operation counts and routes, and the symbol table.

Every right-hand side of the recursion is a SymPy expression in the names printed before it, so
``sympify`` evaluates the printed text line by line (``tests/test_report_structure.py`` does, and
checks the tool point against a plain forward kinematics). Its size grows linearly with the
number of bodies: under 1 kB of text per link, 12 kB at 10 links (the expanded closed forms:
182 kB at 8).
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import sympy as sp

from planar_sym.model.description import COULOMB_SMOOTHING, GROUND, Description, builtin_robots

from . import size
from .report import _table
from .report_parts import Rich, m
from .structure_doc import Block, Code, Eq, Part, Structure
from .structure_print import latex, markdown, num, text
from .structure_walk import Names, Walk, exact, nonzero, tex_name, walk

ROOT = Path(__file__).resolve().parents[1]


def render(desc: Description, operations: dict[str, tuple[int, str]]) -> dict[str, str]:
    """{'text': ..., 'latex': ..., 'markdown': ...}: the structure report of one robot.

    ``operations`` maps each generated function's quantity to (operations per sample, route).
    """
    st = build(desc, operations)
    return {"text": text(st), "latex": latex(st), "markdown": markdown(st)}


# -- what the report says ---------------------------------------------------------------------


def _gravity_unit(desc: Description) -> tuple[sp.Expr, sp.Expr]:
    gx, gy = desc.gravity_m_s2
    norm = math.hypot(gx, gy)
    if norm == 0:
        return sp.S.Zero, sp.S.Zero
    return tuple(exact(c / norm) if c in (0.0, norm, -norm) else sp.Float(c / norm, 10)
                 for c in (gx, gy))  # type: ignore[return-value]


def _moving(desc: Description):
    return [j for j in desc.tree_joints if j.moves]


def _energy(desc: Description, nm: Names, wk: Walk) -> Part:
    half = sp.Rational(1, 2)
    kinetic, potential, has_izz = [], [], False
    ux, uy = _gravity_unit(desc)
    g = nm.param("g")
    for b in desc.bodies:
        if b == GROUND:
            continue
        tb = tex_name(b)
        vx = nm.new(f"vx_{b}", rf"v_{{x,{tb}}}")
        vy = nm.new(f"vy_{b}", rf"v_{{y,{tb}}}")
        mass, izz = nm.param(f"m_{b}"), nm.param(f"izz_{b}")
        kinetic.append(half * mass * (vx**2 + vy**2))
        w = wk.w[b]
        if izz != 0 and w != 0:
            kinetic.append(half * izz * w**2)
            has_izz = True
        xc, yc = wk.cg[b]
        potential += nonzero([-ux * g * mass * xc, -uy * g * mass * yc])
    rotors = []
    for k, j in enumerate(_moving(desc)):
        jm = nm.param(f"jm_{j.name}")
        if j.actuator is None or jm == 0:
            continue
        rotors.append(half * jm * (wk.w[j.parent] + nm.param(f"gear_{j.name}", 1.0)
                                   * nm.qd[k])**2)
    kinetic += rotors
    part = Part(("Kinetic and potential energy, Lagrangian",), blocks=[Block(None, [
        Eq(m("T"), kinetic), Eq(m("V"), potential), Eq(m("L"), m("T - V"))])])
    u = f"({num(ux)}, {num(uy)})"
    note: list = [m("T = 1/2 sum_b (m_b |v_b|^2 + Izz_b w_b^2)",
                    r"T = \tfrac12 \sum_b (m_b |v_b|^2 + I_{zz,b}\, \omega_b^2)")]
    if rotors:
        note += [" plus the rotors' ", m("1/2 J_m (w_parent + N qd_k)^2",
                                         r"\tfrac12 J_m (\omega_\mathrm{parent} + N \dot q_k)^2"),
                 " (stator on the joint's parent body, exact: not only the reflected ",
                 m("N^2 J_m"), ")"]
    note += [" and ", m("V = -sum_b m_b g (u . r_b)", r"V = -\sum_b m_b g\, (u \cdot r_b)"),
             f" over the bodies b, with u = {u} the direction of gravity and ",
             m("r_b = (xc_b, yc_b)", r"r_b = (x_{c,b}, y_{c,b})"), "."]
    if not has_izz:
        note.append(" No body has a rotational inertia here (point masses).")
    rate_eg: list = []
    for i, r in enumerate(wk.rates):
        rate_eg += [", " if i else "", m(*r)]
    part.notes = [tuple(note), (
        m("vx_b, vy_b", r"v_{x,b}, v_{y,b}"), ", ", m("w_b", r"\omega_b"),
        (": the velocity of the centre of gravity and the angular velocity of body b, i.e. "
         "the time derivatives of "), m("xc_b, yc_b, theta_b", r"x_{c,b}, y_{c,b}, \theta_b"),
        ": the recursion above differentiated line by line along ", m("qd", r"\dot q"),
        " (forward mode), e.g. ", *rate_eg,
        ". Nothing is expanded: each body's velocity reuses its parent's.")]
    return part


def _dynamics(desc: Description, nm: Names, friction: bool) -> Part:
    closed = bool(desc.loop_joints)
    q_rhs = (m("S^T tau + Phi_q^T lambda", r"S^\top \tau + \Phi_q^\top \lambda") if closed
             else m("tau", r"\tau"))
    d_text, d_tex = (" + D(qd)", r" + D(\dot q)") if friction else ("", "")
    eqs = [
        Eq(m("p"), m("dT/dqd", r"\partial T/\partial \dot q")),
        Eq(m("M(q)"), m("dp/dqd = d2T/dqd2",
                        r"\partial p/\partial \dot q = \partial^2 T/\partial \dot q^2")),
        Eq(m("h(q, qd)", r"h(q, \dot q)"),
           m("(dp/dq) qd - dT/dq + dV/dq" + d_text,
             r"\frac{\partial p}{\partial q} \dot q - \frac{\partial T}{\partial q}"
             r" + \frac{\partial V}{\partial q}" + d_tex)),
        Eq(m("g(q)"), m("dV/dq", r"\partial V/\partial q")),
        Eq(q_rhs, m("M(q) qdd + h(q, qd)", r"M(q) \ddot q + h(q, \dot q)")),
    ]
    if not closed:
        eqs.append(Eq(m("qdd", r"\ddot q"), m("M(q)^-1 (tau - h(q, qd))",
                                                r"M(q)^{-1} (\tau - h(q, \dot q))")))
    part = Part(("Equations of motion (Lagrange) ",
                 m("M(q) qdd + h(q, qd) = " + q_rhs[0],
                   r"M(q) \ddot q + h(q, \dot q) = " + q_rhs[1])),
                blocks=[Block(None, eqs)])
    slides = "m" in desc.coordinate_units
    part.notes.append((
        "Here ", m("d/dt dL/dqd - dL/dq = Q",
                   r"\frac{d}{dt}\frac{\partial L}{\partial \dot q} - "
                   r"\frac{\partial L}{\partial q} = Q"),
        " with ", m("dT/dqd = p", r"\partial T/\partial \dot q = p"), " and ",
        m("d/dt p = (dp/dq) qd + (dp/dqd) qdd",
          r"\frac{d}{dt} p = \frac{\partial p}{\partial q} \dot q + "
          r"\frac{\partial p}{\partial \dot q} \ddot q"),
        "; ", m("h", "h"), " is the left-hand side at ", m("qdd = 0", r"\ddot q = 0"),
        (" (Coriolis, centrifugal and gravity terms" + (", friction" if friction else "")
         + "). " + ("tau holds torques (N*m) for revolute and forces (N) for prismatic "
                    "coordinates." if slides else "")),))
    part.notes.append((
        ("How each is evaluated (CasADi, derive/ad_dynamics.py): T and V once through the "
         "recursion above, O(n) operations for n coordinates; the velocities by forward mode "
         "(one sweep along "), m("qd", r"\dot q"), "); ",
        m("p = dT/dqd", r"p = \partial T/\partial \dot q"), " and ",
        m("dT/dq", r"\partial T/\partial q"), " by reverse mode (one gradient sweep); ",
        m("d/dt p", r"\tfrac{d}{dt} p"), " along ", m("(qd, qdd)", r"(\dot q, \ddot q)"),
        (" would take one forward sweep over that reverse sweep (forward over reverse); the "
         "code computes the same torques by Newton-Euler over the recursion's frames instead "
         "(derive/newton_euler.py: each body's angular and point accelerations from the "
         "ground out, then forces and moments from the leaves in, rotors and friction "
         "included; O(n) operations, half those of the sweeps); "),
        m("M = dp/dqd", r"M = \partial p/\partial \dot q"), ", the Hessian of T in ",
        m("qd", r"\dot q"), (", is summed by composite bodies instead (derive/composite.py: "
                              "each joint's subtree once, O(n) sums, then one dot product "
                              "an entry, O(n^2); about a third of the operations of n "
                              "sweeps).")
        + ("" if closed else " The forward dynamics solves M qdd = tau - h by L D L^T "
           "(O(n^3), small for a few links) or, where it takes fewer operations (from about "
           "four links), by the articulated-body recursion (derive/articulated.py, O(n)), "
           "as the manifest's route says.")))
    return part


def _friction(desc: Description, nm: Names) -> Part | None:
    eqs = []
    for k, j in enumerate(_moving(desc)):
        terms = nonzero([nm.param(f"fv_{j.name}") * nm.qd[k]])
        fc = nm.param(f"fc_{j.name}")
        if fc != 0:
            vs = nm.param(f"vs_{j.name}", COULOMB_SMOOTHING)
            terms.append(fc * sp.tanh(nm.qd[k] / vs))
        if terms:
            eqs.append(Eq(m(f"D{k + 1}", f"D_{{{k + 1}}}"), terms))
    if not eqs:
        return None
    return Part(("Actuator friction ", m("D(qd)", r"D(\dot q)"),
                 (" (joint side: viscous b qd + Coulomb c tanh(qd / v_s), smoothed over "
                  "v_s; rows not shown are zero)")), blocks=[Block(None, eqs)])


def _closure(desc: Description, nm: Names, wk: Walk) -> list[Part]:
    def at(body: str, point: str):
        v = (nm.param(f"px_{body}_{point}"), nm.param(f"py_{body}_{point}"))
        return wk.frames[body].point(v)

    phi = Part(("Loop closure ", m("Phi(q) = 0", r"\Phi(q) = 0"),
                " (m): parent point minus child point at each cut joint, x then y"))
    for c, j in enumerate(desc.loop_joints):
        a, b = 2 * c + 1, 2 * c + 2
        (px, py), (cx, cy) = at(j.parent, j.parent_point), at(j.child, j.child_point)
        phi.blocks.append(Block(
            (m(f"Phi{a}, Phi{b}", rf"\Phi_{{{a}}}, \Phi_{{{b}}}"),
             (f": cut joint {j.name} ({j.type}), point {j.parent_point} of {j.parent} "
              f"minus point {j.child_point} of {j.child}")),
            [Eq(m(f"Phi{a}", rf"\Phi_{{{a}}}"), nonzero([*px, *(-t for t in cx)])),
             Eq(m(f"Phi{b}", rf"\Phi_{{{b}}}"), nonzero([*py, *(-t for t in cy)]))]))
    derived = Part(("Constraint Jacobian, acceleration term and multipliers",), blocks=[
        Block(None, [
            Eq(m("Phi_q"), m("dPhi/dq", r"\partial \Phi/\partial q")),
            Eq(m("gamma", r"\gamma"), m("-(Phi_q qd)_q qd", r"-(\Phi_q \dot q)_q \dot q")),
            Eq(m("M(q) qdd + h(q, qd)", r"M(q) \ddot q + h(q, \dot q)"),
               m("S^T tau + Phi_q^T lambda", r"S^\top \tau + \Phi_q^\top \lambda")),
            Eq(m("Phi_q qdd", r"\Phi_q \ddot q"), m("gamma", r"\gamma"))])])
    act = ", ".join(nm.q[i].name for i in desc.actuated)
    derived.notes.append((
        m("Phi_q", r"\Phi_q"),
        " is the Jacobian of the lines above (algorithmic differentiation, nothing expanded); ",
        m("gamma", r"\gamma"), " is two forward sweeps along ", m("qd", r"\dot q"), ", so that ",
        m("Phi_q qdd = gamma", r"\Phi_q \ddot q = \gamma"), " keeps the loops closed. ",
        m("S^T tau", r"S^\top \tau"),
        (f" has the actuated coordinates' torques (actuated: {act}) and zeros in the rows of "
         "the passive ones.")))
    for c, j in enumerate(desc.loop_joints):
        a, b = 2 * c + 1, 2 * c + 2
        derived.notes.append((
            m(f"lambda{a}, lambda{b}", rf"\lambda_{{{a}}}, \lambda_{{{b}}}"),
            (f" (N, world x and y): the force that body {j.child} (child of cut joint {j.name}) "
             f"exerts on body {j.parent} (its parent); {j.child} feels the opposite. This "
             "follows from "), m("Phi = r(parent point) - r(child point)",
                                 r"\Phi = r_\mathrm{parent} - r_\mathrm{child}"), "."))
    return [phi, derived]


def _command(desc: Description) -> str:
    """The command that derives this robot with its closed forms: ``make derive``'s for a
    built-in robot, ``planar-sym derive`` (which works from an install) for a user's file."""
    if desc.name in builtin_robots():
        return f"python -m derive {desc.name} --equations closed"
    try:
        path = desc.path.resolve().relative_to(ROOT).as_posix()
    except ValueError:
        path = desc.path.name
    return f"planar-sym derive {path} --out DIR --equations closed"


def _preamble(desc: Description, nm: Names) -> list[Rich]:
    coords = ", ".join(f"{nm.q[i].name} = {c}" for i, c in enumerate(desc.coordinates))
    act = ", ".join(nm.q[i].name for i in desc.actuated)
    units = "rad" if "m" not in desc.coordinate_units else "rad; d: m"
    sz = size.measure(desc)
    cmd = Code(_command(desc))
    how = ("The generated code computes the numbers from this structure: the kinematics as a "
           "recursion over the bodies (each body's angle and position from its parent's, "
           "computed once and shared by every body beyond it), the kinetic and potential "
           "energies summed over the bodies, and the equations of motion by algorithmic "
           "differentiation of those energies in CasADi, with nothing expanded. ")
    head = f"{desc.name}: the structure of its equations of motion, not the expanded closed forms"
    if sz.closed_forms_fit:
        why = (head + "; they would fit for this robot, and ", cmd, " prints them. " + how)
    else:
        why = (head + ". Why: " + sz.reason() + ". " + how + "To get the expanded closed forms "
               "anyway (long, and slow to derive at this size): ", cmd, ".")
    return [why, (f"Coordinates ({units}): {coords}; actuated: {act}.",),
            ("Notation: ", m("qd, qdd", r"\dot q, \ddot q"),
             (": rates and accelerations of the coordinates; parameters by the names in the "
              "symbol table below; the intermediate terms of the recursion are named in its "
              "section."))]


def _recursion_part(desc: Description, wk: Walk) -> Part:
    types = {j.type for j in desc.tree_joints}
    part = Part(("Kinematic recursion (body by body, parents first)",), blocks=wk.blocks)
    part.intro.append((
        "Each body's frame from its parent's (the ground: angle 0, origin 0), with ",
        m("R(theta)", r"R(\theta)"), " the rotation by theta. Revolute joint k: ",
        m("theta_B = theta_P + q_k", r"\theta_B = \theta_P + q_k"), ", joint point ",
        m("r_J = o_P + R(theta_P) p", r"r_J = o_P + R(\theta_P)\, p"), ", origin ",
        m("o_B = r_J - R(theta_B) c", r"o_B = r_J - R(\theta_B)\, c"),
        ", centre of gravity ", m("r_B = o_B + R(theta_B) (cgx_B, cgy_B)",
                                  r"r_B = o_B + R(\theta_B)\, (cgx_{B}, cgy_{B})"),
        (", with p and c the joint's point in the parent's and in the child's body frame "
         "(zero where the description makes it so; the origin is then the joint point).")))
    extra: list = []
    if "prismatic" in types:
        extra += [("Prismatic joint k: the child frame is the parent's turned by the "
                   "constant drawn angle, and the joint point slides along the axis u (parent "
                   "frame) by "),
                  m("s_J = s0_J + d_k", r"s_J = s_{0,J} + d_k"), ": ",
                  m("r_J = o_P + R(theta_P) (p + u s_J)",
                    r"r_J = o_P + R(\theta_P) (p + u\, s_J)"), ". "]
    if "weld" in types:
        extra += ["Weld: the parent's frame turned by the constant drawn angle (rad). "]
    if extra:
        extra.append("Where that angle is not zero, the code takes the cosine and sine from the "
                     "parent's by the addition theorem (no new trigonometric call).")
        part.intro.append(tuple(extra))
    part.intro.append((
        "Names: ", m("theta_B", r"\theta_B"), " absolute angle of body B (rad); ",
        m("xo_B, yo_B", r"x_{o,B}, y_{o,B}"), " origin of its frame; ",
        m("xj_J, yj_J", r"x_{j,J}, y_{j,J}"), " the point of joint J; ",
        m("xc_B, yc_B", r"x_{c,B}, y_{c,B}"),
        (" its centre of gravity (m, world axes). The cosine and sine of each angle are "
         "computed once and shared; a term printed as 0 is left out where it is used.")))
    return part


def build(desc: Description, operations: dict[str, tuple[int, str]]) -> Structure:
    nm = Names(desc)
    wk = walk(desc, nm)
    parts = [_recursion_part(desc, wk), _energy(desc, nm, wk)]
    friction = _friction(desc, nm)
    parts.append(_dynamics(desc, nm, friction is not None))
    if friction is not None:
        parts.append(friction)
    if desc.loop_joints:
        parts += _closure(desc, nm, wk)
    functions = [(q, int(ops), route) for q, (ops, route) in operations.items()]
    return Structure(desc.name, desc.title, _preamble(desc, nm), parts, functions,
                     _table(SimpleNamespace(desc=desc)), nm.latex)


# -- printing ---------------------------------------------------------------------------------
