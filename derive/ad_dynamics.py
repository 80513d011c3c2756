"""Equations of motion by algorithmic differentiation of the energies: the numeric route.

SymPy's closed forms expand ``M``, the Christoffel symbols and ``h`` term by term; their size
grows about as n^4 with the length of a chain, and so did the generated C. Here CasADi
differentiates the energies of the recursive kinematics (``recursion.py``) instead, as one
would by hand but without expanding anything:

.. code:: text

    T = sum_b 1/2 (m_b |v_cg,b|^2 + Izz_b w_b^2) + rotors,   v = (dr/dq) qd   (forward mode)
    V = -sum_b m_b g (u . r_cg,b)
    p = dT/dqd                                               (reverse mode)
    M = dp/dqd (summed by composite bodies, composite.py),   g = dV/dq
    tau = dp/dq qd + dp/dqd qdd - dT/dq + dV/dq + D(qd)      (by Newton-Euler, newton_euler.py)
    h = tau at qdd = 0

Each sweep costs a fixed multiple of evaluating ``T``, which the recursion makes O(n); the
inverse dynamics is O(n) operations, ``M`` O(n^2). The torques themselves come from Newton-Euler
over the same frames, which needs half the operations of the forward sweep over the reverse one
(``tests/test_newton_euler.py`` checks the two agree). Loop closure likewise: ``Phi`` from the
tree, ``Phi_q`` its Jacobian, ``gamma = -(Phi_q qd)_q qd`` two forward sweeps.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from planar_sym.model.description import COULOMB_SMOOTHING, GROUND, Description

from . import newton_euler
from .composite import mass_matrix
from .quantities import AD, Quantities
from .recursion import Symbols, Tree, walk


@dataclass
class Dynamics:
    """Every quantity the generated functions return, as SX in ``sym``'s inputs."""

    desc: Description
    sym: Symbols
    tree: Tree
    kinetic: ca.SX
    potential: ca.SX
    momentum: ca.SX  # p = dT/dqd
    mass_matrix: ca.SX
    bias: ca.SX  # h(q, qd) = C qd + g + D
    gravity: ca.SX
    inverse_dynamics: ca.SX  # M qdd + h, by Newton-Euler
    body_names: tuple[str, ...]
    poses: ca.SX  # every body's cg x, y (m) and angle (rad), stacked body by body
    pose_rates: ca.SX  # their time derivatives (one forward sweep)

    def rates(self, e: ca.SX) -> ca.SX:
        """d/dt of an expression in q: (de/dq) qd, one forward sweep."""
        return ca.jtimes(e, self.sym.q, self.sym.qd)

    def second_rates(self, e_dot: ca.SX) -> ca.SX:
        """d/dt of an expression in (q, qd): (d/dq) qd + (d/dqd) qdd, one forward sweep."""
        s = self.sym
        return ca.jtimes(e_dot, ca.vertcat(s.q, s.qd), ca.vertcat(s.qd, s.qdd))

    def velocity_product(self, e: ca.SX) -> ca.SX:
        """(de/dq qd)_q qd: the ``Jdot qd`` of an expression in q, two forward sweeps."""
        return ca.jtimes(self.rates(e), self.sym.q, self.sym.qd)


def gravity_unit(desc: Description) -> tuple[float, float]:
    gx, gy = desc.gravity_m_s2
    norm = (gx * gx + gy * gy) ** 0.5
    return (0.0, 0.0) if norm == 0 else (gx / norm, gy / norm)


