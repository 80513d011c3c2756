"""The length unit a robot's description is typed in (``[units].length``): pictures of the
mechanism (drawings, animations, atlas maps, the explorer) use it, so a robot typed in cm is
drawn in cm. Numbers in files and arrays stay SI whatever the description's unit.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from .units import UNITS, factor

#: a description whose file is not at hand is drawn in the SI unit
DEFAULT = "m"


def typed_length_unit(path: Path | str | None) -> str:
    """``[units].length`` of the description file at ``path`` ("m", "cm" or "mm"), or "m"
    when there is no file (a generated folder without its description) or no such unit."""
    if path is None:
        return DEFAULT
    try:
        unit = tomllib.loads(Path(path).read_text()).get("units", {}).get("length", DEFAULT)
    except (OSError, tomllib.TOMLDecodeError, AttributeError):
        return DEFAULT
    # an unknown unit was refused when the robot was derived; a file edited since is drawn in m
    return unit if isinstance(unit, str) and unit in UNITS["length"] else DEFAULT


def per_metre(unit: str) -> float:
    """How many ``unit`` make one metre: 1e3 for mm, 100 for cm, 1 for m."""
    return 1.0 / factor("length", unit)
