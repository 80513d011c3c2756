"""Joints and the kinematic graph: each joint's two body points, the spanning tree from ground
(parents before children), the loop cuts, and the closure check of a pose taken as typed."""

from __future__ import annotations

import math

from ...spelling import unknown_keys
from . import mobility
from .actuators import Actuators
from .fields import JOINT_KEYS, JOINT_TYPES, NAME
from .types import (
    ANGLE_TURN_RAD,
    CLOSURE_TOLERANCE_M,
    GROUND,
    MOVING,
    ZERO_SNAP_M,
    Body,
    Joint,
    wrap_angle,
)


def _exact(v: float) -> float:
    """An axis component: rounding below ``ZERO_SNAP_M`` is 0, near +-1 is exactly +-1."""
    if abs(v) < ZERO_SNAP_M:
        return 0.0
    return math.copysign(1.0, v) if abs(abs(v) - 1.0) < ZERO_SNAP_M else v


class Topology(Actuators):
    """The joint and tree stage of the validator."""

    #: body names given in the file, even those with problems of their own
    declared: frozenset = frozenset()
    #: a joint angle beyond a turn in radians was warned (degrees typed as radians): closing
    #: the loops then turns joints far from those angles, which says nothing more
    angle_slip: bool = False

    def _joint(self, i: int, raw: dict, bodies: dict[str, Body], pose: str | None,
               scale: dict[str, float]) -> Joint | None:
        f = f"joints[{i}]"
        unknown_keys(raw, JOINT_KEYS, lambda key, msg: self.err(f"{f}.{key}", msg))
        name = self._str(raw, "name", f"{f}.name")
        if name is not None:
            f = f"joints[{i}] ({name})"
        jtype = raw.get("type")
        if jtype not in JOINT_TYPES:
            self.err(f"{f}.type", f"must be 'revolute', 'prismatic' or 'weld' (got {jtype!r})")
        ends = [self._end(raw, key, f, bodies) for key in ("parent", "child")]
        # actuated is required of a coordinate only: a wrong type is one problem, not two
        actuated = raw.get("actuated", None if jtype in MOVING else False)
        if actuated is None:
            self.err(f"{f}.actuated", "missing: true where a motor drives the joint, false where "
                                      "it is passive")
        elif not isinstance(actuated, bool):
            self.err(f"{f}.actuated", f"must be true or false (got {actuated!r})")
        loop = raw.get("closes_loop", False)
        if not isinstance(loop, bool):
            self.err(f"{f}.closes_loop", f"must be true or false (got {loop!r})")
        if jtype == "weld" and (actuated or loop):
            self.err(f"{f}", "a weld can be neither actuated nor a loop closure")
        if loop and actuated:
            self.err(f"{f}.actuated", "a loop-closing joint is cut, so it cannot be actuated")
        if jtype == "prismatic" and loop is True:
            self.err(f"{f}.closes_loop", "a loop cannot be cut at a prismatic joint (its cut "
                                         "would need a slide and an angle equation, not the two "
                                         "point equations of a revolute cut): cut the loop at "
                                         "one of its revolute joints, and make this one a tree "
                                         "joint (closes_loop = false)")
        known = jtype in JOINT_TYPES  # else the type is the one mistake: nothing more on it
        axis = self._axis(raw, f, jtype, ends[0], bodies) if known else None
        actuator = self._actuator(raw, f, jtype, actuated, scale)
        if jtype == "prismatic":
            angle = self._slide(raw, f, pose, loop is True, scale)
            rel = self._rel_angle(raw, f, pose, scale.get("angle"), ends, bodies)
        else:
            if "displacement" in raw and known:
                self.err(f"{f}.displacement", "only a prismatic joint has a displacement")
            angle = self._angle(raw, f, pose, loop is True, scale.get("angle"))
            rel = None
        if name is None or None in ends or jtype not in JOINT_TYPES:
            return None
        if jtype == "prismatic" and (axis is None or (pose == "joints" and rel is None)):
            return None
        if name is not None and not NAME.match(name):
            self.err(f"{f}.name", f"must be an identifier (got {name!r})")
        (pb, pp), (cb, cp) = ends  # type: ignore[misc]
        if pb == cb:
            self.err(f, f"joins body {pb!r} to itself")
        return Joint(name, jtype, pb, pp, cb, cp, bool(actuated), bool(loop), angle, axis, rel,
                     actuator)

    def _axis(self, raw: dict, f: str, jtype, parent, bodies) -> tuple[float, float] | None:
        """A prismatic joint's ``axis``: a direction in the drawn pose (pose = "world") or in the
        parent body's own coordinates (pose = "joints"), returned as a unit vector in the parent
        body's frame."""
        if jtype != "prismatic":
            if "axis" in raw:
                self.err(f"{f}.axis", f"only a prismatic joint has an axis (this one is "
                                      f"{jtype!r})")
            return None
        before = len(self.problems)
        v = self._vec(raw, "axis", f"{f}.axis", 1.0)
        if len(self.problems) > before:
            return None
        norm = math.hypot(*v)
        if norm == 0.0 or not math.isfinite(norm):
            self.err(f"{f}.axis", f"must have a length (got {list(raw['axis'])!r}: zero length, "
                                  "no direction to slide along)")
            return None
        if parent is None:
            return None
        # into the parent's frame; axis-aligned directions stay exact
        a = bodies[parent[0]].drawn_angle_rad
        c, s = math.cos(a), math.sin(a)
        ux, uy = v[0] / norm, v[1] / norm
        return (_exact(c * ux + s * uy), _exact(-s * ux + c * uy))

    def _slide(self, raw: dict, f: str, pose: str | None, loop: bool,
               scale: dict[str, float]) -> float | None:
        """``displacement`` (pose = "joints", length units, default 0): where the child point
        sits along the axis from the parent point; None in pose = "world"."""
        if "angle" in raw and pose != "joints":
            self.err(f"{f}.angle", "a prismatic joint slides: it has no angle (with pose = "
                                   "'joints', angle is the child's fixed angle to the parent)")
        if "displacement" not in raw:
            return 0.0 if pose == "joints" and not loop else None
        if pose == "world":
            self.err(f"{f}.displacement", "only with pose = 'joints' (with pose = 'world', the "
                                          "points give every displacement)")
            return None
        value = self._num(raw, "displacement", f"{f}.displacement")
        unit = scale.get("length")
        return None if value is None or unit is None else value * unit

    def _rel_angle(self, raw: dict, f: str, pose: str | None, unit: float | None, ends,
                   bodies) -> float | None:
        """The child frame's fixed angle to the parent frame across a prismatic joint (rad):
        as drawn (pose = "world"), or ``angle`` (pose = "joints", default 0)."""
        if pose == "joints":
            if "angle" not in raw:
                return 0.0
            value = self._num(raw, "angle", f"{f}.angle")
            return None if value is None or unit is None else value * unit
        if None in ends:
            return None
        return bodies[ends[1][0]].drawn_angle_rad - bodies[ends[0][0]].drawn_angle_rad

    def _angle(self, raw: dict, f: str, pose: str | None, loop: bool,
               unit: float | None) -> float | None:
        """``angle``: the approximate joint coordinate of a tree joint with pose = "joints" (in
        [units].angle, default 0); None in pose = "world"."""
        if "angle" not in raw:
            return 0.0 if pose == "joints" and not loop else None
        if pose == "world":
            self.err(f"{f}.angle", "only with pose = 'joints' (with pose = 'world', the default, "
                                   "the points give every angle)")
            return None
        if loop:
            self.err(f"{f}.angle", "a loop-closing joint is cut: it is not a coordinate, so it "
                                   "has no angle (the loop gives it)")
            return None
        value = self._num(raw, "angle", f"{f}.angle")
        if value is None or unit is None:
            return None
        if unit == 1.0 and abs(value) > ANGLE_TURN_RAD:
            self.angle_slip = True  # the sketch's angles are the slip: said once, here
            self.warn(f"{f}.angle", f"{value:g} rad is {abs(value) / ANGLE_TURN_RAD:.3g} turns "
                                    f"(a warning beyond one): the drawn pose takes it as "
                                    f"{math.degrees(wrap_angle(value)):.4g} deg; were the angles "
                                    f"typed in degrees? (units.angle = \"deg\" makes it "
                                    f"{value:g} deg)")
        return value * unit

    def _end(self, raw: dict, key: str, f: str, bodies) -> tuple[str, str] | None:
        ref = self._str(raw, key, f"{f}.{key}")
        if ref is None:
            return None
        body, _, point = ref.partition(".")
        if body not in bodies and body in self.declared:
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
            self._unplaced(unplaced, joints, bodies)
        self._repeated(joints)
        if not [j for j in tree if j.moves] and not self.problems:
            self.err("joints", "no revolute or prismatic joint: the robot has no coordinates")
        return ordered, loops

    def _unplaced(self, unplaced: list[str], joints: list[Joint], bodies) -> None:
        """Bodies off the tree: disconnected, or reached only through cut joints (then there are
        more cuts than independent loops, and the cut bodies would have no coordinates)."""
        reach, grew = {GROUND}, True
        while grew:
            grew = False
            for j in joints:
                if (j.parent in reach) != (j.child in reach):
                    reach |= {j.parent, j.child}
                    grew = True
        cut_only = [b for b in unplaced if b in reach]
        if cut_only:
            cuts = [j.name for j in joints if j.closes_loop
                    and ((j.parent in cut_only) != (j.child in cut_only))]
            loops = len(joints) - (len(bodies) - 1)  # edges - nodes + 1, ground a node
            n_cut = sum(j.closes_loop for j in joints)
            self.err("joints", f"bodies {cut_only} reach ground only through cut joints "
                               f"({', '.join(cuts)}): {n_cut} cuts for {loops} independent "
                               f"loop{'s' if loops != 1 else ''} leave the tree disconnected; "
                               f"make {' or '.join(cuts)} a tree joint (closes_loop = false)")
        if len(cut_only) < len(unplaced):
            self.err("joints", f"bodies {[b for b in unplaced if b not in reach]} are not "
                               "connected to ground by a chain of joints (the kinematic graph "
                               "is disconnected)")

    def _repeated(self, joints: list[Joint]) -> None:
        """Two joints joining the same two body points: the second adds no loop, only the same
        two equations again (a loop cut twice), and the loop equations become dependent."""
        seen: dict[frozenset, Joint] = {}
        for j in joints:
            key = frozenset({(j.parent, j.parent_point), (j.child, j.child_point)})
            if key in seen and (seen[key].closes_loop or j.closes_loop):  # else: a body with
                first = seen[key]  # two parents, reported already
                what = "loop cut twice" if first.closes_loop else "joint repeated"
                self.err("joints", f"{what}: {first.name} and {j.name} both join "
                                   f"{j.parent}.{j.parent_point} to {j.child}.{j.child_point}, "
                                   f"so {j.name} closes no new loop, it only repeats "
                                   f"{first.name}'s 2 equations; remove {j.name}")
            else:
                seen[key] = j

    def _mobility(self, tree: list[Joint], loops: list[Joint], bodies: dict[str, Body],
                  drawn: bool) -> None:
        """Degrees of freedom against actuation and the rank of Phi_q at the drawn pose (see
        ``mobility``), once that pose is built (``drawn``); else only what the count shows,
        which explains a loop that the actuated joints hold open."""
        for problem in mobility.problems(bodies, tree, loops, drawn):
            self.err("joints", problem)

    def _closure(self, joints: list[Joint], bodies: dict[str, Body]) -> None:
        """Every joint's two points meet in the pose as typed (pose = "world", no assemble)."""
        for j in joints:
            if j.parent == j.child:  # said already: "joins body ... to itself"
                continue
            a = bodies[j.parent].world(bodies[j.parent].points_m[j.parent_point])
            b = bodies[j.child].world(bodies[j.child].points_m[j.child_point])
            gap = math.hypot(a[0] - b[0], a[1] - b[1])
            if j.type == "prismatic":
                self._on_axis(j, bodies, a, b)
                continue
            if gap > CLOSURE_TOLERANCE_M:
                what = "loop" if j.closes_loop else "joint"
                self.err(f"joints ({j.name})",
                         f"{what} does not close in the drawn configuration: "
                         f"{j.parent}.{j.parent_point} and {j.child}.{j.child_point} are "
                         f"{gap * 1e3:.6g} mm apart (tolerance {CLOSURE_TOLERANCE_M * 1e3:g} mm)"
                         + ("; set assemble = true to let planar-sym close it from this pose"
                            if j.closes_loop else ""))

    def _on_axis(self, j: Joint, bodies: dict[str, Body], a, b) -> None:
        """A prismatic joint's child point lies on the line through its parent point along
        the axis, in the pose as typed."""
        wx, wy = bodies[j.parent].direction(j.axis)  # type: ignore[arg-type]
        off = abs((b[0] - a[0]) * wy - (b[1] - a[1]) * wx)
        if off > CLOSURE_TOLERANCE_M:
            self.err(f"joints ({j.name})",
                     f"prismatic joint's axis does not pass both its points: "
                     f"{j.child}.{j.child_point} is {off * 1e3:.6g} mm off the line through "
                     f"{j.parent}.{j.parent_point} along the axis [{wx:.6g}, {wy:.6g}] in the "
                     f"drawn configuration (tolerance {CLOSURE_TOLERANCE_M * 1e3:g} mm): the "
                     "child point slides along the axis through the parent point")
