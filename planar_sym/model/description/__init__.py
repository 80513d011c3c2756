"""Robot descriptions: read a TOML file, validate all of it at once, convert to SI body frames.

Stage 1 of the pipeline, shared by ``derive`` (build time) and the runtime; imports no SymPy.
The stages, one module each: ``reader`` (find and read the file), ``fields`` (one value at a
time), ``bodies`` (body frames, plausibility), ``topology`` (joints, tree order, loops),
``assembly`` (placing bodies from joint angles, closing loops numerically), ``plausibility``
(the span against the length unit, gravity, centres of gravity, display names: errors and
warnings), ``validator`` (runs them all, collects every problem), ``types`` (what comes out).

Conventions (written once, used everywhere)
-------------------------------------------

* Each body gets a frame; every point is stored in it. The coordinate of a revolute joint is the
  angle of the child frame minus the angle of the parent frame (rad); with link-aligned frames
  the seed's angles come out directly: q1 absolute, q2 relative for the serial arms, th2 and th5
  absolute for the 5-bars. The drawn pose's coordinates (``q_drawn``) are wrapped to (-pi, pi].
* A joint with ``closes_loop = true`` is cut: it is not a coordinate but two loop-closure
  equations (its two points coincide).

The format
----------

Top level: ``name`` (an identifier), ``title``, ``gravity = [gx, gy]`` in [units].acceleration,
``[units]`` (``length`` m|cm|mm, ``mass`` kg|g, ``inertia`` kg*m^2|kg*cm^2|kg*mm^2|g*mm^2|g*cm^2,
``angle`` rad|deg, ``acceleration`` m/s^2|mm/s^2; all five required), ``[ground]`` with
``points = { NAME = [x, y] }`` (world coordinates, always), ``[[bodies]]``, ``[[joints]]``,
``[task]`` (``point = "body.point"``, optional ``orientation = "body"``), optional
``[symbols]`` (parameter name = display string) and ``notes``. Any number may be typed as an
expression in a string (``"100*cos(30*deg)"``), with names from an optional top-level
``[constants]`` table (``planar_sym.expressions`` has the rules). Two optional top-level keys say
how the drawn pose is given:

``pose = "world"`` (the default; the seed's tables)
    A body's ``points`` are world coordinates of the drawn pose; ``cg`` is relative to
    ``cg_from`` (required: one of its points, or ``"world"`` for the world origin) in world
    axes; ``frame = [origin]`` or ``[origin, x_toward]`` names its points (default: the first
    point, world-aligned). Joints take no ``angle``. Every joint and loop must close to
    ``CLOSURE_TOLERANCE_M`` (0.01 mm), unless

    ``assemble = true``
        (only for a robot with a loop) the world points may be approximate, as read off a
        sketch. Each body keeps the shape of its own points (its frame as above), the tree is
        re-placed from ground (a child's joint point put on its parent's, the typed angles kept)
        and the loops are closed numerically (below).

``pose = "joints"``
    A body's ``points`` and ``cg`` are in the body's own coordinates (x along the link, y
    across, say); ``cg`` is relative to ``cg_from`` if given (one of its points), else to the
    origin (0, 0) of those coordinates, in the same axes. ``frame = [origin]`` or ``[origin,
    x_toward]`` re-expresses them in a frame at a point (x toward another); omitted, the body
    frame is the coordinates as typed. Each tree joint (revolute or weld) may carry ``angle =
    <value in [units].angle>`` (default 0): its coordinate in the drawn pose, child frame angle
    minus parent frame angle, approximate where the robot has loops. Bodies are placed by
    forward kinematics from ground along the tree (child frame angle = parent frame angle +
    angle; the child's joint point on the parent's), then the loops are closed numerically.
    A cut joint (``closes_loop = true``) takes no ``angle``; ``assemble`` may be omitted (or
    true).

Closing the loops (``assembly``): Gauss-Newton with minimum-norm steps on the cut joints' gaps,
from the given pose, moving the passive joints only (the actuated ones keep their given angles:
they are the design's input, never turned behind the user's back), steps at most 0.3 rad and halved until the gap shrinks, so the assembly mode of the given pose is kept, until
every gap is below 1e-12 m. The Description then holds the assembled pose exactly as if it had
been typed, and ``Description.assembly`` records each joint's given and assembled angle and how
far each point moved (``Assembly.report()``, printed by ``planar-sym draw``). A loop that cannot
close is refused, naming the cut joint and the gap that remains.
"""

from .assembly import ASSEMBLY_TOL_M, place_at
from .reader import builtin_robots, load, resolve, robots_dir
from .types import (
    CLOSURE_TOLERANCE_M,
    COULOMB_SMOOTHING,
    G_LIMIT,
    GROUND,
    GYRATION_LIMIT,
    ZERO_SNAP_M,
    Actuator,
    Assembly,
    Body,
    Description,
    Joint,
    Parameter,
    wrap_angle,
)

__all__ = ["ASSEMBLY_TOL_M", "CLOSURE_TOLERANCE_M", "COULOMB_SMOOTHING", "GROUND",
           "GYRATION_LIMIT", "G_LIMIT", "ZERO_SNAP_M", "Actuator",
           "Assembly", "Body", "Description", "Joint", "Parameter", "builtin_robots", "load",
           "place_at", "resolve", "robots_dir", "wrap_angle"]
