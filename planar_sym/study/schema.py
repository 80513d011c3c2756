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

What each key means (``description``, with its unit) is written in ``_description`` (here)
and ``_study`` (``schema_study``), one entry per key: building a schema fails
(``SchemaDrift``, ``schema_parts``) when a validator's table has a key without an entry, an
entry names a key no validator knows, or an entry gives a type to a place where ``NUMBERS``
puts a number (or ``INTEGERS`` an integer). The rules that join several fields (``by`` or
``end``; which kind needs which section) are checked by the validators; a few are repeated
as ``if``/``then`` (``KIND_SECTIONS``, and see ``_description``), tested against the
validators in ``tests/test_schema.py``.

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

from ..files import atomic_files
from ..model.description.actuators import ACTUATOR_KEYS
from ..model.description.fields import (
    BODY_KEYS,
    GROUND_KEYS,
    JOINT_KEYS,
    JOINT_TYPES,
    POSES,
    TASK_KEYS,
    TOP_KEYS,
    UNIT_KEYS,
)
from ..model.description.types import GROUND, MOVING
from ..model.description.validator import NUMBERS as DESCRIPTION_NUMBERS
from ..model.units import SI, UNITS
from .schema_parts import (
    ANY,
    BOOL,
    DRAFT,
    IDENT,
    NOTES,
    NUM,
    REF,
    STRING,
    SchemaDrift,
    _constants,
    _enum,
    _points,
    _table,
)
from .schema_study import KIND_SECTIONS, _study

__all__ = ["DRAFT", "FILES", "FOLDER", "KIND_SECTIONS", "SchemaDrift", "render", "schemas",
           "stale", "write"]

#: where the schemas ship: ``planar_sym/schemas``
FOLDER = Path(__file__).resolve().parents[1] / "schemas"
FILES = {"description": "description.schema.json", "study": "study.schema.json"}


# -- the robot description ------------------------------------------------------------------------
# built here from the validators' tables as this module names them, so that a table changed
# here (as tests/test_schema.py does) reaches the builder
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


# -- the files ----------------------------------------------------------------------------------

def schemas() -> dict[str, dict]:
    """``{"description": schema, "study": schema}``, built from the validators' tables.

    Raises
    ------
    SchemaDrift
        A validator's table and the entries describing it disagree.
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
