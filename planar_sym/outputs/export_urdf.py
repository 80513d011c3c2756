"""URDF of a planar robot that is a tree (an open chain); a closed chain is refused.

Construction (``export_model.RigidModel``, the robot's current parameters):

* links are the bodies; ``ground`` is the root link (fixed base: the world frame, no inertia);
* a link's frame is its body frame moved to the body's point of the joint to its parent (URDF
  puts a link's frame at its parent joint), axes unchanged; so a point ``p`` of body B (body
  frame) is at ``p - c_B`` in link B, ``c_B`` that joint's child point;
* a revolute joint is ``continuous`` (planar-sym has no joint limits) about z, its ``origin``
  the parent point in the parent link, no rotation: the joint angle is exactly our q (child
  frame angle minus parent frame angle). Pinocchio makes a ``continuous`` joint a
  ``JointModelRUBZ``: nq = 2 (cos q, sin q), nv = 1;
* a prismatic joint: ``origin`` at the parent point moved by the drawn offset ``s0`` along the
  axis, rotated by the drawn relative angle; ``axis`` the description's (parent frame) written
  in that rotated joint frame; its coordinate is exactly our d. URDF requires a ``<limit>``:
  ``lower``/``upper`` +-``UNLIMITED`` m, ``effort`` and ``velocity`` ``UNLIMITED`` (N, m/s),
  i.e. none;
* a weld is a ``fixed`` joint rotated by the drawn relative angle;
* the drive train (``[joints.actuator]``) where URDF has a place for it: ``<dynamics damping
  friction>`` the joint's viscous (N*m*s/rad, N*s/m) and Coulomb (N*m, N) friction, ``<limit
  effort velocity>`` the actuator's limits at the joint (the joint's own torque limit or the
  motor's times N, whichever binds; the motor's speed over N). URDF has no rotor: a rotor
  inertia is not exported (the header and a warning say so; Pinocchio takes it as
  ``model.armature``), and its friction is dry, not our smooth ``c tanh(qd / v_s)``. A user
  trial found friction and limits said to have "no place" in URDF, and dropped;
* ``inertial``: mass, origin at the centre of gravity, ``ixx = iyy = izz/2`` (they never enter
  planar dynamics; the same choice as the MJCF), products zero;
* visuals: a cylinder from the centre of gravity to each point and a sphere at the centre of
  gravity (geometry only: URDF takes mass and inertia from ``inertial`` alone).

Gravity is not part of URDF: set it in the engine to ``[gx, gy, 0]`` (the header says the
value; Pinocchio: ``model.gravity.linear``). Joints are matched by name: a parser orders them
as it likes (Pinocchio depth-first).

A closed chain cannot be written: the URDF specification allows trees only ("only tree
structures can be represented, ruling out all parallel robots", wiki.ros.org/urdf/XML/model).
Loop extensions have been proposed (a ``<loop_joint>`` or ``<constraint>`` element: URDF 2.0
drafts, urdfdom PR #264, "Extended URDF", arXiv 2504.04767), but none is in the specification
or read by the common parsers (urdfdom, Pinocchio, Drake, MuJoCo's URDF import): each would
silently drop the loop and load the spanning tree, a different mechanism. So ``to_urdf``
refuses and points to MJCF, which keeps every cut joint as an equality constraint.
"""

from __future__ import annotations

import math

from ..errors import InputError
from ..model.description import GROUND
from .export_model import RigidModel, from_robot, header
from .export_model import numbers as _v

#: what a prismatic joint's required <limit> says when planar-sym has none (m, N, m/s)
UNLIMITED = 1e9


