"""MJCF (MuJoCo's XML) of a planar robot: its spanning tree as nested bodies, each cut joint an
equality constraint. The user-facing file (``to_mjcf``) and the benchmarks' bare model
(benchmarks/baselines/mujoco_model.py) are both written here.

Construction, generic over the robot (``export_model.RigidModel``):

* every body becomes an MJCF body whose frame *is* that body's frame, so MuJoCo's ``qpos``
  equals planar-sym's ``q`` (child frame angle minus parent frame angle; a slide's displacement
  from the drawn pose), joints matched by name (``qpos`` is in MJCF nesting order, depth-first
  from ground, which may differ from our coordinate order);
* a revolute joint: child body at ``parent_point - child_point`` in the parent's frame (q = 0
  means "aligned with the parent"), ``hinge`` at the child point, axis z;
* a prismatic joint: child body at ``parent_point + s0 u - R(rel) child_point``, rotated by the
  drawn relative angle ``rel``, ``slide`` along ``u`` (the description's axis, in the parent's
  frame; written in the child's frame as MJCF wants it);
* a weld: a joint-less child body, rotated by the drawn relative angle;
* ``inertial``: mass, ``pos`` = centre of gravity, ``diaginertia = izz/2, izz/2, izz``. MuJoCo
  demands ``ixx + iyy >= izz`` (triangle inequality); ``izz/2`` each satisfy it and never enter
  the dynamics (every angular velocity is along z);
* gravity ``[gx, gy, 0]``: the robot moves in the plane z = 0 with gravity in that plane;
* cut joints (closed chains): a site at the cut joint's point on each of its two bodies and
  ``<equality><connect site1 site2/>`` holding them together. Every cut joint is revolute: a
  description cannot cut a loop at a prismatic joint (its cut would need a slide and an angle
  equation; MuJoCo would need a ``weld`` with a freed slide, which it has not), so that case is
  refused here too. MuJoCo's equality constraints are soft (``solref``, ``solimp``: a
  spring-damper towards the constraint, solved with the other constraint forces at every step),
  so the loops close only approximately; a ``connect`` holds x, y and z, its z row identically
  satisfied in a planar model.

The user-facing file adds, without changing the dynamics: visual geoms (capsules from each
body's centre of gravity to its points, a sphere at the centre of gravity) with ``density 0``,
``contype = conaffinity = 0`` and ``inertiafromgeom="false"`` (mass and inertia come from
``inertial`` only, and nothing collides); one ``motor`` per actuated joint; a camera ``plane``
looking down -z at the drawn pose; MuJoCo's constraint and equality flags on (its defaults).
The benchmarks' model is the same tree with no geoms, motors or header (``viewer=False``).

The drive train (``Robot.drive_train``), unless the ideal machine is asked for (``ideal``):

* a joint's rotor: ``armature = N^2 J_m`` on the joint, and J_m added to the inertia of the body
  carrying the stator (the rotor turns with it); the coupling N J_m between the joint and the
  joints that turn that body has no place in MJCF (armature is diagonal), so for a stator on a
  moving body MuJoCo's torques differ by ``N J_m alpha_stator`` at the joint and ``N J_m qdd``
  at each joint turning the stator (the header says so, with the figure);
* viscous friction: ``damping = b`` (exact); Coulomb friction: ``frictionloss = c``, MuJoCo's dry
  friction (a soft constraint), not planar-sym's ``c tanh(qd / v_s)``;
* the motor: ``gear = N``, so ``ctrl`` is the motor torque (N*m); ``ctrlrange`` the motor's
  torque limit, ``forcerange`` the joint-side limit over N, where the description gives them
  (MuJoCo clips the actuator's force, ``gain * ctrl``, to ``forcerange`` and then multiplies
  it by the gear: the joint gets at most the joint-side limit).

The ideal machine: no armature, damping or friction, ``gear = 1`` (``ctrl`` the joint torque,
N*m or N), unlimited.
"""

from __future__ import annotations

import math
from xml.sax.saxutils import quoteattr

from ..errors import InputError
from ..model.description import GROUND
from .export_model import RigidModel, from_robot, header
from .export_model import numbers as _v

