"""The report's base-parameter sections: the closed forms of ``base_forms``, and the lumped
parameters and gravity terms shown to be combinations of them (checked by expanding back)."""

from __future__ import annotations

import sympy as sp

from planar_sym.model.description import GROUND

from .base_forms import BaseForms, base_forms
from .lumping import Lumped, by_factors
from .model import Model
from .notation import Notation
from .report_parts import Eq, Section, m

_KIND = {"m": "mass", "mcx": "mass", "mcy": "mass", "izo": "inertia", "jm": "inertia",
         "fv": "other", "fc": "other"}


def sections(model: Model, nt: Notation, lp: Lumped, grav: list) -> list[Section]:
    forms = base_forms(model)
    title = ("Base parameters (identification: ", m("tau = Y(q, qd, qdd) pi",
                                                     r"\tau = Y(q, \dot q, \ddot q)\, \pi"), ")")
    if isinstance(forms, str):
        return [Section(title, intro=[(f"Not printed here: {forms}.",)])]
    for name, sym in forms.standard.items():
        kind, owner = name.split("_", 1)
        nt.add(sym, _KIND[kind], name, rf"\mathrm{{{kind}}}_{{\mathrm{{{_tex(owner)}}}}}")
    base = [nt.symbol(n, "lumped", rf"\mathrm{{{n.split('_', 1)[0]}}}_{{\mathrm{{"
                                   rf"{_tex(n.split('_', 1)[1])}}}}}") for n in forms.names]
    sec = Section(title, [Eq(m(b.name, nt.info[b].latex),
                             nt.grouped(nt.compact(e), nt.is_kind("mass", "inertia")))
                          for b, e in zip(base, forms.expressions)])
    counts = (f"{len(forms.names)} combinations of the {len(forms.standard)} change the "
              "torques, the base parameters: each named after the standard parameter it keeps, "
              "R where others regroup into it (planar-sym identify estimates them under these "
              "names):")
    sec.intro.append((
        ("The torques are linear in the standard parameters of identification: per body its "
         "mass m, first moments about its frame's origin "),
        m("mcx = m cx, mcy = m cy", r"\mathrm{mcx} = m c_x,\ \mathrm{mcy} = m c_y"),
        " and inertia about that origin ",
        m("izo = I + m (cx^2 + cy^2)", r"\mathrm{izo} = I + m (c_x^2 + c_y^2)"),
        "; per motor its rotor inertia jm, viscous fv and Coulomb fc friction. " + counts))
    if forms.unidentifiable:
        sec.notes.append((("No effect on any torque (not identifiable): "
                           f"{', '.join(forms.unidentifiable)}."),))
    sec.notes.append((("Found as planar-sym identify finds them (Gautier's method, the same "
                       "order of preference) but exactly: independence at exact rational "
                       "states, the regrouping coefficients solved with the lengths as symbols "
                       "and checked at states not used to find them."),))
    out = [sec]
    shown = _in_base(model, nt, lp, grav, forms)
    if shown.eqs:
        out.append(shown)
    return out


def _in_base(model: Model, nt: Notation, lp: Lumped, grav: list, forms: BaseForms) -> Section:
    """The lumped parameters and the gravity coefficients as base combinations: the report's
    textbook quantities are exactly what identification can find."""
    to_std, zeros = _standard_of(model, nt, forms)
    points = _point_masses(model, forms, zeros)
    raw = {v: k for k, v in nt.sub.items()}

    def combo(e: sp.Expr) -> sp.Expr | None:
        linear = sp.expand(sp.expand(e.xreplace(raw).xreplace(to_std)).subs(points))
        got = forms.express(linear, zeros)
        return None if got is None else nt.compact(got)

    sec = Section(("Lumped parameters and gravity terms in base parameters",))
    for name, prim in lp.definitions:
        c = combo(prim)
        if c is not None:
            sec.eqs.append(Eq(m(name.name, nt.info[name].latex), nt.grouped(c)))
    g = model.sym.param("g")
    shown_g = nt.sub.get(g, g)
    for i, gi in enumerate(grav):
        if gi == 0 or shown_g == 0:
            continue
        total, ok = sp.S.Zero, True
        for key, coef in by_factors(gi, nt.is_kind("trig")).items():
            c = combo(sp.expand(coef / shown_g))
            if c is None:
                ok = False
                break
            total += shown_g * c * key
        if ok:
            sec.eqs.append(Eq(m(f"g{i + 1}", f"g_{{{i + 1}}}"),
                              nt.grouped(total, nt.is_kind("trig"))))
    if sec.eqs:
        sec.notes.append(("Each expands back to its definition above (checked at derive time).",))
    return sec


def _standard_of(model: Model, nt: Notation, forms: BaseForms) -> tuple[dict, dict]:
    """The description's parameters in the standard ones (m, I = izo - |mc|^2 / m, cx = mcx /
    m, cy = mcy / m; rotor inertia and friction as they are), and the standard parameters its
    structure holds at zero (a first moment off an axis the centre of gravity is on)."""
    s, std = model.sym, forms.standard
    out, zeros = {}, {}
    for b in (b for b in model.desc.bodies if b != GROUND):
        mass, mx, my, io = (std[f"{k}_{b}"] for k in ("m", "mcx", "mcy", "izo"))
        for axis, first in (("x", mx), ("y", my)):
            if s.param(f"cg{axis}_{b}") == 0:
                zeros[first] = sp.S.Zero
            else:
                out[s.param(f"cg{axis}_{b}")] = first / mass
        out[s.param(f"m_{b}")] = mass
        # a point mass has no I: its m |c|^2 is all of izo (a term m cx^2 reads izo, below)
        out[s.param(f"izz_{b}")] = io - (mx**2 + my**2).xreplace(zeros) / mass
    for name in std:
        if name.startswith(("jm_", "fv_", "fc_")):
            out[s.param(name)] = std[name]
    return {k: v for k, v in out.items() if k != 0}, zeros


def _point_masses(model: Model, forms: BaseForms, zeros: dict) -> dict:
    """For a point mass (no I), |mc|^2 / m is its izo: the substitution that makes its
    m |c|^2 terms linear."""
    out = {}
    for b in (b for b in model.desc.bodies if b != GROUND):
        if model.sym.param(f"izz_{b}") != 0:
            continue
        mass, mx, my, io = (forms.standard[f"{k}_{b}"] for k in ("m", "mcx", "mcy", "izo"))
        free = [f for f in (mx, my) if f not in zeros]
        if free:  # mx^2 = m izo - my^2 (or m izo alone when the cg is on the x axis)
            out[free[0] ** 2] = mass * io - sum((f**2 for f in free[1:]), sp.S.Zero)
    return out


def _tex(name: str) -> str:
    return name.replace("_", r"\_")
