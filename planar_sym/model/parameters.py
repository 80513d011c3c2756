"""Physical checks of a parameter vector changed at run time (``Robot.with_parameters``, a
study's ``[parameters]``), the same rules the description's own values pass at derive time.

Rules, with their figures:

* every value finite; masses > 0; inertias >= 0 (a body with extent needs > 0);
* a radius of gyration sqrt(izz / m) at most ``GYRATION_LIMIT`` (3) times the body's extent,
  the largest distance from its centre of gravity to its points (as in the description; here
  the points the equations use and the frame origin, which is always one of its points);
* every other quantity by its row of the one table (``description.quantities``) that
  ``[joints.actuator]`` and the description's fields are checked by too: gravity magnitude
  ``g`` from 0 to ``G_LIMIT`` = 300 m/s^2 (the Sun's surface gives 274; more is a unit slip
  such as mm/s^2 read as m/s^2); gear ratios and Coulomb smoothing speeds > 0; rotor inertias,
  viscous and Coulomb friction >= 0;
* ``doubts``: the table's plausibility warnings (a likely slip: a value outside its plausible
  range, or far from the robot's own value where another reading of it lands near it).
"""

from __future__ import annotations

import math

from .description import CLOSURE_TOLERANCE_M, GYRATION_LIMIT
from .description.quantities import (
    QUANTITIES,
    doubt,
    inertia_doubt,
    mass_doubt,
    of_parameter,
)


def _physical(name: str, v: float, unit: str) -> str | None:
    """The table's physical rule for a parameter other than mass and inertia (which the body
    rules below judge with the body's extent)."""
    q = of_parameter(name, unit)
    if q is None or name.startswith(("m_", "izz_")) or (msg := q.error(v)) is None:
        return None
    return (f"parameter {name} ({q.what}) {msg}"
            + ("; a unit slip?" if name == "g" and v > 0 else ""))


def doubts(names, values: dict[str, float], units: dict[str, str],
           reference: dict[str, float], bodies: tuple[str, ...] = (),
           typed: dict[str, tuple[float, str]] | None = None) -> list[str]:
    """A warning for each parameter of ``names`` whose value in ``values`` (every name -> SI,
    physical) is likely a slip: outside its quantity's plausible range, or far from the robot's
    own value (``reference``) where another reading of it lands near; a body's mass heavier
    than osmium filling its reach, or its inertia's radius of gyration below 1% of its reach
    (``description.quantities``, the description's table and rules). ``typed``: a value as the
    user typed it and the unit it was read in, {name: (value, unit)}, where not SI."""
    typed = typed or {}
    out, judged = [], set()
    for body in bodies:
        m, izz = f"m_{body}", f"izz_{body}"
        if (m in names or izz in names) and m in values and izz in values:
            extent = _extent(values, body, bodies)
            if extent < CLOSURE_TOLERANCE_M:
                continue
            if m in names and (msg := mass_doubt(*typed.get(m, (values[m], "kg")),
                                                 extent)) is not None:
                out.append(f"parameter {m} = {msg}")
                judged.add(m)
            elif (msg := inertia_doubt(*typed.get(izz, (values[izz], "kg*m^2")), values[m],
                                       extent)) is not None:
                out.append(f"parameter {izz} = {msg}")
                judged.add(izz)
    for name in names:
        q = of_parameter(name, units.get(name, ""))
        if name not in judged and q is not None and (
                msg := doubt(q, *typed.get(name, (values[name], q.unit)),
                             reference=_reference(name, reference, bodies))) is not None:
            out.append(f"parameter {name} = {msg}")
    return out


#: a body-frame coordinate this small against its body's reach is "about zero": no reference
#: for a slip (the seed's 5-bar has cg offsets of 5e-8 m; a value 2000 times that is no slip)
NEGLIGIBLE = 1e-3


def _reference(name: str, reference: dict[str, float], bodies: tuple[str, ...]
               ) -> float | None:
    """The robot's own value of ``name`` as a reference for a slip, or None where it is a
    body-frame coordinate negligible against that body's own reach (the robot's values, not
    the changed ones: a slip must not hide itself by stretching the body)."""
    ref = reference.get(name)
    if ref is None or not name.startswith(("cgx_", "cgy_", "px_", "py_")):
        return ref
    rest = name.split("_", 1)[1]
    owners = [b for b in bodies if rest == b or rest.startswith(f"{b}_")]
    if not owners:
        return ref
    body = max(owners, key=len)  # the longest name that fits (L_Link1 before L)
    return None if abs(ref) < NEGLIGIBLE * _extent(reference, body, bodies) else ref


