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
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import sympy as sp

from planar_sym.errors import DescriptionError
from planar_sym.model.description import COULOMB_SMOOTHING, GROUND, Description, builtin_robots

from . import report_format as fmt
from . import size
from .report import _table
from .report_parts import Rich, m
from .symbols import make_symbols

ROOT = Path(__file__).resolve().parents[1]


class Code(str):
    """A command in running text: backticks in text and Markdown, ``\\texttt`` in LaTeX."""


class Strong(str):
    """A word to find the block by: plain in text, bold in LaTeX and Markdown."""


@dataclass
class Eq:
    lhs: tuple[str, str]  # (text, latex)
    rhs: list[sp.Expr] | tuple[str, str]  # SymPy terms in print order, or fixed math


@dataclass
class Block:
    """Equations under an optional caption (a comment line in text, a paragraph elsewhere)."""

    caption: Rich | None
    eqs: list[Eq]


@dataclass
class Part:
    title: Rich
    intro: list[Rich] = field(default_factory=list)
    blocks: list[Block] = field(default_factory=list)
    notes: list[Rich] = field(default_factory=list)


@dataclass
class Structure:
    name: str
    title: str
    preamble: list[Rich]
    parts: list[Part]
    functions: list[tuple[str, int, str]]  # (quantity, operations per sample, route)
    table: list[dict[str, str]]  # symbol table rows, as report._table gives them
    latex_names: dict[sp.Symbol, str]  # the coordinates' and intermediate terms' LaTeX


def render(desc: Description, operations: dict[str, tuple[int, str]]) -> dict[str, str]:
    """{'text': ..., 'latex': ..., 'markdown': ...}: the structure report of one robot.

    ``operations`` maps each generated function's quantity to (operations per sample, route).
    """
    st = build(desc, operations)
    return {"text": text(st), "latex": latex(st), "markdown": markdown(st)}


# -- what the report says ---------------------------------------------------------------------


@dataclass
class _Frame:
    angle: sp.Expr  # the symbol theta_B, or 0 for the ground
    origin: tuple[sp.Expr, sp.Expr]  # symbols (or 0)

    def rotate(self, v: tuple[sp.Expr, sp.Expr]) -> tuple[list[sp.Expr], list[sp.Expr]]:
        """R(angle) v as term lists (x, y), zero terms left out."""
        c, s = sp.cos(self.angle), sp.sin(self.angle)
        return (_nonzero([v[0] * c, -v[1] * s]), _nonzero([v[0] * s, v[1] * c]))

    def point(self, v: tuple[sp.Expr, sp.Expr]) -> tuple[list[sp.Expr], list[sp.Expr]]:
        x, y = self.rotate(v)
        return _nonzero([self.origin[0], *x]), _nonzero([self.origin[1], *y])


def _nonzero(terms: list[sp.Expr]) -> list[sp.Expr]:
    return [t for t in terms if t != 0]


class _Names:
    """Parameter symbols (display names, as the closed-form report prints them), coordinates,
    and the named intermediate terms with their LaTeX."""

    def __init__(self, desc: Description) -> None:
        s = make_symbols(desc)
        real = {"real": True}
        self.latex: dict[sp.Symbol, str] = {}
        self.params: dict[str, sp.Symbol] = {}
        for p in desc.parameters():
            self.params[p.name] = sp.Symbol(desc.display.get(p.name, p.name), **real)
        self.taken = {sym.name for sym in self.params.values()}
        self.q, self.qd, self.qdd = [], [], []
        for i, (q, qd, qdd) in enumerate(zip(s.q, s.qd, s.qdd), start=1):
            c = q.name[0]  # q, or d for a prismatic joint's displacement
            self.q.append(self._add(q.name, f"{c}_{{{i}}}"))
            self.qd.append(self._add(qd.name, rf"\dot{{{c}}}_{{{i}}}"))
            self.qdd.append(self._add(qdd.name, rf"\ddot{{{c}}}_{{{i}}}"))

    def param(self, name: str, default: float = 0.0) -> sp.Expr:
        """A parameter, or ``default`` where the description makes it structural (absent)."""
        return self.params.get(name, _exact(default))

    def _add(self, name: str, latex: str) -> sp.Symbol:
        sym = sp.Symbol(name, real=True)
        self.latex[sym] = latex
        return sym

    def new(self, text: str, latex: str) -> sp.Symbol:
        """A named intermediate term; a display name of the same spelling would be ambiguous."""
        if text in self.taken:
            raise DescriptionError([(f"symbols: {text!r} is taken by the structure report's "
                                    "notation (an intermediate term of the recursion)")])
        self.taken.add(text)
        return self._add(text, latex)


