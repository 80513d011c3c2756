"""The inverse of a loop-closure Jacobian block by block: its block triangular form.

The closed-chain inverse dynamics needs ``Phi_p^-T`` explicitly (its 1-norm gives the condition
number the runtime reports). A symbolic inverse of the whole m x m matrix costs what a dense one
does, but the loops of a multi-loop linkage are solved one after another: permuted, ``Phi_p^T``
is block lower triangular (CasADi's ``Sparsity.btf``, Dulmage-Mendelsohn), one small diagonal
block per loop that can be closed on its own. Then ``X = B^-1`` follows block row by block row
from the diagonal blocks' inverses alone:

.. code:: text

    B = A[r, c],   X_ij = B_ii^-1 (delta_ij I - sum_{j <= k < i} B_ik X_kj)   (i >= j)
    A^-1[c_i, r_j] = X_ij

Exact as a whole inverse is (no pivoting enters: ``det A`` is the product of the diagonal
blocks' determinants, so a block is singular exactly where ``A`` is). Jansen's leg (three
loops, six passive coordinates): 91 operations instead of 555. A one-block matrix (one loop,
or loops that cannot be closed apart, as the 3-RRR's) is inverted whole, as before.
``tests/test_block_triangular.py`` checks ``A A^-1 = I`` on every closed robot.
"""

from __future__ import annotations

import casadi as ca


def inverse(a: ca.SX) -> ca.SX:
    """``a^-1`` for a square SX matrix, block by block where its sparsity allows."""
    n = a.shape[0]
    count, rows, cols, row_block, col_block, _, _ = a.sparsity().btf()
    blocks = [(row_block[k], row_block[k + 1]) for k in range(count)]
    b = a[rows, cols]
    lower = all(b[r0:r1, blocks[k][0]:blocks[k][1]].nnz() == 0
                for i, (r0, r1) in enumerate(blocks) for k in range(i + 1, count))
    square = blocks == [(col_block[k], col_block[k + 1]) for k in range(count)]
    if count == 1 or not (lower and square):  # one block, or a form not met yet: whole
        return ca.inv(a)
    x: dict[tuple[int, int], ca.SX] = {}
    for i, (r0, r1) in enumerate(blocks):
        diagonal = ca.inv(b[r0:r1, r0:r1])
        for j in range(i + 1):
            c0, c1 = blocks[j]
            rhs = ca.SX.eye(r1 - r0) if i == j else ca.SX(r1 - r0, c1 - c0)
            for k in range(j, i):
                coupling = b[r0:r1, blocks[k][0]:blocks[k][1]]
                if coupling.nnz() and (k, j) in x:
                    rhs = rhs - ca.mtimes(coupling, x[k, j])
            if rhs.nnz():
                x[i, j] = ca.mtimes(diagonal, rhs)
    out = ca.SX(n, n)
    for (i, j), block in x.items():
        (r0, r1), (c0, c1) = blocks[i], blocks[j]
        for u in range(r1 - r0):
            for v in range(c1 - c0):
                out[cols[r0 + u], rows[c0 + v]] = block[u, v]
    return out
