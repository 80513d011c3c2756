"""A Pinocchio model of a description's spanning tree: the independent engine of the tests and
the benchmarks (tests/pinocchio_model.py re-exports it; this module needs no pytest).

* one ``JointModelRZ`` per revolute tree joint, placed in the parent joint's frame at the
  parent point; the placement carries the rotation of the parent *body* frame in its joint
  frame (non-identity only below a weld or a prismatic joint with a drawn relative rotation),
  so that the joint angle is exactly our q (child frame angle minus parent frame angle);
* one ``JointModelPrismaticUnaligned`` per prismatic tree joint, its axis ``[ux, uy, 0]`` the
  description's unit axis in the parent body's frame, placed at the parent point moved by the
  drawn offset ``s0`` along the axis, so that its coordinate is exactly our d (the child point's
  displacement along the axis from the drawn pose); the child body keeps its drawn angle to
  the parent (a rotation in the body placement);
* the child body's frame sits at minus its child point in the new joint frame;
* welded bodies are appended to their parent's joint at the parent point, rotated by the drawn
  relative angle;
* inertia ``pin.Inertia(m, [cgx, cgy, 0], diag(0, 0, izz))`` in the body frame (a point mass,
  ``mass_at``: izz = 0); gravity ``[gx, gy, 0]``. Loop joints are ignored.

Joint order. Pinocchio's ``crba`` (and everything built on its subtree bookkeeping) assumes
the joints were added depth-first: parents before children and every subtree a contiguous
block of q/v indices. A description keeps its file's order where the tree allows (parents
before children only), so a file that interleaves branches (A1, A2, elbow1, elbow2) would give
a model whose ``crba`` is silently wrong while ``rnea`` and ``aba`` (which only follow the
parent links) stay right. ``pinocchio_tree`` therefore adds the joints depth-first (siblings in
file order) and returns the permutation between our coordinates and Pinocchio's indices;
``pinocchio_model`` (the older interface, our order assumed) refuses a description whose
depth-first order differs from its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from planar_sym.model import description
from planar_sym.model.description import GROUND
from planar_sym.model.description.types import snap_offset

#: joint orders ``pinocchio_tree`` can build in: depth-first (what Pinocchio needs) or the
#: description's own (kept to show what goes wrong, tests/test_pinocchio_builder.py)
ORDERS = ("depth_first", "description")


def xyz(xy) -> np.ndarray:
    return np.array([xy[0], xy[1], 0.0])


def rotz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class PinocchioTree:
    """A Pinocchio model of the spanning tree and how its indices map to our coordinates.

    Attributes
    ----------
    model : pinocchio.Model
        One joint per coordinate (nq == nv == n: every joint has one degree of freedom).
    where : dict of str to (int, pinocchio.SE3)
        Every body's joint id and the placement of its frame in that joint's frame.
    order : tuple of int
        ``order[k]`` is Pinocchio's q/v index of our coordinate k (``desc.coordinates[k]``).
    """

    model: pin.Model
    where: dict
    order: tuple[int, ...]

    @property
    def identity(self) -> bool:
        """Whether Pinocchio's indices are ours (no permutation)."""
        return self.order == tuple(range(len(self.order)))

    def to_pin(self, x) -> np.ndarray:
        """Our coordinate order -> Pinocchio's, along the last axis (q, qd, qdd, tau)."""
        x = np.asarray(x, dtype=float)
        out = np.empty_like(x)
        out[..., list(self.order)] = x
        return out

    def from_pin(self, x) -> np.ndarray:
        """Pinocchio's index order -> ours, along the last axis (a vector, or Jacobian columns)."""
        return np.asarray(x)[..., list(self.order)]

    def matrix_from_pin(self, m) -> np.ndarray:
        """An n x n matrix (M) in Pinocchio's order -> ours, rows and columns."""
        idx = list(self.order)
        return np.asarray(m)[np.ix_(idx, idx)]


