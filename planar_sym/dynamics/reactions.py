"""Joint loads: the force and the couple every joint transmits, along an inverse-dynamics motion.

Sign convention (as MSC Adams reports a joint's reaction): for each joint, tree joints and the
cut joints of closed chains alike,

.. code:: text

    F_j  (N, world x and y)  the force the joint's parent body exerts on its child body,
                             acting at the joint's child point
    M_j  (N*m)               the couple the parent exerts on the child (counter-clockwise +)

and the child exerts ``-F_j``, ``-M_j`` on the parent at the same point. ``|F_j|`` is the bearing
load. Loads are link side: what the child's links feel, so every body's free-body balance closes
with them. The couple is the gearbox's output less the joint's friction at a revolute joint (0
at a passive one), a reaction moment at a weld and at a prismatic joint. A prismatic joint's
force splits into its axial part ``F_j . u`` (along the slide axis ``u``, in world axes; 0 if
passive) and its normal part ``F_j . (k x u)`` (``k x u`` = u turned +90 deg).

The drive train (``Robot.drive_train``) is reported beside: ``drive`` is the generalised force
the actuator delivers at its joint (the Lagrangian tau of the inverse dynamics, its rotor and
friction included) and ``motor_torque`` that torque at the motor, tau / N. They differ from
the link-side couple (or axial force) by the joint's friction and the rotor's inertia:

.. code:: text

    tau_j = M_j (or F_j . u) + D_j(qd_j) + N_j J_j (alpha_parent + N_j qdd_j)

A rotor turns with the body that carries its stator (the joint's parent) at alpha_parent plus
N qdd_j, so its spin J (alpha_parent + N qdd_j) is part of that body's moment balance.

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

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, LibraryError
from ..model.arrays import as_samples
from ..model.description import GROUND
from ..model.robot import Robot
from .series import Series


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
        M_j (N*m): parent on child, link side, from the child subtree's moment balance. At a
        revolute joint without a drive model it equals the Lagrangian tau (0 at a passive
        joint of a closed chain and at a cut joint); welds and prismatic joints: the reaction
        moment.
    axial, normal : dict of str to ndarray (N,)
        Prismatic joints only: F_j along the slide axis and across it (N), link side.
    drive : dict of str to ndarray (N,)
        Actuated joints: the generalised force the actuator delivers at the joint (N*m, N at a
        slider): the inverse dynamics' tau, its rotor and friction included.
    motor_torque : dict of str to ndarray (N,)
        Actuated joints: that torque at the motor, tau / N (N*m).
    """

    names: tuple[str, ...]
    types: tuple[str, ...]
    force: np.ndarray
    couple: np.ndarray
    axial: dict[str, np.ndarray]
    normal: dict[str, np.ndarray]
    drive: dict[str, np.ndarray] = field(default_factory=dict)
    motor_torque: dict[str, np.ndarray] = field(default_factory=dict)

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
    slides: tuple[tuple[int, str], ...]  # prismatic tree joints: (index, name)
    #: rotors with inertia: (coordinate, body carrying the stator or -1 for ground, N, J kg*m^2)
    rotors: tuple[tuple[int, int, float, float], ...] = ()


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
    by_name = {j["name"]: j for j in tree}
    rotors = tuple(
        (d.coordinate, bodies.index(by_name[d.joint]["parent"])
         if by_name[d.joint]["parent"] != GROUND else -1, d.gear_ratio, d.rotor_inertia)
        for d in robot.drive_train.drives if d.rotor_inertia != 0.0)
    s = _Structure(
        names=tuple(j["name"] for j in (*tree, *cuts)),
        types=tuple(j["type"] for j in (*tree, *cuts)),
        mass=mass,
        izz=np.array([par.get(f"izz_{b}", 0.0) for b in bodies]),
        weight=gravity[:, None] * mass,
        subtree=incidence(tree, lambda j, b: b in below[j["child"]]).T.copy(),
        cut_force=parent - child,
        cut_moment=np.vstack([-child, parent]),
        slides=tuple((k, j["name"]) for k, j in enumerate(tree) if j["type"] == "prismatic"),
        rotors=rotors)
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
    _structure(robot)  # a library that predates joint loads is refused before anything runs
    q, qd, qdd = (as_samples(k, a, robot.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                  ("qdd", qdd)))
    if robot.is_closed_chain:
        tau, lam = inverse or robot.closed_chain_inverse_dynamics(q, qd, qdd, t=t)
    else:
        tau, lam = (inverse[0] if inverse else robot.tree_inverse_dynamics(q, qd, qdd)), None
    motion = robot.body_motion(q, qd, qdd)
    return loads_of_motion(robot, qdd, tau, lam, motion)


