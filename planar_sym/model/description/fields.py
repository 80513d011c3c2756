"""Field validators: each reads one value of the TOML data, records a problem naming the file,
the field and the value when it is wrong, and returns None (or a neutral value) so the checks go
on and every problem is reported at once.

Numbers may be typed as expressions (``planar_sym.expressions``). They are evaluated once, before
any check (``_expressions``), at the places the validator's schema names: every later stage
(the plausibility checks read the raw points too) then sees the floats a typed decimal gives. A
string there that is no expression is a ``Bad``, reported by ``_num`` or ``_vec`` where they
check that field, like any other wrong value of it: one mistake, one message.
"""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

from ...expressions import Bad, constants, numbers
from ...spelling import unknown_keys
from ..units import SI, UNITS, factor
from .quantities import QUANTITIES, doubt
from .types import ZERO_SNAP_M

NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
TOP_KEYS = {"name", "title", "units", "gravity", "ground", "bodies", "joints", "task", "symbols",
            "notes", "assemble", "pose", "constants"}
UNIT_KEYS = {"length", "mass", "inertia", "angle", "acceleration"}
BODY_KEYS = {"name", "mass", "izz", "cg", "cg_from", "points", "frame", "notes", "mass_at"}
JOINT_KEYS = {"name", "type", "parent", "child", "actuated", "closes_loop", "angle", "notes",
              "axis", "displacement", "actuator"}
#: joint types: a revolute or prismatic joint is a coordinate (or a cut), a weld is rigid
JOINT_TYPES = ("revolute", "prismatic", "weld")
TASK_KEYS = {"point", "orientation"}
#: keys of ``[ground]``, in the order its message names them
GROUND_KEYS = ("points", "notes")
#: ``pose``: how points are given. world: world coordinates of the drawn pose (the seed's
#: tables); joints: each body in its own frame, placed by approximate joint angles
POSES = ("world", "joints")


