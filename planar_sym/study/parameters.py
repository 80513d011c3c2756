"""A study's parameter overrides, converted to SI: a number is in the robot description's own
units (its ``[units]`` table), a string carries its unit (``"0.5 kg"``, ``"90.992 kg*mm^2"``).
"""

from __future__ import annotations

import tomllib

from ..errors import InputError
from ..model.parameter_set import QUANTITY
from ..model.robot import Robot
from ..model.units import factor
from ..spelling import did_you_mean


def description_units(robot: Robot) -> dict[str, str] | None:
    """The ``[units]`` table of the robot's description, or None where no description is at hand
    (a generated folder without its ``description.toml`` copy)."""
    path = robot.description_file
    if path is None:
        return None
    try:
        units = tomllib.loads(path.read_text(encoding="utf-8")).get("units")
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return None
    return units if isinstance(units, dict) else None


def to_si(robot: Robot, overrides: dict[str, tuple[float, str | None]],
          where: str = "parameters") -> dict[str, float]:
    """SI values of ``{name: (value, unit or None)}``; every problem reported at once."""
    return _convert(robot, overrides, where)[0]


def _convert(robot: Robot, overrides: dict[str, tuple[float, str | None]], where: str):
    """(SI values, {name: (value as typed, the unit it was read in)}) of ``overrides``."""
    known = {p.name: p for p in robot.parameter_list}
    units = description_units(robot)
    problems, out, typed = [], {}, {}
    for name, (value, unit) in overrides.items():
        if name not in known:
            problems.append(f"{where}.{name}: not a parameter of {robot.name} (known: "
                            f"{', '.join(known)}){did_you_mean(name, known)}")
            continue
        quantity = QUANTITY.get(known[name].unit)
        if unit is None:
            if units is None:
                problems.append(f"{where}.{name}: give the unit (e.g. \"{value} "
                                f"{known[name].unit}\"): {robot.name} has no description here "
                                "to say which units a bare number is in")
                continue
            unit = units.get(quantity, known[name].unit) if quantity else known[name].unit
        try:
            out[name] = value * (factor(quantity, unit) if quantity else 1.0)
            typed[name] = (value, unit)
        except KeyError as exc:
            problems.append(f"{where}.{name}: {exc.args[0]} for a {quantity} (got {unit!r})")
    if problems:
        raise InputError("; ".join(problems) if len(problems) == 1
                         else "invalid parameters:\n  " + "\n  ".join(problems))
    return out, typed


def with_overrides(robot: Robot, overrides: dict[str, tuple[float, str | None]],
                   where: str) -> Robot:
    """``robot.with_parameters`` of the SI values of ``overrides`` (``to_si``), a value the
    physical rules refuse named by ``where`` (the file and table it came from)."""
    values, typed = _convert(robot, overrides, where)
    return robot.with_values(robot.parameters.replace(where, typed=typed, **values))
