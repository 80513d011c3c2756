"""One table of the physical quantities a user types, and one rule to judge a value of each,
whichever route it comes by: a description field, a study's ``[parameters]`` or
``[control.plant]``, ``--set``, a sweep's ``--vary`` range, or ``Robot.with_parameters``.

Each quantity has its SI unit, a physical range (outside it: an error, no machine has it), a
plausible range (outside it: a warning, a real machine could, but a slip is likelier) and the
readings a slip usually comes from (the other units of its kind, a gear ratio typed upside
down, a speed typed in rad/s where rpm is read). A warning names the field, the value, the unit
it was read in and the readings that would make it plausible. Where the robot's own value is
known (every run-time route), a value far from it that a reading brings back near it is a slip
too. numpy-free: shared by derive and the runtime.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from ..units import UNITS
from .types import (
    DENSITY_MAX,
    G_HIGH,
    G_LIMIT,
    G_LOW,
    GYRATION_LIMIT,
    GYRATION_LOW,
    GYRATION_TYPICAL,
    SIZE_LARGE_M,
)

INF = math.inf

#: a run-time value this many times the robot's own (or its inverse) is judged a slip when a
#: reading brings it within NEAR times of the robot's own value
FAR, NEAR = 30.0, 3.0


@dataclass(frozen=True)
class Quantity:
    """One kind of typed value and the rules of its range.

    Attributes
    ----------
    what : str
        What it is, in words, for messages ("mass of a body").
    unit : str
        Its SI unit, the unit every run-time route reads.
    low, high : float
        The physical range (SI); ``strict``: the value must exceed ``low`` (else may equal it).
    plausible : (float, float)
        Magnitudes outside it are a warning; a value of exactly 0 is not judged when the
        physical range allows 0 (a frictionless joint, a horizontal robot).
    kind : str or None
        Its row of ``units.UNITS`` (the other units of its kind are its slip readings).
    readings : tuple of (str, callable)
        Other slips: (what was probably typed, the SI value that reading gives).
    signed : bool
        Any sign is physical (a coordinate); the plausible range holds for its magnitude.
    """

    what: str
    unit: str
    low: float = 0.0
    strict: bool = True
    high: float = INF
    plausible: tuple[float, float] = (0.0, INF)
    kind: str | None = None
    readings: tuple[tuple[str, Callable[[float], float]], ...] = ()
    signed: bool = False

    def error(self, v: float, unit: str | None = None) -> str | None:
        """Why ``v`` (SI, or as typed in ``unit`` of its kind: the rules are about sign and
        zero, the same in every unit but gravity's ceiling) is not physical, or None."""
        unit = unit or self.unit
        if not math.isfinite(v):
            return f"must be finite (got {v!r})"
        if self.signed:
            return None
        above = v > self.low if self.strict else v >= self.low
        if self.high < INF and not (above and v <= self.high):
            return f"must be from {self.low:g} to {self.high:g}{_u(unit)} (got {v:.6g})"
        if not above:
            return f"must be {'>' if self.strict else '>='} {self.low:g}{_u(unit)} (got {v:.6g})"
        return None

    def implausible(self, v: float) -> bool:
        lo, hi = self.plausible
        a = abs(v)
        return not (a == 0.0 and (self.signed or not self.strict)) and not lo <= a <= hi

    def alternatives(self, typed: float, unit: str) -> list[tuple[str, float]]:
        """(reading, SI value) of every likely slip of ``typed``, read in ``unit``."""
        out = []
        table = UNITS.get(self.kind or "", {})
        if unit in table:
            out += [(f'in "{u}"', typed * f) for u, f in table.items() if u != unit]
        out += [(label, fn(typed * table.get(unit, 1.0))) for label, fn in self.readings]
        return [(label, v) for label, v in out if math.isfinite(v)]


def _reciprocal(v: float) -> float:
    return 1.0 / v if v else INF


def _lead_mm(v: float) -> float:
    return 2.0 * math.pi / (v * 1e-3) if v else INF


_INERTIA = "inertia"
#: every quantity a user types, by name
QUANTITIES: dict[str, Quantity] = {
    "mass": Quantity("mass of a body", "kg", plausible=(1e-4, 1e4), kind="mass"),
    "inertia": Quantity("inertia of a body about its centre of gravity", "kg*m^2",
                        strict=False, kind=_INERTIA),
    "length": Quantity("coordinate of a point or centre of gravity", "m", signed=True,
                       plausible=(0.0, SIZE_LARGE_M), kind="length"),
    "gravity": Quantity("gravity magnitude", "m/s^2", strict=False, high=G_LIMIT,
                        plausible=(G_LOW, G_HIGH), kind="acceleration",
                        readings=(("in g (standard gravities)", lambda v: v * 9.80665),)),
    "gear_ratio": Quantity("gear ratio", "1", plausible=(0.1, 1e4),
                           readings=(("upside down (joint turns per motor turn)", _reciprocal),)),
    "gear_ratio_slider": Quantity("gear ratio", "rad/m",
                                  plausible=(1.0, 1e6),
                                  readings=(("as a screw lead in mm", _lead_mm),)),
    "rotor_inertia": Quantity("rotor inertia", "kg*m^2", strict=False, plausible=(0.0, 1.0),
                              kind=_INERTIA),
    "viscous": Quantity("viscous friction", "N*m*s/rad", strict=False, plausible=(0.0, 1e4),
                        readings=(("per deg/s", math.degrees),)),
    "viscous_slider": Quantity("viscous friction", "N*s/m", strict=False, plausible=(0.0, 1e5)),
    "coulomb": Quantity("Coulomb friction", "N*m", strict=False, plausible=(0.0, 1e5),
                        readings=(("in N*mm", lambda v: v * 1e-3),)),
    "coulomb_slider": Quantity("Coulomb friction", "N", strict=False, plausible=(0.0, 1e6)),
    "smoothing": Quantity("Coulomb smoothing speed", "rad/s", plausible=(0.0, 1.0),
                          readings=(("in deg/s", math.radians),)),
    "smoothing_slider": Quantity("Coulomb smoothing speed", "m/s", plausible=(0.0, 1.0),
                                 readings=(("in mm/s", lambda v: v * 1e-3),)),
    "torque_limit": Quantity("joint torque limit", "N*m", plausible=(0.0, 1e5),
                             readings=(("in N*mm", lambda v: v * 1e-3),)),
    "force_limit": Quantity("joint force limit", "N", plausible=(0.0, 1e6)),
    "motor_torque_limit": Quantity("motor torque limit", "N*m", plausible=(0.0, 1e4),
                                   readings=(("in N*mm (mN*m)", lambda v: v * 1e-3),)),
    "motor_speed_rpm": Quantity("motor speed limit", "rpm", plausible=(10.0, 1e5),
                                readings=(("in rad/s", lambda v: v * 60.0 / (2.0 * math.pi)),
                                          ("in thousands of rpm", lambda v: v * 1e3),
                                          ("in rev/s", lambda v: v * 60.0))),
    "torque_constant": Quantity("motor torque constant", "N*m/A", plausible=(1e-4, 10.0),
                                readings=(("in mN*m/A", lambda v: v * 1e-3),)),
    "winding_resistance": Quantity("motor winding resistance", "ohm", plausible=(1e-3, 1e3),
                                   readings=(("in milliohm", lambda v: v * 1e-3),)),
}

#: a parameter's name prefix -> its quantity (revolute joint, prismatic joint)
PARAMETER_QUANTITY = {
    "m_": ("mass", "mass"),
    "izz_": ("inertia", "inertia"),
    "cgx_": ("length", "length"), "cgy_": ("length", "length"),
    "px_": ("length", "length"), "py_": ("length", "length"),
    "gear_": ("gear_ratio", "gear_ratio_slider"),
    "jm_": ("rotor_inertia", "rotor_inertia"),
    "fv_": ("viscous", "viscous_slider"),
    "fc_": ("coulomb", "coulomb_slider"),
    "vs_": ("smoothing", "smoothing_slider"),
}

#: ``[joints.actuator]`` key -> its quantity (revolute joint, prismatic joint)
ACTUATOR_QUANTITY = {
    "gear_ratio": ("gear_ratio", "gear_ratio_slider"),
    "rotor_inertia": ("rotor_inertia", "rotor_inertia"),
    "viscous_friction": ("viscous", "viscous_slider"),
    "coulomb_friction": ("coulomb", "coulomb_slider"),
    "coulomb_smoothing": ("smoothing", "smoothing_slider"),
    "torque_limit": ("torque_limit", "force_limit"),
    "motor_torque_limit": ("motor_torque_limit", "motor_torque_limit"),
    "motor_speed_limit_rpm": ("motor_speed_rpm", "motor_speed_rpm"),
    "torque_constant": ("torque_constant", "torque_constant"),
    "winding_resistance": ("winding_resistance", "winding_resistance"),
}

#: a parameter's SI unit as its manifest writes it at a prismatic joint
_SLIDER_UNITS = {"rad/m", "N*s/m", "N", "m/s"}


def of_parameter(name: str, unit: str = "") -> Quantity | None:
    """The quantity of parameter ``name`` (``unit`` its manifest unit: tells a slider's), or
    None for a name the table does not know."""
    if name == "g":
        return QUANTITIES["gravity"]
    for prefix, (revolute, slider) in PARAMETER_QUANTITY.items():
        if name.startswith(prefix):
            return QUANTITIES[slider if unit in _SLIDER_UNITS else revolute]
    return None


def doubt(q: Quantity, typed: float, unit: str | None = None,
          reference: float | None = None) -> str | None:
    """A warning for a physical value that is likely a slip, or None.

    ``typed`` is the value as typed, read in ``unit`` (default the SI unit); ``reference`` is
    the robot's own value of the same field (SI), where one is known. The message names the
    value, the unit read and the readings that would make it plausible; the caller puts the
    field before it."""
    unit = unit or q.unit
    table = UNITS.get(q.kind or "", {})
    v = typed * table.get(unit, 1.0)
    shown = _shown(typed, unit, q)
    alts = q.alternatives(typed, unit)
    if reference and v and (abs(v / reference) >= FAR or abs(v / reference) <= 1.0 / FAR):
        near = [(label, a) for label, a in alts if 1.0 / NEAR <= abs(a / reference) <= NEAR]
        if near:
            return (f"{shown} is {abs(v / reference):.4g} times the robot's own "
                    f"{reference:.6g}{_u(q.unit)}; a slip? {_readings(near, q.unit)}")
    if not q.implausible(v):
        return None
    lo, hi = q.plausible
    side = f"above the plausible {hi:g}" if abs(v) > hi else f"below the plausible {lo:g}"
    fits = [(label, a) for label, a in alts if not q.implausible(a)]
    hint = f"a slip? {_readings(fits, q.unit)}" if fits else "a unit or decimal-point slip?"
    return f"{shown} is {side}{_u(q.unit)} for a {q.what}; {hint}"


def _u(unit: str) -> str:
    """`` unit`` to follow a number, nothing for a pure number."""
    return "" if unit == "1" else f" {unit}"


def _readings(alts: list[tuple[str, float]], unit: str) -> str:
    text = " or ".join(f"{label} it would be {a:.6g}{_u(unit)}" for label, a in alts)
    return text[0].upper() + text[1:]


# -- a body's mass and inertia against its size ---------------------------------------------------

#: the ball a single-point body's mass is held against: the robot's span as its radius
POINT_BALL = "a ball as wide as the robot's span"


def mass_doubt(typed: float, unit: str, extent: float,
               ball: str = "the ball its points reach from its centre of gravity") -> str | None:
    """A warning for a mass (``typed`` in ``unit``) heavier than osmium filling the ball of
    radius ``extent`` (m, its points' reach from its centre of gravity, or the robot's span for
    a body of a single point: ``ball`` says which), or None."""
    q = QUANTITIES["mass"]
    most = DENSITY_MAX * 4.0 / 3.0 * math.pi * extent ** 3
    m = typed * UNITS["mass"][unit]
    if extent <= 0.0 or m <= most:
        return None
    fits = [(label, a) for label, a in q.alternatives(typed, unit) if a <= most]
    return (f"{_shown(typed, unit, q)} is more than osmium filling {ball} "
            f"({extent * 1e3:.4g} mm) would weigh ({most:.4g} kg); "
            + (f"a slip? {_readings(fits, q.unit)}" if fits else "a unit or decimal slip?"))


def inertia_doubt(typed: float, unit: str, mass: float, extent: float) -> str | None:
    """A warning for an inertia (``typed`` in ``unit``) whose radius of gyration is below
    ``GYRATION_LOW`` times the body's reach ``extent`` (m), given its ``mass`` (kg), or None."""
    q = QUANTITIES["inertia"]
    izz = typed * UNITS["inertia"][unit]
    if extent <= 0.0 or mass <= 0.0 or izz <= 0.0 or math.sqrt(izz / mass) >= GYRATION_LOW * extent:
        return None
    return (f"{_shown(typed, unit, q)} gives a radius of gyration of "
            f"{math.sqrt(izz / mass) * 1e3:.4g} mm, less than {GYRATION_LOW:g} times the "
            f"{extent * 1e3:.4g} mm its points reach from its centre of gravity; "
            + inertia_fits(typed, unit, mass, extent, "a unit or decimal slip?"))


def inertia_fits(typed: float, unit: str, mass: float, extent: float, otherwise: str) -> str:
    """How an implausible inertia (``typed`` in ``unit``) may have been meant: the units that
    give a body of ``mass`` (kg) and reach ``extent`` (m) a plausible radius of gyration, or
    ``otherwise``. 3000 typed in kg*m^2 for kg*mm^2 names kg*mm^2."""
    q = QUANTITIES["inertia"]
    fits = [(label, a) for label, a in q.alternatives(typed, unit)
            if GYRATION_LOW * extent <= math.sqrt(a / mass) <= GYRATION_LIMIT * extent]
    return f"a slip? {_readings(fits, q.unit)}" if fits else otherwise


def gyration_slip(typed: tuple[float, float], units: dict,
                  extent: float) -> tuple[str, str] | None:
    """(field, message) when a body's radius of gyration is implausible (above
    ``GYRATION_LIMIT`` or below ``GYRATION_LOW`` times its reach ``extent``, m) and its mass, or
    else its points (the reach), read in another unit bring it within ``GYRATION_TYPICAL``;
    else None (izz is the field to blame). ``typed`` is (mass, izz) as typed in ``units`` (the
    description's [units]). A reading that makes the body denser than osmium (its mass in the
    ball of its reach) is no fit. The message names every reading that fits, izz's too: any
    may be the slip, and one mistake gives one message."""
    mass_u, izz_u, length_u = units["mass"], units["inertia"], units.get("length")
    mass, izz = typed[0] * UNITS["mass"][mass_u], typed[1] * UNITS["inertia"][izz_u]
    if extent <= 0.0 or mass <= 0.0 or izz <= 0.0:
        return None
    radius = math.sqrt(izz / mass)
    if GYRATION_LOW * extent <= radius <= GYRATION_LIMIT * extent:
        return None

    def typical(m: float, i: float, reach: float = extent) -> bool:
        return GYRATION_TYPICAL[0] <= math.sqrt(i / m) / reach <= GYRATION_TYPICAL[1]

    def possible(m: float, reach: float = extent) -> bool:  # not denser than osmium
        return m <= DENSITY_MAX * 4.0 / 3.0 * math.pi * reach ** 3

    masses = [(u, typed[0] * f) for u, f in UNITS["mass"].items()
              if u != mass_u and possible(typed[0] * f) and typical(typed[0] * f, izz)]
    lengths = UNITS["length"]
    reaches = [(u, extent * f / lengths[length_u]) for u, f in lengths.items()
               if length_u in lengths and u != length_u
               and possible(mass, r := extent * f / lengths[length_u]) and typical(mass, izz, r)]
    if not masses and not reaches:
        return None
    side = (f"more than {GYRATION_LIMIT:g}" if radius > GYRATION_LIMIT * extent
            else f"less than {GYRATION_LOW:g}")
    said = [f'the mass (units.mass = "{mass_u}") read in "{u}" would be {a:.6g} kg, a radius of '
            f"gyration of {math.sqrt(izz / a) * 1e3:.4g} mm" for u, a in masses]
    said += [f'its points and cg (units.length = "{length_u}") read in "{u}" would reach '
             f"{r * 1e3:.4g} mm, the radius of gyration {radius / r:.3g} times that"
             for u, r in reaches]
    inertias = [(u, typed[1] * f) for u, f in UNITS["inertia"].items()
                if u != izz_u and typical(mass, typed[1] * f)]
    said += [f'izz (units.inertia = "{izz_u}") read in "{u}" would be {a:.6g} kg*m^2, a radius '
             f"of gyration of {math.sqrt(a / mass) * 1e3:.4g} mm" for u, a in inertias]
    field = "mass" if masses else "points"
    text = (f"{_shown(typed[0], mass_u, QUANTITIES['mass'])} with izz = {typed[1]:g} {izz_u} "
            f"gives a radius of gyration of {radius * 1e3:.4g} mm for a body whose points reach "
            f"{extent * 1e3:.4g} mm from its centre of gravity ({side} times; izz / (mass * "
            f"reach^2) = {izz / (mass * extent ** 2):.3g}, a uniform rod's is 1/3): a unit slip? "
            + "; or ".join(said)[0].upper() + "; or ".join(said)[1:])
    return field, text


def _shown(typed: float, unit: str, q: Quantity) -> str:
    """A typed value with the unit it was read in (and its SI value where that differs)."""
    v = typed * UNITS.get(q.kind or "", {}).get(unit, 1.0)
    return f"{typed:.6g}{_u(unit)}" + (f" (read in {unit}" if unit != "1" else "") + (
        f", {v:.6g}{_u(q.unit)})" if unit != q.unit else ")" if unit != "1" else "")
