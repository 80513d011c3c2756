"""JSON Schemas of the two input formats, for editors: a robot description and a study file.

Editors' TOML plugins (Even Better TOML / taplo in VS Code, the JetBrains IDEs) check a file
against a JSON Schema as it is typed and complete its keys and choices; the schemas ship in
``planar_sym/schemas/`` (``description.schema.json``, ``study.schema.json``). They are generated
here from the tables the validators themselves read, never written by hand:

* the keys of each table: ``fields.TOP_KEYS``, ``BODY_KEYS``, ``JOINT_KEYS``, ...,
  ``actuators.ACTUATOR_KEYS``, and ``spec._TOP``, ``_MOTION``, ``control_spec._CONTROL``, ...
  (``additionalProperties: false`` where the validator refuses an unknown key);
* where a number goes, from the readers' ``NUMBERS``: a number there may also be an expression
  in a string (``planar_sym.expressions``), so such a place is ``"type": ["number", "string"]``;
* the choices (``JOINT_TYPES``, ``POSES``, ``units.UNITS``, ``KINDS``, ``PROFILES``, ``LAWS``,
  ...) and the integers' ranges (``spec.INTEGERS``) as ``enum``, ``minimum`` and ``maximum``.

What each key means (``description``, with its unit) is written here, in ``_description``
and ``_study``, one entry per key: building a schema fails (``SchemaDrift``) when a validator's
table has a key without an entry, an entry names a key no validator knows, or an entry gives a
type to a place where ``NUMBERS`` puts a number (or ``INTEGERS`` an integer). The rules that
join several fields (``by`` or ``end``; which kind needs which section) are checked by the
validators; a few are repeated here as ``if``/``then`` (``KIND_SECTIONS``, and see
``_description``), tested against the validators in ``tests/test_schema.py``.

Draft-07 (not 2020-12): taplo validates with a draft-07 engine and completes from
``properties``, ``items`` and ``anyOf``, and JetBrains reads draft-07 fully; every schema is
inline (no ``$ref``) and no ``allOf`` stands where keys are completed (taplo would then offer
none).

Regenerate with ``planar-sym schema`` (or ``python -m planar_sym.study.schema``);
``tests/test_schema.py`` fails while a shipped file differs from what this writes.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..expressions import BUILT_IN, FUNCTIONS, MAX_CONSTANTS
from ..files import atomic_files
from ..model.description.actuators import ACTUATOR_KEYS
from ..model.description.fields import (
    BODY_KEYS,
    GROUND_KEYS,
    JOINT_KEYS,
    JOINT_TYPES,
    NAME,
    POSES,
    TASK_KEYS,
    TOP_KEYS,
    UNIT_KEYS,
)
from ..model.description.types import GROUND, MOVING
from ..model.description.validator import NUMBERS as DESCRIPTION_NUMBERS
from ..model.units import SI, UNITS
from ..optimal.point_to_point import OBJECTIVES
from . import control_spec as ctl
from . import optimal_spec as opt
from . import spec

DRAFT = "http://json-schema.org/draft-07/schema#"
#: where the schemas ship: ``planar_sym/schemas``
FOLDER = Path(__file__).resolve().parents[1] / "schemas"
FILES = {"description": "description.schema.json", "study": "study.schema.json"}

#: the sections each study kind requires and those it refuses, as ``spec.parse`` has them; a
#: kind = "optimal" study takes [events] only with its [control]
KIND_SECTIONS = {
    "inverse": (("motion",), ("simulation", "control", "events", "optimal")),
    "forward": (("simulation",), ("motion", "control", "events", "optimise", "optimal")),
    "control": (("motion", "control"), ("simulation", "optimise", "optimal")),
    "optimal": (("optimal",), ("motion", "simulation", "optimise")),
}

#: an identifier (``fields.NAME``): a robot, body, joint, point or constant name
IDENT = NAME.pattern
_WORD = IDENT.removeprefix("^").removesuffix("$")
#: "body.point"
REF = f"^{_WORD}\\.{_WORD}$"

#: entry types: NUM takes the place's shape from ``NUMBERS``, INT its range from ``INTEGERS``
NUM, INT = "number place", "integer place"
STRING = {"type": "string"}
TEXT = {"type": "string", "minLength": 1}
BOOL = {"type": "boolean"}
ANY: dict = {}
NOTES = (ANY, "Free text, not read.")
EXPRESSION = {"type": ["number", "string"]}


class SchemaDrift(RuntimeError):
    """A validator's table and this module's entries disagree: a key without an entry, an
    entry for a key no validator knows, or a number's (an integer's) place typed otherwise."""


def _enum(options, default=None) -> dict:
    out = {"enum": list(options)}
    if default is not None:
        out["default"] = default
    return out


def _number(shape, pair: bool) -> dict:
    """The schema of a number place of a ``NUMBERS`` table (``expressions.numbers``): 0 a
    number, 1 a list of numbers (``pair``: two, [x, y]), 2 a list of such lists, (0, 1) a
    number or a list; every number may be an expression string."""
    if shape == (0, 1):
        return {"type": ["number", "string", "array"], "items": EXPRESSION, "minItems": 1}
    if shape == 0:
        return dict(EXPRESSION)
    if shape == 1:
        return {"type": "array", "items": EXPRESSION,
                **({"minItems": 2, "maxItems": 2} if pair else {"minItems": 1})}
    if shape == 2:
        return {"type": "array", "items": _number(1, pair), "minItems": 1}
    raise SchemaDrift(f"no schema for the number place {shape!r}")


def _leaf(shape) -> bool:
    """A number place itself (not a table or list of tables holding some)."""
    return isinstance(shape, int) or (isinstance(shape, tuple)
                                      and all(isinstance(s, int) for s in shape))


def _table(where: str, keys, entries: dict, numbers=None, integers=None, *, pair: bool = False,
           required=(), closed: bool = True, **rules) -> dict:
    """An object schema of the keys a validator knows (``keys``, its own table), each
    described by ``entries[key] = (schema or NUM or INT, text)``; ``numbers`` and ``integers``:
    the validator's tables at this level."""
    numbers = numbers if isinstance(numbers, dict) else {}
    integers = integers or {}
    where = where or "the top level"
    if set(keys) != set(entries):
        raise SchemaDrift(f"{where}: keys the validator knows but this module does not describe: "
                          f"{sorted(set(keys) - set(entries))}; described but unknown: "
                          f"{sorted(set(entries) - set(keys))}")
    unknown = (set(numbers) - {"*"} | set(integers)) - set(keys)
    if unknown or not set(required) <= set(keys):
        raise SchemaDrift(f"{where}: numbers, integers or required keys no validator knows: "
                          f"{sorted(unknown | (set(required) - set(keys)))}")
    props = {}
    for key in sorted(keys):
        kind, text = entries[key]
        is_number = key in numbers and _leaf(numbers[key])
        if (kind == NUM) != is_number or (kind == INT) != (key in integers):
            raise SchemaDrift(f"{where}.{key}: the validator's NUMBERS or INTEGERS and this "
                              "module's entry disagree on whether it is a number or an integer")
        if kind == NUM:
            schema = _number(numbers[key], pair)
        elif kind == INT:
            default, low, high = integers[key]
            schema = {"type": "integer", "minimum": low, "maximum": high, "default": default}
        else:
            schema = kind
        props[key] = {"description": text, **schema}
    out: dict = {"type": "object", "properties": props}
    if closed:
        out["additionalProperties"] = False
    if required:
        out["required"] = sorted(required)
    out.update(rules)
    return out


