"""Lagrange's equations of a planar tree: T, V, then M(q), C(q, qd), g(q) and h = C qd + g.

.. code:: text

    L = T - V,   T = 1/2 sum_b (m_b |v_cg,b|^2 + Izz_b w_b^2),   V = -sum_b m_b (g . r_cg,b)
    d/dt dL/dqd - dL/dq = M(q) qdd + C(q, qd) qd + g(q) = tau
    M = d^2 T / dqd^2,   C_ij = sum_k Gamma_ijk qd_k,
    Gamma_ijk = 1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i),   g = dV/dq
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.model.description import COULOMB_SMOOTHING, GROUND, Description

from .kinematics import Frame, angle_rate, body_vec
from .symbols import Symbols


@dataclass(frozen=True)
class Lagrangian:
    kinetic: sp.Expr
    potential: sp.Expr
    mass_matrix: sp.Matrix
    coriolis: sp.Matrix  # C(q, qd), from the Christoffel symbols
    coriolis_qd: sp.Matrix  # C(q, qd) qd
    gravity: sp.Matrix  # g(q) = dV/dq
    friction: sp.Matrix  # D(qd): actuators' viscous and (smoothed) Coulomb friction

    @property
    def bias(self) -> sp.Matrix:
        """h(q, qd) = C(q, qd) qd + g(q) + D(qd)."""
        return (self.coriolis_qd + self.gravity + self.friction).applyfunc(_tidy)


def _tidy(e: sp.Expr) -> sp.Expr:
    return sp.expand(e)


def gravity_direction(desc: Description) -> tuple[sp.Expr, sp.Expr]:
    """Unit vector of gravity; exact where the description is axis-aligned."""
    gx, gy = desc.gravity_m_s2
    norm = (gx * gx + gy * gy) ** 0.5
    if norm == 0:
        return (sp.S.Zero, sp.S.Zero)
    return tuple(sp.nsimplify(c / norm, tolerance=1e-15, rational=False)  # type: ignore[return-value]
                 if c in (0.0, norm, -norm) else sp.Float(c / norm) for c in (gx, gy))


def derive(desc: Description, s: Symbols, fr: dict[str, Frame]) -> Lagrangian:
    rate = angle_rate(s)
    ux, uy = gravity_direction(desc)
    g = s.param("g")
    kinetic, potential = sp.S.Zero, sp.S.Zero
    for name in desc.bodies:
        if name == GROUND:
            continue
        m, izz = s.param(f"m_{name}"), s.param(f"izz_{name}")
        cg = fr[name].point(body_vec(desc, s, name, None))
        kinetic += m * cg.speed_squared(rate) / 2 + izz * rate(fr[name].angle) ** 2 / 2
        pos = cg.position()
        potential += -m * g * (ux * pos[0] + uy * pos[1])
    kinetic += _rotors(desc, s, fr, rate)
    kinetic, potential = sp.expand(kinetic), sp.expand(potential)
    mass = sp.hessian(kinetic, s.qd).applyfunc(_tidy)
    n = len(s.q)
    coriolis = sp.zeros(n, n)
    for i in range(n):
        for j in range(n):
            coriolis[i, j] = _tidy(sum(
                (sp.diff(mass[i, j], s.q[k]) + sp.diff(mass[i, k], s.q[j])
                 - sp.diff(mass[j, k], s.q[i])) * s.qd[k] / 2 for k in range(n)))
    gravity = sp.Matrix([_tidy(sp.diff(potential, qi)) for qi in s.q])
    coriolis_qd = (coriolis * sp.Matrix(s.qd)).applyfunc(_tidy)
    return Lagrangian(kinetic, potential, mass, coriolis, coriolis_qd, gravity,
                      _friction(desc, s))


def _rotors(desc: Description, s: Symbols, fr: dict[str, Frame], rate) -> sp.Expr:
    """Kinetic energy of the actuators' rotors: 1/2 J_m (w_parent + N qd_j)^2, the stator on
    the joint's parent body (exact, not only the reflected N^2 J_m)."""
    total = sp.S.Zero
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        jm = s.param(f"jm_{j.name}")
        if j.actuator is None or jm == 0:
            continue
        ratio = s.by_name.get(f"gear_{j.name}", sp.S.One)
        total += jm * (rate(fr[j.parent].angle) + ratio * s.qd[k]) ** 2 / 2
    return total


def _friction(desc: Description, s: Symbols) -> sp.Matrix:
    """D(qd): per coordinate, b qd + c tanh(qd / v_s) of its actuator (0 without one)."""
    rows = []
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        b, c = s.param(f"fv_{j.name}"), s.param(f"fc_{j.name}")
        smooth = s.by_name.get(f"vs_{j.name}", sp.Float(COULOMB_SMOOTHING))
        rows.append(b * s.qd[k] + (c * sp.tanh(s.qd[k] / smooth) if c != 0 else 0))
    return sp.Matrix(rows)
