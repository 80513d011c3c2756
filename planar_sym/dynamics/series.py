"""Typed series: one sampled quantity with its unit and what it belongs to, and the column name
the files give it.

A result (``Simulation``, a study's ``Result``) holds its data as ``Series``: the quantity
(``"q"``, ``"tau"``, ``"fx"``, ``"energy"``, ...), its unit (``"rad"``, ``"N*m"``, ...), the
values, shape (N,), and the coordinate (``index``, 0-based) or joint (``joint``) it belongs to.
Code reads these fields; the column name (``q1_rad``, ``tau2_n``, ``fx_C_n``, ``energy_j``) is
made from them only where a file or a table needs one (CSV, NPZ, DataFrame), and is never
parsed back.

.. code:: text

    quantity   index  joint  unit      column
    "t"        -      -      "s"       t_s
    "q"        0      -      "rad"     q1_rad        (a slider's: "m", q2_m)
    "qd"       1      -      "m/s"     qd2_m_s
    "qdd"      0      -      "rad/s^2" qdd1_rad_s2
    "tau"      1      -      "N"       tau2_n        (a revolute joint's: "N*m", tau1_n_m)
    "tau_cmd"  0      -      "N*m"     tau_cmd1_n_m
    "q_ref"    0      -      "rad"     q1_ref_rad    ("qd_ref": qd1_ref_rad_s)
    "e"        0      -      "rad"     e1_rad
    "p"        0      -      "W"       p1_w
    "x_ref"    -      -      "mm"      x_ref_mm
    "fx"       -      "C"    "N"       fx_C_n
    "jm"       -      "A"    "N*m"     jm_A_n_m
    "energy"   -      -      "J"       energy_j
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SeriesNotFound

#: every unit a series may have -> the suffix its column name ends with
UNIT_SUFFIX = {"s": "s", "rad": "rad", "m": "m", "mm": "mm", "rad/s": "rad_s", "m/s": "m_s",
               "rad/s^2": "rad_s2", "m/s^2": "m_s2", "N*m": "n_m", "N": "n", "W": "w",
               "J": "j", "rpm": "rpm"}

#: a coordinate's quantities by what they are of it: its value, rate, acceleration, effort
_ORDER = {"q": 0, "q_ref": 0, "e": 0, "qd": 1, "qd_ref": 1, "qdd": 2, "tau": 3, "tau_cmd": 3}
#: a coordinate's unit ("rad" or "m") -> the units of its value, rate, acceleration, effort
_COORDINATE_UNITS = {"rad": ("rad", "rad/s", "rad/s^2", "N*m"), "m": ("m", "m/s", "m/s^2", "N")}
#: quantities whose coordinate number goes inside their name: q1_ref, not q_ref1
_NUMBER_INSIDE = {"q_ref": ("q", "_ref"), "qd_ref": ("qd", "_ref")}


def coordinate_unit(quantity: str, unit: str) -> str:
    """The unit of a coordinate's ``quantity`` (``"q"``, ``"qd"``, ``"qdd"``, ``"tau"``,
    ``"tau_cmd"``, ``"q_ref"``, ``"qd_ref"``, ``"e"``) for a coordinate in ``unit`` (``"rad"``,
    or ``"m"`` at a slider): ``("qd", "m")`` -> ``"m/s"``, ``("tau", "m")`` -> ``"N"``."""
    return _COORDINATE_UNITS[unit][_ORDER[quantity]]


def column_stem(quantity: str, index: int | None = None, joint: str | None = None) -> str:
    """A column's name without its unit: ``tau2``, ``q1_ref``, ``fx_C``, ``energy``."""
    if index is not None:
        head, tail = _NUMBER_INSIDE.get(quantity, (quantity, ""))
        return f"{head}{index + 1}{tail}"
    return quantity if joint is None else f"{quantity}_{joint}"


def column_name(quantity: str, unit: str, index: int | None = None,
                joint: str | None = None) -> str:
    """The column name of a series: its stem and its unit's suffix (``tau2_n``, ``t_s``)."""
    if unit not in UNIT_SUFFIX:
        raise InputError(f"unknown unit {unit!r} of {quantity!r}; known: "
                         f"{', '.join(UNIT_SUFFIX)}")
    return f"{column_stem(quantity, index, joint)}_{UNIT_SUFFIX[unit]}"


