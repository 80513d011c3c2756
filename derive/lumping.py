"""Lumped parameters: the textbook ``M11 = alpha + 2 beta c2`` form, found generically.

Every entry of M(q) is collected by its trigonometric factors; each coefficient depends on the
parameters only. Up to a rational factor and sign, each distinct coefficient that is more than a
single parameter gets a Greek name, in order of first appearance (row by row, constant part
first). For the 2-DOF arm this gives exactly the textbook alpha, beta, delta. Gamma, lambda, tau,
phi and pi are skipped: the report uses them for other things.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .notation import Notation, _common_factor, _split

GREEK = ("alpha", "beta", "delta", "epsilon", "zeta", "eta", "theta", "kappa", "mu", "nu", "xi",
         "rho", "sigma", "chi", "psi", "omega")


@dataclass
class Lumped:
    nt: Notation
    names: dict[sp.Expr, sp.Symbol]  # primitive coefficient -> its name

    @property
    def definitions(self) -> list[tuple[sp.Symbol, sp.Expr]]:
        return [(name, prim) for prim, name in self.names.items()]

    def physical(self, e: sp.Expr) -> sp.Expr:
        """Lumped names replaced by their definitions."""
        return sp.expand(e.xreplace({n: p for p, n in self.names.items()}))

    def express(self, e: sp.Expr) -> sp.Expr:
        """A compact expression in lumped names where its coefficients allow, else as it is."""
        out = sp.S.Zero
        for key, coef in by_factors(e, self.nt.is_kind("trig", "rate", "accel")).items():
            out += self._combo(coef) * key
        return out  # report._check_lumped expands it back against the derived expression

    def _combo(self, c: sp.Expr) -> sp.Expr:
        """c as a rational combination of named coefficients, if there is a unique one."""
        content, prim = normalise(c)
        if prim in self.names:
            return content * self.names[prim]
        if c.atoms(sp.Function):  # a coordinate left inside (a turned slider's sin(q + a)):
            return c              # not a polynomial in the parameters, so no combination
        mons = _monomials(c)
        cands = [p for p in self.names if _monomials(p) <= mons]
        if not cands:
            return c
        r = [sp.Dummy(f"r{k}") for k in range(len(cands))]
        residual = sp.expand(c - sum((ri * p for ri, p in zip(r, cands)), sp.S.Zero))
        params = sorted(residual.free_symbols - set(r), key=sp.default_sort_key)
        if not params:
            return c
        sol = sp.linsolve(sp.Poly(residual, *params).coeffs(), r)
        if len(sol) != 1:
            return c
        vals = next(iter(sol))
        if not all(v.is_Rational for v in vals):
            return c  # not unique (free r left) or not a rational combination
        return sum((v * self.names[p] for v, p in zip(vals, cands)), sp.S.Zero)


def by_factors(e: sp.Expr, pick) -> dict[sp.Expr, sp.Expr]:
    """{monomial of the picked factors: its coefficient}, in order of appearance."""
    out: dict[sp.Expr, sp.Expr] = {}
    for t in sp.Add.make_args(sp.expand(e)):
        if t == 0:
            continue
        _, powers = _split(t)
        key = sp.Mul(*[b**x for b, x in powers.items() if pick(b)])
        out[key] = out.get(key, sp.S.Zero) + t / key
    return out


def normalise(c: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """c = content * prim, prim with integer-coprime coefficients and a positive leading term."""
    content, mono, rest = _common_factor(c)
    prim = sp.expand(mono * rest)
    lead = min(sp.Add.make_args(prim), key=sp.default_sort_key)
    if lead.could_extract_minus_sign():
        content, prim = -content, -prim
    return content, prim


def _monomials(e: sp.Expr) -> set[sp.Expr]:
    return {sp.Mul(*[b**x for b, x in _split(t)[1].items()])
            for t in sp.Add.make_args(sp.expand(e))}


def lump(entries: list[sp.Expr], nt: Notation) -> Lumped:
    """Name the coefficients of ``entries`` (compact M entries, row by row)."""
    taken = {s.name for s in nt.info}
    free = iter([g for g in GREEK if g not in taken]
                + [f"pi_{k}" for k in range(1, 1000) if f"pi_{k}" not in taken])
    names: dict[sp.Expr, sp.Symbol] = {}
    trig = nt.is_kind("trig")
    for e in entries:
        groups = by_factors(e, trig)
        for key in sorted(groups, key=lambda k: (k != 1, nt.factor_keys(k))):
            _, prim = normalise(groups[key])
            if prim.is_Symbol or prim in names:
                continue  # a bare parameter needs no second name
            name = next(free)
            names[prim] = nt.symbol(name, "lumped", "\\" + name if name in GREEK else None,
                                    key=(len(names),))
    return Lumped(nt, names)
