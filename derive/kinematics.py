"""Planar kinematics of a tree: every position as a sum of rotated body-frame vectors.

Keeping positions as ``sum_k R(theta_k) v_k`` (theta_k a sum of joint angles) lets the kinetic
energy be written straight in compact form: ``v_k . v_l cos(theta_l - theta_k) - ...``, which is
the textbook ``cos(q2)`` instead of ``cos(q1) cos(q1 + q2) + sin(q1) sin(q1 + q2)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from planar_sym.model.description import GROUND, Description

from .symbols import Symbols

Vec = tuple[sp.Expr, sp.Expr]


@dataclass(frozen=True)
class Rotated:
    """``sum_k R(theta_k) v_k``: a planar position kept as rotated body-frame vectors."""

    terms: tuple[tuple[sp.Expr, Vec], ...]

    def __add__(self, other: Rotated) -> Rotated:
        merged: dict[sp.Expr, Vec] = {}
        for th, v in (*self.terms, *other.terms):
            a = merged.get(th, (sp.S.Zero, sp.S.Zero))
            merged[th] = (a[0] + v[0], a[1] + v[1])
        return Rotated(tuple((th, v) for th, v in merged.items() if v != (0, 0)))

    def position(self) -> sp.Matrix:
        x = sum((sp.cos(th) * v[0] - sp.sin(th) * v[1] for th, v in self.terms), sp.S.Zero)
        y = sum((sp.sin(th) * v[0] + sp.cos(th) * v[1] for th, v in self.terms), sp.S.Zero)
        return sp.Matrix([x, y])

    def speed_squared(self, rate) -> sp.Expr:
        """|d/dt position|^2 with ``rate(e)`` the time derivative of an expression in q.

        Uses v_k^T R(theta_l - theta_k) v_l = cos(D)(v_k . v_l) - sin(D)(v_k x v_l). A vector
        that a prismatic joint lengthens (v_k depends on q) moves as well as turns: its term's
        velocity is R(theta_k) w_k with w_k = theta_k' J v_k + v_k' (J the quarter turn), and
        the same identity applies to the w's.
        """
        coords = _coords(rate)
        if any((sp.sympify(v[0]).free_symbols | sp.sympify(v[1]).free_symbols) & coords
               for _, v in self.terms):
            return self._speed_squared_sliding(rate)
        total = sp.S.Zero
        for k, (tk, vk) in enumerate(self.terms):
            for l_, (tl, vl) in enumerate(self.terms[k:], start=k):
                d = sp.expand(tl - tk)
                dot = vk[0] * vl[0] + vk[1] * vl[1]
                cross = vk[0] * vl[1] - vk[1] * vl[0]
                term = rate(tk) * rate(tl) * (sp.cos(d) * dot - sp.sin(d) * cross)
                total += term if l_ == k else 2 * term
        return total

    def _speed_squared_sliding(self, rate) -> sp.Expr:
        w = [(tk, (-rate(tk) * vk[1] + rate(vk[0]), rate(tk) * vk[0] + rate(vk[1])))
             for tk, vk in self.terms]
        total = sp.S.Zero
        for k, (tk, wk) in enumerate(w):
            for l_, (tl, wl) in enumerate(w[k:], start=k):
                d = sp.expand(tl - tk)
                dot = wk[0] * wl[0] + wk[1] * wl[1]
                cross = wk[0] * wl[1] - wk[1] * wl[0]
                term = sp.cos(d) * dot - sp.sin(d) * cross
                total += term if l_ == k else 2 * term
        return total


def _coords(rate) -> set:
    """The coordinate symbols a ``rate`` differentiates with respect to."""
    return set(rate.coordinates)


@dataclass(frozen=True)
class Frame:
    """Absolute angle and origin of one body frame as functions of q."""

    angle: sp.Expr
    origin: Rotated

    def point(self, v: Vec) -> Rotated:
        return self.origin + Rotated(((self.angle, v),))


def body_vec(desc: Description, s: Symbols, body: str, point: str | None) -> Vec:
    """A body-frame point (or the centre of gravity, point None) in symbols."""
    if point is None:
        return (s.param(f"cgx_{body}"), s.param(f"cgy_{body}"))
    return (s.param(f"px_{body}_{point}"), s.param(f"py_{body}_{point}"))


def frames(desc: Description, s: Symbols) -> dict[str, Frame]:
    """Frames of every body, walking the tree from the ground."""
    out = {GROUND: Frame(sp.S.Zero, Rotated(()))}
    k = 0
    for j in desc.tree_joints:
        parent = out[j.parent]
        joint_at = parent.point(body_vec(desc, s, j.parent, j.parent_point))
        if j.type == "revolute":
            angle = parent.angle + s.q[k]
            k += 1
        else:  # weld and prismatic: the drawn relative angle, a constant
            rel = desc.bodies[j.child].drawn_angle_rad - desc.bodies[j.parent].drawn_angle_rad
            angle = parent.angle + (sp.Float(rel) if rel else sp.S.Zero)
        if j.type == "prismatic":
            # the child point slides along the axis (parent frame) from its drawn offset
            travel = s.param(f"s0_{j.name}") + s.q[k]
            k += 1
            ux, uy = (_exact(c) for c in j.axis)
            joint_at = joint_at + Rotated(((parent.angle, (travel * ux, travel * uy)),))
        sc = body_vec(desc, s, j.child, j.child_point)
        out[j.child] = Frame(angle, joint_at + Rotated(((angle, (-sc[0], -sc[1])),)))
    return out


def _exact(c: float) -> sp.Expr:
    """An axis component as an exact number where it is one (0, +-1), else a Float."""
    return sp.Integer(int(c)) if c in (0.0, 1.0, -1.0) else sp.Float(c)


class angle_rate:
    """d/dt of an expression in q: an angle (linear in q) or a slide length."""

    def __init__(self, s: Symbols):
        self.s = s
        self.coordinates = frozenset(s.q)

    def __call__(self, e: sp.Expr) -> sp.Expr:
        return sum((sp.diff(e, qi) * qdi for qi, qdi in zip(self.s.q, self.s.qd)), sp.S.Zero)


def task(desc: Description, s: Symbols, fr: dict[str, Frame]) -> sp.Matrix:
    """Task coordinates: tool point (m) and, where the task has one, orientation phi (rad);
    none (0 rows) for a robot without ``[task]``."""
    if desc.task_point is None:
        return sp.zeros(0, 1)
    body, point = desc.task_point
    x = fr[body].point(body_vec(desc, s, body, point)).position()
    if desc.task_orientation:
        x = x.col_join(sp.Matrix([fr[desc.task_orientation].angle]))
    return x
