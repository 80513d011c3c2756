"""The equation report of one robot: what it says, independent of the output format.

Sections: notation; T, V, L; the Euler-Lagrange equations row by row; M(q) in physical
parameters, the lumped parameters and M in them; C(q, qd) from the Christoffel symbols and
C qd; g(q); for closed chains Phi, Phi_q, gamma and the multiplier equation with its sign
convention; the base parameters of identification (``report_base``); the symbol table; the properties checked at derive time. ``report_format`` prints
it as text, LaTeX or Markdown.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass

import sympy as sp

from planar_sym.model.units import SI, factor

from . import properties
from .lumping import Lumped, lump
from .model import Model
from .notation import Notation, Prod, Sum
from .report_base import sections as base_sections
from .report_closed import sections as closed_sections
from .report_parts import Eq, Report, Rich, Section, m


@dataclass
class _Derived:
    """The model's quantities in notation form, shared by the section builders."""

    model: Model
    nt: Notation
    M: list  # M[i][j], compact
    lp: Lumped
    C: list  # C[i][j], in lumped parameters where they fit
    cqd: list  # (C qd)_i, likewise
    grav: list  # g_i, compact

    @property
    def upper(self) -> list[tuple[int, int]]:
        n = len(self.M)
        return [(i, j) for i in range(n) for j in range(i, n) if self.M[i][j] != 0]


def build(model: Model) -> Report:
    lag, n = model.lagrangian, len(model.sym.q)
    nt = Notation(model)
    M = [[nt.compact(lag.mass_matrix[i, j]) for j in range(n)] for i in range(n)]
    lp = lump([M[i][j] for i in range(n) for j in range(i, n)], nt)
    d = _Derived(model, nt, M, lp,
                 [[lp.express(nt.compact(lag.coriolis[i, j])) for j in range(n)]
                  for i in range(n)],
                 [lp.express(nt.compact(lag.coriolis_qd[i])) for i in range(n)],
                 [nt.compact(lag.gravity[i]) for i in range(n)])
    _check_lumped(d)
    sec = [_energy(d), _euler_lagrange(d), *_mass(d), _coriolis(d), _gravity(d)]
    if any(f != 0 for f in lag.friction):
        sec.append(_friction(d, nt))
    if model.constraints.count:
        sec += closed_sections(model, nt)
    sec += base_sections(model, nt, lp, d.grav)
    return Report(model.desc.name, model.desc.title, _preamble(model, nt), sec, _table(model),
                  _properties(model), nt)


def _energy(d: _Derived) -> Section:
    nt, lag = d.nt, d.model.lagrangian
    rate, trig, mass = nt.is_kind("rate"), nt.is_kind("trig"), nt.is_kind("mass")
    energy = Section(("Kinetic and potential energy, Lagrangian",), [
        Eq(m("T"), nt.grouped(nt.compact(lag.kinetic), rate, mass)),
        Eq(m("V"), nt.grouped(nt.compact(lag.potential), trig, mass)),
        Eq(m("L"), m("T - V"))])
    # the rotors' terms are in T above (a trial: the note left them out)
    rotors = any(f"jm_{j.name}" in d.model.sym.by_name for j in d.model.desc.tree_joints
                 if j.actuator is not None)
    spun = (" plus the rotors' ", m("1/2 J_m (w_parent + N qd_k)^2",
                                    r"\tfrac12 J_m (\omega_\mathrm{parent} + N \dot q_k)^2"),
            " (stator on the joint's parent body)") if rotors else ()
    energy.notes.append((
        m("T = 1/2 sum_b (m_b |v_b|^2 + I_b w_b^2)",
          r"T = \tfrac12 \sum_b (m_b |v_b|^2 + I_b \omega_b^2)"), *spun,
        " and ", m("V = sum_b m_b g y_b", r"V = \sum_b m_b g y_b"),
        " over the bodies b (", m("v_b, y_b"), ": velocity and height of the centre of gravity, ",
        m("w_b", r"\omega_b"), f": angular velocity; {_gravity_along(d.model)})."))
    return energy


def _gravity_along(model: Model) -> str:
    """Which way "height" is measured: against gravity (a tilted [6, -8] was said to be -y)."""
    gx, gy = model.desc.gravity_m_s2
    if gx == 0.0 and gy < 0.0:
        return "gravity along -y"
    n = math.hypot(gx, gy) or 1.0
    return f"gravity along ({gx / n:.4g}, {gy / n:.4g}), the height measured against it"


