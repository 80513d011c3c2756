"""Robot descriptions: read a TOML file, validate all of it at once, convert to SI body frames.

Stage 1 of the pipeline, shared by ``derive`` (build time) and the runtime; imports no SymPy.

Conventions (written once, used everywhere):

* Every point of the description is given in world coordinates of the *drawn* configuration,
  as the seed's tables do ("CS from World"); the centre of gravity is given relative to a named
  point in world axes ("CG Position from CS1"), or relative to the world origin.
* Each body gets a frame: origin at a named point, x-axis toward a second named point (a
  link-aligned frame) or world-aligned in the drawn configuration.
* The coordinate of a revolute joint is the angle of the child frame minus the angle of the
  parent frame (rad). With link-aligned frames the seed's angles come out directly: q1 absolute,
  q2 relative for the serial arms, th2 and th5 absolute for the 5-bars.
* A joint with ``closes_loop = true`` is cut: it is not a coordinate but two loop-closure
  equations (its two points coincide).
"""

from __future__ import annotations

import hashlib
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import DescriptionError
from .units import SI, factor

#: Joints (and loops) must close in the drawn configuration to this gap, in metres. The seed's
#: tables carry six decimals, so its own rounding stays far below it.
CLOSURE_TOLERANCE_M = 1e-5

#: A radius of gyration sqrt(izz / m) more than this many times the body's extent (largest
#: distance from the centre of gravity to one of its points) is an error: a uniform rod has
#: 0.58 times, mass beyond its points (a housing, a wide link) rarely more than 2. Catches the
#: seed's 3-RRR "90992 kg*mm^2" (28 times) and kg*mm^2 written where kg*m^2 was meant.
GYRATION_LIMIT = 3.0

#: Body-frame coordinates smaller than this (m) are exact zeros: rotating a point that lies on a
#: link's axis into the link frame leaves ~1e-17 of rounding, which must not become a parameter.
ZERO_SNAP_M = 1e-12

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_TOP_KEYS = {"name", "title", "units", "gravity", "ground", "bodies", "joints", "task", "symbols",
             "notes", "assemble"}
_UNIT_KEYS = {"length", "mass", "inertia", "angle", "acceleration"}
_BODY_KEYS = {"name", "mass", "izz", "cg", "cg_from", "points", "frame", "notes"}
_JOINT_KEYS = {"name", "type", "parent", "child", "actuated", "closes_loop", "notes"}
_TASK_KEYS = {"point", "orientation"}
GROUND = "ground"


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


@dataclass(frozen=True)
class Joint:
    """A joint between two body points: ``revolute`` (a coordinate, or a cut) or ``weld``."""

    name: str
    type: str
    parent: str
    parent_point: str
    child: str
    child_point: str
    actuated: bool
    closes_loop: bool


@dataclass(frozen=True)
class Parameter:
    """One entry of the parameter vector ``p`` of every generated function."""

    name: str
    value: float  # SI
    unit: str
    meaning: str


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
    #: what ``assemble = true`` changed (model.assembly.Assembly), None otherwise
    assembly: object = None

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
        """Joint coordinates of the drawn configuration (rad)."""
        b = self.bodies
        return tuple(
            b[j.child].drawn_angle_rad - b[j.parent].drawn_angle_rad for j in self._revolutes()
        )

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


def robots_dir() -> Path:
    """Folder of the built-in robot descriptions."""
    return Path(__file__).resolve().parents[1] / "robots"


def builtin_robots() -> list[str]:
    return sorted(p.stem for p in robots_dir().glob("*.toml"))


def resolve(robot: str | Path) -> Path:
    """A built-in robot name or a path to a TOML file."""
    p = Path(robot)
    if p.suffix == ".toml":
        return p
    candidate = robots_dir() / f"{robot}.toml"
    if not candidate.exists():
        raise DescriptionError(
            [f"unknown robot {robot!r}; built in: {', '.join(builtin_robots())}"]
        )
    return candidate


def load(robot: str | Path) -> Description:
    """Read and validate a description; raises DescriptionError listing every problem."""
    path = resolve(robot)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise DescriptionError([f"{path}: cannot read ({exc.strerror})"]) from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise DescriptionError([f"{path}: not valid TOML: {exc}"]) from None
    return _Validator(path, data, hashlib.sha256(raw).hexdigest()).run()


