"""Physical checks of a parameter vector changed at run time (``Robot.with_parameters``, a
study's ``[parameters]``), the same rules the description's own values pass at derive time.

Rules, with their figures:

* every value finite; masses > 0; inertias >= 0 (a body with extent needs > 0);
* a radius of gyration sqrt(izz / m) at most ``GYRATION_LIMIT`` (3) times the body's extent,
  the largest distance from its centre of gravity to its points (as in the description; here
  the points the equations use and the frame origin, which is always one of its points); a
  body of a single point against the robot's reach (the sum of its bodies' sizes, the
  description's bound of its span);
* the centre of gravity at most ``CG_ERROR`` (10) times the body's size outside the outline of
  its points (the robot's reach for a single point), a warning beyond ``CG_WARN`` (1), as in
  the description (a user trial: cgx = 1.2 m on a 0.1 m link was refused in a description and
  taken without a word by ``with_parameters``, ``--set``, a study and a sweep);
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
from .description.plausibility import diameter, outside_hull
from .description.quantities import (
    POINT_BALL,
    QUANTITIES,
    doubt,
    inertia_doubt,
    mass_doubt,
    of_parameter,
)
from .description.types import CG_ERROR, CG_WARN


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
        moved = _cg_names(body, names, bodies)
        ratio, size, off, yardstick = _cg_outside(values, body, bodies)
        if moved and CG_WARN < ratio <= CG_ERROR:
            out.append(_cg_message(moved, ratio, size, off, yardstick))
            judged.update(moved)
        m, izz = f"m_{body}", f"izz_{body}"
        if (m in names or izz in names) and m in values and izz in values:
            extent = _extent(values, body, bodies)
            if extent < CLOSURE_TOLERANCE_M:  # a single point: its mass against the reach
                reach = _reach(values, bodies)
                if m in names and reach >= CLOSURE_TOLERANCE_M and (
                        msg := mass_doubt(*typed.get(m, (values[m], "kg")), reach,
                                          POINT_BALL)) is not None:
                    out.append(f"parameter {m} = {msg}")
                    judged.add(m)
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
             units: dict[str, str] | None = None, changed=()) -> list[str]:
    """Every physical problem of ``values`` (name -> SI value), one message each; a message
    names the ``changed`` parameters among those it is about, where there are any."""
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
        if (msg := _outline(values, body, bodies, changed)) is not None:
            out.append(msg)
            continue
        extent = _extent(values, body, bodies)
        radius = math.sqrt(izz / m)
        if extent < CLOSURE_TOLERANCE_M:
            continue  # a single point: judged against the robot's reach by _outline
        if izz == 0.0:
            out.append(f"parameter izz_{body} must be > 0 for a body with extent (its points "
                       f"reach {extent * 1e3:.4g} mm from its centre of gravity)")
        elif radius > GYRATION_LIMIT * extent:
            out.append(f"parameter izz_{body} = {izz:.6g} kg*m^2 with m_{body} = {m:.6g} kg "
                       f"gives a radius of gyration of {radius * 1e3:.4g} mm for a body whose "
                       f"points reach {extent * 1e3:.4g} mm from its centre of gravity (more "
                       f"than {GYRATION_LIMIT:g} times); a unit or decimal-point slip?")
    return out


def _outline(values: dict[str, float], body: str, bodies: tuple[str, ...],
             changed=()) -> str | None:
    """The rules a body's outline sets (the description's): its centre of gravity more than
    ``CG_ERROR`` times its size outside it; a single point's radius of gyration beyond
    ``GYRATION_LIMIT`` times the robot's reach. The message, or None. A massless link with its
    mass at one of its points (``mass_at``: no izz) has no outline to hold that point to, as in
    the description."""
    if f"izz_{body}" not in values:
        return None
    ratio, size, off, yardstick = _cg_outside(values, body, bodies)
    if ratio > CG_ERROR:
        cg = [n for n in (f"cgx_{body}", f"cgy_{body}") if n in values] or [f"cgx_{body}"]
        cg = [n for n in cg if n in changed] or cg  # the one the user moved, where known
        return (_cg_message(cg, ratio, size, off, yardstick) + " If the mass is really "
                "there, give the body a point there")
    m, izz = values.get(f"m_{body}"), values[f"izz_{body}"]
    if m is None or not m > 0 or not izz >= 0:
        return None
    if _extent(values, body, bodies) >= CLOSURE_TOLERANCE_M:
        return None
    reach, radius = _reach(values, bodies), math.sqrt(izz / m)
    if reach < CLOSURE_TOLERANCE_M or radius <= GYRATION_LIMIT * reach:
        return None
    return (f"parameter izz_{body} = {izz:.6g} kg*m^2 with m_{body} = {m:.6g} kg gives a radius "
            f"of gyration of {radius * 1e3:.4g} mm to a body of a single point in a robot that "
            f"reaches {reach * 1e3:.4g} mm (more than {GYRATION_LIMIT:g} times); a unit or "
            "decimal-point slip?")


def _extent(values: dict[str, float], body: str, bodies: tuple[str, ...]) -> float:
    """Largest distance (m) from the body's centre of gravity to its known points."""
    cg = (values.get(f"cgx_{body}", 0.0), values.get(f"cgy_{body}", 0.0))
    return max(math.dist(cg, xy) for xy in _points(values, body, bodies).values())


