"""SymPy expressions -> CasADi SX, by a small deterministic tree walk (no string eval)."""

from __future__ import annotations

import casadi as ca
import sympy as sp

_FUNCS = {sp.sin: ca.sin, sp.cos: ca.cos, sp.tan: ca.tan, sp.exp: ca.exp, sp.log: ca.log,
          sp.atan2: ca.atan2, sp.sqrt: ca.sqrt, sp.Abs: ca.fabs, sp.tanh: ca.tanh}


class Translator:
    """Maps SymPy symbols to CasADi symbols and converts expressions, sharing subtrees."""

    def __init__(self, mapping: dict[sp.Symbol, ca.SX]):
        self.cache: dict[sp.Expr, ca.SX] = dict(mapping)

    def __call__(self, e: sp.Expr) -> ca.SX:
        hit = self.cache.get(e)
        if hit is not None:
            return hit
        out = self._convert(e)
        self.cache[e] = out
        return out

    def _convert(self, e: sp.Expr) -> ca.SX:
        if e.is_Number:
            return ca.SX(float(e))
        if e.is_Symbol:
            raise KeyError(f"symbol {e} has no CasADi counterpart")
        if e.is_Add:
            return _fold(self, e.args, lambda a, b: a + b)
        if e.is_Mul:
            return _fold(self, e.args, lambda a, b: a * b)
        if e.is_Pow:
            base, ex = e.args
            if ex.is_Integer and ex > 0:
                return ca.constpow(self(base), int(ex))
            if ex == sp.Rational(1, 2):
                return ca.sqrt(self(base))
            return ca.power(self(base), self(ex))
        fn = _FUNCS.get(type(e))
        if fn is not None:
            return fn(*[self(a) for a in e.args])
        raise TypeError(f"cannot translate {type(e).__name__}: {e}")

    def matrix(self, m: sp.Matrix) -> ca.SX:
        rows, cols = m.shape
        out = ca.SX.zeros(rows, cols)
        for i in range(rows):
            for j in range(cols):
                out[i, j] = self(m[i, j])
        return out


def _fold(tr: Translator, args, op):
    # sympy's canonical argument order makes this deterministic
    acc = tr(args[0])
    for a in args[1:]:
        acc = op(acc, tr(a))
    return acc