def _euler_lagrange(d: _Derived) -> Section:
    """Row i: sum_j M_ij qdd_j + (C qd)_i + g_i = Q_i, M and C in lumped parameters."""
    nt, s, desc = d.nt, d.model.sym, d.model.desc
    closed, trig, n = d.model.constraints.count > 0, nt.is_kind("trig"), len(d.M)
    q_rhs = (m("S^T tau + Phi_q^T lambda", r"S^\top \tau + \Phi_q^\top \lambda") if closed
             else m("tau", r"\tau"))
    el = Section(("Euler-Lagrange equations ",
                  m("d/dt dL/dqd - dL/dq = Q", r"\frac{d}{dt}\frac{\partial L}{\partial \dot q}"
                    r" - \frac{\partial L}{\partial q} = Q"),
                  ", i.e. ", m("M(q) qdd + C(q, qd) qd + g(q) = " + q_rhs[0],
                               r"M(q) \ddot q + C(q, \dot q) \dot q + g(q) = " + q_rhs[1])))
    for i in range(n):
        terms = []
        for j in range(n):
            if d.M[i][j] == 0:
                continue
            entry, qdd = nt.grouped(d.lp.express(d.M[i][j]), trig), (s.qdd[j], 1)
            if len(entry.terms) == 1:
                terms.append(Prod(entry.terms[0].coef, entry.terms[0].factors + [qdd]))
            else:
                terms.append(Prod(sp.S.One, [entry, qdd]))
        terms += nt.grouped(d.cqd[i], trig).terms
        if d.grav[i] != 0:
            terms.append(Prod(sp.S.One, [(nt.symbol(f"g{i + 1}", "other", f"g_{{{i + 1}}}"), 1)]))
        if d.model.lagrangian.friction[i] != 0:
            terms.append(Prod(sp.S.One, [(nt.symbol(f"D{i + 1}", "other", f"D_{{{i + 1}}}"), 1)]))
        act = i in desc.actuated
        lhs = ([s.tau[i].name] if act else []) + ([f"(Phi_q^T lambda){i + 1}"] if closed else [])
        tex = (([nt.info[s.tau[i]].latex] if act else [])
               + ([rf"(\Phi_q^\top \lambda)_{{{i + 1}}}"] if closed else []))
        lhs, tex = (lhs, tex) if lhs else (["0"], ["0"])  # a passive joint of a tree: no torque
        el.eqs.append(Eq((" + ".join(lhs), " + ".join(tex)), Sum(terms)))
    return el


def _label(head: str, i: int, j: int) -> tuple[str, str]:
    return m(f"{head}{i + 1}{j + 1}", f"{head}_{{{i + 1}{j + 1}}}")


def _mass(d: _Derived) -> list[Section]:
    nt = d.nt
    trig, mass = nt.is_kind("trig"), nt.is_kind("mass")
    out = [Section(("Mass matrix ", m("M(q) = d2T/dqd2", r"M(q) = \partial^2 T/\partial \dot q^2"),
                    " (symmetric; upper triangle, entries not shown are zero)"),
                   [Eq(_label("M", i, j), nt.grouped(d.M[i][j], mass)) for i, j in d.upper])]
    if d.lp.names:
        lumped = Section(("Lumped parameters",), [
            Eq(m(name.name, nt.info[name].latex), nt.grouped(prim, mass))
            for name, prim in d.lp.definitions])
        lumped.intro.append((("Each entry of M collected by its trigonometric factors; every "
                              "distinct parameter-only coefficient (up to a rational factor) "
                              "that is more than a single parameter gets a name:"),))
        lumped.notes.append(_lumped_values(d))
        out.append(lumped)
        out.append(Section(("Mass matrix in lumped parameters",), [
            Eq(_label("M", i, j), nt.grouped(d.lp.express(d.M[i][j]), trig))
            for i, j in d.upper]))
    return out


#: a lumped parameter below this fraction of the largest of its unit is named negligible (it
#: changes M by less): the seed five-bars' CAD drawings put centres of gravity a few 1e-4 mm
#: off the links' axes, 1e-6 of the other terms, where the book's equations have none
NEGLIGIBLE = 1e-5
_UNIT = {2: ("kg*m^2", r"kg\,m^2"), 1: ("kg*m", r"kg\,m"), 0: ("kg", "kg")}  # by length power