def _exact(c: float) -> sp.Expr:
    """A constant as an exact number where it is one (0, +-1, 1/100...), else a Float."""
    if c == int(c):
        return sp.Integer(int(c))
    return sp.Float(c)


def _tex_name(name: str) -> str:
    return r"\mathrm{" + fmt.tex_escape(name) + "}"


@dataclass
class _Walk:
    """The recursion as printed: one block per body, and the frames by body."""

    blocks: list[Block]
    frames: dict[str, _Frame]
    cg: dict[str, tuple[sp.Expr, sp.Expr]]
    w: dict[str, sp.Expr]  # angular velocity by body: the symbol w_B, or 0 where constant
    rates: list[tuple[str, str]]  # w_B = ... examples, (text, latex)


def _walk(desc: Description, nm: _Names) -> _Walk:
    """Mirror of ``recursion.walk``: the same frames, joint points and centres of gravity."""
    frames = {GROUND: _Frame(sp.S.Zero, (sp.S.Zero, sp.S.Zero))}
    w = {GROUND: sp.S.Zero}
    blocks, cgs, rates = [], {}, []
    k = 0

    def vec(body: str, point: str | None) -> tuple[sp.Expr, sp.Expr]:
        if point is None:
            return nm.param(f"cgx_{body}"), nm.param(f"cgy_{body}")
        return nm.param(f"px_{body}_{point}"), nm.param(f"py_{body}_{point}")

    def define(eqs: list[Eq], text: str, latex: str, terms: list[sp.Expr]) -> sp.Expr:
        sym = nm.new(text, latex)
        eqs.append(Eq((text, latex), terms))
        return sym if terms else sp.S.Zero  # a zero is used as zero from here on

    for j in desc.tree_joints:
        parent, b = frames[j.parent], j.child
        eqs: list[Eq] = []
        tb, tj = _tex_name(b), _tex_name(j.name)
        where = f", point {j.parent_point} of {j.parent} to point {j.child_point} of {b}"
        coord = m(nm.q[k].name, nm.latex[nm.q[k]]) if j.moves else None
        if j.type == "revolute":
            angle_terms = _nonzero([parent.angle, nm.q[k]])
            what: tuple = (f"revolute joint {j.name} (", coord, f"){where}")
            w_terms = _nonzero([w[j.parent], nm.qd[k]])
            k += 1
        else:  # weld and prismatic: the parent's frame turned by the drawn relative angle
            rel = desc.bodies[b].drawn_angle_rad - desc.bodies[j.parent].drawn_angle_rad
            angle_terms = _nonzero([parent.angle, sp.Float(rel, 10) if rel else 0])
            turned = f", turned by {_num(sp.Float(rel, 10))} rad" if rel else ""
            what = ((f"weld {j.name}{where}{turned}",)
                    if j.type == "weld" else
                    (f"prismatic joint {j.name} (", coord, (f"){where}, along "
                     f"({_num(j.axis[0])}, {_num(j.axis[1])}) in the frame of {j.parent}")))
            w_terms = _nonzero([w[j.parent]])
        theta = define(eqs, f"theta_{b}", rf"\theta_{{{tb}}}", angle_terms)
        w[b] = nm.new(f"w_{b}", rf"\omega_{{{tb}}}") if w_terms else sp.S.Zero
        if len(rates) < 3 and w_terms:
            wt = Eq(("", ""), w_terms)
            rates.append((f"w_{b} = " + _join(_text_pieces(wt)),
                          rf"\omega_{{{tb}}} = " + _join(_latex_pieces(wt, nm.latex))))
        jx, jy = parent.point(vec(j.parent, j.parent_point))
        if j.type == "prismatic":
            travel = define(eqs, f"s_{j.name}", rf"s_{{{tj}}}",
                            _nonzero([nm.param(f"s0_{j.name}"), nm.q[k]]))
            k += 1
            ux, uy = parent.rotate((travel * _exact(j.axis[0]), travel * _exact(j.axis[1])))
            jx, jy = jx + ux, jy + uy
        child = _Frame(theta, (sp.S.Zero, sp.S.Zero))
        cx, cy = vec(b, j.child_point)
        if cx == 0 and cy == 0:  # the joint is at the child's frame origin
            ox = define(eqs, f"xo_{b}", rf"x_{{o,{tb}}}", jx)
            oy = define(eqs, f"yo_{b}", rf"y_{{o,{tb}}}", jy)
        else:
            px = define(eqs, f"xj_{j.name}", rf"x_{{j,{tj}}}", jx)
            py = define(eqs, f"yj_{j.name}", rf"y_{{j,{tj}}}", jy)
            rx, ry = child.rotate((cx, cy))
            ox = define(eqs, f"xo_{b}", rf"x_{{o,{tb}}}", _nonzero([px, *(-t for t in rx)]))
            oy = define(eqs, f"yo_{b}", rf"y_{{o,{tb}}}", _nonzero([py, *(-t for t in ry)]))
        child.origin = (ox, oy)
        frames[b] = child
        gx, gy = child.point(vec(b, None))
        cgs[b] = (define(eqs, f"xc_{b}", rf"x_{{c,{tb}}}", gx),
                  define(eqs, f"yc_{b}", rf"y_{{c,{tb}}}", gy))
        blocks.append(Block((Strong(b), ": ", *what), eqs))
    if desc.task_point is not None:
        body, point = desc.task_point
        tx, ty = frames[body].point(vec(body, point))
        eqs = [Eq(("x_task", "x_{t}"), tx), Eq(("y_task", "y_{t}"), ty)]
        nm.new("x_task", "x_{t}")
        nm.new("y_task", "y_{t}")
        what = f": point {point} of {body}"
        if desc.task_orientation:
            nm.new("phi_task", r"\varphi_{t}")
            eqs.append(Eq(("phi_task", r"\varphi_{t}"),
                          _nonzero([frames[desc.task_orientation].angle])))
            what += f", orientation: the angle of {desc.task_orientation}"
        what += ("; the task function also returns its Jacobian J = dx/dq (algorithmic "
                 "differentiation) and Jdot qd (two forward sweeps along qd)")
        blocks.append(Block((Strong("task point"), what), eqs))
    return _Walk(blocks, frames, cgs, w, rates)


