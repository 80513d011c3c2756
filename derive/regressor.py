"""The dynamics as a linear map of the inertial and drive parameters: tau = Y(q, qd, qdd) pi.

The energies are written in the *standard parameters* of identification, per body the mass,
its first moments about the body frame's origin and the inertia about that origin, and per
actuated joint the rotor inertia, viscous and Coulomb friction:

.. code:: text

    T_b = 1/2 m |v_o|^2 + w v_o . E R (m c) + 1/2 I_o w^2      (E: a quarter turn; I_o = Izz + m |c|^2)
    V_b = -g u . (m o + R (m c))
    rotor: 1/2 J_m (w_parent + N qd)^2;  friction: f_v qd + f_c tanh(qd / v_s)

Both are linear in pi, so the Euler-Lagrange torques are too and ``Y = d tau / d pi`` holds no
pi: CasADi's exact derivative of the same forward-over-reverse sweeps as ``ad_dynamics.py``.
For a closed chain the torques come through ``[S^T Phi_q^T]`` as the closed-chain inverse
dynamics' do, and the cut-joint forces' regressor with them.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from planar_sym.model.description import COULOMB_SMOOTHING, GROUND, Description

from .ad_dynamics import gravity_unit
from .recursion import Symbols, walk


@dataclass(frozen=True)
class Standard:
    """One standard parameter: its name (a column of Y), unit and meaning."""

    name: str
    unit: str
    meaning: str


def standard_parameters(desc: Description) -> list[Standard]:
    """The columns of Y, in order: per body m, mcx, mcy, izo; then per actuated joint its
    rotor inertia (where the description gives one: it needs the gear to be told from the
    link's), viscous and Coulomb friction."""
    out = []
    for b in (b for b in desc.bodies if b != GROUND):
        out += [Standard(f"m_{b}", "kg", f"mass of {b}"),
                Standard(f"mcx_{b}", "kg*m", f"first moment of {b} about its frame's origin, "
                         "body x (m cx)"),
                Standard(f"mcy_{b}", "kg*m", f"first moment of {b}, body y (m cy)"),
                Standard(f"izo_{b}", "kg*m^2", f"inertia of {b} about its frame's origin "
                         "(Izz + m |c|^2)")]
    for j in (j for j in desc.tree_joints if j.moves and j.actuated):
        slide = j.type == "prismatic"
        force, rate = ("N", "m") if slide else ("N*m", "rad")
        if j.actuator is not None and "rotor_inertia" in j.actuator.given:
            out.append(Standard(f"jm_{j.name}", "kg*m^2", f"rotor inertia of {j.name}'s motor"))
        out += [Standard(f"fv_{j.name}", f"{force}*s/{rate}", f"viscous friction at {j.name}"),
                Standard(f"fc_{j.name}", force, f"Coulomb friction at {j.name}")]
    return out


@dataclass(frozen=True)
class Regressor:
    """Y of the tree's inverse dynamics (n, columns) in ``sym``'s inputs, and for a closed
    chain the actuated torques' (actuated, columns) and the cut-joint forces' (2 cuts,
    columns)."""

    sym: Symbols
    robot: str
    columns: list[Standard]
    tree: ca.SX
    closed_tau: ca.SX | None
    closed_lambda: ca.SX | None


def derive(desc: Description) -> Regressor:
    tree = walk(desc)
    s = tree.sym
    cols = standard_parameters(desc)
    pi = ca.SX.sym("pi", len(cols))
    at = {c.name: pi[i] for i, c in enumerate(cols)}
    bodies = [b for b in desc.bodies if b != GROUND]
    poses = ca.vertcat(*[ca.vertcat(tree.frames[b].origin, tree.frames[b].angle)
                         for b in bodies])
    rates = ca.jtimes(poses, s.q, s.qd)  # one forward sweep: every origin's velocity and w
    ux, uy = gravity_unit(desc)
    kinetic, potential = ca.SX(0.0), ca.SX(0.0)
    omega = {}
    for k, b in enumerate(bodies):
        f = tree.frames[b]
        m, first, izo = at[f"m_{b}"], f.rotate((at[f"mcx_{b}"], at[f"mcy_{b}"])), at[f"izo_{b}"]
        v, w = rates[3 * k:3 * k + 2], rates[3 * k + 2]
        omega[b] = w
        kinetic += m * ca.dot(v, v) / 2 + w * (v[1] * first[0] - v[0] * first[1]) + izo * w * w / 2
        potential += -s.param("g") * (ux * (m * f.origin[0] + first[0])
                                      + uy * (m * f.origin[1] + first[1]))
    friction = []
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        if f"jm_{j.name}" in at:
            w_parent = omega.get(j.parent, ca.SX(0.0))
            kinetic += at[f"jm_{j.name}"] * (w_parent + s.param(f"gear_{j.name}", 1.0)
                                             * s.qd[k]) ** 2 / 2
        d = ca.SX(0.0)
        if f"fv_{j.name}" in at:
            d = at[f"fv_{j.name}"] * s.qd[k] + at[f"fc_{j.name}"] * ca.tanh(
                s.qd[k] / s.param(f"vs_{j.name}", COULOMB_SMOOTHING))
        friction.append(d)
    momentum = ca.gradient(kinetic, s.qd)
    tau = (ca.jtimes(momentum, ca.vertcat(s.q, s.qd), ca.vertcat(s.qd, s.qdd))
           - ca.gradient(kinetic, s.q) + ca.gradient(potential, s.q) + ca.vertcat(*friction))
    y = ca.jacobian(tau, pi)
    if ca.depends_on(y, pi):  # the energies above are linear in pi, so Y never holds it
        raise AssertionError(f"{desc.name}: the regressor depends on the parameters")
    if not desc.loop_joints:
        return Regressor(s, desc.name, cols, y, None, None)
    phi = ca.vertcat(*[tree.at(j.parent, j.parent_point) - tree.at(j.child, j.child_point)
                       for j in desc.loop_joints])
    jac = ca.jacobian(phi, s.q)
    act = list(desc.actuated)
    pas = [i for i in range(s.q.shape[0]) if i not in act]
    # as the closed-chain inverse dynamics: Phi_p^T lambda = b_p, tau = b_a - Phi_a^T lambda
    lam = ca.mtimes(ca.inv(jac[:, pas].T), y[pas, :])
    return Regressor(s, desc.name, cols, y, y[act, :] - ca.mtimes(jac[:, act].T, lam), lam)
