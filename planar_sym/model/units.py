"""Unit conversion at the description boundary: every known unit string to its SI factor.

The seed tables mix m, mm, kg*mm^2 and degrees; this is the one place they become SI.
"""

from __future__ import annotations

#: quantity -> {unit string -> factor to SI}
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": 1e-2, "mm": 1e-3},
    "mass": {"kg": 1.0, "g": 1e-3},
    "inertia": {"kg*m^2": 1.0, "kg*cm^2": 1e-4, "kg*mm^2": 1e-6, "g*mm^2": 1e-9, "g*cm^2": 1e-7},
    "angle": {"rad": 1.0, "deg": 3.141592653589793 / 180.0},
    "acceleration": {"m/s^2": 1.0, "mm/s^2": 1e-3},
}

#: SI unit of each quantity, as written in manifests and tables
SI = {"length": "m", "mass": "kg", "inertia": "kg*m^2", "angle": "rad", "acceleration": "m/s^2"}


def factor(quantity: str, unit: str) -> float:
    """Factor that turns a value in ``unit`` into SI; KeyError names the known units."""
    table = UNITS[quantity]
    if unit not in table:
        raise KeyError(f"unknown {quantity} unit {unit!r}; known: {', '.join(table)}")
    return table[unit]
