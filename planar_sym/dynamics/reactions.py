"""Joint loads: the force and the couple every joint transmits, along an inverse-dynamics motion.

Sign convention (as MSC Adams reports a joint's reaction): for each joint, tree joints and the
cut joints of closed chains alike,

.. code:: text

    F_j  (N, world x and y)  the force the joint's parent body exerts on its child body,
                             acting at the joint's child point
    M_j  (N*m)               the couple the parent exerts on the child (counter-clockwise +)

and the child exerts ``-F_j``, ``-M_j`` on the parent at the same point. ``|F_j|`` is the bearing
load. The couple is the motor torque at a revolute joint (the Lagrangian tau: 0 at a passive
joint), a reaction moment at a weld and at a prismatic joint. A prismatic joint's force splits
into its axial part ``F_j . u`` (along the slide axis ``u``, in world axes: the actuator force,
0 if passive) and its normal part ``F_j . (k x u)`` (``k x u`` = u turned +90 deg).

At a cut joint ``F_j = -lambda``: the multipliers of
``M qdd + h = S^T tau + Phi_q^T lambda`` with ``Phi = r(parent point) - r(child point)`` are the
force the child exerts on the parent (``Phi_q^T lambda`` is the generalised force of
``+lambda`` at the parent point and ``-lambda`` at the child point).

Method: Newton-Euler on the description's spanning tree, vectorised over samples. Every body's
cg acceleration and angular acceleration come exact from the generated ``body_motion``; the
joint force is the sum over the child's subtree of ``m (a_cg - g)`` minus the cut forces acting
on the subtree, and the couple follows from the subtree's moment balance about the joint point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, LibraryError
from ..model.description import GROUND
from ..model.robot import Robot, as_samples


@dataclass(frozen=True)
class JointLoads:
    """Loads of every joint at N samples; joint axis ``j`` follows ``names``.

    Attributes
    ----------
    names : tuple of str
        Every joint: tree joints (parents first), then the cut joints.
    types : tuple of str
        ``revolute``, ``prismatic`` or ``weld`` per joint.
    force : ndarray, shape (N, joints, 2)
        F_j (N, world axes): parent on child, at the joint's child point.
    couple : ndarray, shape (N, joints)
        M_j (N*m): parent on child. Revolute joints: the Lagrangian tau (the motor torque; 0 at
        a passive joint of a closed chain and at a cut joint); welds and prismatic joints: the
        reaction moment from Newton-Euler.
    newton_euler_couple : ndarray, shape (N, joints)
        M_j from the moment balance alone, for every joint: equals ``couple`` to rounding (the
        check of the revolute joints' tau; 0 at cut joints).
    axial, normal : dict of str to ndarray (N,)
        Prismatic joints only: F_j along the slide axis (the actuator force) and across it (N).
    """

    names: tuple[str, ...]
    types: tuple[str, ...]
    force: np.ndarray
    couple: np.ndarray
    newton_euler_couple: np.ndarray
    axial: dict[str, np.ndarray]
    normal: dict[str, np.ndarray]

    @property
    def magnitude(self) -> np.ndarray:
        """|F_j| (N), the bearing load, shape (N, joints)."""
        return np.hypot(self.force[..., 0], self.force[..., 1])

    def index(self, joint: str) -> int:
        """Position of ``joint`` (a name) on the joint axis."""
        try:
            return self.names.index(joint)
        except ValueError:
            raise InputError(f"no joint {joint!r}; joints: {', '.join(self.names)}") from None


@dataclass(frozen=True)
class _Structure:
    """What the load computation needs from the manifest and the parameters, as arrays."""

    names: tuple[str, ...]
    types: tuple[str, ...]
    mass: np.ndarray  # (B,) kg
    izz: np.ndarray  # (B,) kg*m^2
    weight: np.ndarray  # (2, B): m g, N
    subtree: np.ndarray  # (B, T): 1 where body b is at or beyond tree joint j's child
    cut_force: np.ndarray  # (L, B): +1 on the cut's parent (it feels +lambda), -1 on its child
    cut_moment: np.ndarray  # (2L, B): [-child; parent]: moments at the child, then parent points
    revolute: np.ndarray  # (R,) tree joints that are revolute
    revolute_coordinate: np.ndarray  # (R,) their coordinates
    slides: tuple[tuple[int, str], ...]  # prismatic tree joints: (index, name)


_CACHE: dict[tuple, _Structure] = {}


def _structure(robot: Robot) -> _Structure:
    m = robot.library.manifest
    key = (str(robot.library.folder), m["input_hash"], robot.p.tobytes())
    if key in _CACHE:
        return _CACHE[key]
    if "joints" not in m or "gravity_direction" not in m:
        raise LibraryError(f"{robot.name}: the generated code in {robot.library.folder} predates "
                           "joint loads (its manifest lists no joints): re-derive it (`make "
                           "derive`, or `planar-sym derive` for your own robot)")
    par = robot.parameters
    bodies = list(robot.body_names)
    n_b = len(bodies)
    tree = [j for j in m["joints"] if not j["closes_loop"]]
    cuts = [j for j in m["joints"] if j["closes_loop"]]
    below: dict[str, set[str]] = {b: {b} for b in bodies}
    for j in reversed(tree):  # parents come first: reversed, children are complete first
        if j["parent"] != GROUND:
            below[j["parent"]] |= below[j["child"]]

    def incidence(rows, test) -> np.ndarray:
        return np.array([[test(j, b) for b in bodies] for j in rows],
                        dtype=float).reshape(len(rows), n_b)

    parent = incidence(cuts, lambda j, b: j["parent"] == b)
    child = incidence(cuts, lambda j, b: j["child"] == b)
    mass = np.array([par.get(f"m_{b}", 0.0) for b in bodies])
    gravity = par.get("g", 0.0) * np.array(m["gravity_direction"], dtype=float)
    revolute = [k for k, j in enumerate(tree) if j["type"] == "revolute"]
    s = _Structure(
        names=tuple(j["name"] for j in (*tree, *cuts)),
        types=tuple(j["type"] for j in (*tree, *cuts)),
        mass=mass,
        izz=np.array([par.get(f"izz_{b}", 0.0) for b in bodies]),
        weight=gravity[:, None] * mass,
        subtree=incidence(tree, lambda j, b: b in below[j["child"]]).T.copy(),
        cut_force=parent - child,
        cut_moment=np.vstack([-child, parent]),
        revolute=np.array(revolute, dtype=int),
        revolute_coordinate=np.array([tree[k]["coordinate"] for k in revolute], dtype=int),
        slides=tuple((k, j["name"]) for k, j in enumerate(tree) if j["type"] == "prismatic"))
    if len(_CACHE) > 64:
        _CACHE.clear()
    _CACHE[key] = s
    return s


def joint_loads(robot: Robot, q, qd, qdd, t=None, inverse=None) -> JointLoads:
    """The force and the couple at every joint along a motion (inverse dynamics).

    Parameters
    ----------
    robot : Robot
    q, qd, qdd : array_like, shape (N, n) or (n,)
        Every coordinate (rad or m), its rate and acceleration; on the loops for a closed chain
        (from inverse_kinematics or motion.closure.from_actuated). One sample gives N = 1.
    t : ndarray, shape (N,), optional
        Times (s), only to name a refused sample (off the loops, singular).
    inverse : tuple, optional
        The inverse dynamics of these very samples, when the caller has it already (not
        computed twice): a closed chain's ``closed_chain_inverse_dynamics`` output ``(tau,
        lambda)``, a tree's ``(tau, None)`` with tau (N, n) at every coordinate.

    Returns
    -------
    JointLoads
        ``force`` (N, joints, 2) in N, world axes, the parent body on the child body at the
        joint's child point; ``couple`` (N, joints) in N*m, parent on child; ``axial`` and
        ``normal`` of prismatic joints (N). See the module docstring for the conventions.

    For a tree every coordinate's generalised force ``M qdd + h`` is the joint's torque (at a
    joint without a motor, the torque the motion would need); a closed chain's come from
    ``closed_chain_inverse_dynamics``, which also gives the cut forces and refuses samples off
    the loops or at a singular pose.
    """
    n_q = robot.n
    q, qd, qdd = (as_samples(k, a, n_q, times=t) for k, a in (("q", q), ("qd", qd),
                                                              ("qdd", qdd)))
    n_s = len(q)
    s = _structure(robot)
    if robot.is_closed_chain:
        tau_act, lam = inverse or robot.closed_chain_inverse_dynamics(q, qd, qdd, t=t)
        tau = np.zeros((n_s, n_q))
        tau[:, list(robot.actuated)] = tau_act
        lam = np.reshape(lam, (n_s, -1))
    else:
        tau = inverse[0] if inverse else robot.tree_inverse_dynamics(q, qd, qdd)
        tau = np.reshape(tau, (n_s, n_q))
        lam = np.zeros((n_s, 0))
    acc, cg, points = robot.body_motion(q, qd, qdd)
    n_b, n_t, n_l = len(s.mass), len(s.subtree[0]), lam.shape[1] // 2
    n_j = n_t + n_l
    # component arrays (N, bodies or points): each component's columns contiguous per sample
    acc, cg = np.reshape(acc, (n_s, 3, n_b)), np.reshape(cg, (n_s, 2, n_b))
    px, py = np.reshape(points, (n_s, 2, -1)).transpose(1, 0, 2)
    # per body: f = m a - m g and I alpha + c x f, less the cut forces and their moments
    fx = acc[:, 0] * s.mass - s.weight[0]
    fy = acc[:, 1] * s.mass - s.weight[1]
    mz = acc[:, 2] * s.izz + cg[:, 0] * fy - cg[:, 1] * fx
    if n_l:
        lx, ly = lam[:, 0::2], lam[:, 1::2]
        fx -= lx @ s.cut_force
        fy -= ly @ s.cut_force
        rx, ry = px[:, n_t:n_j + n_l], py[:, n_t:n_j + n_l]  # cut child, then parent points
        mz -= (rx * np.hstack([ly, ly]) - ry * np.hstack([lx, lx])) @ s.cut_moment
    # each tree joint carries its child's subtree: one product per component for every joint
    big_fx, big_fy = fx @ s.subtree, fy @ s.subtree
    force = np.empty((n_s, n_j, 2))
    force[:, :n_t, 0], force[:, :n_t, 1] = big_fx, big_fy
    np.negative(lam.reshape(n_s, n_l, 2), out=force[:, n_t:])
    ne_couple = np.zeros((n_s, n_j))
    ne_couple[:, :n_t] = mz @ s.subtree - (px[:, :n_t] * big_fy - py[:, :n_t] * big_fx)
    couple = ne_couple.copy()
    couple[:, s.revolute] = tau[:, s.revolute_coordinate]
    axial, normal = {}, {}
    for i, (k, name) in enumerate(s.slides):
        ux, uy = px[:, n_j + n_l + i], py[:, n_j + n_l + i]
        axial[name] = big_fx[:, k] * ux + big_fy[:, k] * uy
        normal[name] = big_fy[:, k] * ux - big_fx[:, k] * uy
    return JointLoads(s.names, s.types, force, couple, ne_couple, axial, normal)