def depth_first(desc: description.Description) -> list:
    """The tree joints depth-first from ground: each joint followed by its whole subtree,
    siblings in the description's order."""
    children: dict[str, list] = {}
    for j in desc.tree_joints:
        children.setdefault(j.parent, []).append(j)
    out: list = []

    def visit(body: str) -> None:
        for j in children.get(body, []):
            out.append(j)
            visit(j.child)

    visit(GROUND)
    assert len(out) == len(desc.tree_joints), "tree joints not all reached from ground"
    return out


def pinocchio_tree(desc: description.Description, order: str = "depth_first") -> PinocchioTree:
    """The Pinocchio model of ``desc``'s spanning tree, joints added in ``order``.

    ``"depth_first"`` (the default) is the order Pinocchio's algorithms assume; ``"description"``
    adds them in the description's tree order (parents before children, branches possibly
    interleaved), the way this builder used to: only for showing the difference.
    """
    if order not in ORDERS:
        raise ValueError(f"order must be one of {ORDERS} (got {order!r})")
    joints = depth_first(desc) if order == "depth_first" else list(desc.tree_joints)
    model = pin.Model()
    model.gravity = pin.Motion(xyz(desc.gravity_m_s2), np.zeros(3))
    where = {GROUND: (0, pin.SE3.Identity())}
    v_index: dict[str, int] = {}
    for j in joints:
        parent, child = desc.bodies[j.parent], desc.bodies[j.child]
        pid, parent_pl = where[j.parent]
        at = parent_pl * pin.SE3(np.eye(3), xyz(parent.points_m[j.parent_point]))
        to_child_frame = pin.SE3(np.eye(3), -xyz(child.points_m[j.child_point]))
        rel = child.drawn_angle_rad - parent.drawn_angle_rad
        if j.type == "revolute":
            jid = model.addJoint(pid, pin.JointModelRZ(), at, j.name)
            body_pl = to_child_frame
        elif j.type == "prismatic":
            axis = xyz(j.axis)
            s0 = snap_offset(desc.slide_offset_m(j))
            jid = model.addJoint(pid, pin.JointModelPrismaticUnaligned(axis),
                                 at * pin.SE3(np.eye(3), s0 * axis), j.name)
            body_pl = pin.SE3(rotz(rel), np.zeros(3)) * to_child_frame
        else:  # weld
            jid = pid
            body_pl = at * pin.SE3(rotz(rel), np.zeros(3)) * to_child_frame
        if j.moves:
            v_index[j.name] = model.idx_vs[jid]
        inertia = pin.Inertia(child.mass_kg, xyz(child.cg_m), np.diag([0.0, 0.0, child.izz_kg_m2]))
        model.appendBodyToJoint(jid, inertia, body_pl)
        where[j.child] = (jid, body_pl)
    assert model.nq == model.nv == len(desc.coordinates)
    return PinocchioTree(model, where, tuple(v_index[c] for c in desc.coordinates))


def pinocchio_model(desc: description.Description):
    """(model, body placements {body: (joint id, SE3 of the body frame in the joint frame)}),
    Pinocchio's q/v in our coordinate order.

    Built depth-first; a description whose depth-first order is not its own coordinate order
    (branches interleaved in the file) is refused, since the caller would index it as ours:
    use ``pinocchio_tree`` and its permutation for such a robot.
    """
    tree = pinocchio_tree(desc)
    if not tree.identity:
        raise ValueError(f"{desc.name}: its tree joints interleave branches, so Pinocchio's "
                         f"(depth-first) indices {tree.order} are not its coordinate order: use "
                         "pinocchio_tree(desc) and its to_pin/from_pin permutation")
    return tree.model, tree.where


def build(desc: description.Description):
    """(model, data) for timing."""
    model, _ = pinocchio_model(desc)
    return model, model.createData()


def rnea_loop(model, data, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """``pinocchio.rnea`` sample by sample in a Python loop; (N, n) in, (N, n) out."""
    import pinocchio as pin

    out = np.empty_like(q)
    rnea = pin.rnea
    for k in range(len(q)):
        out[k] = rnea(model, data, q[k], qd[k], qdd[k])
    return out
