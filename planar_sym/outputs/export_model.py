"""What an exported MJCF or URDF file holds: a description's bodies and joints with a robot's
current parameter values (SI), and the provenance every exported file states in its header.

The structure (bodies, joints, cut joints, drawn relative angles, slide axes) comes from the
robot's description; every number the equations use (masses, inertias, centres of gravity,
body-frame points, slide offsets, gravity) comes from ``Robot.parameters``, so a robot from
``with_parameters`` exports its own values. A body-frame coordinate that is not a parameter is
an exact structural zero (``Description.parameters``) or a point the equations never use (drawn
only), and keeps the description's value.

The drive train (``Robot.drive_train``: gear, rotor, friction, limits) goes where the format
has a place for it (``drives``; MJCF: ``export_mjcf``); what has no exact place is named in
``RigidModel.not_exported`` and in every header. URDF holds the rigid bodies only.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

from ..model.described import described
from ..model.description import GROUND, Body, Description, Joint
from ..model.description.types import snap_offset

#: actuator parameters that change the dynamics but have no exact place in MJCF or URDF
ACTUATOR_PREFIXES = ("jm_", "fv_", "fc_")


@dataclass(frozen=True)
class RigidModel:
    """A planar robot as rigid bodies, every value SI (m, kg, kg*m^2, rad, m/s^2).

    Attributes
    ----------
    name, title : str
        The robot's.
    bodies : dict of str to Body
        Every body (``"ground"`` included) in its own frame, with the robot's parameter values.
    tree : tuple of Joint
        The spanning tree's joints (revolute, prismatic, weld) in the description's order.
    cuts : tuple of Joint
        The cut (loop-closing) joints, revolute: each holds two body points together.
    offsets_m : dict of str to float
        Each prismatic joint's drawn offset s0 (m): the child point lies ``s0 + d`` along the
        axis from the parent point, ``d`` the joint's coordinate.
    gravity_m_s2 : tuple of float
        (gx, gy), m/s^2.
    coordinates : tuple of str
        The robot's coordinates (its q order): names of the revolute and prismatic tree joints.
    actuated : tuple of str
        The actuated coordinates' joint names.
    input_hash : str
        The generated code's input hash (its manifest), "" for a bare description.
    source : str
        Where the structure came from: the description file's name.
    changed : tuple of str
        ``"name = value unit"`` for each parameter that differs from the description's value.
    not_exported : tuple of str
        Actuator figures (non-zero) that the exported file does not hold exactly, each with why.
    drives : tuple of Drive
        The actuated joints' drives (``model.drive``) the file holds; empty for the ideal
        machine or a format without a place for them.
    """

    name: str
    title: str
    bodies: dict[str, Body]
    tree: tuple[Joint, ...]
    cuts: tuple[Joint, ...]
    offsets_m: dict[str, float]
    gravity_m_s2: tuple[float, float]
    coordinates: tuple[str, ...]
    actuated: tuple[str, ...] = ()
    input_hash: str = ""
    source: str = ""
    changed: tuple[str, ...] = ()
    not_exported: tuple[str, ...] = ()
    drives: tuple = ()

    def rel_angle(self, j: Joint) -> float:
        """The child frame's angle to the parent frame (rad) that a weld or prismatic joint keeps
        (a revolute joint's is its coordinate, 0 here)."""
        if j.type == "revolute":
            return 0.0
        return self.bodies[j.child].drawn_angle_rad - self.bodies[j.parent].drawn_angle_rad

    def children(self) -> dict[str, list[Joint]]:
        """Tree joints by parent body, in the description's order."""
        out: dict[str, list[Joint]] = {}
        for j in self.tree:
            out.setdefault(j.parent, []).append(j)
        return out

    def depth_first(self) -> list[Joint]:
        """The tree joints depth-first from ground (siblings in the description's order): the
        order MJCF nests bodies in, hence MuJoCo's qpos order."""
        kids, out = self.children(), []

        def visit(body: str) -> None:
            for j in kids.get(body, []):
                out.append(j)
                visit(j.child)

        visit(GROUND)
        return out

    @property
    def total_mass_kg(self) -> float:
        return math.fsum(b.mass_kg for k, b in self.bodies.items() if k != GROUND)

    def span_m(self) -> tuple[tuple[float, float], float]:
        """Centre (m) and size (m) of the drawn pose's points: for cameras and geom sizes."""
        pts = [b.world(p) for b in self.bodies.values() for p in (*b.points_m.values(), b.cg_m)]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        size = max(max(xs) - min(xs), max(ys) - min(ys))
        centre = ((max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2)
        return centre, (size if size > 0 else 1.0)


def from_description(desc: Description) -> RigidModel:
    """The description's own values (what the benchmarks' MuJoCo model is built from)."""
    return RigidModel(
        desc.name, desc.title, dict(desc.bodies), tuple(desc.tree_joints),
        tuple(desc.loop_joints),
        {j.name: snap_offset(desc.slide_offset_m(j)) for j in desc.tree_joints
         if j.type == "prismatic"},
        tuple(desc.gravity_m_s2), desc.coordinates,
        tuple(j.name for j in desc.tree_joints if j.moves and j.actuated),
        source=Path(desc.path).name if desc.path else "")


def from_robot(robot, drives: bool = False, left_out: str = "this file has no place for them",
               inexact=None) -> RigidModel:
    """The robot's description with ``robot.parameters`` (SI) in place of its values.

    Parameters
    ----------
    robot : planar_sym.Robot
        A loaded robot (``planar_sym.load``), possibly from ``with_parameters``.
    drives : bool
        Carry the drive train (``RigidModel.drives``), for a format that holds it (MJCF);
        False: the rigid bodies only, every non-zero actuator figure named as not exported.
    left_out : str
        Why, in that warning: the format has no place for them, or the ideal machine was asked.
    inexact : callable, optional
        ``inexact(drive_train, joints by name)``: what the format cannot hold exactly of the
        drive train, one sentence each (default MJCF's, ``_inexact_drives``).

    Raises
    ------
    InputError
        The robot has no description at hand (a generated folder without description.toml).
    LibraryError
        The description no longer matches the generated code (other parameters or joints).
    """
    desc = described(robot, "export it")
    v = robot.parameters
    direction = robot.library.manifest.get("gravity_direction")
    if direction is None:  # manifests from before it: the description's direction
        gx, gy = desc.gravity_m_s2
        norm = math.hypot(gx, gy)
        direction = (gx / norm, gy / norm) if norm else (0.0, 0.0)
    g = v.get("g", 0.0)
    units = {p.name: p.unit for p in robot.parameter_list}
    defaults = {p["name"]: p["value"] for p in robot.library.manifest["parameters"]}
    changed = tuple(f"{k} = {x!r} {units[k]} (description: {defaults[k]!r})"
                    for k, x in v.items() if k in defaults and x != defaults[k])
    train = robot.drive_train
    if drives:
        skipped = (inexact or _inexact_drives)(train, {j.name: j for j in desc.tree_joints})
        if skipped:
            warnings.warn(f"{robot.name}: " + "; ".join(skipped), RuntimeWarning, stacklevel=3)
    else:
        skipped = tuple(k for k, x in v.items() if k.startswith(ACTUATOR_PREFIXES) and x != 0.0)
        if skipped:
            warnings.warn(f"{robot.name}: actuator figures {', '.join(skipped)} are not exported "
                          f"({left_out}): the file holds the rigid bodies only", RuntimeWarning,
                          stacklevel=3)
    return RigidModel(
        robot.name, robot.title, dict(desc.bodies), tuple(desc.tree_joints), tuple(desc.loop_joints),
        {j.name: v.get(f"s0_{j.name}", 0.0) for j in desc.tree_joints if j.type == "prismatic"},
        (g * direction[0], g * direction[1]), robot.coordinates,
        tuple(robot.coordinates[i] for i in robot.actuated),
        robot.library.manifest.get("input_hash", ""),
        Path(robot.library.manifest.get("input") or desc.path).name, changed, skipped,
        train.drives if drives else ())


def _inexact_drives(train, joints: dict[str, Joint]) -> tuple[str, ...]:
    """What MJCF's armature, damping and frictionloss cannot hold exactly, one sentence each."""
    out = []
    for d in train.drives:
        if d.rotor_inertia and _turns(joints[d.joint].parent, joints):
            out.append(f"jm_{d.joint}: the rotor turns with {joints[d.joint].parent}; its "
                       f"coupling N J_m = {d.gear_ratio * d.rotor_inertia!r} kg*m^2 between "
                       f"{d.joint} and the joints that turn {joints[d.joint].parent} is not "
                       "exported (armature is diagonal): MuJoCo's torques differ by N J_m "
                       f"alpha_{joints[d.joint].parent} at {d.joint} and N J_m qdd_{d.joint} at "
                       "each of those joints")
        if d.coulomb:
            out.append(f"fc_{d.joint}: Coulomb friction {d.coulomb!r} is exported as MuJoCo's "
                       f"frictionloss (dry friction, a soft constraint), not as the smooth "
                       f"c tanh(qd / {d.smoothing!r}) of planar-sym")
        if d.motor_speed_limit_rad_s is not None:  # said nowhere before (a trial)
            out.append(f"{d.joint}: the motor's speed limit "
                       f"{d.motor_speed_limit_rad_s * 30 / math.pi:.6g} rpm has no place in "
                       "MJCF (a motor limits its force only): not exported")
    return tuple(out)


def _turns(body: str, joints: dict[str, Joint]) -> bool:
    """Whether ``body`` can turn: a revolute joint between it and the ground. A stator on a
    body that only slides (a cart) adds no coupling, and was warned about (a user trial:
    MuJoCo's mass matrix equal to 3e-17)."""
    by_child = {j.child: j for j in joints.values()}
    while body != GROUND and body in by_child:
        j = by_child[body]
        if j.type == "revolute":
            return True
        body = j.parent
    return False


def header(model: RigidModel, fmt: str, extra: list[str]) -> str:
    """The comment text that opens an exported file (no ``--``: XML comments forbid it)."""
    lines = [f"Written by planar-sym export ({fmt}): robot {model.name}, {model.title}",
             (f"description: {model.source or '(none)'}; generated code input hash "
             f"{model.input_hash or '(none)'}"),
             ("Values are SI: m, kg, kg*m^2, rad, s, m/s^2 (torques N*m, forces N), written "
             "with full float precision (repr)."),
             (f"Total mass {model.total_mass_kg!r} kg; coordinates (our q order): "
             f"{', '.join(model.coordinates)}; actuated: {', '.join(model.actuated) or 'none'}.")]
    if model.changed:
        lines.append("Parameters changed from the description: " + "; ".join(model.changed))
    lines += extra
    if model.not_exported and model.drives:
        lines.append("Drive train, NOT exact here: " + "; ".join(model.not_exported) + ".")
    elif model.not_exported:
        lines.append("NOT exported (actuator models, no exact equivalent here): "
                     f"{', '.join(model.not_exported)}; the file holds the rigid bodies only.")
    return "\n".join("  " + line.replace("--", "- -") for line in lines)


def numbers(*xs: float) -> str:
    """Space-separated values at full precision (``repr``), as MJCF and URDF attributes take
    them: the exported numbers round-trip exactly."""
    return " ".join(repr(float(x)) for x in xs)