def _points(shape, text: str) -> tuple[dict, str]:
    """A table of named points, each [x, y] (``NUMBERS``: ``{"*": 1}``)."""
    return ({"type": "object", "minProperties": 1, "propertyNames": {"pattern": IDENT},
             "additionalProperties": _number(shape["*"], pair=True)}, text)


def _constants() -> tuple[dict, str]:
    return ({"type": "object", "maxProperties": MAX_CONSTANTS,
             "propertyNames": {"pattern": IDENT, "not": _enum([*BUILT_IN, *FUNCTIONS])},
             "additionalProperties": EXPRESSION},
            ("Names for the expressions of this file: name = a number or an expression of "
             "numbers and other constants (\"L = '2*a'\"); any number of the file may then be "
             "an expression using them (\"L/2\"). Built in: pi, deg = pi/180, sqrt, sin, cos, "
             "tan, asin, acos, atan, atan2, hypot."))


# -- the robot description ------------------------------------------------------------------------

def _description() -> dict:
    n = DESCRIPTION_NUMBERS
    units = _table("units", UNIT_KEYS, {
        q: (_enum(UNITS[q]), (f"Unit of every {q} typed in this file (SI: {SI[q]}); required "
                              f"when the file gives any {q}.")) for q in UNITS})
    ground = _table("ground", GROUND_KEYS, {
        "points": _points(n["ground"]["points"], "The ground's named points, name = [x, y] "
                                                 "in [units].length, world coordinates."),
        "notes": NOTES}, n["ground"], pair=True, required=["points"])
    body = _table("bodies", BODY_KEYS, {
        "name": ({"type": "string", "pattern": IDENT, "not": {"const": GROUND}},
                 "The body's name: an identifier other than 'ground'."),
        "mass": (NUM, "Mass in [units].mass, > 0."),
        "izz": (NUM, ("Moment of inertia about the centre of gravity, normal to the plane, in "
                      "[units].inertia, >= 0 (> 0 for a body with extent); not with mass_at.")),
        "cg": (NUM, ("Centre of gravity [x, y] in [units].length, from cg_from; not with "
                     "mass_at.")),
        "cg_from": (STRING, ("What cg is measured from: one of the body's points, or 'world' "
                             "(pose = 'world', where it is required); with pose = 'joints' "
                             "omitted for the origin of the body's own coordinates.")),
        "points": _points(n["bodies"][0]["points"],
                          "The body's named points, name = [x, y] in [units].length: world "
                          "coordinates of the drawn pose (pose = 'world') or the body's own "
                          "coordinates (pose = 'joints')."),
        "frame": ({"type": "array", "items": STRING, "minItems": 1, "maxItems": 2},
                  ("The body frame: [origin] or [origin, x_toward], naming its points "
                   "(default: at its first point, world-aligned; pose = 'joints': the "
                   "coordinates as typed).")),
        "notes": NOTES,
        "mass_at": (STRING, ("A massless link carrying a point mass at this one of its "
                             "points (then no izz, cg or cg_from).")),
    }, n["bodies"][0], pair=True, required=["name", "mass", "points"],
        **{"if": {"required": ["mass_at"]},
           "then": {"properties": {"izz": False, "cg": False, "cg_from": False}},
           "else": {"required": ["cg", "izz"]}})
    actuator_numbers = n["joints"][0]["actuator"]
    actuator = _table("joints.actuator", ACTUATOR_KEYS, {
        key: (NUM if key in actuator_numbers else ANY, meaning[0].upper() + meaning[1:] + ".")
        for key, meaning in ACTUATOR_KEYS.items()}, actuator_numbers)
    prismatic = "prismatic"
    if prismatic not in MOVING:
        raise SchemaDrift(f"no {prismatic!r} joint type: the rules of joints need it")
    joint = _table("joints", JOINT_KEYS, {
        "name": ({"type": "string", "pattern": IDENT}, "The joint's name: an identifier."),
        "type": (_enum(JOINT_TYPES), ("revolute (a hinge), prismatic (a slide along axis) or "
                                      "weld (rigid).")),
        "parent": ({"type": "string", "pattern": REF}, ("'body.point': the parent body's point "
                                                        "at the joint (the tree grows from "
                                                        "ground).")),
        "child": ({"type": "string", "pattern": REF}, ("'body.point': the child body's point at "
                                                       "the joint.")),
        "actuated": (BOOL, ("true where a motor drives the joint, false where it is passive "
                            "(required of a revolute or prismatic joint).")),
        "closes_loop": (BOOL, ("true: the joint closing a loop, where the loop is cut (a "
                               "revolute joint, not actuated); default false.")),
        "angle": (NUM, ("pose = 'joints' only: the approximate angle of a tree joint in "
                        "[units].angle (default 0); across a prismatic joint, the child's fixed "
                        "angle to the parent.")),
        "displacement": (NUM, ("pose = 'joints', prismatic joints only: where the child point "
                               "sits along the axis from the parent point, in [units].length "
                               "(default 0).")),
        "axis": (NUM, ("Prismatic joints only: the direction of the slide [x, y], any length; in "
                       "the drawn pose (pose = 'world') or in the parent's coordinates (pose = "
                       "'joints').")),
        "actuator": (actuator, ("The actuator of an actuated joint: gearbox, rotor, friction, "
                                "limits, all optional; figures at the joint side, SI (the rotor "
                                "inertia in [units].inertia).")),
        "notes": NOTES,
    }, n["joints"][0], pair=True, required=["name", "type", "parent", "child"],
        **{"if": {"properties": {"type": {"const": prismatic}}, "required": ["type"]},
           "then": {"required": ["actuated", "axis"]},
           "else": {"properties": {"axis": False, "displacement": False},
                    "if": {"properties": {"type": _enum(MOVING)}, "required": ["type"]},
                    "then": {"required": ["actuated"]}}})
    task = _table("task", TASK_KEYS, {
        "point": ({"type": "string", "pattern": REF}, "'body.point': the tool point."),
        "orientation": ({"type": "string", "pattern": IDENT},
                        "A body whose angle is the tool's orientation (optional)."),
    }, required=["point"])
    top = _table("", TOP_KEYS, {
        "name": ({"type": "string", "pattern": IDENT},
                 "The robot's name: an identifier (it names the generated code)."),
        "title": (STRING, "A one-line title (default: the name)."),
        "notes": NOTES,
        "units": (units, ("The units this file's numbers are typed in, each turned into SI "
                          "when the file is read.")),
        "gravity": (NUM, "Gravity [gx, gy] in [units].acceleration, e.g. [0.0, -9.81]."),
        "ground": (ground, "The fixed body: its points, in world coordinates."),
        "bodies": ({"type": "array", "items": body}, ("The moving bodies, one [[bodies]] "
                                                      "table each.")),
        "joints": ({"type": "array", "items": joint},
                   ("The joints, one [[joints]] table each: each joins a point of its parent "
                    "body to a point of its child; the tree grows from ground, and a joint "
                    "with closes_loop = true closes a loop.")),
        "task": (task, ("The tool: its point and, optionally, the body giving its "
                        "orientation; leave it out for a robot without an end-effector.")),
        "symbols": ({"type": "object", "additionalProperties": STRING},
                    ("Display names of parameters in the printed equations: parameter = "
                     "'m_1'.")),
        "assemble": (BOOL, ("true: close the loops numerically from the typed pose (always "
                            "done with pose = 'joints').")),
        "pose": (_enum(POSES, POSES[0]),
                 ("How points are given: 'world' (default), world coordinates of the drawn "
                  "pose; or 'joints', each body in its own coordinates, placed by approximate "
                  "joint angles.")),
        "constants": _constants(),
    }, n, pair=True, required=["name", "units", "gravity", "ground", "bodies", "joints"],
        **{"if": {"properties": {"pose": {"const": "joints"}}, "required": ["pose"]},
           "else": {"properties": {
               "bodies": {"items": {"if": {"required": ["mass_at"]},
                                    "else": {"required": ["cg_from"]}}},
               "joints": {"items": {"properties": {"angle": False, "displacement": False}}}}}})
    return {"$schema": DRAFT, "title": "planar-sym robot description",
            "description": "A planar robot: its units, bodies and points, joints and tool "
                           "(planar_sym.model.description). Numbers are in the file's [units] "
                           "and may be expressions in strings.", **top}