#: the user file's step (s) and integrator; MuJoCo's own default step is 2e-3 s
USER_TIMESTEP_S = 1e-3
#: the user file's constraint softness: time constant 2 steps (the least MuJoCo's ``refsafe``
#: allows), critical damping; impedance 0.9999 (MuJoCo's largest). Released from rest for
#: 0.5 s, the 5-bar (type 1) follows planar-sym's simulation to 5e-4 rad and the four-bar to
#: 5e-5 rad (tests/test_export.py tightens the step to reach 1e-7 rad); with impedance 0.99
#: the 5-bar's error is 8e-3 rad.
USER_SOLREF = (2 * USER_TIMESTEP_S, 1.0)
USER_SOLIMP = (0.9999, 0.9999, 0.001)


#: a point mass (izz = 0) on its own joint gets izz = POINT_MASS_IZZ * m * size^2 in the user
#: file (size: the robot's span), at least MJ_MINVAL_IZZ: MuJoCo refuses a moving body with zero
#: inertia ("mass and inertia of moving bodies must be larger than mjMINVAL", 1e-15). Torques
#: change by about 1e-12 of their scale (nothing, for a body that only slides).
POINT_MASS_IZZ = 1e-12
MJ_MINVAL_IZZ = 1e-14


def point_mass_inertia(model: RigidModel, mass_kg: float) -> float:
    """The inertia (kg*m^2) the user file gives a moving point mass (``POINT_MASS_IZZ``)."""
    return max(POINT_MASS_IZZ * mass_kg * model.span_m()[1] ** 2, MJ_MINVAL_IZZ)


def to_mjcf(robot, ideal: bool = False) -> str:
    """The MJCF text of ``robot`` with its current parameters, for a user (see module doc).

    Parameters
    ----------
    robot : planar_sym.Robot
        Any robot, tree or closed chain, revolute and prismatic joints.
    ideal : bool
        True: the rigid bodies and ideal motors only (no rotors, friction, gears or limits).

    Returns
    -------
    str
        A complete MJCF file: gravity on, equality constraints on, RK4 at 1e-3 s, soft loop
        closures ``USER_SOLREF``/``USER_SOLIMP``, a header comment naming robot, description,
        input hash and SI units.
    """
    model = from_robot(robot, drives=not ideal, left_out="--ideal: the ideal machine, as asked")
    # laid out in the drawn pose (on the loops): MuJoCo's reset state (qpos0, the joints'
    # ref) is then a pose the equality constraints hold, not q = 0, where a closed chain's
    # cut joints gape and the first steps blow it apart; qpos stays q
    return mjcf(model, timestep=USER_TIMESTEP_S, loops=True, solref=USER_SOLREF,
                solimp=USER_SOLIMP, viewer=True,
                ref=dict(zip(robot.coordinates, map(float, robot.q_drawn))))


