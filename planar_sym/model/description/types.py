"""What a validated description is made of: bodies, joints, parameters, the assembly record.

Every quantity is SI; every position of a body is in its own frame. Nothing here reads a file:
the stages that build these (``reader``, ``fields``, ``bodies``, ``topology``, ``assembly``) do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

#: Joints (and loops) must close in the drawn configuration to this gap, in metres. The seed's
#: tables carry six decimals, so its own rounding stays far below it.
CLOSURE_TOLERANCE_M = 1e-5

#: A radius of gyration sqrt(izz / m) more than this many times the body's extent (largest
#: distance from the centre of gravity to one of its points) is an error: a uniform rod has
#: 0.58 times, mass beyond its points (a housing, a wide link) rarely more than 2. Catches the
#: seed's 3-RRR "90992 kg*mm^2" (28 times) and kg*mm^2 written where kg*m^2 was meant.
GYRATION_LIMIT = 3.0

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

    def world(self, local: tuple[float, float]) -> tuple[float, float]:
        """A body-frame position (m) in world coordinates of the drawn configuration (m)."""
        c, s = math.cos(self.drawn_angle_rad), math.sin(self.drawn_angle_rad)
        o = self.drawn_origin_m
        return (o[0] + c * local[0] - s * local[1], o[1] + s * local[0] + c * local[1])


@dataclass(frozen=True)
class Joint:
    """A joint between two body points: ``revolute`` (a coordinate, or a cut) or ``weld``.

    ``angle_rad`` is the approximate joint coordinate given with ``pose = "joints"`` (None in
    ``pose = "world"``, where the points give every angle).
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
    """

    pose: str
    given_rad: dict[str, float]
    angles_rad: dict[str, float]
    angle_change_rad: dict[str, float]
    point_moved_m: dict[str, float]
    gaps_before_m: dict[str, float]
    gaps_after_m: dict[str, float]
    iterations: int

    def report(self) -> str:
        """Plain-text account of the assembled pose and of what moved (``planar-sym draw``)."""
        lines = [(f"assembled the loops from the given pose (pose = \"{self.pose}\") in "
                  f"{self.iterations} Gauss-Newton steps:")]
        lines += [f"  loop {k}: gap {v * 1e3:.4g} mm closed (now {self.gaps_after_m[k]:.2g} m)"
                  for k, v in self.gaps_before_m.items()]
        for k, v in self.angles_rad.items():
            change = self.angle_change_rad[k]
            moved = (f"changed by {math.degrees(change):+.4g} deg" if abs(change) > 1e-12
                     else "kept")
            lines.append(f"  joint {k}: {math.degrees(v):.6g} deg (given "
                         f"{math.degrees(self.given_rad[k]):.6g} deg, {moved})")
        moved_pts = sorted(self.point_moved_m.items(), key=lambda kv: -kv[1])
        lines += [f"  point {k} moved {v * 1e3:.4g} mm" for k, v in moved_pts if v > 1e-12]
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
    task_point: tuple[str, str]
    task_orientation: str | None
    display: dict[str, str] = field(default_factory=dict)
    #: what closing the loops numerically changed; None when the pose was taken as typed
    assembly: Assembly | None = None

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Names of the generalised coordinates q (revolute tree joints, tree order)."""
        return tuple(j.name for j in self.tree_joints if j.type == "revolute")

    @property
    def actuated(self) -> tuple[int, ...]:
        """Indices into q of the actuated joints."""
        return tuple(i for i, j in enumerate(self._revolutes()) if j.actuated)

    @property
    def task_names(self) -> tuple[str, ...]:
        return ("x", "y", "phi") if self.task_orientation else ("x", "y")

    def _revolutes(self) -> list[Joint]:
        return [j for j in self.tree_joints if j.type == "revolute"]

    def q_drawn(self) -> tuple[float, ...]:
        """Joint coordinates of the drawn configuration (rad), wrapped to (-pi, pi]."""
        b = self.bodies
        return tuple(wrap_angle(b[j.child].drawn_angle_rad - b[j.parent].drawn_angle_rad)
                     for j in self._revolutes())

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
        return tuple(params)

    def used_points(self) -> list[tuple[str, str]]:
        """(body, point) pairs the equations need: joint locations and the task point."""
        seen: list[tuple[str, str]] = []
        for j in (*self.tree_joints, *self.loop_joints):
            for bp in ((j.parent, j.parent_point), (j.child, j.child_point)):
                if bp not in seen:
                    seen.append(bp)
        if self.task_point not in seen:
            seen.append(self.task_point)
        return seen

    def parameter_values(self) -> list[float]:
        return [p.value for p in self.parameters()]
