"""Closed-form equations for teaching: text and LaTeX, in the description's display names.

Each entry is collected by its trigonometric factors, so the parameter groups read like the
hand-derived textbook form (``M11 = I_1 + ... + 2 a_1 l_c2 m_2 cos(q2)``).
"""

from __future__ import annotations

import sympy as sp

from .model import Model


def _display(model: Model) -> dict[sp.Symbol, sp.Symbol]:
    names = model.desc.display
    return {s: sp.Symbol(names[s.name], **s.assumptions0) for s in model.sym.p if s.name in names}


def _collect(e: sp.Expr) -> sp.Expr:
    trig = sorted(e.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
    qd = sorted((s for s in e.free_symbols if s.name.startswith("qd")), key=sp.default_sort_key)
    if not trig:
        return e
    # products of trig and rates (sin(q2) qd1 qd2) group first, then each trig factor alone
    keys = sorted({t * m for t in trig for m in _rate_monomials(e, qd)} | set(trig),
                  key=sp.default_sort_key)
    return sp.collect(sp.expand(e), keys)


def _rate_monomials(e: sp.Expr, qd) -> set[sp.Expr]:
    out = set()
    for term in sp.Add.make_args(sp.expand(e)):
        rates = [f for f in sp.Mul.make_args(term) if f.free_symbols & set(qd)]
        if rates:
            out.add(sp.Mul(*rates))
    return out


def _entries(model: Model) -> list[tuple[str, str, list[tuple[str, sp.Expr]]]]:
    lag, con = model.lagrangian, model.constraints
    n = len(model.sym.q)
    sections = [
        ("Kinetic energy", "T", [("T", lag.kinetic)]),
        ("Potential energy", "V", [("V", lag.potential)]),
        ("Mass matrix M(q) (symmetric; upper triangle)", "M",
         [(f"M{i + 1}{j + 1}", lag.mass_matrix[i, j]) for i in range(n) for j in range(i, n)]),
        ("Velocity terms C(q, qd) qd (Coriolis and centrifugal)", "c",
         [(f"c{i + 1}", lag.coriolis_qd[i]) for i in range(n)]),
        ("Gravity terms g(q) = dV/dq", "g", [(f"g{i + 1}", lag.gravity[i]) for i in range(n)]),
    ]
    if con.count:
        sections.append(("Loop closure Phi(q) = 0 (m): parent point minus child point, x then y",
                         "Phi", [(f"Phi{i + 1}", con.phi[i]) for i in range(con.count)]))
        sections.append(("Acceleration term gamma = -(Phi_q qd)_q qd, with Phi_q qdd = gamma",
                         "gamma", [(f"gamma{i + 1}", con.accel_bias[i])
                                   for i in range(con.count)]))
    return sections


def render(model: Model) -> dict[str, str]:
    """{'text': ..., 'latex': ...} for one robot."""
    desc, sub = model.desc, _display(model)
    coords = ", ".join(f"q{i + 1} = {c}" for i, c in enumerate(desc.coordinates))
    act = ", ".join(f"q{i + 1}" for i in desc.actuated)
    eq = "M(q) qdd + C(q, qd) qd + g(q) = tau"
    if model.constraints.count:
        eq = "M(q) qdd + C(q, qd) qd + g(q) = S^T tau + Phi_q(q)^T lambda"
    text = [f"{desc.title}", "", f"  {eq}", "",
            f"Coordinates (rad): {coords}", f"Actuated: {act}", ""]
    latex = [f"% {desc.title}", r"\begin{gather*}",
             r"M(q)\,\ddot q + C(q,\dot q)\,\dot q + g(q) = "
             + (r"S^\top \tau + \Phi_q^\top \lambda" if model.constraints.count else r"\tau"),
             r"\end{gather*}"]
    for title, _, rows in _entries(model):
        text.append(f"{title}:")
        latex += [f"% {title}", r"\begin{align*}"]
        for label, expr in rows:
            e = _collect(expr.xreplace(sub))
            text.append(f"  {label} = {sp.sstr(e, order='none')}")
            latex.append(rf"{_latex_label(label)} &= {sp.latex(e, order='none')} \\")
        latex[-1] = latex[-1].rstrip(" \\")
        latex.append(r"\end{align*}")
        text.append("")
    text.append("Parameters:")
    for par in desc.parameters():
        shown = desc.display.get(par.name, par.name)
        text.append(f"  {shown:<10} {par.name:<18} = {par.value:<14.8g} {par.unit:<7} {par.meaning}")
    return {"text": "\n".join(text) + "\n", "latex": "\n".join(latex) + "\n"}


def _latex_label(label: str) -> str:
    head = label.rstrip("0123456789")
    idx = label[len(head):]
    head = {"Phi": r"\Phi", "gamma": r"\gamma"}.get(head, head)
    return f"{head}_{{{idx}}}" if idx else head