# -- the study file -------------------------------------------------------------------------------

def _torque(shape) -> dict:
    """Input torques (``NUMBERS``: a list, or a profile table): "zero", constants, a CSV file
    or a profile."""
    listed, profile = shape
    file = _table("torque (a file)", ctl.TORQUE_FILE_KEYS, {
        "file": (TEXT, "A CSV of t_s and tau<k>_n_m (N*m or N), relative to this study file."),
        "interpolation": (_enum(ctl.INTERPOLATIONS, "linear"),
                          "How the table is read between its rows (default linear)."),
    }, required=["file"])
    ramp = _table("torque (a profile)", ctl.TORQUE_PROFILE_KEYS, {
        "profile": (_enum(ctl.TORQUE_PROFILES), "The shape from start to end."),
        "start": (NUM, "Torques at the start, N*m (N at a slider), one per motor."),
        "end": (NUM, "Torques at the end, N*m (N), one per motor."),
        "duration": (NUM, "Duration of the change, s (> 0); then end holds."),
    }, profile, required=sorted(ctl.TORQUE_PROFILE_KEYS))
    return {"anyOf": [{"const": "zero"}, _number(listed, pair=False), file, ramp]}


def _parameters(what: str) -> tuple[dict, str]:
    return ({"type": "object", "additionalProperties": EXPRESSION},
            (f"{what}: name = a number in the description's units, or a string with an "
             "expression and a unit (\"0.5 kg\", \"2*0.3 kg\", \"90.992 kg*mm^2\")."))


