"""Properties of the derived equations, checked at derive time and stated in the report.

- M(q) symmetric (symbolically: M - M^T expands to zero) and positive definite at sampled poses
  with the seed parameter values (numerically: smallest eigenvalue over the samples);
- N = Mdot - 2C skew-symmetric (symbolically: N + N^T expands to zero), the property passivity
  based control relies on; it holds because C comes from the Christoffel symbols.

A failed check raises: the report never states a property that does not hold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

#: poses sampled for positive definiteness: q uniform in [-pi, pi], fixed seed (reproducible)
SAMPLES = 1000
SEED = 20240611


@dataclass(frozen=True)
class Properties:
    samples: int
    min_eigenvalue: float  # kg*m^2 (mixed units for prismatic joints; none here)
    max_eigenvalue: float


def check(model) -> Properties:
    lag, s = model.lagrangian, model.sym
    M, C = lag.mass_matrix, lag.coriolis
    n = M.shape[0]
    if any(sp.expand(M[i, j] - M[j, i]) != 0 for i in range(n) for j in range(i + 1, n)):
        raise AssertionError(f"{model.desc.name}: M(q) is not symmetric")
    mdot = sp.zeros(n, n)
    for qk, qdk in zip(s.q, s.qd):
        mdot += M.diff(qk) * qdk
    N = mdot - 2 * C
    if any(sp.expand(N[i, j] + N[j, i]) != 0 for i in range(n) for j in range(i, n)):
        raise AssertionError(f"{model.desc.name}: Mdot - 2C is not skew-symmetric")
    f = sp.lambdify([s.q, s.p], M, "numpy")
    p = model.desc.parameter_values()
    rng = np.random.default_rng(SEED)
    eig = np.array([np.linalg.eigvalsh(np.asarray(f(q, p), dtype=float))
                    for q in rng.uniform(-np.pi, np.pi, (SAMPLES, n))])
    if not eig.min() > 0:
        raise AssertionError(f"{model.desc.name}: M(q) is not positive definite at a sample")
    return Properties(SAMPLES, float(eig.min()), float(eig.max()))