def _lumped_values(d: _Derived) -> Rich:
    """The lumped parameters' values for this robot (SI), the negligible ones named: a lecturer
    reads off which terms the board can drop."""
    params = d.model.desc.parameters()
    value = {d.nt.sub[p]: par.value for p, par in zip(d.model.sym.p, params)}
    # each is a mass times lengths: its power of length from every length scaled by 10
    scale = {"m": 10.0, "kg*m^2": 100.0}
    scaled = {d.nt.sub[p]: par.value * scale.get(par.unit, 1.0)
              for p, par in zip(d.model.sym.p, params)}
    rows = []
    for name, prim in d.lp.definitions:
        if prim.free_symbols - set(value):
            continue  # a slider's displacement in it: a function, no one value
        v = float(prim.xreplace(value))
        power = round(math.log10(abs(float(prim.xreplace(scaled)) / v))) if v else None
        rows.append((name, v, power))
    if not rows:
        return ("Each depends on a slider's displacement: no one value.",)
    largest: dict = {}
    for _, v, power in rows:
        largest[power] = max(largest.get(power, 0.0), abs(v))
    parts: list = ["With this robot's values: "]
    for k, (name, v, power) in enumerate(rows):
        unit, unit_tex = _UNIT.get(power, ("", ""))
        mant, _, exp = f"{v:.4g}".partition("e")
        v_tex = mant + (rf" \times 10^{{{int(exp)}}}" if exp else "")
        parts.append(m(f"{name.name} = {v:.4g} {unit}".rstrip(),
                       rf"{d.nt.info[name].latex} = {v_tex}\,\mathrm{{{unit_tex}}}"))
        if v and abs(v) < NEGLIGIBLE * largest[power]:
            parts.append(f" ({abs(v) / largest[power]:.1g} of the largest: negligible)")
        parts.append("; " if k < len(rows) - 1 else ".")
    return tuple(parts)


def _coriolis(d: _Derived) -> Section:
    nt, n, trig = d.nt, len(d.M), d.nt.is_kind("trig")
    cc = Section(("Coriolis and centrifugal matrix ", m("C(q, qd)", r"C(q,\dot q)"),
                  " from the Christoffel symbols (entries not shown are zero)"))
    cc.eqs = [Eq(_label("C", i, j), nt.grouped(d.C[i][j], trig))
              for i in range(n) for j in range(n) if d.C[i][j] != 0]
    cc.eqs += [Eq(m(f"(C qd){i + 1}", rf"(C\dot q)_{{{i + 1}}}"), nt.grouped(d.cqd[i], trig))
               for i in range(n) if d.cqd[i] != 0]
    cc.notes.append((m("C_ij = sum_k Gamma_ijk qd_k", r"C_{ij} = \sum_k \Gamma_{ijk} \dot q_k"),
                     ", ", m("Gamma_ijk = 1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i)",
                             r"\Gamma_{ijk} = \tfrac12 \left(\frac{\partial M_{ij}}{\partial q_k}"
                             r" + \frac{\partial M_{ik}}{\partial q_j} - "
                             r"\frac{\partial M_{jk}}{\partial q_i}\right)"), "."))
    return cc


def _gravity(d: _Derived) -> Section:
    nt = d.nt
    levels = (nt.is_kind("trig"), nt.is_kind("mass"))
    return Section(("Gravity terms ", m("g(q) = dV/dq", r"g(q) = \partial V/\partial q")),
                   [Eq(m(f"g{i + 1}", f"g_{{{i + 1}}}"), nt.grouped(g, *levels))
                    for i, g in enumerate(d.grav)])


def _friction(d: _Derived, nt: Notation) -> Section:
    """The actuators' friction D(qd), in the equations of motion as D_i."""
    fr = d.model.lagrangian.friction
    return Section(("Actuator friction ", m("D(qd)", r"D(\dot q)"),
                    " (joint side: viscous b qd + Coulomb c tanh(qd / v_s), smoothed over v_s)"),
                   [Eq(m(f"D{i + 1}", f"D_{{{i + 1}}}"), nt.grouped(nt.compact(f)))
                    for i, f in enumerate(fr) if f != 0])