def to_urdf(robot, ideal: bool = False) -> str:
    """The URDF text of a tree robot with its current parameters (see module doc).

    Parameters
    ----------
    robot : planar_sym.Robot
        An open chain (no cut joints); revolute, prismatic and weld joints.
    ideal : bool
        True: the rigid bodies only (no friction or limits).

    Returns
    -------
    str
        A complete URDF file with a header comment naming robot, description, input hash,
        SI units and the gravity to set in the engine.

    Raises
    ------
    InputError
        ``robot`` is a closed chain (URDF holds trees only; export MJCF).
    """
    if robot.is_closed_chain:
        cuts = ", ".join(robot.loops)
        raise InputError(f"{robot.name} is a closed chain (cut joint{'s' * (len(robot.loops) > 1)} "
                         f"{cuts}): URDF describes trees only, and no loop "
                         "extension of it is read by the common parsers, so its spanning tree "
                         "would load as a different mechanism; export MJCF instead "
                         "(--format mjcf, or to_mjcf), which keeps every cut joint as an "
                         "equality constraint")
    return urdf(from_robot(robot, drives=not ideal,
                           left_out="--ideal: the ideal machine, as asked" if ideal
                           else "this file has no place for them", inexact=_inexact))


def _inexact(train, joints) -> tuple[str, ...]:
    """What URDF cannot hold of the drive train, one sentence each."""
    out = []
    for d in train.drives:
        if d.rotor_inertia:
            out.append(f"jm_{d.joint}: URDF has no rotor: its N^2 J_m = "
                       f"{_v(d.gear_ratio ** 2 * d.rotor_inertia)} kg*m^2 at {d.joint} (and J_m on "
                       "its stator's body) is not exported (Pinocchio: model.armature; the MJCF "
                       "export carries it)")
        if d.coulomb:
            out.append(f"fc_{d.joint}: Coulomb friction {_v(d.coulomb)} is URDF's dry friction "
                       f"here, not the smooth c tanh(qd / {_v(d.smoothing)}) of planar-sym")
    return tuple(out)


def _drive_lines(d, prismatic: bool) -> list[str]:
    """A joint's <dynamics> and <limit> from its drive (a prismatic joint's limit is required:
    ``UNLIMITED`` where the actuator gives none)."""
    out = []
    if d is not None and (d.viscous or d.coulomb):
        out.append(f'    <dynamics damping="{_v(d.viscous)}" friction="{_v(d.coulomb)}"/>')
    limits = [] if d is None else [v for v in (
        d.torque_limit, None if d.motor_torque_limit is None
        else d.motor_torque_limit * d.gear_ratio) if v is not None]
    effort = min(limits) if limits else None
    velocity = (None if d is None or d.motor_speed_limit_rad_s is None
                else d.motor_speed_limit_rad_s / d.gear_ratio)
    if prismatic or effort is not None or velocity is not None:
        span = f'lower="{_v(-UNLIMITED)}" upper="{_v(UNLIMITED)}" ' if prismatic else ""
        out.append(f'    <limit {span}effort="{_v(UNLIMITED if effort is None else effort)}" '
                   f'velocity="{_v(UNLIMITED if velocity is None else velocity)}"/>')
    return out


