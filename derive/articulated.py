"""``M^-1 B`` by articulated bodies (Featherstone's ABA, planar, inertia only): O(n) per column.

``L D L^T`` of the mass matrix costs about n^3 / 6 operations and n^2 per right-hand side, and
needs ``M`` first (composite bodies, O(n^2)). The articulated-body recursion never forms ``M``:
run with no velocity and no gravity, it turns generalised forces ``b`` into accelerations
``M^-1 b`` in O(n). The forward dynamics is then ``qdd = M^-1 (tau - h)`` with ``h`` from the
inverse dynamics' own O(n) sweep, so every term stays linear in the tree's size.

Planar spatial vectors, each about a point of its body (the joint's point for a revolute joint,
the slider's block for a prismatic one) in world axes: motion ``(w, vx, vy)``, force
``(n, fx, fy)``. Per moving joint k with motion axis S (``(1, 0, 0)`` revolute, ``(0, u)``
prismatic) and a rotor ``J_m`` geared by N whose stator is on the parent:

.. code:: text

    I^A = I_body + sum over children of shift(I^a_child)          (children first)
    U   = I^A S + N J_m e,   D = S^T I^A S + N^2 J_m,   e = (1, 0, 0)
    I^a = I^A + J_m e e^T - U U^T / D
    p^A = sum shift*(p^a_child),  u = b_k - S^T p^A,  p^a = p^A + U u / D   (per column)
    a   = shift(a_parent),  qdd_k = (u - U^T a) / D,  a += S qdd_k            (parents first)

The rotor turns at ``w_parent + N qd_k`` (the same exact model as ``ad_dynamics._rotors``): it
adds ``J_m`` to what the parent feels and ``N J_m`` to the coupling. A weld passes its child's
articulated inertia up unchanged. ``tests/test_articulated.py`` checks ``M^-1 B`` against
``M`` itself to 1e-12 on serial, branched, sliding, welded and geared trees.
"""

from __future__ import annotations

import casadi as ca

from planar_sym.model.description import GROUND, Description

from .recursion import Tree

Sym3 = list  # a symmetric 3 x 3 as its six entries (a, b, c, e, f, g): [[a b c] [b e f] [c f g]]


def _shift_inertia(i: Sym3, d: ca.SX) -> Sym3:
    """A planar spatial inertia about point A, expressed about B = A + d (14 operations)."""
    a, b, c, e, f, g = i
    b2 = b + d[1] * e - d[0] * f
    c2 = c + d[1] * f - d[0] * g
    return [a + d[1] * (b + b2) - d[0] * (c + c2), b2, c2, e, f, g]


def _shift_force(f: list, d: ca.SX) -> list:
    """A force about A, about B = A + d: the moment changes by -d x F."""
    return [f[0] + d[1] * f[1] - d[0] * f[2], f[1], f[2]]


def _shift_motion(m: list, d: ca.SX) -> list:
    """A motion about A, about B = A + d: the point velocity changes by w z x d."""
    return [m[0], m[1] - m[0] * d[1], m[2] + m[0] * d[0]]


def _times(i: Sym3, v: list) -> list:
    a, b, c, e, f, g = i
    return [a * v[0] + b * v[1] + c * v[2], b * v[0] + e * v[1] + f * v[2],
            c * v[0] + f * v[1] + g * v[2]]


def _dot(u: list, v: list) -> ca.SX:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


class Articulated:
    """The inertia-only articulated-body factorisation of one tree (depends on q and p)."""

    def __init__(self, desc: Description, tree: Tree):
        s = tree.sym
        self.desc, self.tree = desc, tree
        zero, one = ca.SX(0.0), ca.SX(1.0)
        children: dict[str, list] = {}
        for j in desc.tree_joints:
            children.setdefault(j.parent, []).append(j)
        self.children = children
        ref: dict[str, ca.SX] = {GROUND: ca.SX.zeros(2, 1)}
        axis: dict[str, list] = {}
        k = 0
        self.coordinate: dict[str, int] = {}
        for j in desc.tree_joints:
            if j.type == "prismatic":
                ref[j.child] = tree.at(j.child, j.child_point)
                u = tree.slide_axis(j)
                axis[j.name] = [zero, u[0], u[1]]
            else:
                ref[j.child] = tree.at(j.parent, j.parent_point)
                if j.type == "revolute":
                    axis[j.name] = [one, zero, zero]
            if j.moves:
                self.coordinate[j.name] = k
                k += 1
        self.ref, self.axis = ref, axis
        self.U: dict[str, list] = {}
        self.D: dict[str, ca.SX] = {}
        passed: dict[str, Sym3] = {}  # each joint's I^a, about its child's reference
        for j in reversed(desc.tree_joints):  # children before parents
            body = j.child
            m = s.param(f"m_{body}")
            r = tree.cg(body) - ref[body]
            inertia = [s.param(f"izz_{body}") + m * ca.dot(r, r), -m * r[1], m * r[0],
                       m, zero, m]
            for c in children.get(body, []):
                shifted = _shift_inertia(passed[c.name], ref[body] - ref[c.child])
                inertia = [x + y for x, y in zip(inertia, shifted)]
            if not j.moves:
                passed[j.name] = inertia
                continue
            S = axis[j.name]
            U = _times(inertia, S)
            D = _dot(S, U)
            if j.actuator is not None and s.has(f"jm_{j.name}"):
                jm, gear = s.param(f"jm_{j.name}"), s.param(f"gear_{j.name}", 1.0)
                U = [U[0] + gear * jm, U[1], U[2]]
                D = D + gear * gear * jm
                inertia = [inertia[0] + jm, *inertia[1:]]
            a, b, c, e, f, g = inertia
            w = [U[0] / D, U[1] / D, U[2] / D]  # U / D once, then U U^T / D is 6 products
            passed[j.name] = [a - U[0] * w[0], b - U[0] * w[1], c - U[0] * w[2],
                              e - U[1] * w[1], f - U[1] * w[2], g - U[2] * w[2]]
            self.U[j.name], self.D[j.name] = U, D

    def solve(self, b: ca.SX) -> ca.SX:
        """``M^-1 b`` for ``b`` (n, k): one backward and one forward pass per column."""
        return ca.horzcat(*[self._column(b[:, c]) for c in range(b.shape[1])])

    def _column(self, b: ca.SX) -> ca.SX:
        desc, ref, zero = self.desc, self.ref, ca.SX(0.0)
        passed: dict[str, list] = {}
        u: dict[str, ca.SX] = {}
        for j in reversed(desc.tree_joints):
            force = [zero, zero, zero]
            for c in self.children.get(j.child, []):
                shifted = _shift_force(passed[c.name], ref[j.child] - ref[c.child])
                force = [x + y for x, y in zip(force, shifted)]
            if j.moves:
                u[j.name] = b[self.coordinate[j.name]] - _dot(self.axis[j.name], force)
                ratio = u[j.name] / self.D[j.name]
                force = [x + U * ratio for x, U in zip(force, self.U[j.name])]
            passed[j.name] = force
        out = [zero] * len(self.coordinate)
        acc: dict[str, list] = {GROUND: [zero, zero, zero]}
        for j in desc.tree_joints:  # parents before children
            a = _shift_motion(acc[j.parent], ref[j.child] - ref[j.parent])
            if j.moves:
                qdd = (u[j.name] - _dot(self.U[j.name], a)) / self.D[j.name]
                a = [x + s * qdd for x, s in zip(a, self.axis[j.name])]
                out[self.coordinate[j.name]] = qdd
            acc[j.child] = a
        return ca.vertcat(*out)