def _study() -> dict:
    n, ints = spec.NUMBERS, spec.INTEGERS
    if n["control"]["torque"] != n["simulation"]["torque"]:
        raise SchemaDrift("[simulation] and [control] read torque inputs differently")
    torque = _torque(n["simulation"]["torque"])
    length = "[units] (length; angle for a hinge or phi)"
    units = _table("units", spec._UNITS, {
        q: (_enum(UNITS[q], SI[q]), (f"Unit of every {q} typed in this file (default {SI[q]}); "
                                     "times are in s.")) for q in spec._UNITS})
    motion = _table("motion", spec._MOTION, {
        "space": (_enum(spec.SPACES), ("task: start, by and end are task coordinates (x, y[, "
                                       "phi]); joint: every joint of a tree, the actuated "
                                       "joints of a closed chain.")),
        "profile": (_enum(spec.PROFILES, "cubic"),
                    ("cubic (default) or quintic from start by (or to end) in duration; "
                     "trapezoid (v_max, a_max); via (times, points); table (file).")),
        "start": (NUM, f"Where the move starts, in {length}."),
        "by": (NUM, f"The displacement from start, in {length}; give by or end, not both."),
        "end": (NUM, f"Where the move ends, in {length}; give by or end, not both."),
        "duration": (NUM, ("Duration, s (> 0); optional for trapezoid (as fast as v_max and "
                           "a_max allow).")),
        "samples": (INT, "Number of samples of the move."),
        "v_max": (NUM, "trapezoid: the speed limit per coordinate, [units] per s (> 0)."),
        "a_max": (NUM, ("trapezoid: the acceleration limit per coordinate, [units] per s^2 "
                        "(> 0).")),
        "times": (NUM, "via: the times of the via points, s, from 0, increasing."),
        "points": (NUM, f"via: the via points, one list per time, in {length}."),
        "file": (TEXT, "table: a CSV of t_s and the coordinates, relative to this study file."),
        "ik": (_enum(spec.SOLVERS, "auto"), ("space = 'task' only: the inverse-kinematics "
                                             "solver (default auto).")),
        "start_pose": (NUM, ("Joint coordinates near the start, in [units], choosing the "
                             "assembly (working) mode.")),
    }, n["motion"], ints["motion"], required=["space"])
    simulation = _table("simulation", spec._SIMULATION, {
        "q0": (NUM, "The start: every coordinate, in [units]."),
        "qd0": (NUM, "The start speeds, [units] per s (default 0)."),
        "duration": (NUM, "Duration, s (> 0)."),
        "samples": (INT, "Number of output samples."),
        "torque": ({**torque}, ("Input torques: 'zero' (default), constants [N*m or N, one per "
                                "motor], a CSV { file, interpolation } or a profile { profile, "
                                "start, end, duration }.")),
        "method": (_enum(spec.METHODS, "dopri5"), "The integrator (default dopri5)."),
        "rtol": (NUM, "Relative tolerance of the integrator (> 0)."),
        "atol": (NUM, "Absolute tolerance of the integrator (> 0)."),
    }, n["simulation"], ints["simulation"], required=["q0", "duration"])
    outputs = _table("outputs", spec._OUTPUTS, {
        "csv": (BOOL, "Write the results as CSV (default true)."),
        "plot": (BOOL, "Draw the plots (default true)."),
        "split": (BOOL, "One plot per quantity (default false)."),
        "animation": ({"enum": [False, True, *spec.ANIMATIONS]},
                      "An animation: false (default), true (a GIF) or the format."),
        "frames": (INT, "Frames of the animation."),
    }, None, ints["outputs"])
    control = _table("control", ctl._CONTROL, {
        "law": (_enum(ctl.LAWS), ("pd: PD + gravity compensation; computed_torque; lqr: "
                                  "time-varying LQR along the motion (q_weight, r_weight); "
                                  "none: open loop (needs torque).")),
        "kp": (NUM, ("Proportional gains, SI: N*m/rad (N/m) for pd, 1/s^2 for "
                     "computed_torque; one number for every joint or one per actuated joint; "
                     "with kd, instead of natural_frequency_hz.")),
        "kd": (NUM, ("Derivative gains, SI: N*m*s/rad (N*s/m) for pd, 1/s for computed_torque; "
                     "one number or one per actuated joint.")),
        "natural_frequency_hz": (NUM, ("Gains from a bandwidth, Hz (> 0), instead of kp and "
                                       "kd.")),
        "damping": (NUM, "Damping ratio with natural_frequency_hz (default 1)."),
        "saturate": (BOOL, "Clip at the description's actuator limits (default true)."),
        "duration": (NUM, "Duration, s (default: the motion's; the reference then holds)."),
        "samples": (INT, "Number of output samples."),
        "start_error": (NUM, "Start off the reference: one per actuated joint, in [units]."),
        "torque": ({**torque}, ("Input torques added to the controller's, N*m (N): constants, "
                                "a CSV { file, interpolation } or a profile; required by law = "
                                "'none'.")),
        "method": (_enum(ctl.CONTROL_METHODS, "dopri5"), "The integrator (default dopri5)."),
        "rtol": (NUM, "Relative tolerance of the integrator (> 0)."),
        "atol": (NUM, "Absolute tolerance of the integrator (> 0)."),
        "plant": _parameters("The plant's parameters where they differ from the model's (a "
                             "model error)"),
        "q_weight": (NUM, ("lqr: state weights, SI, 2n values (coordinates, then speeds), >= 0; "
                           "or one number.")),
        "r_weight": (NUM, "lqr: input weights, SI, one per motor, >= 0; or one number."),
    }, n["control"], ints["control"], required=["law"])
    events = _table("events", ctl._EVENTS, {
        "joint_limits": ({"type": "object", "additionalProperties": _number(
            n["events"]["joint_limits"]["*"], pair=True)},
            "Joint limits, coordinate = [lower, upper] in [units] (angle, length)."),
        "on_joint_limit": (_enum(ctl.ON_LIMIT, "stop"), ("At a joint limit: stop (default) or "
                                                         "continue.")),
        "on_actuator_limit": (_enum(ctl.ON_LIMIT, "continue"),
                              "At an actuator limit: continue (default) or stop."),
    }, n["events"])
    optimise = _table("optimise", spec._OPTIMISE, {
        "torque_limit": (NUM, ("Torque limits, N*m (N at a slider), one per motor, > 0 "
                               "(default: the description's torque_limit).")),
        "speed_limit": (NUM, "Speed limits per coordinate, [units] per s, > 0 (optional)."),
    }, n["optimise"])
    optimal = _table("optimal", opt._OPTIMAL, {
        "start": (NUM, (f"The start state (at rest): every coordinate of a tree, a closed "
                        f"chain's actuated ones, in {length}.")),
        "end": (NUM, f"The end state (at rest), in {length}."),
        "objective": (_enum(OBJECTIVES, "effort"),
                      ("effort (default: in the given duration), energy (the motors' "
                       "electrical energy in the given duration: each motor's "
                       "torque_constant and winding_resistance) or time (the fastest; needs "
                       "torque limits).")),
        "duration": (NUM, "Duration, s (> 0): objective = 'effort' or 'energy' only."),
        "intervals": (INT, "Intervals of the collocation grid."),
        "torque_limit": (NUM, ("Torque limits, N*m (N at a slider), one per motor, > 0 "
                               "(default: the description's).")),
        "speed_limit": (NUM, "Speed limits per coordinate, [units] per s, > 0 (optional)."),
    }, n["optimal"], ints["optimal"], required=["start", "end"])
    top = _table("", spec._TOP, {
        "title": (STRING, "A one-line title (default: the file's name)."),
        "robot": (TEXT, ("A built-in robot's name, a description file (.toml) or a generated "
                         "folder; a path is relative to this study file.")),
        "kind": (_enum(spec.KINDS), ("inverse: the torques along a motion; forward: simulate "
                                     "from a start; control: track the motion under a "
                                     "controller; optimal: the best move between two "
                                     "states.")),
        "units": (units, ("The units of this file's numbers: length and angle (default m and "
                          "rad); times are in s, gains and torques SI.")),
        "parameters": _parameters("Overrides of the robot's parameters"),
        "motion": (motion, "The move: kind = 'inverse' or 'control'."),
        "simulation": (simulation, "The run: kind = 'forward'."),
        "outputs": (outputs, "What to write."),
        "notes": NOTES,
        "control": (control, ("The controller: kind = 'control' (or 'optimal', to track the "
                              "move found).")),
        "events": (events, "Events and what each does, with [control]."),
        "optimise": (optimise, ("kind = 'inverse': time the motion's path as fast as these "
                                "limits allow, rest to rest.")),
        "optimal": (optimal, ("The best rest-to-rest move between two states: kind = "
                              "'optimal'.")),
        "constants": _constants(),
    }, n, required=["robot", "kind"], **_by_kind())
    return {"$schema": DRAFT, "title": "planar-sym study",
            "description": "One run of a robot: inverse dynamics along a motion, a forward "
                           "simulation, control in the loop or an optimal move "
                           "(planar_sym.study.spec). Numbers are in the file's [units] and "
                           "may be expressions in strings.", **top}