class _Validator:
    """Collects every problem of one description before raising."""

    def __init__(self, path: Path, data: dict, sha: str):
        self.path, self.data, self.sha = path, data, sha
        self.problems: list[str] = []

    def err(self, fld: str, msg: str) -> None:
        self.problems.append(f"{self.path}: {fld}: {msg}")

    def run(self) -> Description:
        d = self.data
        for key in sorted(set(d) - _TOP_KEYS):
            self.err(key, f"unknown key (known: {', '.join(sorted(_TOP_KEYS))})")
        name = self._str(d, "name", "name")
        if name and not _NAME.match(name):
            self.err("name", f"must be an identifier (got {name!r})")
        scale = self._units(d.get("units"))
        gravity = self._vec(d, "gravity", "gravity", scale.get("acceleration"))
        ground = self._ground(d.get("ground"), scale)
        bodies = {GROUND: ground} if ground else {}
        # bodies with their own errors are still declared: joints naming them say nothing more
        raw_bodies = self._list(d, "bodies")
        self.declared = {GROUND} | {b.get("name") for b in raw_bodies
                                    if isinstance(b.get("name"), str)}
        duplicate = False
        for i, raw in enumerate(raw_bodies):
            body = self._body(i, raw, scale)
            if body is None:
                continue
            if body.name in bodies:
                self.err(f"bodies[{i}].name", f"duplicate body name {body.name!r}")
                duplicate = True
                continue
            bodies[body.name] = body
        joints = [j for i, raw in enumerate(self._list(d, "joints"))
                  if (j := self._joint(i, raw, bodies)) is not None]
        before = len(self.problems)
        tree, loops = self._tree(joints, bodies)
        assemble = d.get("assemble", False)
        if not isinstance(assemble, bool):
            self.err("assemble", f"must be true or false (got {assemble!r})")
            assemble = False
        assembly = None
        if not duplicate and len(self.problems) == before:
            if assemble:
                bodies, assembly = self._assemble(tree, loops, bodies)
            else:
                self._closure(joints, bodies)
        task = self._task(d.get("task"), bodies)
        display = d.get("symbols", {})
        if not isinstance(display, dict) or not all(isinstance(v, str) for v in display.values()):
            self.err("symbols", "must be a table of parameter name = display string")
            display = {}
        if self.problems:
            raise DescriptionError(self.problems)
        desc = Description(name, str(d.get("title", name)), self.path, self.sha,
                           gravity, bodies, tuple(tree), tuple(loops), task[0], task[1],
                           dict(display), assembly)
        unknown = sorted(set(display) - {p.name for p in desc.parameters()})
        for key in unknown:
            self.err(f"symbols.{key}", "not a parameter of this robot")
        if self.problems:
            raise DescriptionError(self.problems)
        return desc

    # -- fields -----------------------------------------------------------------------------
    def _str(self, tbl: dict, key: str, fld: str) -> str | None:
        v = tbl.get(key)
        if v is None:
            self.err(fld, "missing")
        elif not isinstance(v, str):
            self.err(fld, f"must be a string (got {v!r})")
        else:
            return v
        return None

    def _num(self, tbl: dict, key: str, fld: str) -> float | None:
        v = tbl.get(key)
        if v is None:
            self.err(fld, "missing")
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            self.err(fld, f"must be a number (got {v!r})")
        elif not _finite(v):
            self.err(fld, f"must be finite (got {v!r:.40})")
        else:
            return float(v)
        return None

    def _vec(self, tbl: dict, key: str, fld: str, unit: float | None) -> tuple[float, float]:
        v = tbl.get(key)
        if v is None:
            self.err(fld, "missing")
        elif (not isinstance(v, list) or len(v) != 2
              or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)):
            self.err(fld, f"must be a list of two numbers [x, y] (got {v!r})")
        elif not all(_finite(x) for x in v):
            self.err(fld, f"must be finite (got {v!r:.60})")
        elif unit is not None:
            return (float(v[0]) * unit, float(v[1]) * unit)
        return (0.0, 0.0)

    def _list(self, tbl: dict, key: str) -> list:
        v = tbl.get(key)
        if v is None:
            self.err(key, "missing")
            return []
        if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            self.err(key, "must be an array of tables ([[" + key + "]])")
            return []
        return v

    def _units(self, u) -> dict[str, float]:
        if not isinstance(u, dict):
            self.err("units", "missing table [units] (length, mass, inertia, angle, acceleration)")
            return {}
        out = {}
        for key in sorted(set(u) - _UNIT_KEYS):
            self.err(f"units.{key}", f"unknown quantity (known: {', '.join(sorted(_UNIT_KEYS))})")
        for q in sorted(_UNIT_KEYS):
            if q not in u:
                self.err(f"units.{q}", f"missing (SI would be {SI[q]!r})")
                continue
            try:
                out[q] = factor(q, u[q]) if isinstance(u[q], str) else factor(q, repr(u[q]))
            except KeyError as exc:
                self.err(f"units.{q}", f"{exc.args[0]} (got {u[q]!r})")
        return out

    def _points(self, raw, fld: str, length: float | None) -> dict[str, tuple[float, float]]:
        if not isinstance(raw, dict) or not raw:
            self.err(fld, "must be a non-empty table of name = [x, y]")
            return {}
        pts = {}
        for pname in raw:
            if not _NAME.match(pname):
                self.err(f"{fld}.{pname}", "point names must be identifiers")
            pts[pname] = self._vec(raw, pname, f"{fld}.{pname}", length)
        return pts

    def _ground(self, g, scale) -> Body | None:
        if not isinstance(g, dict):
            self.err("ground", "missing table [ground] with its points (world frame)")
            return None
        for key in sorted(set(g) - {"points", "notes"}):
            self.err(f"ground.{key}", "unknown key (known: points, notes)")
        pts = self._points(g.get("points"), "ground.points", scale.get("length"))
        return Body(GROUND, 0.0, 0.0, (0.0, 0.0), pts, 0.0, (0.0, 0.0))

    def _body(self, i: int, raw: dict, scale) -> Body | None:
        f = f"bodies[{i}]"
        for key in sorted(set(raw) - _BODY_KEYS):
            self.err(f"{f}.{key}", f"unknown key (known: {', '.join(sorted(_BODY_KEYS))})")
        name = self._str(raw, "name", f"{f}.name")
        if name is not None:
            f = f"bodies[{i}] ({name})"
            if not _NAME.match(name) or name == GROUND:
                self.err(f"{f}.name", f"must be an identifier other than 'ground' (got {name!r})")
        length, mass_u, inertia_u = scale.get("length"), scale.get("mass"), scale.get("inertia")
        mass = self._num(raw, "mass", f"{f}.mass")
        if mass is not None and mass <= 0:
            self.err(f"{f}.mass", f"must be > 0 (got {mass})")
        izz = self._num(raw, "izz", f"{f}.izz")
        if izz is not None and izz < 0:
            self.err(f"{f}.izz", f"must be >= 0 (got {izz})")
        pts = self._points(raw.get("points"), f"{f}.points", length)
        cg_world = self._vec(raw, "cg", f"{f}.cg", length)
        cg_from = self._str(raw, "cg_from", f"{f}.cg_from")
        if cg_from is not None and cg_from != "world" and cg_from not in pts:
            self.err(f"{f}.cg_from", f"must be 'world' or one of its points {sorted(pts)} "
                                     f"(got {cg_from!r})")
        frame = raw.get("frame", [next(iter(pts))] if pts else [])
        if (not isinstance(frame, list) or not 1 <= len(frame) <= 2
                or any(not isinstance(p, str) or p not in pts for p in frame)):
            self.err(f"{f}.frame", f"must be [origin] or [origin, x_toward], naming its points "
                                   f"{sorted(pts)} (got {frame!r})")
            return None
        if (None in (name, mass, izz, cg_from, length, mass_u, inertia_u) or not pts
                or (cg_from != "world" and cg_from not in pts)):
            return None
        origin = pts[frame[0]]
        angle = 0.0
        if len(frame) == 2:
            dx, dy = pts[frame[1]][0] - origin[0], pts[frame[1]][1] - origin[1]
            if math.hypot(dx, dy) < CLOSURE_TOLERANCE_M:
                self.err(f"{f}.frame", f"points {frame} coincide: no x-axis direction")
            angle = math.atan2(dy, dx)
        local = {p: _to_body(xy, origin, angle) for p, xy in pts.items()}
        # offset rotated on its own, then added in the body frame: keeps 0.04168 exact
        base = _to_body((0.0, 0.0), origin, angle) if cg_from == "world" else local[cg_from]
        off = _to_body(cg_world, (0.0, 0.0), angle)
        cg = _snap(base[0] + off[0]), _snap(base[1] + off[1])
        body = Body(name, mass * mass_u, izz * inertia_u, cg, local, angle, origin)
        self._plausible(f, body, raw["izz"], self.data["units"].get("inertia"))
        return body

    def _plausible(self, f: str, body: Body, izz_given: float, unit: str) -> None:
        """A body with extent needs inertia, and not more than its size allows."""
        if body.mass_kg <= 0 or body.izz_kg_m2 < 0:
            return  # reported already
        extent = max(math.dist(body.cg_m, xy) for xy in body.points_m.values())
        if extent < CLOSURE_TOLERANCE_M:
            return  # a point mass (a motor at a joint): any izz >= 0 is a rotor's
        if body.izz_kg_m2 == 0.0:
            self.err(f"{f}.izz", f"must be > 0 for a body with extent (its points reach "
                                 f"{extent * 1e3:.4g} mm from its centre of gravity); only a "
                                 "body with a single point may be a point mass")
            return
        radius = math.sqrt(body.izz_kg_m2 / body.mass_kg)
        if radius > GYRATION_LIMIT * extent:
            self.err(f"{f}.izz", f"implausible: {izz_given} {unit} gives a radius of gyration "
                                 f"of {radius * 1e3:.4g} mm for a body whose points reach "
                                 f"{extent * 1e3:.4g} mm from its centre of gravity (more than "
                                 f"{GYRATION_LIMIT:g} times); a unit or decimal-point slip?")

    def _joint(self, i: int, raw: dict, bodies: dict[str, Body]) -> Joint | None:
        f = f"joints[{i}]"
        for key in sorted(set(raw) - _JOINT_KEYS):
            self.err(f"{f}.{key}", f"unknown key (known: {', '.join(sorted(_JOINT_KEYS))})")
        name = self._str(raw, "name", f"{f}.name")
        if name is not None:
            f = f"joints[{i}] ({name})"
        jtype = raw.get("type")
        if jtype not in ("revolute", "weld"):
            self.err(f"{f}.type", f"must be 'revolute' or 'weld' (got {jtype!r})")
        ends = [self._end(raw, key, f, bodies) for key in ("parent", "child")]
        actuated = raw.get("actuated", False if jtype == "weld" else None)
        if not isinstance(actuated, bool):
            self.err(f"{f}.actuated", f"must be true or false (got {actuated!r})")
        loop = raw.get("closes_loop", False)
        if not isinstance(loop, bool):
            self.err(f"{f}.closes_loop", f"must be true or false (got {loop!r})")
        if jtype == "weld" and (actuated or loop):
            self.err(f"{f}", "a weld can be neither actuated nor a loop closure")
        if loop and actuated:
            self.err(f"{f}.actuated", "a loop-closing joint is cut, so it cannot be actuated")
        if name is None or None in ends or jtype not in ("revolute", "weld"):
            return None
        if name is not None and not _NAME.match(name):
            self.err(f"{f}.name", f"must be an identifier (got {name!r})")
        (pb, pp), (cb, cp) = ends  # type: ignore[misc]
        if pb == cb:
            self.err(f, f"joins body {pb!r} to itself")
        return Joint(name, jtype, pb, pp, cb, cp, bool(actuated), bool(loop))

    def _end(self, raw: dict, key: str, f: str, bodies) -> tuple[str, str] | None:
        ref = self._str(raw, key, f"{f}.{key}")
        if ref is None:
            return None
        body, _, point = ref.partition(".")
        if body not in bodies and body in getattr(self, "declared", ()):
            return None  # the body's own problems are reported already
        if body not in bodies:
            self.err(f"{f}.{key}", f"unknown body {body!r} (known: {', '.join(bodies)})")
        elif point not in bodies[body].points_m:
            self.err(f"{f}.{key}", f"body {body!r} has no point {point!r} "
                                   f"(it has {', '.join(bodies[body].points_m)})")
        else:
            return body, point
        return None

    def _tree(self, joints: list[Joint], bodies: dict[str, Body]):
        names = [j.name for j in joints]
        for n in sorted({n for n in names if names.count(n) > 1}):
            self.err("joints", f"duplicate joint name {n!r}")
        tree = [j for j in joints if not j.closes_loop]
        loops = [j for j in joints if j.closes_loop]
        into: dict[str, list[Joint]] = {}
        for j in tree:
            into.setdefault(j.child, []).append(j)
        for body, js in into.items():
            if body == GROUND:
                self.err("joints", f"ground is the child of {[j.name for j in js]}; ground is "
                                   "the root of the tree, make it the parent")
            elif len(js) > 1:
                self.err("joints", f"body {body!r} is the child of several joints "
                                   f"{[j.name for j in js]}: mark all but one closes_loop = true")
        # topological order that keeps the file's order where the tree allows: coordinates follow
        # the file, parents always before children
        ordered, placed, pending = [], {GROUND}, list(tree)
        while (ready := next((j for j in pending if j.parent in placed), None)) is not None:
            ordered.append(ready)
            placed.add(ready.child)
            pending.remove(ready)
        unplaced = sorted(set(bodies) - placed)
        if unplaced and not any(len(v) > 1 for v in into.values()) and not self.problems:
            self.err("joints", f"bodies {unplaced} are not connected to ground by a chain of "
                               "joints (the kinematic graph is disconnected)")
        if not [j for j in tree if j.type == "revolute"] and not self.problems:
            self.err("joints", "no revolute joint: the robot has no coordinates")
        return ordered, loops

    def _closure(self, joints: list[Joint], bodies: dict[str, Body]) -> None:
        for j in joints:
            a = _world(bodies[j.parent], j.parent_point)
            b = _world(bodies[j.child], j.child_point)
            gap = math.hypot(a[0] - b[0], a[1] - b[1])
            if gap > CLOSURE_TOLERANCE_M:
                what = "loop" if j.closes_loop else "joint"
                self.err(f"joints ({j.name})",
                         f"{what} does not close in the drawn configuration: "
                         f"{j.parent}.{j.parent_point} and {j.child}.{j.child_point} are "
                         f"{gap * 1e3:.6g} mm apart (tolerance {CLOSURE_TOLERANCE_M * 1e3:g} mm)"
                         + ("; set assemble = true to let planar-sym close it from this pose"
                            if j.closes_loop else ""))

    def _assemble(self, tree, loops, bodies: dict[str, Body]):
        """The loops closed numerically from the given (approximate) pose; see model.assembly."""
        from .assembly import assemble

        if not loops:
            self.err("assemble", "the robot has no loop (no joint with closes_loop = true) to "
                                 "assemble")
            return bodies, None
        placed, result = assemble(bodies, tree, loops)
        if placed is None:
            self.err(f"joints ({result.split()[1]})", result)
            return bodies, None
        return placed, result

    def _task(self, t, bodies) -> tuple[tuple[str, str], str | None]:
        if not isinstance(t, dict):
            self.err("task", "missing table [task] with point = 'body.point'")
            return ("", ""), None
        for key in sorted(set(t) - _TASK_KEYS):
            self.err(f"task.{key}", f"unknown key (known: {', '.join(sorted(_TASK_KEYS))})")
        end = self._end(t, "point", "task", bodies) or ("", "")
        orient = t.get("orientation")
        if orient is not None and (not isinstance(orient, str) or orient not in bodies):
            self.err("task.orientation", f"must name a body (got {orient!r})")
            orient = None
        return end, orient


def _to_body(xy, origin, angle: float) -> tuple[float, float]:
    dx, dy = xy[0] - origin[0], xy[1] - origin[1]
    c, s = math.cos(angle), math.sin(angle)
    return (_snap(c * dx + s * dy), _snap(-s * dx + c * dy))


def _finite(v) -> bool:
    """A TOML integer may exceed float range (1 followed by 400 zeros): that is not finite."""
    try:
        return math.isfinite(float(v))
    except OverflowError:
        return False


def _snap(v: float) -> float:
    return 0.0 if abs(v) < ZERO_SNAP_M else v


def _world(body: Body, point: str) -> tuple[float, float]:
    x, y = body.points_m[point]
    c, s = math.cos(body.drawn_angle_rad), math.sin(body.drawn_angle_rad)
    o = body.drawn_origin_m
    return (o[0] + c * x - s * y, o[1] + s * x + c * y)