def _gravity_unit(desc: Description) -> tuple[sp.Expr, sp.Expr]:
    gx, gy = desc.gravity_m_s2
    norm = math.hypot(gx, gy)
    if norm == 0:
        return sp.S.Zero, sp.S.Zero
    return tuple(_exact(c / norm) if c in (0.0, norm, -norm) else sp.Float(c / norm, 10)
                 for c in (gx, gy))  # type: ignore[return-value]


def _moving(desc: Description):
    return [j for j in desc.tree_joints if j.moves]


def _energy(desc: Description, nm: _Names, wk: _Walk) -> Part:
    half = sp.Rational(1, 2)
    kinetic, potential, has_izz = [], [], False
    ux, uy = _gravity_unit(desc)
    g = nm.param("g")
    for b in desc.bodies:
        if b == GROUND:
            continue
        tb = _tex_name(b)
        vx = nm.new(f"vx_{b}", rf"v_{{x,{tb}}}")
        vy = nm.new(f"vy_{b}", rf"v_{{y,{tb}}}")
        mass, izz = nm.param(f"m_{b}"), nm.param(f"izz_{b}")
        kinetic.append(half * mass * (vx**2 + vy**2))
        w = wk.w[b]
        if izz != 0 and w != 0:
            kinetic.append(half * izz * w**2)
            has_izz = True
        xc, yc = wk.cg[b]
        potential += _nonzero([-ux * g * mass * xc, -uy * g * mass * yc])
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
    u = f"({_num(ux)}, {_num(uy)})"
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