def urdf(model: RigidModel) -> str:
    """The URDF text of ``model`` (a tree: ``model.cuts`` must be empty)."""
    if model.cuts:
        raise InputError(f"{model.name} is a closed chain: URDF describes trees only; export "
                         "MJCF instead (--format mjcf)")
    frame = {GROUND: (0.0, 0.0)}  # each body's link-frame origin in its body frame (m)
    for j in model.tree:
        frame[j.child] = model.bodies[j.child].points_m[j.child_point]
    radius = 0.01 * model.span_m()[1]
    links = ['  <link name="ground"/>']
    for name, body in model.bodies.items():
        if name == GROUND:
            continue
        ox, oy = frame[name]
        cg = (body.cg_m[0] - ox, body.cg_m[1] - oy)
        izz = body.izz_kg_m2
        links += [f'  <link name="{name}">',
                  "    <inertial>",
                  f'      <origin xyz="{_v(*cg, 0)}" rpy="0 0 0"/>',
                  f'      <mass value="{_v(body.mass_kg)}"/>',
                  (f'      <inertia ixx="{_v(izz / 2)}" ixy="0" ixz="0" iyy="{_v(izz / 2)}" iyz="0" '
                  f'izz="{_v(izz)}"/>'),
                  "    </inertial>",
                  *_visuals(cg, [(x - ox, y - oy) for x, y in body.points_m.values()], radius),
                  "  </link>"]
    joints = []
    drive = {d.joint: d for d in model.drives}
    for j in model.tree:
        px, py = model.bodies[j.parent].points_m[j.parent_point]
        ox, oy = frame[j.parent]
        x, y, rel = px - ox, py - oy, model.rel_angle(j)
        lines = [f'    <parent link="{j.parent}"/>', f'    <child link="{j.child}"/>']
        if j.type == "revolute":
            kind = "continuous"
            lines += [f'    <origin xyz="{_v(x, y, 0)}" rpy="0 0 0"/>', '    <axis xyz="0 0 1"/>',
                      *_drive_lines(drive.get(j.name), False)]
        elif j.type == "prismatic":
            kind = "prismatic"
            ux, uy = j.axis
            s0 = model.offsets_m[j.name]
            c, s = math.cos(rel), math.sin(rel)
            at = _v(x + s0 * ux, y + s0 * uy, 0)
            lines += [f'    <origin xyz="{at}" rpy="{_v(0, 0, rel)}"/>',
                      f'    <axis xyz="{_v(c * ux + s * uy, -s * ux + c * uy, 0)}"/>',
                      *_drive_lines(drive.get(j.name), True)]
        else:
            kind = "fixed"
            lines += [f'    <origin xyz="{_v(x, y, 0)}" rpy="{_v(0, 0, rel)}"/>']
        joints += [f'  <joint name="{j.name}" type="{kind}">', *lines, "  </joint>"]
    gx, gy = model.gravity_m_s2
    extra = [(f"GRAVITY IS NOT PART OF URDF: set it in your engine to [{_v(gx, gy, 0)}] m/s^2 "
             "(the robot moves in the plane z = 0; Pinocchio: model.gravity.linear)."),
             ("Link frames: each body's planar-sym frame moved to its joint to the parent (axes "
             "unchanged); revolute joints are continuous about z, so each joint value is our q "
             "(Pinocchio: nq 2 per continuous joint, cos q and sin q). Match joints by name."),
             ("Inertia: ixx = iyy = izz/2 (they never enter planar dynamics). No position "
             f"limits (a prismatic joint's required lower/upper are +-{UNLIMITED:g}: none); "
             "effort and velocity limits are the actuators' at the joint where they give them "
             f"(else {UNLIMITED:g}: none), friction <dynamics damping friction> the joints' "
             "viscous and Coulomb friction (an engine's inverse dynamics, Pinocchio's rnea, "
             "leaves them out).")]
    return "\n".join(['<?xml version="1.0"?>', f"<!--\n{header(model, 'URDF', extra)}\n-->",
                      f'<robot name="{model.name}">', *links, *joints, "</robot>", ""])


def _visuals(cg, points, r: float) -> list[str]:
    """Visual-only cylinders from the centre of gravity to each point, a sphere at it."""
    out = [_visual(cg, 0.0, "<sphere radius=\"%r\"/>" % (1.5 * r))]
    for x, y in points:
        dx, dy = x - cg[0], y - cg[1]
        length = math.hypot(dx, dy)
        if length > 1e-9:  # a z-cylinder turned onto the segment: pitch pi/2, then yaw
            mid = (cg[0] + dx / 2, cg[1] + dy / 2)
            out.append(_visual(mid, math.atan2(dy, dx),
                               f'<cylinder radius="{_v(r)}" length="{_v(length)}"/>', pitch=True))
    return out


def _visual(xy, yaw: float, shape: str, pitch: bool = False) -> str:
    rpy = _v(0, math.pi / 2 if pitch else 0.0, yaw)
    return (f'    <visual><origin xyz="{_v(*xy, 0)}" rpy="{rpy}"/>'
            f"<geometry>{shape}</geometry></visual>")
