"""Joints and the kinematic graph: each joint's two body points, the spanning tree from ground
(parents before children), the loop cuts, and the closure check of a pose taken as typed."""

from __future__ import annotations

import math

from .fields import JOINT_KEYS, NAME, Fields
from .types import CLOSURE_TOLERANCE_M, GROUND, Body, Joint


class Topology(Fields):
    """The joint and tree stage of the validator."""

    #: body names given in the file, even those with problems of their own
    declared: frozenset = frozenset()

    def _joint(self, i: int, raw: dict, bodies: dict[str, Body], pose: str | None,
               angle_unit: float | None) -> Joint | None:
        f = f"joints[{i}]"
        for key in sorted(set(raw) - JOINT_KEYS):
            self.err(f"{f}.{key}", f"unknown key (known: {', '.join(sorted(JOINT_KEYS))})")
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
        angle = self._angle(raw, f, pose, loop is True, angle_unit)
        if name is None or None in ends or jtype not in ("revolute", "weld"):
            return None
        if name is not None and not NAME.match(name):
            self.err(f"{f}.name", f"must be an identifier (got {name!r})")
        (pb, pp), (cb, cp) = ends  # type: ignore[misc]
        if pb == cb:
            self.err(f, f"joins body {pb!r} to itself")
        return Joint(name, jtype, pb, pp, cb, cp, bool(actuated), bool(loop), angle)

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
            self.err("joints", f"bodies {unplaced} are not connected to ground by a chain of "
                               "joints (the kinematic graph is disconnected)")
        if not [j for j in tree if j.type == "revolute"] and not self.problems:
            self.err("joints", "no revolute joint: the robot has no coordinates")
        return ordered, loops

    def _closure(self, joints: list[Joint], bodies: dict[str, Body]) -> None:
        """Every joint's two points meet in the pose as typed (pose = "world", no assemble)."""
        for j in joints:
            a = bodies[j.parent].world(bodies[j.parent].points_m[j.parent_point])
            b = bodies[j.child].world(bodies[j.child].points_m[j.child_point])
            gap = math.hypot(a[0] - b[0], a[1] - b[1])
            if gap > CLOSURE_TOLERANCE_M:
                what = "loop" if j.closes_loop else "joint"
                self.err(f"joints ({j.name})",
                         f"{what} does not close in the drawn configuration: "
                         f"{j.parent}.{j.parent_point} and {j.child}.{j.child_point} are "
                         f"{gap * 1e3:.6g} mm apart (tolerance {CLOSURE_TOLERANCE_M * 1e3:g} mm)"
                         + ("; set assemble = true to let planar-sym close it from this pose"
                            if j.closes_loop else ""))