def problems(values: dict[str, float], bodies: tuple[str, ...],
             units: dict[str, str] | None = None) -> list[str]:
    """Every physical problem of ``values`` (name -> SI value), one message each."""
    out = []
    for name, v in values.items():
        if not math.isfinite(v):
            out.append(f"parameter {name} must be finite (got {v!r})")
    if out:
        return out
    units = units or {}
    out += [msg for name, v in values.items() if (msg := _physical(name, v, units.get(name, "")))]
    for body in bodies:
        m, izz = values.get(f"m_{body}"), values.get(f"izz_{body}")
        if m is not None and (msg := QUANTITIES["mass"].error(m)) is not None:
            out.append(f"parameter m_{body} {msg}")
            continue
        if izz is not None and (msg := QUANTITIES["inertia"].error(izz)) is not None:
            out.append(f"parameter izz_{body} {msg}")
            continue
        if m is None or izz is None:
            continue
        extent = _extent(values, body, bodies)
        radius = math.sqrt(izz / m)
        if extent >= CLOSURE_TOLERANCE_M and izz == 0.0:
            out.append(f"parameter izz_{body} must be > 0 for a body with extent (its points "
                       f"reach {extent * 1e3:.4g} mm from its centre of gravity)")
        elif extent >= CLOSURE_TOLERANCE_M and radius > GYRATION_LIMIT * extent:
            out.append(f"parameter izz_{body} = {izz:.6g} kg*m^2 with m_{body} = {m:.6g} kg "
                       f"gives a radius of gyration of {radius * 1e3:.4g} mm for a body whose "
                       f"points reach {extent * 1e3:.4g} mm from its centre of gravity (more "
                       f"than {GYRATION_LIMIT:g} times); a unit or decimal-point slip?")
    return out


def _extent(values: dict[str, float], body: str, bodies: tuple[str, ...]) -> float:
    """Largest distance (m) from the body's centre of gravity to its known points."""
    cg = (values.get(f"cgx_{body}", 0.0), values.get(f"cgy_{body}", 0.0))
    points = {"": (0.0, 0.0)}  # the frame origin is one of the body's points
    longer = [b for b in bodies if b != body and b.startswith(f"{body}_")]
    for name, v in values.items():
        for axis in "xy":
            prefix = f"p{axis}_{body}_"
            if name.startswith(prefix) and not any(name.startswith(f"p{axis}_{b}_")
                                                   for b in longer):
                point = name[len(prefix):]
                xy = points.setdefault(point, (0.0, 0.0))
                points[point] = (v, xy[1]) if axis == "x" else (xy[0], v)
    return max(math.dist(cg, xy) for xy in points.values())


def failing(names: list[str], P, bodies: tuple[str, ...], units: dict[str, str] | None = None):
    """Which rows of ``P`` (designs, parameters in ``names`` order, SI) break a rule of
    ``problems``: the same rules, evaluated on whole columns at once (a sweep checks 10^5
    designs in milliseconds); ``problems`` then words the message for a failing row."""
    import numpy as np

    P = np.asarray(P, dtype=float)
    col = {n: P[:, k] for k, n in enumerate(names)}
    bad = ~np.all(np.isfinite(P), axis=1)
    units = units or {}
    for name, v in col.items():
        q = of_parameter(name, units.get(name, ""))
        if q is None or q.signed or name.startswith(("m_", "izz_")):
            continue
        bad |= ~(v > q.low) if q.strict else v < q.low
        bad |= v > q.high
    with np.errstate(invalid="ignore", divide="ignore"):
        for body in bodies:
            m, izz = col.get(f"m_{body}"), col.get(f"izz_{body}")
            if m is not None:
                bad |= ~(m > 0)
            if izz is not None:
                bad |= izz < 0
            if m is None or izz is None:
                continue
            extent = _extent_columns(col, body, bodies, len(P))
            radius = np.sqrt(np.abs(izz) / m)
            big = extent >= CLOSURE_TOLERANCE_M
            bad |= big & ((izz == 0.0) | (radius > GYRATION_LIMIT * extent))
    return bad


def _extent_columns(col: dict, body: str, bodies: tuple[str, ...], D: int):
    """``_extent`` for every design at once. Kept apart from it: numpy on one design would
    make ``problems`` (every ``with_parameters``) 2.5x slower; tests/test_sweep.py checks the
    two agree on random designs of several robots."""
    import numpy as np

    zero = np.zeros(D)
    cg = (col.get(f"cgx_{body}", zero), col.get(f"cgy_{body}", zero))
    longer = [b for b in bodies if b != body and b.startswith(f"{body}_")]
    points: dict[str, list] = {"": [zero, zero]}
    for name, v in col.items():
        for axis, i in (("x", 0), ("y", 1)):
            prefix = f"p{axis}_{body}_"
            if name.startswith(prefix) and not any(name.startswith(f"p{axis}_{b}_")
                                                   for b in longer):
                points.setdefault(name[len(prefix):], [zero, zero])[i] = v
    return np.max([np.hypot(x - cg[0], y - cg[1]) for x, y in points.values()], axis=0)