def derive(desc: Description) -> Dynamics:
    tree = walk(desc)
    s = tree.sym
    names = tuple(b for b in desc.bodies if b != GROUND)
    ux, uy = gravity_unit(desc)
    # every cg and angle in one vector: one forward sweep gives all velocities (sweeping
    # body by body would repeat each body's chain: O(n^2))
    poses = ca.vertcat(*[ca.vertcat(tree.cg(b), tree.frames[b].angle) for b in names])
    rates = ca.jtimes(poses, s.q, s.qd)
    kinetic, potential = ca.SX(0.0), ca.SX(0.0)
    for k, b in enumerate(names):
        m, izz = s.param(f"m_{b}"), s.param(f"izz_{b}")
        v, w = rates[3 * k:3 * k + 2], rates[3 * k + 2]
        kinetic += m * ca.dot(v, v) / 2 + izz * w * w / 2
        potential += -m * s.param("g") * (ux * poses[3 * k] + uy * poses[3 * k + 1])
    kinetic += _rotors(desc, tree, dict(zip(names, (rates[3 * k + 2] for k in range(len(names))))))
    momentum = ca.gradient(kinetic, s.qd)
    gravity = ca.gradient(potential, s.q)
    friction = _friction(desc, s)
    # tau and h = tau at qdd = 0 by Newton-Euler (newton_euler.py): half the operations of
    # dp/dt - dT/dq + dV/dq by forward sweeps over the reverse one, which it equals to 1e-15
    g = s.param("g") * ca.vertcat(ux, uy)
    inverse = newton_euler.inverse_dynamics(desc, tree, g, friction, s.qd, s.qdd)
    bias = newton_euler.inverse_dynamics(desc, tree, g, friction, s.qd, ca.SX.zeros(s.qd.shape))
    mass = mass_matrix(desc, tree)  # composite bodies: a third of dp/dqd's operations
    return Dynamics(desc, s, tree, kinetic, potential, momentum, mass, bias, gravity, inverse,
                    names, poses, rates)


def _rotors(desc: Description, tree: Tree, omega: dict[str, ca.SX]) -> ca.SX:
    """Kinetic energy of the actuators' rotors: 1/2 J_m (w_parent + N qd_j)^2, the stator on
    the joint's parent body (exact, not only the reflected N^2 J_m)."""
    s, total = tree.sym, ca.SX(0.0)
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        if j.actuator is None or not s.has(f"jm_{j.name}"):
            continue
        w_parent = omega.get(j.parent, ca.SX(0.0))  # the ground's is zero
        total += s.param(f"jm_{j.name}") * (w_parent + s.param(f"gear_{j.name}", 1.0)
                                              * s.qd[k]) ** 2 / 2
    return total


def _friction(desc: Description, s: Symbols) -> ca.SX:
    """D(qd): per coordinate, b qd + c tanh(qd / v_s) of its actuator (0 without one)."""
    rows = []
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        d = s.param(f"fv_{j.name}") * s.qd[k]
        if s.has(f"fc_{j.name}"):
            d += s.param(f"fc_{j.name}") * ca.tanh(
                s.qd[k] / s.param(f"vs_{j.name}", COULOMB_SMOOTHING))
        rows.append(d)
    return ca.vertcat(*rows) if rows else ca.SX.zeros(0, 1)


def quantities(desc: Description) -> Quantities:
    """Every generated quantity by this route (see ``quantities.Quantities``)."""
    d = derive(desc)
    s, tree = d.sym, d.tree
    frames = [tree.frames[b] for b in d.body_names]
    acc = d.second_rates(d.pose_rates)
    joints = (*desc.tree_joints, *desc.loop_joints)
    points = [tree.at(j.child, j.child_point) for j in joints]
    points += [tree.at(j.parent, j.parent_point) for j in desc.loop_joints]
    points += [tree.slide_axis(j) for j in desc.tree_joints if j.type == "prismatic"]
    task = ca.SX.zeros(0, 1)
    if desc.task_point is not None:
        task = tree.at(*desc.task_point)
        if desc.task_orientation:
            task = ca.vertcat(task, tree.frames[desc.task_orientation].angle)
    phi = ca.vertcat(*[tree.at(j.parent, j.parent_point) - tree.at(j.child, j.child_point)
                       for j in desc.loop_joints]) if desc.loop_joints else ca.SX.zeros(0, 1)
    n = s.q.shape[0]
    return Quantities(
        AD, desc, s, d.mass_matrix, d.bias, d.gravity, d.inverse_dynamics, d.kinetic,
        d.potential,
        ca.horzcat(*[ca.vertcat(f.origin, f.angle) for f in frames]).T,
        ca.reshape(acc, 3, len(frames)),
        ca.horzcat(*[tree.cg(b) for b in d.body_names]),
        ca.horzcat(*points),
        task, ca.jacobian(task, s.q) if task.shape[0] else ca.SX.zeros(0, n),
        d.velocity_product(task) if task.shape[0] else ca.SX.zeros(0, 1),
        phi, ca.jacobian(phi, s.q) if phi.shape[0] else ca.SX.zeros(0, n),
        -d.velocity_product(phi) if phi.shape[0] else ca.SX.zeros(0, 1))