def _by_kind() -> dict:
    """``KIND_SECTIONS`` as one chain of if/then/else on ``kind`` (no allOf at the top: taplo
    would then complete no key there)."""
    if set(KIND_SECTIONS) != set(spec.KINDS):
        raise SchemaDrift(f"KIND_SECTIONS has {sorted(KIND_SECTIONS)}, spec.KINDS "
                          f"{sorted(spec.KINDS)}")
    chain: dict = {}
    for kind in reversed(spec.KINDS):
        requires, refuses = KIND_SECTIONS[kind]
        then: dict = {"required": list(requires), "properties": dict.fromkeys(refuses, False)}
        if kind == "optimal":
            then.update({"if": {"not": {"required": ["control"]}},
                         "then": {"properties": {"events": False}}})
        branch = {"if": {"properties": {"kind": {"const": kind}}, "required": ["kind"]},
                  "then": then}
        if chain:
            branch["else"] = chain
        chain = branch
    return chain


# -- the files ----------------------------------------------------------------------------------

def schemas() -> dict[str, dict]:
    """``{"description": schema, "study": schema}``, built from the validators' tables.

    Raises
    ------
    SchemaDrift
        A validator's table and this module's entries disagree.
    """
    return {"description": _description(), "study": _study()}


def render(schema: dict) -> str:
    """The JSON text of a schema as it is shipped."""
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def stale(folder: Path = FOLDER) -> list[Path]:
    """The schema files in ``folder`` that are missing or differ from what ``write`` writes."""
    made = schemas()
    return [folder / FILES[k] for k in FILES
            if not (folder / FILES[k]).is_file()
            or (folder / FILES[k]).read_text(encoding="utf-8") != render(made[k])]


def write(folder: Path = FOLDER) -> list[Path]:
    """Write both schemas into ``folder`` (each whole or not at all); their paths."""
    made = schemas()
    targets = [folder / FILES[k] for k in FILES]
    with atomic_files(targets) as temps:
        for tmp, k in zip(temps, FILES):
            tmp.write_text(render(made[k]), encoding="utf-8")
    return targets


if __name__ == "__main__":
    for path in write(Path(sys.argv[1]) if len(sys.argv) > 1 else FOLDER):
        print(f"wrote {path}")