def mjcf(model: RigidModel, *, timestep: float = 1e-3, loops: bool = False,
         solref: tuple[float, float] | None = None, solimp: tuple[float, ...] | None = None,
         viewer: bool = False, ref: dict[str, float] | None = None) -> str:
    """The MJCF text of ``model``'s spanning tree; with ``loops``, its cut joints as ``connect``
    equality constraints (``solref``/``solimp``: MuJoCo's softness, default MuJoCo's own).

    ``viewer``: the user-facing file (header comment, zero-mass visual geoms, motors, camera);
    without it, the benchmarks' bare model (no geoms, no motors, no comment). ``ref``: joint
    name -> its coordinate (rad or m) in the pose the bodies are laid out in (MuJoCo's joint
    ``ref``, so its reset state qpos0 is that pose and qpos stays q); default q = 0.
    """
    sites: dict[str, list[str]] = {}
    equalities: list[str] = []
    (cx0, cy0), size = model.span_m()
    radius = 0.01 * size
    site_size = f' size="{_v(radius)}"' if viewer else ""
    if loops:
        for j in model.cuts:
            if j.type != "revolute":
                raise InputError(f"{model.name}: cut joint {j.name} is {j.type}; only revolute "
                                 "cut joints have an MJCF equality (connect)")
            for side, body, point in (("a", j.parent, j.parent_point),
                                      ("b", j.child, j.child_point)):
                x, y = model.bodies[body].points_m[point]
                sites.setdefault(body, []).append(
                    f'<site name="{j.name}_{side}" pos="{_v(x, y, 0)}"{site_size}/>')
            extra = ""
            if solref is not None:
                extra += f' solref="{_v(*solref)}"'
            if solimp is not None:
                extra += f' solimp="{_v(*solimp)}"'
            equalities.append(f'    <connect name="{j.name}" site1="{j.name}_a" '
                              f'site2="{j.name}_b"{extra}/>')
    children: dict[str, list[str]] = {}
    bodies: dict[str, str] = {}  # body name -> opening tag with inertial and joint
    drives = {d.joint: d for d in model.drives}
    stators: dict[str, float] = {}  # body -> the spin inertia of the rotors it carries
    for j in model.tree:
        if j.name in drives:
            stators[j.parent] = stators.get(j.parent, 0.0) + drives[j.name].rotor_inertia
    for j in model.tree:
        parent, child = model.bodies[j.parent], model.bodies[j.child]
        px, py = parent.points_m[j.parent_point]
        cx, cy = child.points_m[j.child_point]
        rel = model.rel_angle(j)
        q0 = (ref or {}).get(j.name, 0.0)
        at = f' ref="{_v(q0)}"' if q0 else ""
        at += _drive_attributes(drives.get(j.name))
        if j.type == "revolute":
            rel += q0  # turned about the joint point to the laid-out pose
            joint = (f'<joint name="{j.name}" type="hinge" pos="{_v(cx, cy, 0)}" '
                     f'axis="0 0 1"{at}/>')
        elif j.type == "prismatic":
            ux, uy = j.axis  # parent frame; MJCF wants the child's
            s0 = model.offsets_m[j.name] + q0
            px, py = px + s0 * ux, py + s0 * uy
            c, s = math.cos(rel), math.sin(rel)
            joint = (f'<joint name="{j.name}" type="slide" pos="{_v(cx, cy, 0)}" '
                     f'axis="{_v(c * ux + s * uy, -s * ux + c * uy, 0)}"{at}/>')
        else:
            joint = ""
        c, s = math.cos(rel), math.sin(rel)
        pos = (px - (c * cx - s * cy), py - (s * cx + c * cy), 0.0)
        quat = (math.cos(rel / 2), 0.0, 0.0, math.sin(rel / 2))
        izz = child.izz_kg_m2 + stators.get(j.child, 0.0)
        if viewer and izz == 0.0 and j.moves:  # MuJoCo refuses it (point_mass_inertia)
            izz = point_mass_inertia(model, child.mass_kg)
        inertial = (f'<inertial pos="{_v(*child.cg_m, 0)}" mass="{_v(child.mass_kg)}" '
                    f'diaginertia="{_v(izz / 2, izz / 2, izz)}"/>')
        geoms = _geoms(child.cg_m, child.points_m.values(), radius) if viewer else ""
        bodies[j.child] = (f'<body name="{j.child}" pos="{_v(*pos)}" quat="{_v(*quat)}">'
                           f"{joint}{inertial}{geoms}" + "".join(sites.get(j.child, ())))
        children.setdefault(j.parent, []).append(j.child)

    def emit(name: str, depth: int) -> list[str]:
        pad = "  " * depth
        lines = [pad + bodies[name]]
        for ch in children.get(name, []):
            lines += emit(ch, depth + 1)
        return lines + [pad + "</body>"]

    gx, gy = model.gravity_m_s2
    tree = [line for ch in children.get(GROUND, []) for line in emit(ch, 3)]
    tree += ["      " + site for site in sites.get(GROUND, ())]  # ground's frame is the world
    opening = [f'<mujoco model="{model.name}">',
               '  <compiler angle="radian" inertiafromgeom="false"/>',
               f'  <option gravity="{_v(gx, gy, 0)}" timestep="{_v(timestep)}" integrator="RK4"/>']
    motors: list[str] = []
    if viewer:
        tree = [f"      {_sphere(xy, 1.5 * radius)}"
                for xy in model.bodies[GROUND].points_m.values()] + tree
        tree.insert(0, f'      <camera name="plane" pos="{_v(cx0, cy0, 2.0 * size)}"/>')
        opening = [f"<!--\n{_comment(model, solref, solimp)}\n-->", *opening,
                   f'  <statistic center="{_v(cx0, cy0, 0)}" extent="{_v(size)}"/>',
                   "  <default>",
                   ('    <geom contype="0" conaffinity="0" density="0" group="1" '
                   'rgba="0.35 0.55 0.8 1"/>'),
                   '    <site group="2" rgba="0.9 0.3 0.2 1"/>',
                   "  </default>"]
        motors = [_motor(k, drives.get(k)) for k in model.actuated]
    return "\n".join([
        *opening,
        "  <worldbody>", *tree, "  </worldbody>",
        *(["  <equality>", *equalities, "  </equality>"] if equalities else []),
        *(["  <actuator>", *motors, "  </actuator>"] if motors else []),
        "</mujoco>", ""])