def _points(values: dict[str, float], body: str, bodies: tuple[str, ...]
            ) -> dict[str, tuple[float, float]]:
    """The body's known points (m, body frame), the frame origin among them."""
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
    return points


def _reach(values: dict[str, float], bodies: tuple[str, ...]) -> float:
    """The robot's reach (m): the sum of its bodies' sizes, the description's bound of the
    span of a robot given by its joints' angles; a single-point body's yardstick."""
    return sum(diameter(_points(values, b, bodies))[0] for b in bodies)


def _cg_outside(values: dict[str, float], body: str, bodies: tuple[str, ...]
                ) -> tuple[float, float, float, str]:
    """(how many times its yardstick the centre of gravity lies outside the outline of the
    body's points, the yardstick (m), the distance (m), what the yardstick is)."""
    pts = _points(values, body, bodies)
    cg = (values.get(f"cgx_{body}", 0.0), values.get(f"cgy_{body}", 0.0))
    size, yardstick = diameter(pts)[0], "the body's size"
    if size < CLOSURE_TOLERANCE_M:
        size, yardstick = _reach(values, bodies), "the robot's reach (the body has one point)"
        if size < CLOSURE_TOLERANCE_M:
            return 0.0, size, 0.0, yardstick
    off = outside_hull(cg, list(pts.values()))
    return off / size, size, off, yardstick


def _cg_names(body: str, names, bodies: tuple[str, ...]) -> list[str]:
    """The parameters among ``names`` that place the body's centre of gravity or points."""
    own = (f"cgx_{body}", f"cgy_{body}", f"px_{body}_", f"py_{body}_")
    longer = [b for b in bodies if b != body and b.startswith(f"{body}_")]
    return [n for n in names if n.startswith(own) and not any(
        n.startswith((f"px_{b}_", f"py_{b}_")) for b in longer)]


def _cg_message(names: list[str], ratio: float, size: float, off: float, yardstick: str
                ) -> str:
    which = (f"parameter {names[0]} puts" if len(names) == 1
             else f"parameters {', '.join(names)} put")
    return (f"{which} the centre of gravity {off * 1e3:.4g} mm outside the outline of the body's "
            f"points, {ratio:.3g} times {yardstick} of {size * 1e3:.4g} mm (a warning beyond "
            f"{CG_WARN:g} times, an error beyond {CG_ERROR:g}): is cg in another unit or frame?")


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
    return bad | _outline_columns(names, P, bodies)


def _outline_columns(names: list[str], P, bodies: tuple[str, ...]):
    """``_outline`` of every row of ``P``, evaluated once per distinct row of the columns it
    reads (a grid sweep has a few; a random sweep of lengths pays some 20 us a design)."""
    import numpy as np

    keep = [k for k, n in enumerate(names) if n.startswith(("cgx_", "cgy_", "px_", "py_",
                                                             "m_", "izz_"))]
    if not keep or not bodies:
        return np.zeros(len(P), dtype=bool)
    rows, inverse = np.unique(P[:, keep], axis=0, return_inverse=True)
    sub = [names[k] for k in keep]
    with np.errstate(all="ignore"):
        found = np.array([any(_outline(dict(zip(sub, map(float, row))), b, bodies) is not None
                              for b in bodies) if np.all(np.isfinite(row)) else False
                          for row in rows])
    return found[np.ravel(inverse)]


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
