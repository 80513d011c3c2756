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
    real = {"real": True}
    # a prismatic joint's displacement is d<i> (m), its rates dd<i>, ddd<i>, its force f<i>
    slide = [u == "m" for u in desc.coordinate_units]
    q = tuple(sp.Symbol(f"{'d' if sl else 'q'}{i + 1}", **real) for i, sl in enumerate(slide))
    qd = tuple(sp.Symbol(f"{'dd' if sl else 'qd'}{i + 1}", **real) for i, sl in enumerate(slide))
    qdd = tuple(sp.Symbol(f"{'ddd' if sl else 'qdd'}{i + 1}", **real)
                for i, sl in enumerate(slide))
    tau = tuple(sp.Symbol(f"{'f' if sl else 'tau'}{i + 1}", **real) for i, sl in enumerate(slide))
    p = tuple(sp.Symbol(par.name, positive=par.name.startswith(("m_", "g")), **real)
              for par in desc.parameters())
    return Symbols(q, qd, qdd, tau, p, {s.name: s for s in p})