def _check_lumped(d: _Derived) -> None:
    """The lumped forms must expand to the derived ones exactly: nothing printed is unchecked."""
    lag, nt, lp, n = d.model.lagrangian, d.nt, d.lp, len(d.M)
    for i in range(n):
        diffs = [nt.compact(lag.coriolis_qd[i]) - lp.physical(d.cqd[i])]
        for j in range(n):
            diffs += [d.M[i][j] - lp.physical(lp.express(d.M[i][j])),
                      nt.compact(lag.coriolis[i, j]) - lp.physical(d.C[i][j])]
        if any(sp.expand(e) != 0 for e in diffs):
            raise AssertionError(f"{d.model.desc.name}: a lumped form differs in row {i + 1}")


def _preamble(model: Model, nt: Notation) -> list[Rich]:
    desc = model.desc
    q = model.sym.q  # q<i> for an angle, d<i> for a prismatic joint's displacement
    coords = ", ".join(f"{q[i].name} = {c}" for i, c in enumerate(desc.coordinates))
    act = ", ".join(q[i].name for i in desc.actuated)
    trig = sorted(nt.defs, key=lambda t: nt.info[t].key)
    note: list = ["Notation: "]
    for k, t in enumerate(trig):
        note += [", " if k else "", m(f"{t.name} = {nt.defs[t][0]}",
                                      f"{nt.info[t].latex} = {nt.defs[t][1]}")]
    note += ["; ", m("qd, qdd", r"\dot q, \ddot q"), (": joint rates (rad/s) and accelerations "
             "(rad/s^2)")]
    if "m" in desc.coordinate_units:
        note += ["; ", m("d, dd, ddd, f", r"d, \dot d, \ddot d, f"),
                 (": a prismatic joint's displacement from the drawn pose (m), its rate (m/s), "
                  "acceleration (m/s^2) and force (N)")]
    note += ["; parameters by the names in the symbol table below."]
    units = "rad" if "m" not in desc.coordinate_units else "rad; d: m"
    return [(f"Coordinates ({units}): {coords}; actuated: {act}.",), tuple(note)]


def _table(model: Model) -> list[dict[str, str]]:
    desc = model.desc
    units = tomllib.loads(desc.path.read_text()).get("units", {})
    kind = {"m_": "mass", "izz_": "inertia", "jm_": "inertia", "cg": "length", "px_": "length",
            "py_": "length", "s0_": "length"}
    rows = []
    for p in desc.parameters():
        q = "acceleration" if p.name == "g" else next(
            (v for k, v in kind.items() if p.name.startswith(k)), None)
        seed_unit = (SI[q] if q is None or not isinstance(units.get(q, SI[q]), str)
                     else units.get(q, SI[q])) if q else p.unit
        seed = ""
        if seed_unit != p.unit:
            seed = f"{p.value / factor(q, seed_unit):.10g} {seed_unit}"
        rows.append({"symbol": desc.display.get(p.name, p.name), "parameter": p.name,
                     "value": f"{p.value:.10g}", "unit": p.unit, "seed": seed,
                     "meaning": p.meaning})
    return rows


def _properties(model: Model) -> list[Rich]:
    pr = properties.check(model)
    closed = model.constraints.count > 0
    tree = " (of the tree: the chain cut open at its loop joints)" if closed else ""
    slides = "m" in model.desc.coordinate_units
    poses = ("every coordinate uniform in [-pi, pi], rad or m at a slider" if slides
             else "q uniform in [-pi, pi]")
    unit, tail = (("", " (SI: kg*m^2, kg*m or kg by the rows' joints)") if slides
                  else (" kg*m^2", ""))
    return [
        ("M(q)" + tree + " is symmetric (checked symbolically: ",
         m("M - M^T", r"M - M^\top"), (" expands to zero) and positive definite at "
                                       f"{pr.samples} sampled poses ({poses}, "
                                       "seed parameter values, random-number seed "
                                       f"{properties.SEED}): smallest eigenvalue found "
                                       f"{pr.min_eigenvalue:.4g}{unit}, largest "
                                       f"{pr.max_eigenvalue:.4g}{unit}{tail}.")),
        (m("Mdot - 2C", r"\dot M - 2C"), " is skew-symmetric (checked symbolically: with ",
         m("N = Mdot - 2C", r"N = \dot M - 2C"), " and ",
         m("Mdot = sum_k dM/dq_k qd_k",
           r"\dot M = \sum_k \frac{\partial M}{\partial q_k} \dot q_k"),
         ", ", m("N + N^T", r"N + N^\top"), " expands to the zero matrix).",),
        (("The lumped forms above are checked at derive time to expand back to the derived M "
          "and C exactly."),),
    ]
