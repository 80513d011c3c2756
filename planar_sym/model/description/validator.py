"""The validator: every stage run over one description's TOML data, every problem collected,
then either a Description or one DescriptionError listing them all."""

from __future__ import annotations

import math

from ...errors import DescriptionError
from ...spelling import unknown_keys
from ..units import UNITS
from .actuators import ACTUATOR_KEYS
from .assembly import assemble, place, tree_angles
from .bodies import Bodies
from .fields import NAME, TASK_KEYS, TOP_KEYS
from .topology import Topology
from .types import GROUND, Body, Description, Joint
from .unit_slips import unit_slips

#: where a description takes numbers, for ``expressions.numbers``: 0 a number, 1 a list of
#: numbers; a string there is an expression. Every ``_num`` and ``_vec`` field is here.
NUMBERS = {
    "gravity": 1,
    "ground": {"points": {"*": 1}},
    "bodies": [{"mass": 0, "izz": 0, "cg": 1, "points": {"*": 1}}],
    "joints": [{"angle": 0, "displacement": 0, "axis": 1,
                "actuator": {k: 0 for k in ACTUATOR_KEYS if k != "notes"}}],
}



#: closing the loops may turn a joint this far from its given angle without a warning (deg)
SKETCH_TURN_DEG = 30.0

class AnyBody(frozenset):
    """The declared bodies when one has no usable name (missing, not an identifier, a
    duplicate): any body a joint names may be that one, so no joint says 'unknown body'."""

    def __contains__(self, item) -> bool:
        return True


