"""A Pinocchio model of a description's spanning tree: the independent engine of the tests and
the benchmarks (tests/pinocchio_model.py re-exports it; this module needs no pytest).

* one ``JointModelRZ`` per revolute tree joint, placed in the parent joint's frame at the
  parent point; the placement carries the rotation of the parent *body* frame in its joint
  frame (non-identity only below a weld with a drawn relative rotation), so that the joint angle
  is exactly our q (child frame angle minus parent frame angle);
* the child body's frame sits at minus its child point in the new joint frame;
* welded bodies are appended to their parent's joint at the parent point, rotated by the drawn
  relative angle;
* inertia ``pin.Inertia(m, [cgx, cgy, 0], diag(0, 0, izz))`` in the body frame; gravity
  ``[gx, gy, 0]``. Loop joints are ignored.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from planar_sym.model import description
from planar_sym.model.description import GROUND


def xyz(xy) -> np.ndarray:
    return np.array([xy[0], xy[1], 0.0])


def rotz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def pinocchio_model(desc: description.Description):
    """(model, body placements {body: (joint id, SE3 of the body frame in the joint frame)})."""
    model = pin.Model()
    model.gravity = pin.Motion(xyz(desc.gravity_m_s2), np.zeros(3))
    where = {GROUND: (0, pin.SE3.Identity())}
    for j in desc.tree_joints:
        parent, child = desc.bodies[j.parent], desc.bodies[j.child]
        pid, parent_pl = where[j.parent]
        at = parent_pl * pin.SE3(np.eye(3), xyz(parent.points_m[j.parent_point]))
        to_child_frame = pin.SE3(np.eye(3), -xyz(child.points_m[j.child_point]))
        if j.type == "revolute":
            jid = model.addJoint(pid, pin.JointModelRZ(), at, j.name)
            body_pl = to_child_frame
        else:
            rel = child.drawn_angle_rad - parent.drawn_angle_rad
            jid = pid
            body_pl = at * pin.SE3(rotz(rel), np.zeros(3)) * to_child_frame
        inertia = pin.Inertia(child.mass_kg, xyz(child.cg_m), np.diag([0.0, 0.0, child.izz_kg_m2]))
        model.appendBodyToJoint(jid, inertia, body_pl)
        where[j.child] = (jid, body_pl)
    return model, where


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