def _dynamics(desc: Description, nm: _Names, friction: bool) -> Part:
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
        (" by one forward sweep over that reverse sweep (forward over reverse). Each sweep "
         "costs a fixed multiple of evaluating T, so the inverse dynamics is O(n) operations, "
         "like Newton-Euler; "),
        m("M = dp/dqd", r"M = \partial p/\partial \dot q"), ", the Hessian of T in ",
        m("qd", r"\dot q"), ", takes n such sweeps: O(n^2)."
        + ("" if closed else " The forward dynamics solves the linear system M qdd = "
           "tau - h (O(n^3), small for these sizes).")))
    return part


def _friction(desc: Description, nm: _Names) -> Part | None:
    eqs = []
    for k, j in enumerate(_moving(desc)):
        terms = _nonzero([nm.param(f"fv_{j.name}") * nm.qd[k]])
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


def _closure(desc: Description, nm: _Names, wk: _Walk) -> list[Part]:
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
            [Eq(m(f"Phi{a}", rf"\Phi_{{{a}}}"), _nonzero([*px, *(-t for t in cx)])),
             Eq(m(f"Phi{b}", rf"\Phi_{{{b}}}"), _nonzero([*py, *(-t for t in cy)]))]))
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


def _preamble(desc: Description, nm: _Names) -> list[Rich]:
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


def _recursion_part(desc: Description, wk: _Walk) -> Part:
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
    nm = _Names(desc)
    wk = _walk(desc, nm)
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


def _num(c) -> str:
    c = sp.sympify(c)
    if isinstance(c, sp.Float):
        return f"{float(c):.10g}"
    return sp.sstr(c)


def _split(t: sp.Expr) -> tuple[str, sp.Expr, sp.Expr]:
    coef, rest = t.as_coeff_Mul()
    if coef < 0:
        return "-", -coef, rest
    return "+", coef, rest


def _text_pieces(eq: Eq) -> list[tuple[str, str]]:
    if not eq.rhs:
        return [("+", "0")]
    out = []
    for t in eq.rhs:
        sign, coef, rest = _split(t)
        if rest == 1:
            out.append((sign, _num(coef)))
        else:
            body = sp.sstr(rest)
            out.append((sign, body if coef == 1 else f"{_num(coef)}*{body}"))
    return out


def _latex_pieces(eq: Eq, names: dict[sp.Symbol, str]) -> list[tuple[str, str]]:
    if not eq.rhs:
        return [("+", "0")]
    out = []
    for t in eq.rhs:
        sign, coef, rest = _split(t)
        if rest == 1:
            out.append((sign, _num(coef)))
            continue
        body = sp.latex(rest, symbol_names=names, fold_func_brackets=True)
        if coef == 1:
            out.append((sign, body))
        elif isinstance(coef, sp.Rational) and coef.q != 1:
            out.append((sign, rf"\frac{{{coef.p}}}{{{coef.q}}} {body}"))
        else:
            out.append((sign, f"{_num(coef)} {body}"))
    return out