def loads_of_motion(robot: Robot, qdd: np.ndarray, tau, lam, motion) -> JointLoads:
    """``joint_loads`` from one pass through the model, made by the caller on checked samples:
    ``qdd`` (N, n) every coordinate's acceleration, the inverse dynamics ``tau`` and ``lam``
    (a closed chain's ``closed_chain_inverse_dynamics`` output; a tree's tau (N, n) at every
    coordinate and None) and ``motion``, ``Robot.body_motion`` of the same samples."""
    n_q, s = robot.n, _structure(robot)
    n_s = len(qdd)
    if robot.is_closed_chain:
        tau_act, tau = tau, np.zeros((n_s, n_q))
        tau[:, list(robot.actuated)] = tau_act
        lam = np.reshape(lam, (n_s, -1))
    else:
        tau = np.reshape(tau, (n_s, n_q))
        lam = np.zeros((n_s, 0))
    acc, cg, points = motion
    n_t, n_l = len(s.subtree[0]), lam.shape[1] // 2
    n_j = n_t + n_l
    # component arrays (N, bodies or points): acc (N, 3, bodies), cg (N, 2, bodies), points
    # (N, 2, points), shaped so by the generated functions for a q of shape (N, n)
    px, py = points.transpose(1, 0, 2)
    # per body: f = m a - m g and I alpha + c x f, less the cut forces and their moments
    fx = acc[:, 0] * s.mass - s.weight[0]
    fy = acc[:, 1] * s.mass - s.weight[1]
    mz = acc[:, 2] * s.izz + cg[:, 0] * fy - cg[:, 1] * fx
    for coordinate, body, ratio, inertia in s.rotors:  # a rotor's spin, on its stator's body
        if body >= 0:
            mz[:, body] += inertia * (acc[:, 2, body] + ratio * qdd[:, coordinate])
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
    couple = np.zeros((n_s, n_j))
    couple[:, :n_t] = mz @ s.subtree - (px[:, :n_t] * big_fy - py[:, :n_t] * big_fx)
    axial, normal = {}, {}
    for i, (k, name) in enumerate(s.slides):
        ux, uy = px[:, n_j + n_l + i], py[:, n_j + n_l + i]
        axial[name] = big_fx[:, k] * ux + big_fy[:, k] * uy
        normal[name] = big_fy[:, k] * ux - big_fx[:, k] * uy
    drives = robot.drive_train.drives
    drive = {d.joint: tau[:, d.coordinate] for d in drives}
    motor = {d.joint: tau[:, d.coordinate] / d.gear_ratio for d in drives}
    return JointLoads(s.names, s.types, force, couple, axial, normal, drive, motor)


def load_series(loads: JointLoads, driven: set[str] = frozenset()) -> list[Series]:
    """Every joint's load as series of that ``joint``: ``jfx``, ``jfy`` (N, world axes, the
    parent body on the child body; columns ``jfx_<joint>_n``), ``jload`` (|F|, the bearing
    load); the reaction couple ``jm`` (N*m) of welds and prismatic joints, and of the revolute
    joints in ``driven`` (with an actuator model: the gearbox's output the link feels, less
    friction and rotor than the torque; without one a revolute joint's couple is its torque,
    or 0 if passive); a prismatic joint's normal force ``jfn`` (N)."""
    out = []
    load = loads.magnitude
    for i, (name, kind) in enumerate(zip(loads.names, loads.types)):
        out += [Series("jfx", "N", loads.force[:, i, 0], joint=name),
                Series("jfy", "N", loads.force[:, i, 1], joint=name),
                Series("jload", "N", load[:, i], joint=name)]
        if kind in ("weld", "prismatic") or (kind == "revolute" and name in driven):
            out.append(Series("jm", "N*m", loads.couple[:, i], joint=name))
        if kind == "prismatic":
            out.append(Series("jfn", "N", loads.normal[name], joint=name))
    return out
