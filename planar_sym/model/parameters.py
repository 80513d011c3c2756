"""Physical checks of a parameter vector changed at run time (``Robot.with_parameters``, a
study's ``[parameters]``), the same rules the description's own values pass at derive time.

Rules, with their figures:

* every value finite; masses > 0; inertias >= 0 (a body with extent needs > 0);
* a radius of gyration sqrt(izz / m) at most ``GYRATION_LIMIT`` (3) times the body's extent,
  the largest distance from its centre of gravity to its points (as in the description; here
  the points the equations use and the frame origin, which is always one of its points);
* gravity magnitude ``g`` from 0 to ``G_LIMIT`` = 300 m/s^2 (the Sun's surface gives 274;
  more is a unit slip such as mm/s^2 read as m/s^2), the bound the description's gravity has;
* the drive train, as ``[joints.actuator]`` is checked (``ACTUATOR_RULES``): gear ratios and
  Coulomb smoothing speeds > 0; rotor inertias, viscous and Coulomb friction >= 0.
"""

from __future__ import annotations

import math

from .description import CLOSURE_TOLERANCE_M, G_LIMIT, GYRATION_LIMIT

#: parameter prefix -> (strictly positive?, what it is, unit): the rules of [joints.actuator]
ACTUATOR_RULES = {
    "gear_": (True, "gear ratio", "(motor rad per joint rad, or per m)"),
    "vs_": (True, "Coulomb smoothing speed", "rad/s (m/s)"),
    "jm_": (False, "rotor inertia", "kg*m^2"),
    "fv_": (False, "viscous friction", "N*m*s/rad (N*s/m)"),
    "fc_": (False, "Coulomb friction", "N*m (N)"),
}


def _actuator_problem(name: str, v: float) -> str | None:
    for prefix, (positive, what, unit) in ACTUATOR_RULES.items():
        if name.startswith(prefix) and ((positive and not v > 0) or v < 0):
            return (f"parameter {name} ({what}) must be {'> 0' if positive else '>= 0'} {unit} "
                    f"(got {v:.6g})")
    return None


def problems(values: dict[str, float], bodies: tuple[str, ...]) -> list[str]:
    """Every physical problem of ``values`` (name -> SI value), one message each."""
    out = []
    for name, v in values.items():
        if not math.isfinite(v):
            out.append(f"parameter {name} must be finite (got {v!r})")
    if out:
        return out
    g = values.get("g")
    if g is not None and not 0.0 <= g <= G_LIMIT:
        out.append(f"parameter g must be from 0 to {G_LIMIT:g} m/s^2 (got {g:.6g}); a unit slip?")
    out += [msg for name, v in values.items() if (msg := _actuator_problem(name, v))]
    for body in bodies:
        m, izz = values.get(f"m_{body}"), values.get(f"izz_{body}")
        if m is not None and not m > 0:
            out.append(f"parameter m_{body} must be > 0 kg (got {m:.6g})")
            continue
        if izz is not None and izz < 0:
            out.append(f"parameter izz_{body} must be >= 0 kg*m^2 (got {izz:.6g})")
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


def failing(names: list[str], P, bodies: tuple[str, ...]):
    """Which rows of ``P`` (designs, parameters in ``names`` order, SI) break a rule of
    ``problems``: the same rules, evaluated on whole columns at once (a sweep checks 10^5
    designs in milliseconds); ``problems`` then words the message for a failing row."""
    import numpy as np

    P = np.asarray(P, dtype=float)
    col = {n: P[:, k] for k, n in enumerate(names)}
    bad = ~np.all(np.isfinite(P), axis=1)
    if "g" in col:
        bad |= ~((col["g"] >= 0.0) & (col["g"] <= G_LIMIT))
    for name, v in col.items():
        for prefix, (positive, _, _) in ACTUATOR_RULES.items():
            if name.startswith(prefix):
                bad |= ~(v > 0) if positive else v < 0
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