def _join(pieces: list[tuple[str, str]]) -> str:
    return fmt._lines(pieces, 10**9)[0]


def _rhs(st: Structure, eq: Eq, style: str, width: int) -> list[str]:
    if isinstance(eq.rhs, tuple):
        return [eq.rhs[0] if style == "text" else eq.rhs[1]]
    if style == "text":
        return fmt._lines(_text_pieces(eq), width)
    return fmt._lines(_latex_pieces(eq, st.latex_names), width, fmt.visible)


def _rich(r: Rich, style: str) -> str:
    out = []
    for part in r:
        if isinstance(part, Code):  # in text kept on one line (see _wrap)
            out.append(f"\\texttt{{{fmt.tex_escape(part)}}}" if style == "latex" else
                       f"`{part}`" if style == "markdown" else f"`{part.replace(' ', _NBSP)}`")
        elif isinstance(part, Strong) and style != "text":
            out.append(f"\\textbf{{{fmt.tex_escape(part)}}}" if style == "latex"
                       else f"**{fmt.md_escape(part)}**")
        else:
            out.append(fmt.rich((part,), style))
    return "".join(out)


_NBSP = "\x00"  # a space that text wrapping does not break at (a command stays whole)


def _wrap(s: str, indent: str = "") -> list[str]:
    lines = textwrap.wrap(s, fmt.WIDTH, initial_indent=indent, subsequent_indent=indent,
                          break_on_hyphens=False, break_long_words=False)
    return [line.replace(_NBSP, " ") for line in lines]


def text(st: Structure) -> str:
    out = [st.title, ""]
    for p in st.preamble:
        out += _wrap(_rich(p, "text"))
    out.append("")
    for part in st.parts:
        out.append(_rich(part.title, "text") + ":")
        for note in part.intro:
            out += _wrap(_rich(note, "text"), "  # ")
        for block in part.blocks:
            if block.caption is not None:
                out += _wrap(_rich(block.caption, "text"), "  # ")
            for eq in block.eqs:
                head = f"  {eq.lhs[0]} = "
                body = _rhs(st, eq, "text", fmt.WIDTH - len(head))
                out.append(head + body[0])
                out += [" " * len(head) + line for line in body[1:]]
        for note in part.notes:
            out += _wrap(_rich(note, "text"), "  # ")
        out.append("")
    out.append("Generated functions (operations per sample, route):")
    if st.functions:
        wq = max(len(q) for q, _, _ in st.functions)
        wo = max(len(str(o)) for _, o, _ in st.functions)
        out += [f"  {q:<{wq}}  {o:>{wo}}  {r}" for q, o, r in st.functions]
    out += _wrap(_FUNCTIONS_NOTE, "  # ")
    out += ["", _SYMBOLS_HEADING]
    cells = [(r["symbol"], f"{r['value']} {r['unit']}" + (f" [{r['seed']}]" if r["seed"] else ""),
              r["parameter"], r["meaning"]) for r in st.table]
    widths = [max((len(c[k]) for c in cells), default=0) for k in range(3)]
    for c in cells:
        out.append("  " + "  ".join(f"{c[k]:<{widths[k]}}" for k in range(3)) + f"  {c[3]}")
    return "\n".join(out) + "\n"


_SYMBOLS_HEADING = ("Symbols (name, value in SI [and as the description gives it], parameter, "
                    "meaning):")
_FUNCTIONS_NOTE = ("operations: arithmetic and trigonometric operations per sample of each "
                   "generated C function (inputs, outputs and constants not counted); route: "
                   "where the expression came from.")


def _aligned(st: Structure, eqs: list[Eq]) -> list[str]:
    rows = []
    lhs = max(fmt.visible(eq.lhs[1]) for eq in eqs)
    for eq in eqs:
        lines = _rhs(st, eq, "latex", max(fmt.TEX_WIDTH - lhs, 30))
        rows.append(f"{eq.lhs[1]} &= {lines[0]}")
        rows += [rf"&\quad {line}" for line in lines[1:]]
    return [row + r" \\" for row in rows[:-1]] + rows[-1:]