def _drive_attributes(drive) -> str:
    """A joint's armature (N^2 J_m), damping (b) and frictionloss (c), where non-zero."""
    if drive is None:
        return ""
    out = ""
    for name, value in (("armature", drive.gear_ratio**2 * drive.rotor_inertia),
                        ("damping", drive.viscous), ("frictionloss", drive.coulomb)):
        if value:
            out += f' {name}="{_v(value)}"'
    return out


def _motor(joint: str, drive) -> str:
    """The joint's motor: gear N (ctrl the motor torque), its limits where given."""
    attrs = f'name={quoteattr(joint)} joint={quoteattr(joint)}'
    if drive is None:
        return f'    <motor {attrs} gear="1"/>'
    attrs += f' gear="{_v(drive.gear_ratio)}"'
    if drive.motor_torque_limit is not None:
        attrs += f' ctrllimited="true" ctrlrange="{_v(-drive.motor_torque_limit, drive.motor_torque_limit)}"'
    if drive.torque_limit is not None:  # MuJoCo clips the actuator's force before its gear
        motor_side = drive.torque_limit / drive.gear_ratio
        attrs += f' forcelimited="true" forcerange="{_v(-motor_side, motor_side)}"'
    return f"    <motor {attrs}/>"


def _sphere(xy, r: float) -> str:
    return f'<geom type="sphere" pos="{_v(*xy, 0)}" size="{_v(r)}"/>'


def _geoms(cg, points, r: float) -> str:
    """Zero-mass visual geoms of one body: a sphere at its centre of gravity, a capsule from
    it to each of its points (body frame, m)."""
    out = [_sphere(cg, 1.5 * r)]
    for x, y in points:
        if math.hypot(x - cg[0], y - cg[1]) > 1e-9:
            out.append(f'<geom type="capsule" fromto="{_v(*cg, 0, x, y, 0)}" size="{_v(r)}"/>')
    return "".join(out)


def _motors_sentence(model: RigidModel) -> str:
    if not model.drives:
        return ("Motors: one per actuated joint, ctrl = joint torque (N*m) or force (N), "
                "unlimited (the ideal machine: no rotors, friction or gears).")
    return ("Motors: one per actuated joint, gear = the gear ratio N, so ctrl = motor torque "
            "(N*m); ctrlrange = the motor torque limit, forcerange = the joint-side limit / N "
            "where given (MuJoCo clips the motor-side force before the gear). Drive train: armature = N^2 J_m (rotor), J_m added to the inertia of the "
            "body carrying the stator, damping = viscous friction, frictionloss = Coulomb "
            "friction.")


def _comment(model: RigidModel, solref, solimp) -> str:
    extra = [("Planar: bodies move in the plane z = 0; gravity [gx, gy, 0] is in the file "
             "(<option gravity>). Body frames are planar-sym's, so qpos = q joint by joint "
             "(match joints by name: qpos follows the nesting, depth-first from ground: "
             f"{', '.join(j.name for j in model.depth_first() if j.moves)})."),
             ("Inertia: diaginertia izz/2, izz/2, izz (ixx, iyy never enter planar dynamics). "
             "Geoms are visual only (density 0, no contacts): mass and inertia come from "
             "<inertial>."),
             _motors_sentence(model)]
    points = [j.child for j in model.tree
              if j.moves and model.bodies[j.child].izz_kg_m2 == 0.0]
    if points:
        extra.append(f"Point masses on their own joint ({', '.join(points)}): izz = 0 raised to "
                     f"{POINT_MASS_IZZ:g} m size^2 (at least {MJ_MINVAL_IZZ:g} kg*m^2), since "
                     "MuJoCo refuses a moving body without inertia.")
    if model.cuts:
        extra.append(f"Closed chain: each cut joint ({', '.join(j.name for j in model.cuts)}) is "
                     "an <equality><connect> of two sites. MuJoCo's constraints are soft: "
                     f"solref {_v(*solref)}, solimp {_v(*solimp)} here; a smaller timestep "
                     "and solref closes the loops tighter.")
    return header(model, "MJCF", extra)
