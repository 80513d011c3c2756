"""Inverse dynamics by Newton-Euler in the plane (recursive, world axes): the third route.

Forward-over-reverse differentiation of the energies (``ad_dynamics.py``) is O(n) but carries
the derivative sweeps' bookkeeping: about 80 operations a link. Newton-Euler needs only each
body's angular velocity and acceleration and the acceleration of one point per body, then sums
forces and moments from the leaves down: about 45 a link. Every body's reference point is its
joint's point (on the slider's block for a prismatic joint), world axes throughout:

.. code:: text

    w_b = w_p + qd_k (revolute),  al_b = al_p + qdd_k
    a(r) = a(o_p) + al_p z x (r - o_p) - w_p^2 (r - o_p)           (a point r of body p)
    prismatic: a(o_b) = a(coincident point of p) + 2 w_p z x u qd_k + u qdd_k
    f_b = m_b (a_cg - g) + sum f_c,   n_b = Izz al_b + (cg - o_b) x m_b (a_cg - g)
                                            + sum (n_c + (o_c - o_b) x f_c) + stators' J_m al_r
    tau_k = n_b (revolute) or u . f_b (prismatic), + N J_m al_r + D(qd)

A rotor turns at ``w_parent + N qd_k`` (as ``ad_dynamics._rotors``): its angular acceleration
``al_r = al_p + N qdd_k`` needs ``J_m al_r`` from its stator, a pure moment on the parent body
(so every revolute joint below it feels it), and ``N J_m al_r`` through the gear on its own
joint. ``tests/test_newton_euler.py`` checks it against the differentiated energies to 1e-12.
"""

from __future__ import annotations

import casadi as ca

from planar_sym.model.description import GROUND, Description

from .recursion import Tree, cross_z


def _cross(a: ca.SX, b: ca.SX) -> ca.SX:
    """The z component of a x b for plane vectors."""
    return a[0] * b[1] - a[1] * b[0]


def inverse_dynamics(desc: Description, tree: Tree, gravity: ca.SX, friction: ca.SX,
                     qd: ca.SX, qdd: ca.SX) -> ca.SX:
    """tau (n, 1) for velocities ``qd`` and accelerations ``qdd`` (SX columns; pass zeros for
    the bias or gravity terms); ``gravity`` the (2, 1) acceleration of gravity (m/s^2) and
    ``friction`` D(qd) per coordinate (added as is)."""
    s = tree.sym
    zero = ca.SX(0.0)
    children: dict[str, list] = {}
    for j in desc.tree_joints:
        children.setdefault(j.parent, []).append(j)
    coordinate, k = {}, 0
    for j in desc.tree_joints:
        if j.moves:
            coordinate[j.name] = k
            k += 1
    origin = {GROUND: ca.SX.zeros(2, 1)}
    omega, alpha, acc = {GROUND: zero}, {GROUND: zero}, {GROUND: ca.SX.zeros(2, 1)}

    def point_acc(body: str, r: ca.SX) -> ca.SX:
        d = r - origin[body]
        return acc[body] + alpha[body] * cross_z(d) - omega[body] * omega[body] * d

    axis = {}
    for j in desc.tree_joints:  # parents first
        p, b = j.parent, j.child
        if j.type == "prismatic":
            o = tree.at(b, j.child_point)
            u = tree.slide_axis(j)
            axis[j.name] = u
            c = coordinate[j.name]
            acc[b] = (point_acc(p, o) + 2 * omega[p] * cross_z(u) * qd[c] + u * qdd[c])
            omega[b], alpha[b] = omega[p], alpha[p]
        else:
            o = tree.at(p, j.parent_point)
            acc[b] = point_acc(p, o)
            if j.type == "revolute":
                c = coordinate[j.name]
                omega[b], alpha[b] = omega[p] + qd[c], alpha[p] + qdd[c]
            else:
                omega[b], alpha[b] = omega[p], alpha[p]
        origin[b] = o

    rotors = {j.name: (s.param(f"jm_{j.name}"), s.param(f"gear_{j.name}", 1.0))
              for j in desc.tree_joints
              if j.moves and j.actuator is not None and s.has(f"jm_{j.name}")}
    rotor_alpha = {name: alpha[j.parent] + gear * qdd[coordinate[name]]
                   for j in desc.tree_joints if j.name in rotors
                   for name, gear in [(j.name, rotors[j.name][1])]}
    force: dict[str, ca.SX] = {}
    moment: dict[str, ca.SX] = {}
    tau = [zero] * k
    for j in reversed(desc.tree_joints):  # children first
        b = j.child
        m = s.param(f"m_{b}")
        cg = tree.cg(b)
        inertial = m * (point_acc(b, cg) - gravity)
        f = inertial
        n = s.param(f"izz_{b}") * alpha[b] + _cross(cg - origin[b], inertial)
        for c in children.get(b, []):
            f = f + force[c.child]
            n = n + moment[c.child] + _cross(origin[c.child] - origin[b], force[c.child])
            if c.name in rotors:  # the stator on b holds the rotor's angular acceleration
                n = n + rotors[c.name][0] * rotor_alpha[c.name]
        force[b], moment[b] = f, n
        if j.moves:
            c = coordinate[j.name]
            t = n if j.type == "revolute" else ca.dot(axis[j.name], f)
            if j.name in rotors:
                jm, gear = rotors[j.name]
                t = t + gear * jm * rotor_alpha[j.name]
            tau[c] = t + friction[c]
    return ca.vertcat(*tau) if tau else ca.SX.zeros(0, 1)