@dataclass(frozen=True, eq=False)
class Series:
    """One sampled quantity: ``values`` of shape (N,) in ``unit`` (SI, or mm for task
    positions as the seed writes them), typed by ``quantity``, the coordinate ``index`` (0-based)
    or the ``joint`` (a cut or a joint of the description) it belongs to.

    Attributes
    ----------
    quantity : str
        What it is: ``"t"``, ``"q"``, ``"qd"``, ``"qdd"``, ``"tau"``, ``"tau_cmd"``,
        ``"q_ref"``, ``"e"``, ``"p"``, ``"x"``, ``"y"``, ``"phi"``, ``"e_task"``, ``"fx"``,
        ``"jload"``, ``"energy"``, ``"work"``, ... (the module's table).
    unit : str
        Its unit: ``"s"``, ``"rad"``, ``"m"``, ``"mm"``, ``"rad/s"``, ``"m/s"``,
        ``"rad/s^2"``, ``"m/s^2"``, ``"N*m"``, ``"N"``, ``"W"``, ``"J"`` (``UNIT_SUFFIX``).
    values : ndarray, shape (N,)
        The samples, in ``unit``.
    index : int or None
        The coordinate it belongs to (0-based), if any.
    joint : str or None
        The joint or loop cut it belongs to (``"C"``, ``"A"``), if any.
    """

    quantity: str
    unit: str
    values: np.ndarray
    index: int | None = None
    joint: str | None = None

    def __post_init__(self) -> None:
        if self.unit not in UNIT_SUFFIX:
            raise InputError(f"unknown unit {self.unit!r} of {self.quantity!r}; known: "
                             f"{', '.join(UNIT_SUFFIX)}")

    @classmethod
    def of_coordinate(cls, quantity: str, index: int, unit: str,
                      values: np.ndarray) -> Series:
        """Coordinate ``index``'s ``quantity`` (``"q"``, ``"tau"``, ...; shape (N,)), its
        unit from the coordinate's ``unit`` (``"rad"``, or ``"m"`` at a slider)."""
        return cls(quantity, coordinate_unit(quantity, unit), values, index=index)

    @property
    def stem(self) -> str:
        """The column name without its unit: ``tau2``, ``q1_ref``, ``fx_C``, ``energy``."""
        return column_stem(self.quantity, self.index, self.joint)

    @property
    def column(self) -> str:
        """The column name in files and tables, the unit in it: ``q1_rad``, ``tau2_n``,
        ``fx_C_n``, ``energy_j``."""
        return f"{self.stem}_{UNIT_SUFFIX[self.unit]}"

    def __repr__(self) -> str:
        return f"Series({self.column}, {len(self.values)} samples)"


def columns_of(series) -> dict[str, np.ndarray]:
    """Column name -> values (each (N,), SI or mm as the name's unit says: the very arrays of
    ``series``), in order; InputError if two series would share a column."""
    out: dict[str, np.ndarray] = {}
    for s in series:
        name = s.column
        if name in out:
            raise InputError(f"two series are named {name!r}")
        out[name] = s.values
    return out


def select(series, quantity: str | None = None, index: int | None = None,
           joint: str | None = None) -> tuple[Series, ...]:
    """The series of ``quantity`` (every one if None), of coordinate ``index`` (0-based) and of
    ``joint`` where given, in order; each holds (N,) values in its own unit."""
    return tuple(s for s in series
                 if (quantity is None or s.quantity == quantity)
                 and (index is None or s.index == index)
                 and (joint is None or s.joint == joint))


def one(series, quantity: str, index: int | None = None, joint: str | None = None) -> Series:
    """The one series of ``quantity`` (at coordinate ``index``, or ``joint``), shape (N,), in
    its unit; SeriesNotFound (an InputError and a KeyError) naming those there are if there is
    none or more than one."""
    found = select(series, quantity, index, joint)
    if len(found) == 1:
        return found[0]
    where = " and ".join(f"{k}={v!r}" for k, v in (("index", index), ("joint", joint))
                         if v is not None)
    same = select(series, quantity)
    have = ", ".join(_label(s) for s in same)
    if found:
        raise SeriesNotFound(f"{len(found)} series of {quantity!r}: name one with index= (the "
                             f"0-based coordinate number) or joint= ({have})")
    if not same:
        names = ", ".join(dict.fromkeys(s.quantity for s in series))
        raise SeriesNotFound(f"no series of {quantity!r} in this result (its quantities: "
                             f"{names or 'none'})")
    hint = (" (index is the 0-based coordinate number: a coordinate missing here has no "
            f"{quantity!r}, as a passive joint has no torque)") if index is not None else ""
    raise SeriesNotFound(f"no series of {quantity!r} with {where}{hint}; {quantity!r} has "
                         f"{have}")


def _label(s: Series) -> str:
    """A series as a refusal lists it: its column, and the coordinate or joint it is of."""
    if s.joint is not None:
        return f"{s.column} (joint {s.joint!r})"
    return s.column if s.index is None else f"{s.column} (index {s.index})"