class Validator(Bodies, Topology):
    """Collects every problem of one description before raising."""

    def run(self) -> Description:
        d = self.data
        unknown_keys(d, TOP_KEYS, self.err)
        if not self._expressions(NUMBERS):
            raise DescriptionError(self.problems)
        d = self.data
        name = self._str(d, "name", "name")
        if name and not NAME.match(name):
            self.err("name", f"must be an identifier (got {name!r})")
        pose = self._pose(d)
        scale = self._units(d.get("units"))
        self._span(d, pose, scale)
        gravity = self._vec(d, "gravity", "gravity", scale.get("acceleration"))
        self._gravity_plausible(gravity, d)
        ground = self._ground(d.get("ground"), scale)
        bodies = {GROUND: ground} if ground else {}
        # bodies with their own errors are still declared: joints naming them say nothing more
        raw_bodies = self._list(d, "bodies")
        self.declared = _declared(d, raw_bodies)
        duplicate = False
        for i, raw in enumerate(raw_bodies):
            body = self._body(i, raw, scale, pose)
            if body is None:
                continue
            if body.name in bodies:
                self.err(f"bodies[{i}].name", f"duplicate body name {body.name!r}")
                duplicate = True
                continue
            bodies[body.name] = body
        raw_joints = self._list(d, "joints")
        joints = [j for i, raw in enumerate(raw_joints)
                  if (j := self._joint(i, raw, bodies, pose, scale))
                  is not None]
        # every body and joint built: only then can the loops be assembled (a partial robot
        # would add 'no loop' or 'cannot close' to the problem already reported)
        complete = (len(bodies) == len(raw_bodies) + 1 and len(joints) == len(raw_joints)
                    and not (pose == "joints" and any(j.angle_rad is None for j in joints
                                                      if not j.closes_loop)))
        before = len(self.problems)
        tree, loops = self._tree(joints, bodies)
        closing = self._assemble_option(d, pose)
        assembly = None
        if not duplicate and len(self.problems) == before and closing is not None:
            bodies, assembly = self._drawn_pose(pose, closing, joints, tree, loops, bodies,
                                                complete)
            if complete:  # a body or joint left out for its own problem: no count to make
                # a body's points in another unit: its drawn pose is no pose (said at them)
                self._mobility(tree, loops, bodies,
                               len(self.problems) == before and not self.points_slip)
        task = self._task(d.get("task"), bodies)
        display = d.get("symbols", {})
        if not isinstance(display, dict) or not all(isinstance(v, str) for v in display.values()):
            self.err("symbols", "must be a table of parameter name = display string")
            display = {}
        self._symbols_plausible(display)
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
        self._show_warnings()
        return desc

    def _assemble_option(self, d: dict, pose: str | None) -> bool | None:
        """Whether the loops are closed numerically; None when the pose cannot be built (a
        problem with ``pose`` or ``assemble`` is reported, and no gap should be on top of it)."""
        if pose is None:
            return None
        if "assemble" not in d:
            return pose == "joints"
        value = self._bool(d, "assemble", "assemble", None)
        if value is False and pose == "joints":
            self.err("assemble", "pose = 'joints' gives approximate joint angles, so its loops "
                                 "are always assembled: remove assemble = false")
            return None
        return value

    def _drawn_pose(self, pose: str, closing: bool, joints: list[Joint], tree: list[Joint],
                    loops: list[Joint], bodies: dict[str, Body], complete: bool):
        """(bodies placed in the drawn pose, Assembly or None); ``joints`` in the file's order,
        ``tree`` parents first; ``complete``: no body or joint left out for its own problems."""
        if pose == "world" and not closing:  # joint by joint: those built can be checked
            self._closure([j for j in joints if not {j.parent, j.child} & self.points_slip],
                          bodies)  # (not at a body whose points are in another unit: said)
            return bodies, None
        if not complete:
            return bodies, None
        if pose == "world":
            if not loops:
                self.err("assemble", "the robot has no loop (no joint with closes_loop = true) "
                                     "to assemble")
                return bodies, None
            start, reference = tree_angles(bodies, tree), bodies
        else:
            if any(j.angle_rad is None for j in tree):
                return bodies, None  # a joint's angle is wrong, reported already
            start = {j.name: j.angle_rad for j in tree}
            reference = place(bodies, tree, start)
            if not loops:
                return reference, None  # a tree: the angles place it exactly
        unit = self.unit_names.get("length", "m")
        placed, result = assemble(bodies, tree, loops, start, reference, pose, unit)
        if placed is None:
            if self.points_slip:  # a body's points in another unit, reported at them
                return bodies, None
            loop, message = result
            start_of = (lambda b: tree_angles(b, tree)) if pose == "world" else lambda b: start
            self.err(f"joints ({loop})", message + self._unit_hint(
                unit_slips(bodies, tree, loops, start_of, unit), unit))
            return bodies, None
        self._far_from_sketch(result)
        return placed, result

    def _unit_hint(self, slips: dict, unit: str) -> str:
        """The loop's message's hint at bodies typed in another length unit (``unit_slips``),
        naming their fields, or nothing."""
        if not slips:
            return ""
        index = {b.get("name"): i for i, b in enumerate(self.data["bodies"])}
        per = UNITS["length"][unit]
        said = [("ground.points" if n == GROUND else f"bodies[{index[n]}] ({n}).points")
                + f' read in "{s.unit}" (size {s.size_m / per:.4g} {unit} as typed, '
                f"{s.meant_m / per:.4g} {unit} so read, the others' median {s.others_m / per:.4g}"
                f" {unit})" for n, s in slips.items()]
        units = sorted({s.unit for s in slips.values()})
        typed = " or ".join(f'"{u}"' for u in units)
        return (f"; a length unit slip? {' and '.join(said)} would close every loop: were they "
                f'typed in {typed}, not units.length = "{unit}"?')

    def _far_from_sketch(self, result) -> None:
        """A warning where closing the loops turned a joint far from its given angle: rough
        angles move a few degrees (1.6 on the shipped four- and six-bars); a link typed 20 mm
        for 120 turned a student's rocker 79 degrees without a word (a trial)."""
        if self.angle_slip:  # degrees typed as radians: warned already
            return
        turned = {n: abs(math.degrees(v)) for n, v in result.angle_change_rad.items()
                  if n not in result.slides}
        name = max(turned, key=turned.get, default=None)
        if name is not None and turned[name] > SKETCH_TURN_DEG:
            gap = max(result.gaps_before_m.values()) / UNITS["length"][result.length_unit]
            self.warn(f"joints ({name})", f"closing the loops turned {name} {turned[name]:.4g} "
                      f"deg from its given angle (a warning beyond {SKETCH_TURN_DEG:g}; the "
                      f"loops' gap was {gap:.4g} {result.length_unit}): do the links' lengths "
                      "match the sketch?")

    def _task(self, t, bodies) -> tuple[tuple[str, str] | None, str | None]:
        """``[task]``: the tool point and, optionally, the body whose angle is the tool's
        orientation; a robot with no end-effector (a pendulum, a slider-crank) leaves it out."""
        if t is None:
            return None, None
        if not isinstance(t, dict):
            self.err("task", "must be a table with point = 'body.point'")
            return None, None
        unknown_keys(t, TASK_KEYS, lambda key, msg: self.err(f"task.{key}", msg))
        end = self._end(t, "point", "task", bodies) or ("", "")
        orient = t.get("orientation")
        if orient is not None and (not isinstance(orient, str) or orient not in bodies):
            if not isinstance(orient, str) or orient not in self.declared:
                self.err("task.orientation", f"must name a body (got {orient!r})")
            orient = None
        return end, orient


def _declared(d: dict, raw_bodies: list[dict]) -> frozenset:
    """Body names given in the file, those with problems of their own too (joints naming them
    say nothing more); bodies under a misspelt key (``[[bodys]]``) count, and a body without a
    usable name makes every name declared (``AnyBody``)."""
    names = [b.get("name") for b in raw_bodies]
    usable = [n for n in names if isinstance(n, str) and NAME.match(n) and n != GROUND]
    if len(usable) < len(names) or len(set(usable)) < len(usable):
        return AnyBody()
    for key in set(d) - TOP_KEYS:
        items = d[key] if isinstance(d[key], list) else [d[key]]
        usable += [x["name"] for x in items
                   if isinstance(x, dict) and isinstance(x.get("name"), str)]
    return frozenset({GROUND, *usable})
