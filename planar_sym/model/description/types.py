"""What a validated description is made of: bodies, joints, parameters, the assembly record.

Every quantity is SI; every position of a body is in its own frame. Nothing here reads a file:
the stages that build these (``reader``, ``fields``, ``bodies``, ``topology``, ``assembly``) do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ..units import UNITS

#: Joints (and loops) must close in the drawn configuration to this gap, in metres. The seed's
#: tables carry six decimals, so its own rounding stays far below it.
CLOSURE_TOLERANCE_M = 1e-5

#: A radius of gyration sqrt(izz / m) more than this many times the body's extent (largest
#: distance from the centre of gravity to one of its points) is an error: a uniform rod has
#: 0.58 times, mass beyond its points (a housing, a wide link) rarely more than 2. Catches the
#: seed's 3-RRR "90992 kg*mm^2" (28 times) and kg*mm^2 written where kg*m^2 was meant.
GYRATION_LIMIT = 3.0
#: ... and less than this many times is a warning: all the mass within 1% of the body's reach
#: of its centre of gravity; kg*m^2 typed where kg*mm^2 is read gives 1e-3 times.
GYRATION_LOW = 0.01
#: A mass (or the body's points) read in another unit that brings such a radius within these
#: times the body's reach (a uniform rod has 0.58, a ring 1, a compact hub with a light arm
#: about 0.1) is named as the slip rather than izz: 0.12 typed for 120 g (units.mass = "g") made
#: a coupler's radius 18 times its reach, and a trial read it blamed on izz. One reading of the
#: mass is a factor 1e3, 31.6 in the radius, so a radius 3 times the reach comes back to 0.1.
GYRATION_TYPICAL = (0.1, 1.5)
#: A body heavier than the densest element (osmium, 22 590 kg/m^3) filling the ball its points
#: reach from its centre of gravity is a warning: grams typed as kg make a 71 g link 71 kg,
#: three times the 24 kg such a ball of osmium around the seed's link1 would weigh.
DENSITY_MAX = 22_590.0

#: Largest plausible gravity magnitude (m/s^2), an error beyond it here and in the run-time
#: parameter check: the Sun's surface gives 274; more is a unit slip such as 9810 (mm/s^2)
#: typed with acceleration = "m/s^2".
G_LIMIT = 300.0
#: Gravity magnitudes outside [G_LOW, G_HIGH] m/s^2 (but not 0, a horizontal robot) are a
#: warning: Pluto gives 0.62 and Jupiter 24.8, so beyond these only small moons, asteroids, stars
#: or a centrifuge; 9.81 typed in mm/s^2 gives 0.00981.
G_LOW, G_HIGH = 0.1, 30.0

#: The robot's span (largest distance between two of its points or centres of gravity, m)
#: below this is an error: joints close to CLOSURE_TOLERANCE_M (0.01 mm), 1% of it, so the
#: checks could not tell its points apart. A 0.05 to 1 m robot typed in m with length = "mm"
#: spans 0.05 to 1 mm.
SIZE_MIN_M = 1e-3
#: A span above this (m) is a warning: the longest crane booms reach 100 to 200 m, so a planar
#: mechanism can be that large, but a 0.1 to 1 m robot typed in mm with length = "m" spans 100 to
#: 1000 m.
SIZE_LARGE_M = 100.0
#: A span above this (m) is an error: no machine's planar linkage is a kilometre across.
SIZE_MAX_M = 1000.0

#: A centre of gravity further outside the outline of its body's points (their convex hull) than
#: CG_WARN times the body's size (largest distance between its points) is a warning, more than
#: CG_ERROR times an error. A bent link's cg lies off the line of its joints by at most about
#: half its length, a counterweight beyond a joint about one length; ten lengths away is
#: cg_from naming the wrong point, cg in world coordinates, or cg typed in another unit. A body
#: whose mass is really there should have a point there (its size then includes it).
CG_WARN, CG_ERROR = 1.0, 10.0

#: With units.angle = "rad", a joint angle (pose = "joints") beyond one turn is a warning: the
#: drawn pose is wrapped to (-pi, pi], so more than a turn says nothing a smaller angle would
#: not, and "angle = -60" with rad was nearly always -60 deg (it draws the joint at 162 deg).
ANGLE_TURN_RAD = 2.0 * math.pi

#: Body-frame coordinates smaller than this (m) are exact zeros: rotating a point that lies on a
#: link's axis into the link frame leaves ~1e-17 of rounding, which must not become a parameter.
ZERO_SNAP_M = 1e-12

GROUND = "ground"
#: joint types that carry a coordinate: an angle (rad) or a displacement (m)
MOVING = ("revolute", "prismatic")


def slide_offset(bodies: dict[str, Body], j: Joint) -> float:
    """How far (m) a prismatic joint's child point lies along the axis from its parent point,
    with the bodies as placed."""
    par, ch = bodies[j.parent], bodies[j.child]
    a, b = par.world(par.points_m[j.parent_point]), ch.world(ch.points_m[j.child_point])
    u = par.direction(j.axis)  # type: ignore[arg-type]
    return (b[0] - a[0]) * u[0] + (b[1] - a[1]) * u[1]


def snap_offset(v: float) -> float:
    """A drawn slide offset (m) with rounding below ``ZERO_SNAP_M`` made an exact zero."""
    return 0.0 if abs(v) < ZERO_SNAP_M else v


def wrap_angle(angle: float) -> float:
    """``angle`` (rad) wrapped to (-pi, pi].

    ``math.remainder`` is exact, so an angle already inside the interval comes back bit for bit
    (the seed's drawn poses keep their values).
    """
    w = math.remainder(angle, 2.0 * math.pi)
    return w + 2.0 * math.pi if w <= -math.pi else w


@dataclass(frozen=True)
class Body:
    """A rigid body; every position in its own frame, SI units."""

    name: str
    mass_kg: float
    izz_kg_m2: float  # about the centre of gravity
    cg_m: tuple[float, float]
    points_m: dict[str, tuple[float, float]]
    drawn_angle_rad: float  # frame angle in the drawn configuration
    drawn_origin_m: tuple[float, float]  # frame origin in world, drawn configuration
    #: a massless link carrying its whole mass at one of its points (``mass_at``): izz is an
    #: exact structural 0, not a parameter
    point_mass: bool = False

    def direction(self, local: tuple[float, float]) -> tuple[float, float]:
        """A body-frame direction (a prismatic joint's axis) in world axes, drawn configuration."""
        c, s = math.cos(self.drawn_angle_rad), math.sin(self.drawn_angle_rad)
        return (c * local[0] - s * local[1], s * local[0] + c * local[1])

    def world(self, local: tuple[float, float]) -> tuple[float, float]:
        """A body-frame position (m) in world coordinates of the drawn configuration (m)."""
        c, s = math.cos(self.drawn_angle_rad), math.sin(self.drawn_angle_rad)
        o = self.drawn_origin_m
        return (o[0] + c * local[0] - s * local[1], o[1] + s * local[0] + c * local[1])


#: default speed (rad/s, or m/s) over which Coulomb friction c sign(qd) is smoothed to
#: c tanh(qd / v_s): at 0.01 rad/s (0.1 rpm at the joint) the friction reaches 76 % of c, and
#: the slope c / v_s near rest stays mild enough for the explicit integrators
COULOMB_SMOOTHING = 0.01


@dataclass(frozen=True)
class Actuator:
    """The actuator of one actuated joint (see ``actuators``): joint-side SI figures."""

    gear_ratio: float = 1.0  # motor rad per joint rad (per m of a prismatic joint)
    rotor_inertia_kg_m2: float = 0.0
    viscous: float = 0.0  # N*m*s/rad (N*s/m)
    coulomb: float = 0.0  # N*m (N)
    smoothing: float = COULOMB_SMOOTHING  # rad/s (m/s)
    torque_limit: float | None = None  # N*m (N) at the joint
    motor_torque_limit: float | None = None  # N*m
    motor_speed_limit_rad_s: float | None = None
    torque_constant: float | None = None  # N*m/A
    winding_resistance: float | None = None  # ohm
    given: frozenset = frozenset()  # the keys the description gave


@dataclass(frozen=True)
class Joint:
    """A joint between two body points: ``revolute`` or ``prismatic`` (a coordinate, or a cut)
    or ``weld``.

    ``angle_rad`` is the approximate joint coordinate given with ``pose = "joints"`` (None in
    ``pose = "world"``, where the points give every angle); for a prismatic joint it is the
    displacement of the child point along the axis from the parent point (m).
    ``axis`` (prismatic only) is the unit slide direction in the parent body's frame, and
    ``rel_angle_rad`` the constant angle of the child frame relative to the parent's.
    """

    name: str
    type: str
    parent: str
    parent_point: str
    child: str
    child_point: str
    actuated: bool
    closes_loop: bool
    angle_rad: float | None = None
    axis: tuple[float, float] | None = None
    rel_angle_rad: float | None = None
    actuator: Actuator | None = None

    @property
    def moves(self) -> bool:
        """Whether the joint is a coordinate (revolute or prismatic), not a weld."""
        return self.type in MOVING


@dataclass(frozen=True)
class Parameter:
    """One entry of the parameter vector ``p`` of every generated function."""

    name: str
    value: float  # SI
    unit: str
    meaning: str


@dataclass(frozen=True)
class Assembly:
    """What closing the loops numerically changed (``assemble = true`` or ``pose = "joints"``).

    Attributes
    ----------
    pose : str
        ``"world"`` (approximate world points) or ``"joints"`` (bodies in their own frames,
        approximate joint angles).
    given_rad, angles_rad : dict of str to float
        Every tree joint's angle (child frame minus parent frame, rad) in the given pose and in
        the assembled one, wrapped to (-pi, pi].
    angle_change_rad : dict of str to float
        Assembled minus given angle (rad), not wrapped: how far each joint turned.
    point_moved_m : dict of str to float
        ``"body.point"``: distance (m) from where the description put the point (typed world
        point, or placed from the given angles) to the assembled pose.
    gaps_before_m : dict of str to float
        Each loop's (cut joint's) gap in the given pose, placed along the tree (m).
    gaps_after_m : dict of str to float
        The same after assembling (m); below ``ASSEMBLY_TOL_M``.
    iterations : int
        Gauss-Newton steps taken.
    length_unit : str
        The description's ``[units].length``: ``report`` gives lengths in it.
    """

    pose: str
    given_rad: dict[str, float]
    angles_rad: dict[str, float]
    angle_change_rad: dict[str, float]
    point_moved_m: dict[str, float]
    gaps_before_m: dict[str, float]
    gaps_after_m: dict[str, float]
    iterations: int
    #: prismatic joints among the above: their values are displacements (m), not angles
    slides: frozenset = frozenset()
    length_unit: str = "m"

    def report(self) -> str:
        """Plain-text account of the assembled pose and of what moved (``planar-sym draw``),
        lengths in the description's own unit."""
        u, per = self.length_unit, 1.0 / UNITS["length"][self.length_unit]
        lines = [(f"assembled the loops from the given pose (pose = \"{self.pose}\") in "
                  f"{self.iterations} Gauss-Newton steps:")]
        lines += [f"  loop {k}: gap {v * per:.4g} {u} closed (now {self.gaps_after_m[k] * per:.2g}"
                  f" {u})" for k, v in self.gaps_before_m.items()]
        for k, v in self.angles_rad.items():
            change = self.angle_change_rad[k]
            if k in self.slides:
                moved = (f"changed by {change * per:+.4g} {u}" if abs(change) > 1e-12 else "kept")
                lines.append(f"  joint {k}: {v * per:.6g} {u} along its axis (given "
                             f"{self.given_rad[k] * per:.6g} {u}, {moved})")
                continue
            moved = (f"changed by {math.degrees(change):+.4g} deg" if abs(change) > 1e-12
                     else "kept")
            lines.append(f"  joint {k}: {math.degrees(v):.6g} deg (given "
                         f"{math.degrees(self.given_rad[k]):.6g} deg, {moved})")
        moved_pts = sorted(self.point_moved_m.items(), key=lambda kv: -kv[1])
        lines += [f"  point {k} moved {v * per:.4g} {u}" for k, v in moved_pts if v > 1e-12]
        return "\n".join(lines)


@dataclass(frozen=True)
class Description:
    """A validated robot: bodies, joints in tree order, loop cuts, task, parameters."""

    name: str
    title: str
    path: Path
    sha256: str
    gravity_m_s2: tuple[float, float]
    bodies: dict[str, Body]  # includes "ground"
    tree_joints: tuple[Joint, ...]  # parents before children
    loop_joints: tuple[Joint, ...]
    task_point: tuple[str, str] | None  # None: no end-effector ([task] left out)
    task_orientation: str | None
    display: dict[str, str] = field(default_factory=dict)
    #: what closing the loops numerically changed; None when the pose was taken as typed
    assembly: Assembly | None = None

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Names of the generalised coordinates q (revolute and prismatic tree joints, tree
        order)."""
        return tuple(j.name for j in self.tree_joints if j.moves)

    @property
    def coordinate_units(self) -> tuple[str, ...]:
        """Unit of each coordinate: ``rad`` (revolute) or ``m`` (prismatic)."""
        return tuple("m" if j.type == "prismatic" else "rad" for j in self._movable())

    @property
    def actuated(self) -> tuple[int, ...]:
        """Indices into q of the actuated joints."""
        return tuple(i for i, j in enumerate(self._movable()) if j.actuated)

    @property
    def task_names(self) -> tuple[str, ...]:
        if self.task_point is None:
            return ()
        return ("x", "y", "phi") if self.task_orientation else ("x", "y")

    def _movable(self) -> list[Joint]:
        return [j for j in self.tree_joints if j.moves]

    def q_drawn(self) -> tuple[float, ...]:
        """Joint coordinates of the drawn configuration: revolute angles (rad) wrapped to
        (-pi, pi]; prismatic displacements 0 (m: they are measured from the drawn pose)."""
        b = self.bodies
        return tuple(0.0 if j.type == "prismatic" else
                     wrap_angle(b[j.child].drawn_angle_rad - b[j.parent].drawn_angle_rad)
                     for j in self._movable())

    def slide_offset_m(self, j: Joint) -> float:
        """A prismatic joint's drawn offset: the child point's distance along the axis from
        the parent point in the drawn configuration (m); its coordinate adds to it."""
        return slide_offset(self.bodies, j)

    def parameters(self) -> tuple[Parameter, ...]:
        """The parameter vector: every non-zero physical quantity, in a fixed order.

        Masses and inertias are always parameters; a body-frame coordinate that is exactly zero
        is structural (it simplifies the equations), any other is a parameter.
        """
        params = [Parameter("g", math.hypot(*self.gravity_m_s2), "m/s^2", "gravity magnitude")]
        for body in self.bodies.values():
            if body.name == GROUND:
                continue
            params.append(Parameter(f"m_{body.name}", body.mass_kg, "kg", f"mass of {body.name}"))
            if not body.point_mass:
                params.append(Parameter(f"izz_{body.name}", body.izz_kg_m2, "kg*m^2",
                                        f"inertia of {body.name} about its centre of gravity"))
            for axis, v in zip("xy", body.cg_m):
                if v != 0.0:
                    params.append(Parameter(f"cg{axis}_{body.name}", v, "m",
                                            f"centre of gravity of {body.name}, body {axis}"))
        for body_name, point in self.used_points():
            for axis, v in zip("xy", self.bodies[body_name].points_m[point]):
                if v != 0.0:
                    params.append(Parameter(f"p{axis}_{body_name}_{point}", v, "m",
                                            f"point {point} of {body_name}, body {axis}"))
        params += self._actuator_parameters()
        for j in self.tree_joints:
            if j.type == "prismatic" and (s0 := snap_offset(self.slide_offset_m(j))) != 0.0:
                params.append(Parameter(f"s0_{j.name}", s0, "m",
                                        f"offset of {j.name} along its axis, drawn pose"))
        return tuple(params)

    def _actuator_parameters(self) -> list[Parameter]:
        """The actuator figures the equations use, for the joints that give them: gear ratio
        and rotor inertia (the rotor's kinetic energy), viscous and Coulomb friction and its
        smoothing speed."""
        out = []
        for j in self.tree_joints:
            a = j.actuator
            if a is None:
                continue
            slide = j.type == "prismatic"
            tq, sp = ("N", "m/s") if slide else ("N*m", "rad/s")
            rows = [("gear_ratio", "gear", a.gear_ratio, "rad/m" if slide else "1",
                     f"gear ratio of {j.name}'s motor (motor {'rad per m' if slide else 'turns per joint turn'})"),
                    ("rotor_inertia", "jm", a.rotor_inertia_kg_m2, "kg*m^2",
                     f"rotor inertia of {j.name}'s motor"),
                    ("viscous_friction", "fv", a.viscous, f"{tq}*s/{'m' if slide else 'rad'}",
                     f"viscous friction at {j.name}"),
                    ("coulomb_friction", "fc", a.coulomb, tq, f"Coulomb friction at {j.name}"),
                    ("coulomb_friction", "vs", a.smoothing, sp,
                     f"speed over which {j.name}'s Coulomb friction is smoothed (tanh)")]
            out += [Parameter(f"{prefix}_{j.name}", v, unit, meaning)
                    for key, prefix, v, unit, meaning in rows if key in a.given]
        return out

    def used_points(self) -> list[tuple[str, str]]:
        """(body, point) pairs the equations need: joint locations and the task point."""
        seen: list[tuple[str, str]] = []
        for j in (*self.tree_joints, *self.loop_joints):
            for bp in ((j.parent, j.parent_point), (j.child, j.child_point)):
                if bp not in seen:
                    seen.append(bp)
        if self.task_point is not None and self.task_point not in seen:
            seen.append(self.task_point)
        return seen

    def parameter_values(self) -> list[float]:
        return [p.value for p in self.parameters()]