class Fields:
    """Collects the problems of one description; the base of the validator's stages."""

    def __init__(self, path: Path, data: dict, sha: str):
        # a copy: a misspelt key is moved to the key it nearly is (spelling.unknown_keys)
        self.path, self.data, self.sha = path, copy.deepcopy(data), sha
        self.problems: list[str] = []
        self.warnings: list[str] = []  # shown only when the description has no error
        #: ``[units]`` as read (a misspelt quantity under the one it nearly is): known units only
        self.unit_names: dict[str, str] = {}

    def err(self, fld: str, msg: str) -> None:
        self.problems.append(f"{self.path}: {fld}: {msg}")

    def _expressions(self, schema) -> bool:
        """Resolves ``[constants]`` and evaluates the strings at the number places of
        ``schema`` (``expressions.numbers``) into ``self.data``; False after a problem in
        ``[constants]`` (reported: every field using the constant would only repeat it)."""
        names, problems = constants(self.data.get("constants"))
        for fld, msg in problems:
            self.err(fld, msg)
        if not problems:
            self.data = numbers(self.data, schema, names)
        return not problems

    def warn(self, fld: str, msg: str) -> None:
        self.warnings.append(f"{self.path}: {fld}: {msg}")

    def _judge(self, fld: str, quantity: str, typed: float) -> bool:
        """The table's rule (``quantities``) on a value typed in its ``[units]`` unit: False
        after an error; a warning where it is likely a slip."""
        q = QUANTITIES[quantity]
        units = self.data.get("units")
        unit = units.get(q.kind) if isinstance(units, dict) and q.kind else None
        known = isinstance(unit, str) and unit in UNITS.get(q.kind or "", {})
        if (msg := q.error(typed, unit if known else q.unit)) is not None:
            self.err(fld, msg)
            return False
        if known and (doubtful := doubt(q, typed, unit)) is not None:
            self.warn(fld, doubtful)
        return True

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
        elif isinstance(v, Bad):
            self.err(fld, v.message)
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            self.err(fld, f"must be a number (got {v!r})")
        elif not finite(v):
            self.err(fld, f"must be finite (got {v!r:.40})")
        else:
            return float(v)
        return None

    def _bool(self, tbl: dict, key: str, fld: str, default: bool | None) -> bool | None:
        v = tbl.get(key, default)
        if not isinstance(v, bool):
            self.err(fld, f"must be true or false (got {v!r})")
            return None
        return v

    def _vec(self, tbl: dict, key: str, fld: str, unit: float | None) -> tuple[float, float]:
        v = tbl.get(key)
        if v is None:
            self.err(fld, "missing")
        elif isinstance(v, list) and any(isinstance(x, Bad) for x in v):
            for x in v:
                if isinstance(x, Bad):
                    self.err(f"{fld}{x.index}", x.message)
        elif (not isinstance(v, list) or len(v) != 2
              or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)):
            self.err(fld, f"must be a list of two numbers [x, y] (got {v!r})")
        elif not all(finite(x) for x in v):
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
        u = dict(u)  # a misspelt quantity is read as the one it nearly is: one message
        unknown_keys(u, UNIT_KEYS, lambda key, msg: self.err(
            f"units.{key}", msg.replace("unknown key", "unknown quantity")))
        used = self._units_used()
        for q in sorted(UNIT_KEYS):
            if q not in u:
                if q in used:
                    self.err(f"units.{q}", f"missing (SI would be {SI[q]!r})")
                else:  # no field of this description is in it: any factor will do
                    out[q] = 1.0
                continue
            try:
                out[q] = factor(q, u[q]) if isinstance(u[q], str) else factor(q, repr(u[q]))
            except KeyError as exc:
                self.err(f"units.{q}", f"{exc.args[0]} (got {u[q]!r})")
            else:
                self.unit_names[q] = u[q]
        return out

    def _units_used(self) -> set[str]:
        """The quantities some field of the description is given in: a unit no field uses
        (inertia with only point masses, angle with no joint angle) is not required."""
        used = {"length", "mass", "acceleration"}
        bodies = self.data.get("bodies")
        joints = self.data.get("joints")
        if not isinstance(bodies, list) or any(not isinstance(b, dict) or "izz" in b
                                               or "mass_at" not in b for b in bodies):
            used.add("inertia")
        if isinstance(joints, list) and any(isinstance(j, dict) and isinstance(
                j.get("actuator"), dict) and "rotor_inertia" in j["actuator"] for j in joints):
            used.add("inertia")
        if not isinstance(joints, list) or any(not isinstance(j, dict) or "angle" in j
                                               for j in joints):
            used.add("angle")
        return used

    def _points(self, raw, fld: str, length: float | None) -> dict[str, tuple[float, float]]:
        if not isinstance(raw, dict) or not raw:
            self.err(fld, "must be a non-empty table of name = [x, y]")
            return {}
        pts = {}
        for pname in raw:
            if not NAME.match(pname):
                self.err(f"{fld}.{pname}", "point names must be identifiers")
            pts[pname] = self._vec(raw, pname, f"{fld}.{pname}", length)
        return pts

    def _pose(self, d: dict) -> str | None:
        """``pose``: "world" (default) or "joints"; None when it is neither (reported)."""
        pose = d.get("pose", "world")
        if pose not in POSES:
            self.err("pose", f"must be {' or '.join(repr(p) for p in POSES)} (got {pose!r})")
            return None
        return pose


def finite(v) -> bool:
    """A TOML integer may exceed float range (1 followed by 400 zeros): that is not finite."""
    try:
        return math.isfinite(float(v))
    except OverflowError:
        return False


def snap(v: float) -> float:
    """``v`` or an exact 0.0 below ``ZERO_SNAP_M``: rounding must not become a parameter."""
    return 0.0 if abs(v) < ZERO_SNAP_M else v
