"""The identified robot as a description file: the source description with its masses,
centres of gravity, inertias, rotor inertias and friction replaced by the identified values,
in the file's own ``[units]``, so every command and study runs on it (``planar-sym run
identified_robot.toml``, ``robot = "..."`` in a study).

Only values change, never the structure (the physical fit keeps a centre of gravity on its
axis and a point mass a point mass) nor the name and title (the equation report prints them),
so the file reuses the compiled code of the source robot: no SymPy, no compiler.
Written from the parsed table, so comments of the source are not carried over; its header
names the source and the identification.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

from ..errors import InputError
from ..expressions import constants, numbers
from ..model.description import load as load_description
from ..model.description.validator import NUMBERS
from ..model.robot import Robot
from ..model.units import factor
from ..toml_write import dumps

#: a centre of gravity moved by less than this keeps its typed value (rounding, not data)
SAME_M = 1e-15


def identified_description(robot: Robot, identified: Robot, note: str = "") -> str:
    """TOML text of ``robot``'s description with ``identified``'s parameter values.

    Raises InputError when ``robot`` was not loaded from a description file.
    """
    path = robot.description_file
    if path is None or not path.exists():
        raise InputError(f"{robot.name}: no description file to start from (the robot was "
                         "not loaded from one): the identified values are in "
                         "identified_parameters.toml")
    raw = tomllib.loads(path.read_text())
    desc = load_description(path)
    par = identified.parameters
    units = raw.get("units", {})

    def scale(quantity: str) -> float:
        return factor(quantity, units[quantity]) if quantity in units else 1.0

    mass_u, inertia_u, length_u = scale("mass"), scale("inertia"), scale("length")
    pose = raw.get("pose", "world")
    # the numbers as the reader sees them (a point may be typed as an expression); the file
    # written keeps what was typed except the values identified
    values = numbers(raw, NUMBERS, constants(raw.get("constants"))[0])
    for entry, read in zip(raw.get("bodies", []), values.get("bodies", [])):
        name = entry["name"]
        body = desc.bodies[name]
        if f"m_{name}" in par:
            entry["mass"] = par[f"m_{name}"] / mass_u
        if f"izz_{name}" in par:
            entry["izz"] = par[f"izz_{name}"] / inertia_u
        cg = (par.get(f"cgx_{name}", body.cg_m[0]), par.get(f"cgy_{name}", body.cg_m[1]))
        if math.dist(cg, body.cg_m) <= SAME_M:
            continue
        origin, angle = _typed_frame(read, pose, length_u)
        if "mass_at" in entry:  # a point mass moved: a point of its own carries it
            point = _free_name(entry["points"], "cg")
            entry["points"][point] = [v / length_u for v in _typed(cg, origin, angle)]
            entry["mass_at"] = point
            continue
        if entry.get("cg_from") in ("world", None):  # typed from the coordinates' origin
            typed = _typed(cg, origin, angle)
        else:  # typed from a point, in the typed axes
            at = body.points_m[entry["cg_from"]]
            typed = _typed((cg[0] - at[0], cg[1] - at[1]), (0.0, 0.0), angle)
        entry["cg"] = [v / length_u for v in typed]
    for entry in raw.get("joints", []):
        name, act = entry["name"], entry.get("actuator")
        for key, param, unit in (("rotor_inertia", f"jm_{name}", inertia_u),
                                 ("viscous_friction", f"fv_{name}", 1.0),
                                 ("coulomb_friction", f"fc_{name}", 1.0)):
            if param in par and act is not None and key in act:
                act[key] = par[param] / unit
    # the user's file's name (the manifest's input), not the cache's copy, description.toml
    library = getattr(robot, "library", None)
    source = Path((library.manifest.get("input") if library else None) or path).name
    head = [(f"# {robot.name} as identified by planar-sym identify, from {source}: masses, "
             "centres of gravity,"),
            ("# inertias, rotor inertias and friction are the physically consistent identified "
             f"values, in [units]. {note}").rstrip()]
    return "\n".join(head) + "\n" + dumps(raw)


def _typed_frame(entry: dict, pose: str, length_u: float):
    """The frame's origin and angle as the reader finds them from the typed points (the
    parsed description's drawn frame is the assembled one, which a typed cg is not in)."""
    pts = {k: (v[0] * length_u, v[1] * length_u) for k, v in entry["points"].items()}
    frame = entry.get("frame") or ([next(iter(pts))] if pose != "joints" else [])
    origin = pts[frame[0]] if frame else (0.0, 0.0)
    if len(frame) < 2:
        return origin, 0.0
    return origin, math.atan2(pts[frame[1]][1] - origin[1], pts[frame[1]][0] - origin[0])


def _typed(local, origin, angle: float) -> tuple[float, float]:
    """A body-frame position in the typed coordinates (the reader's ``to_body`` inverted)."""
    c, s = math.cos(angle), math.sin(angle)
    return (origin[0] + c * local[0] - s * local[1], origin[1] + s * local[0] + c * local[1])


def _free_name(points: dict, stem: str) -> str:
    return next(f"{stem}{k or ''}" for k in range(len(points) + 1)
                if f"{stem}{k or ''}" not in points)
