"""The symbol list of one robot and its fixed order: q, qd, qdd, tau and the parameters p."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.model.description import Description


@dataclass(frozen=True)
class Symbols:
    """Symbols in the one argument order used everywhere: (q, qd, qdd, p)."""

    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    tau: tuple[sp.Symbol, ...]
    p: tuple[sp.Symbol, ...]
    by_name: dict[str, sp.Symbol]

    def param(self, name: str) -> sp.Expr:
        """A parameter symbol, or exact zero where the description makes it structural."""
        return self.by_name.get(name, sp.S.Zero)


def make_symbols(desc: Description) -> Symbols:
    n = len(desc.coordinates)
    real = {"real": True}
    q = tuple(sp.Symbol(f"q{i + 1}", **real) for i in range(n))
    qd = tuple(sp.Symbol(f"qd{i + 1}", **real) for i in range(n))
    qdd = tuple(sp.Symbol(f"qdd{i + 1}", **real) for i in range(n))
    tau = tuple(sp.Symbol(f"tau{i + 1}", **real) for i in range(n))
    p = tuple(sp.Symbol(par.name, positive=par.name.startswith(("m_", "g")), **real)
              for par in desc.parameters())
    return Symbols(q, qd, qdd, tau, p, {s.name: s for s in p})
