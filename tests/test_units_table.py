"""The unit table (``planar_sym.model.units``) against the units' definitions: every factor is
recomputed here from the base units (1 cm = 1/100 m, 1 g = 1/1000 kg, 1 deg = pi/180 rad,
inertia = mass * length^2), every quantity's SI unit is the one its factor 1 belongs to, and an
unknown unit is refused naming the quantity and the known units."""

from __future__ import annotations

import math

import pytest

from planar_sym.model import units

LENGTH = {"m": 1.0, "cm": 1 / 100, "mm": 1 / 1000}
MASS = {"kg": 1.0, "g": 1 / 1000}
EXPECTED = {
    "length": LENGTH,
    "mass": MASS,
    "inertia": {f"{m}*{ln}^2": MASS[m] * LENGTH[ln] ** 2
                for m, ln in (("kg", "m"), ("kg", "cm"), ("kg", "mm"), ("g", "mm"), ("g", "cm"))},
    "angle": {"rad": 1.0, "deg": math.radians(1.0)},
    "acceleration": {"m/s^2": 1.0, "mm/s^2": LENGTH["mm"]},
}


@pytest.mark.parametrize("quantity", EXPECTED)
def test_every_factor_from_its_definition(quantity):
    assert set(units.UNITS[quantity]) == set(EXPECTED[quantity])
    for unit, value in EXPECTED[quantity].items():
        assert units.factor(quantity, unit) == pytest.approx(value, rel=1e-15), unit


def test_the_si_unit_of_each_quantity_has_factor_one():
    assert set(units.SI) == set(units.UNITS)
    for quantity, unit in units.SI.items():
        assert units.factor(quantity, unit) == 1.0
        assert [u for u, f in units.UNITS[quantity].items() if f == 1.0] == [unit]


def test_an_unknown_unit_names_the_quantity_and_the_known_ones():
    with pytest.raises(KeyError) as info:
        units.factor("length", "inch")
    assert info.value.args[0] == "unknown length unit 'inch'; known: m, cm, mm"
    with pytest.raises(KeyError):
        units.factor("speed", "m/s")  # not a quantity of the table
