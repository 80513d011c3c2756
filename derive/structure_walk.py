"""The kinematic recursion of the structure report, body by body, parents first, with named
intermediate terms (``theta_B``, frame origin ``xo_B, yo_B``, joint point ``xj_J, yj_J``,
prismatic travel ``s_J``, centre of gravity ``xc_B, yc_B``), mirroring ``recursion.walk``; and
the names (display names of parameters, coordinates, LaTeX) the whole report prints."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.errors import DescriptionError
from planar_sym.model.description import GROUND, Description

from . import report_format as fmt
from .report_parts import m
from .structure_doc import Block, Eq, Strong
from .structure_print import join_pieces, latex_pieces, num, text_pieces
from .symbols import make_symbols


@dataclass
class Frame:
    angle: sp.Expr  # the symbol theta_B, or 0 for the ground
    origin: tuple[sp.Expr, sp.Expr]  # symbols (or 0)

    def rotate(self, v: tuple[sp.Expr, sp.Expr]) -> tuple[list[sp.Expr], list[sp.Expr]]:
        """R(angle) v as term lists (x, y), zero terms left out."""
        c, s = sp.cos(self.angle), sp.sin(self.angle)
        return (nonzero([v[0] * c, -v[1] * s]), nonzero([v[0] * s, v[1] * c]))

    def point(self, v: tuple[sp.Expr, sp.Expr]) -> tuple[list[sp.Expr], list[sp.Expr]]:
        x, y = self.rotate(v)
        return nonzero([self.origin[0], *x]), nonzero([self.origin[1], *y])


def nonzero(terms: list[sp.Expr]) -> list[sp.Expr]:
    return [t for t in terms if t != 0]


class Names:
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
        return self.params.get(name, exact(default))

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


def exact(c: float) -> sp.Expr:
    """A constant as an exact number where it is one (0, +-1, 1/100...), else a Float."""
    if c == int(c):
        return sp.Integer(int(c))
    return sp.Float(c)


def tex_name(name: str) -> str:
    return r"\mathrm{" + fmt.tex_escape(name) + "}"


@dataclass
class Walk:
    """The recursion as printed: one block per body, and the frames by body."""

    blocks: list[Block]
    frames: dict[str, Frame]
    cg: dict[str, tuple[sp.Expr, sp.Expr]]
    w: dict[str, sp.Expr]  # angular velocity by body: the symbol w_B, or 0 where constant
    rates: list[tuple[str, str]]  # w_B = ... examples, (text, latex)


def walk(desc: Description, nm: Names) -> Walk:
    """Mirror of ``recursion.walk``: the same frames, joint points and centres of gravity."""
    frames = {GROUND: Frame(sp.S.Zero, (sp.S.Zero, sp.S.Zero))}
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
        tb, tj = tex_name(b), tex_name(j.name)
        where = f", point {j.parent_point} of {j.parent} to point {j.child_point} of {b}"
        coord = m(nm.q[k].name, nm.latex[nm.q[k]]) if j.moves else None
        if j.type == "revolute":
            angle_terms = nonzero([parent.angle, nm.q[k]])
            what: tuple = (f"revolute joint {j.name} (", coord, f"){where}")
            w_terms = nonzero([w[j.parent], nm.qd[k]])
            k += 1
        else:  # weld and prismatic: the parent's frame turned by the drawn relative angle
            rel = desc.bodies[b].drawn_angle_rad - desc.bodies[j.parent].drawn_angle_rad
            angle_terms = nonzero([parent.angle, sp.Float(rel, 10) if rel else 0])
            turned = f", turned by {num(sp.Float(rel, 10))} rad" if rel else ""
            what = ((f"weld {j.name}{where}{turned}",)
                    if j.type == "weld" else
                    (f"prismatic joint {j.name} (", coord, (f"){where}, along "
                     f"({num(j.axis[0])}, {num(j.axis[1])}) in the frame of {j.parent}")))
            w_terms = nonzero([w[j.parent]])
        theta = define(eqs, f"theta_{b}", rf"\theta_{{{tb}}}", angle_terms)
        w[b] = nm.new(f"w_{b}", rf"\omega_{{{tb}}}") if w_terms else sp.S.Zero
        if len(rates) < 3 and w_terms:
            wt = Eq(("", ""), w_terms)
            rates.append((f"w_{b} = " + join_pieces(text_pieces(wt)),
                          rf"\omega_{{{tb}}} = " + join_pieces(latex_pieces(wt, nm.latex))))
        jx, jy = parent.point(vec(j.parent, j.parent_point))
        if j.type == "prismatic":
            travel = define(eqs, f"s_{j.name}", rf"s_{{{tj}}}",
                            nonzero([nm.param(f"s0_{j.name}"), nm.q[k]]))
            k += 1
            ux, uy = parent.rotate((travel * exact(j.axis[0]), travel * exact(j.axis[1])))
            jx, jy = jx + ux, jy + uy
        child = Frame(theta, (sp.S.Zero, sp.S.Zero))
        cx, cy = vec(b, j.child_point)
        if cx == 0 and cy == 0:  # the joint is at the child's frame origin
            ox = define(eqs, f"xo_{b}", rf"x_{{o,{tb}}}", jx)
            oy = define(eqs, f"yo_{b}", rf"y_{{o,{tb}}}", jy)
        else:
            px = define(eqs, f"xj_{j.name}", rf"x_{{j,{tj}}}", jx)
            py = define(eqs, f"yj_{j.name}", rf"y_{{j,{tj}}}", jy)
            rx, ry = child.rotate((cx, cy))
            ox = define(eqs, f"xo_{b}", rf"x_{{o,{tb}}}", nonzero([px, *(-t for t in rx)]))
            oy = define(eqs, f"yo_{b}", rf"y_{{o,{tb}}}", nonzero([py, *(-t for t in ry)]))
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
                          nonzero([frames[desc.task_orientation].angle])))
            what += f", orientation: the angle of {desc.task_orientation}"
        what += ("; the task function also returns its Jacobian J = dx/dq (algorithmic "
                 "differentiation) and Jdot qd (two forward sweeps along qd)")
        blocks.append(Block((Strong("task point"), what), eqs))
    return Walk(blocks, frames, cgs, w, rates)