def _sym_latex(name: str) -> str:
    return sp.latex(sp.Symbol(name))


def latex(st: Structure) -> str:
    out = [r"\documentclass[10pt]{article}", r"\usepackage{amsmath}", r"\usepackage{longtable}",
           r"\allowdisplaybreaks", r"\begin{document}",
           rf"\section*{{{fmt.tex_escape(st.name)}: equations of motion (structure)}}",
           fmt.tex_escape(st.title), ""]
    for p in st.preamble:
        out += [_rich(p, "latex"), ""]
    for part in st.parts:
        out.append(rf"\subsection*{{{_rich(part.title, 'latex')}}}")
        for note in part.intro:
            out += [_rich(note, "latex"), ""]
        for block in part.blocks:
            if block.caption is not None:
                out += [r"\medskip\noindent " + _rich(block.caption, "latex"), ""]
            out += [r"\begin{align*}", *_aligned(st, block.eqs), r"\end{align*}"]
        for note in part.notes:
            out += [_rich(note, "latex"), ""]
    out += [r"\subsection*{Generated functions}", r"\begin{tabular}{lrl}",
            r"quantity & operations per sample & route \\ \hline"]
    out += [rf"\texttt{{{fmt.tex_escape(q)}}} & {o} & {fmt.tex_escape(r)} \\"
            for q, o, r in st.functions]
    out += [r"\end{tabular}", "", fmt.tex_escape(_FUNCTIONS_NOTE), ""]
    out += [r"\subsection*{Symbols}", r"{\small\begin{longtable}{llp{2.9cm}p{3.9cm}}",
            r"symbol & parameter & value (SI; as described) & meaning \\ \hline"]
    for r in st.table:
        value = r["value"] + " " + r["unit"] + (f"; {r['seed']}" if r["seed"] else "")
        out.append(f"${_sym_latex(r['symbol'])}$ & \\texttt{{{fmt.tex_escape(r['parameter'])}}}"
                   f" & {fmt.tex_escape(value)} & {fmt.tex_escape(r['meaning'])} \\\\")
    out += [r"\end{longtable}}", r"\end{document}"]
    return "\n".join(out) + "\n"


def markdown(st: Structure) -> str:
    out = [f"# {fmt.md_escape(st.name)}: equations of motion (structure)", "",
           fmt.md_escape(st.title), ""]
    for p in st.preamble:
        out += [_rich(p, "markdown"), ""]
    for part in st.parts:
        out += [f"## {_rich(part.title, 'markdown')}", ""]
        for note in part.intro:
            out += [_rich(note, "markdown"), ""]
        for block in part.blocks:
            if block.caption is not None:
                out += [_rich(block.caption, "markdown"), ""]
            out += ["$$", r"\begin{aligned}", *_aligned(st, block.eqs), r"\end{aligned}", "$$",
                    ""]
        for note in part.notes:
            out += [_rich(note, "markdown"), ""]
    out += ["## Generated functions", "", "| quantity | operations per sample | route |",
            "|---|--:|---|"]
    out += [f"| `{q}` | {o} | {fmt.md_escape(r)} |" for q, o, r in st.functions]
    out += ["", fmt.md_escape(_FUNCTIONS_NOTE), ""]
    out += ["## Symbols", "", "| symbol | parameter | value (SI) | as described | meaning |",
            "|---|---|---|---|---|"]
    for r in st.table:
        out.append(f"| ${_sym_latex(r['symbol'])}$ | `{r['parameter']}` | "
                   f"`{r['value']} {r['unit']}` | {'`' + r['seed'] + '`' if r['seed'] else ''}"
                   f" | {fmt.md_escape(r['meaning'])} |")
    return "\n".join(out) + "\n"
