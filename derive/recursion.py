"""The robot's kinematics as a recursion over its tree, in CasADi SX: the numeric route.

Every body's frame is its parent's frame moved by one joint, so each angle, sine, cosine and
origin is computed once and shared by every body beyond it: O(n) operations for the whole tree,
where the expanded closed forms of ``kinematics.py`` repeat each body's whole chain (O(n^2)
positions, and the derivatives of those grow faster still). The same description fields and
parameter names as the SymPy route; ``tests/test_codegen_vs_sympy.py`` checks the two agree.

.. code:: text

    theta_child = theta_parent + q_k                   (revolute; weld/prismatic: + drawn angle)
    r_joint     = o_parent + R(theta_parent) p_parent  (+ R(theta_parent) u (s0 + q_k), prismatic)
    o_child     = r_joint - R(theta_child) p_child
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca

from planar_sym.model.description import GROUND, Description
from planar_sym.model.description.types import Joint


@dataclass
class Symbols:
    """The function inputs ``q, qd, qdd, tau, p`` and the parameters by name."""

    q: ca.SX
    qd: ca.SX
    qdd: ca.SX
    tau: ca.SX
    p: ca.SX
    names: dict[str, int]

    @classmethod
    def of(cls, desc: Description) -> Symbols:
        n, params = len(desc.coordinates), desc.parameters()
        q, qd, qdd, tau = (ca.SX.sym(k, n) for k in ("q", "qd", "qdd", "tau"))
        return cls(q, qd, qdd, tau, ca.SX.sym("p", len(params)),
                   {par.name: i for i, par in enumerate(params)})

    def param(self, name: str, default: float = 0.0) -> ca.SX:
        """A parameter, or ``default`` where the description makes it structural (absent)."""
        i = self.names.get(name)
        return ca.SX(default) if i is None else self.p[i]

    def has(self, name: str) -> bool:
        return name in self.names


@dataclass
class Frame:
    """One body frame: absolute angle, its cosine and sine, and origin (world axes, m)."""

    angle: ca.SX
    cos: ca.SX
    sin: ca.SX
    origin: ca.SX  # (2, 1)

    def rotate(self, v: tuple[ca.SX, ca.SX]) -> ca.SX:
        return ca.vertcat(self.cos * v[0] - self.sin * v[1], self.sin * v[0] + self.cos * v[1])

    def point(self, v: tuple[ca.SX, ca.SX]) -> ca.SX:
        return self.origin + self.rotate(v)


@dataclass
class Tree:
    """Every body's frame (ground included), from one walk over the tree joints."""

    desc: Description
    sym: Symbols
    frames: dict[str, Frame] = field(default_factory=dict)

    def body_vec(self, body: str, point: str | None) -> tuple[ca.SX, ca.SX]:
        """A body-frame point (the centre of gravity for None), zero where structural."""
        if point is None:
            return (self.sym.param(f"cgx_{body}"), self.sym.param(f"cgy_{body}"))
        return (self.sym.param(f"px_{body}_{point}"), self.sym.param(f"py_{body}_{point}"))

    def at(self, body: str, point: str | None) -> ca.SX:
        """World position (m) of a body's point, or its centre of gravity for None."""
        return self.frames[body].point(self.body_vec(body, point))

    def cg(self, body: str) -> ca.SX:
        return self.at(body, None)

    def slide_axis(self, j: Joint) -> ca.SX:
        """A prismatic joint's axis in world axes (a unit vector)."""
        return self.frames[j.parent].rotate((ca.SX(j.axis[0]), ca.SX(j.axis[1])))


def walk(desc: Description, sym: Symbols | None = None) -> Tree:
    """The frames of every body, parents before children (``desc.tree_joints``' order)."""
    sym = sym or Symbols.of(desc)
    tree = Tree(desc, sym)
    zero = ca.SX(0.0)
    tree.frames[GROUND] = Frame(zero, ca.SX(1.0), zero, ca.SX.zeros(2, 1))
    k = 0
    for j in desc.tree_joints:
        parent = tree.frames[j.parent]
        joint_at = tree.at(j.parent, j.parent_point)
        if j.type == "revolute":
            angle = parent.angle + sym.q[k]
            child = Frame(angle, ca.cos(angle), ca.sin(angle), ca.SX.zeros(2, 1))
            k += 1
        else:  # weld and prismatic: the parent's frame turned by the drawn relative angle
            rel = desc.bodies[j.child].drawn_angle_rad - desc.bodies[j.parent].drawn_angle_rad
            child = _turned(parent, rel)
        if j.type == "prismatic":
            travel = sym.param(f"s0_{j.name}") + sym.q[k]
            k += 1
            joint_at = joint_at + tree.slide_axis(j) * travel
        child.origin = joint_at - child.rotate(tree.body_vec(j.child, j.child_point))
        tree.frames[j.child] = child
    return tree


def cross_z(v: ca.SX) -> ca.SX:
    """z x v: the plane vector v turned by +90 degrees (the recursions' cross products)."""
    return ca.vertcat(-v[1], v[0])


def _turned(parent: Frame, rel: float) -> Frame:
    """The parent's frame turned by a constant angle: its sine and cosine by the addition
    theorem (no new trigonometric call), the same frame where the angle is zero."""
    if rel == 0.0:
        return Frame(parent.angle, parent.cos, parent.sin, ca.SX.zeros(2, 1))
    c, s = math.cos(rel), math.sin(rel)
    return Frame(parent.angle + rel, parent.cos * c - parent.sin * s,
                 parent.sin * c + parent.cos * s, ca.SX.zeros(2, 1))
