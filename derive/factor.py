"""``M x = b`` for the symmetric positive definite mass matrix, as straight-line SX.

CasADi's ``solve`` of an SX matrix is a general symbolic QR (about 4 n^3 operations for an
n-link chain, with square roots); ``M`` is symmetric positive definite, so ``L D L^T`` needs
about n^3 / 3 and no square root. The coordinates are eliminated last to first: in the tree's
order (parents first) that eliminates every leaf before its parent, which causes no fill-in
(Featherstone's LTDL), so the zeros between branches of a tree stay zeros and are never
computed (SX folds products with an exact zero away).
"""

from __future__ import annotations

import casadi as ca


def solve_spd(m: ca.SX, b: ca.SX) -> ca.SX:
    """``m^-1 b`` for a symmetric positive definite ``m`` (n, n) and ``b`` (n, k)."""
    n = m.shape[0]
    order = list(range(n))[::-1]
    a = [[m[i, j] for j in order] for i in order]  # eliminated in this (reversed) order
    lo = [[ca.SX(0.0)] * n for _ in range(n)]
    d = [ca.SX(0.0)] * n
    for j in range(n):
        d[j] = a[j][j] - _sum(lo[j][k] * lo[j][k] * d[k] for k in range(j))
        for i in range(j + 1, n):
            lo[i][j] = (a[i][j] - _sum(lo[i][k] * lo[j][k] * d[k] for k in range(j))) / d[j]
    cols = []
    for c in range(b.shape[1]):
        y = [ca.SX(0.0)] * n
        rhs = [b[i, c] for i in order]
        for i in range(n):
            y[i] = rhs[i] - _sum(lo[i][k] * y[k] for k in range(i))
        x = [ca.SX(0.0)] * n
        for i in reversed(range(n)):
            x[i] = y[i] / d[i] - _sum(lo[k][i] * x[k] for k in range(i + 1, n))
        out = [ca.SX(0.0)] * n
        for pos, i in enumerate(order):
            out[i] = x[pos]
        cols.append(ca.vertcat(*out))
    return ca.horzcat(*cols)


def _sum(terms) -> ca.SX:
    total = ca.SX(0.0)
    for t in terms:
        total = total + t
    return total
