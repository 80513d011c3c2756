"""Plausibility: values that read cleanly but cannot be what was meant (issue 10, "never silently
wrong"): the robot's span against its length unit, gravity against the planets', a centre of
gravity far outside its body, and display names the equation report could not show.

An error where no real robot could be that odd, a warning (``RuntimeWarning``, naming the file
and the field) where one could; the figures and why are in ``types``. Warnings are shown only
for a description without errors (the errors say what to fix first), once per file and process:
a description is loaded several times per command.
"""

from __future__ import annotations

import functools
import math
import re
import threading
import warnings

from ..units import UNITS
from .fields import Fields, finite
from .types import (
    CG_ERROR,
    CG_WARN,
    CLOSURE_TOLERANCE_M,
    G_HIGH,
    G_LIMIT,
    G_LOW,
    SIZE_LARGE_M,
    SIZE_MAX_M,
    SIZE_MIN_M,
    Body,
)

Point = tuple[float, float]
CG = "'s centre of gravity"  # label of a body's cg among its points

#: (file hash, warning text) already shown in this process
_SHOWN: set[tuple[str, str]] = set()
_LOCK = threading.Lock()


class Plausibility(Fields):
    """The plausibility stage of the validator."""

    #: the robot's span is an error (a unit slip): the size checks of single bodies (radius of
    #: gyration) say nothing more about the same slip
    length_slip: bool = False
    #: the span is doubtful (a warning or an error): a body's mass or inertia against its size
    #: would only repeat the same slip
    span_doubt: bool = False
    #: bodies whose points read in another unit would make their radius of gyration plausible
    #: (an error at their points): a joint or loop they leave open says nothing more
    points_slip: frozenset = frozenset()
    #: an upper bound of the span of the robot's points (m), the yardstick of a single-point
    #: body's cg
    span_m: float = 0.0

    def _span(self, d: dict, pose: str | None, scale: dict[str, float]) -> None:
        """The robot's span against ``units.length``: read from the raw points and centres of
        gravity (before the bodies are built, whose own checks it must know about)."""
        length, unit = scale.get("length"), _unit(d, "length")
        if length is None or pose is None:
            return  # reported already
        groups = _raw_groups(d, length)
        lo, hi = _bounds(groups, pose)
        self.span_m = _bounds([{k: v for k, v in g.items() if not k.endswith(CG)}
                               for g in groups], pose)[1][0]
        exact = pose == "world"
        if 0.0 < hi[0] < SIZE_MIN_M:
            self.length_slip = self.span_doubt = True
            self.err("units.length", f"the robot spans {'' if exact else 'at most '}"
                                     f"{_m(hi[0])}{_between(hi, exact)}: below "
                                     f"{SIZE_MIN_M * 1e3:g} mm the joints' closure tolerance "
                                     f"({CLOSURE_TOLERANCE_M * 1e3:g} mm) cannot tell its points "
                                     f"apart; {_other_units(hi[0], unit)}")
        elif lo[0] > SIZE_LARGE_M:
            say = self.err if lo[0] > SIZE_MAX_M else self.warn
            self.span_doubt = True
            what = ("no planar linkage is a kilometre across" if lo[0] > SIZE_MAX_M else
                    f"a warning above {SIZE_LARGE_M:g} m: only the largest cranes are that big")
            say("units.length", f"the robot spans {'' if exact else 'at least '}{_m(lo[0])}"
                                f"{_between(lo, exact)} ({what}); {_other_units(lo[0], unit)}")

    def _gravity_plausible(self, gravity: Point, d: dict) -> None:
        """Gravity's magnitude against the planets' (0 is a horizontal robot)."""
        g = math.hypot(*gravity)
        unit = _unit(d, "acceleration")
        if g == 0.0 or not isinstance(unit, str) or unit not in UNITS["acceleration"]:
            return
        hint = _gravity_units(g, unit)
        power = _earth_power(g)
        if power and G_LOW <= g <= G_HIGH:  # 0.981 from -981 typed in mm/s^2 (cm/s^2 meant)
            self.warn("gravity", f"magnitude {g:.4g} m/s^2 is Earth's 9.81 m/s^2 times "
                                 f"1e{power:+d}: a unit or decimal slip? (cm/s^2 typed as "
                                 "mm/s^2 gives this: give gravity in m/s^2; a robot on a tilted "
                                 "table feels g sin(tilt), which may be anything: then ignore "
                                 "this)")
        elif g > G_LIMIT:
            self.err("gravity", f"magnitude {g:.4g} m/s^2 is above {G_LIMIT:g} m/s^2 (the Sun's "
                                f"surface gives 274; run-time parameters are refused beyond it "
                                f"too); {hint}")
        elif g > G_HIGH:
            self.warn("gravity", f"magnitude {g:.4g} m/s^2 is more than any planet's (Jupiter: "
                                 f"24.8; a warning above {G_HIGH:g} m/s^2); {hint}")
        elif g < G_LOW:
            self.warn("gravity", f"magnitude {g:.4g} m/s^2 is less than any planet's (Pluto: "
                                 f"0.62; a warning below {G_LOW:g} m/s^2; gravity = [0, 0] says a "
                                 f"horizontal robot); {hint}")

    def _cg_plausible(self, f: str, body: Body, cg_from: str | None, pose: str | None) -> bool:
        """The centre of gravity against the outline of the body's points; True when that is an
        error (the body's extent, measured from its cg, then says nothing more)."""
        pts = list(body.points_m.values())
        size = diameter(dict(enumerate(pts)))[0]
        yardstick = "the body's size"
        if size < CLOSURE_TOLERANCE_M:  # a single point (a motor, a bob): the robot's span
            size, yardstick = self.span_m, "the robot's span (the body has a single point)"
            if size < CLOSURE_TOLERANCE_M:
                return False
        out = outside_hull(body.cg_m, pts)
        ratio = out / size
        if ratio <= CG_WARN:
            return False
        if pose == "world":
            where = ("from the world origin" if cg_from == "world"
                     else f"from cg_from = {cg_from!r} in world axes")
        else:
            where = (f"from cg_from = {cg_from!r}" if cg_from else "from the origin") + \
                " in the body's own coordinates"
        say = self.err if ratio > CG_ERROR else self.warn
        say(f"{f}.cg", f"the centre of gravity lies {_m(out)} outside the outline of the body's "
                       f"points, {ratio:.3g} times {yardstick} of {_m(size)} (a warning beyond "
                       f"{CG_WARN:g} times, an error beyond {CG_ERROR:g}); cg is measured "
                       f"{where}: does cg_from name the wrong point, or is cg in world "
                       "coordinates or another unit? If the mass is really there, give the body "
                       "a point there")
        return ratio > CG_ERROR

    def _symbols_plausible(self, display: dict[str, str]) -> None:
        """Every display name shows something in the report: not empty, valid LaTeX."""
        if not display:
            return
        for key, shown in display.items():
            fld = f"symbols.{key}"
            if not shown.strip():
                self.err(fld, f"display name {shown!r} of parameter {key} is empty: the "
                              "equations would show nothing for it")
            elif "$" in shown:
                self.err(fld, f"display name {shown!r} of parameter {key} contains '$': write "
                              "it without math delimiters (the report adds them)")
            elif (reason := _latex_problem(shown)) is not None:
                self.err(fld, f"display name {shown!r} of parameter {key} is not valid LaTeX "
                              f"({reason}): the equation report would lose the symbol")

    def _show_warnings(self) -> None:
        """Each warning once per file (hash) and process."""
        for text in self.warnings:
            with _LOCK:
                if (self.sha, text) in _SHOWN:
                    continue
                _SHOWN.add((self.sha, text))
            warnings.warn(text, RuntimeWarning, stacklevel=4)


def _unit(d: dict, quantity: str):
    units = d.get("units")
    return units.get(quantity) if isinstance(units, dict) else None


# -- geometry -------------------------------------------------------------------------------------

def _pair(v, unit: float) -> Point | None:
    """[x, y] in SI, or None for anything else (reported by the field checks)."""
    if (isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float))
                                                     and not isinstance(x, bool) for x in v)
            and all(finite(x) for x in v)):
        return (float(v[0]) * unit, float(v[1]) * unit)
    return None


def _raw_groups(d: dict, length: float) -> list[dict[str, Point]]:
    """Points (and centres of gravity) of the ground and of each body as typed, in m, labelled
    ``body.point``; whatever is malformed is left out (reported by the field checks)."""
    groups = []
    ground = d.get("ground")
    raw = ground.get("points") if isinstance(ground, dict) else None
    if isinstance(raw, dict):
        groups.append({f"ground.{n}": xy for n, v in raw.items() if (xy := _pair(v, length))})
    bodies = d.get("bodies")
    for i, b in enumerate(bodies if isinstance(bodies, list) else []):
        if not isinstance(b, dict):
            continue
        name = b["name"] if isinstance(b.get("name"), str) else f"bodies[{i}]"
        raw = b.get("points")
        pts = ({n: xy for n, v in raw.items() if (xy := _pair(v, length))}
               if isinstance(raw, dict) else {})
        group = {f"{name}.{n}": xy for n, xy in pts.items()}
        cg, origin = _pair(b.get("cg"), length), b.get("cg_from")
        base = pts.get(origin) if isinstance(origin, str) and origin != "world" else (0.0, 0.0)
        if cg is not None and base is not None:
            group[f"{name}{CG}"] = (base[0] + cg[0], base[1] + cg[1])
        groups.append(group)
    return groups


def _bounds(groups: list[dict[str, Point]], pose: str):
    """(lower, upper) bound of the robot's span, each (m, label, label): with pose = "world"
    one frame, the span itself; with "joints" each body in its own coordinates, the largest body
    and the chain of all of them."""
    if pose == "world":
        span = diameter({k: v for g in groups for k, v in g.items()})
        return span, span
    return (max((diameter(g) for g in groups), default=(0.0, "", "")),
            (sum(diameter(g)[0] for g in groups), "", ""))


def diameter(pts: dict) -> tuple[float, str, str]:
    """(largest distance between two of ``pts``, their labels)."""
    best = (0.0, "", "")
    items = list(pts.items())
    for k, (a, pa) in enumerate(items):
        for b, pb in items[k + 1:]:
            dist = math.dist(pa, pb)
            if dist > best[0]:
                best = (dist, str(a), str(b))
    return best


def _cross(o: Point, a: Point, b: Point) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _hull(pts: list[Point]) -> list[Point]:
    """Convex hull, counter-clockwise (Andrew's monotone chain); collinear points: the ends."""
    pts = sorted(set(pts))
    if len(pts) <= 2:
        return pts

    def half(seq):
        out: list[Point] = []
        for q in seq:
            while len(out) >= 2 and _cross(out[-2], out[-1], q) <= 0:
                out.pop()
            out.append(q)
        return out

    return half(pts)[:-1] + half(reversed(pts))[:-1]


def _segment(p: Point, a: Point, b: Point) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
    t = min(1.0, max(0.0, t))
    return math.dist(p, (a[0] + t * dx, a[1] + t * dy))


def outside_hull(p: Point, pts: list[Point]) -> float:
    """Distance from ``p`` to the convex hull of ``pts`` (0 inside)."""
    hull = _hull(pts)
    if len(hull) == 1:
        return math.dist(p, hull[0])
    edges = list(zip(hull, hull[1:] + hull[:1])) if len(hull) > 2 else [(hull[0], hull[1])]
    if len(hull) > 2 and all(_cross(a, b, p) >= 0 for a, b in edges):
        return 0.0
    return min(_segment(p, a, b) for a, b in edges)


# -- messages -------------------------------------------------------------------------------------

def _m(x: float) -> str:
    return f"{x:.4g} m" if x >= 1.0 else f"{x * 1e3:.4g} mm"


def _between(span: tuple[float, str, str], exact: bool) -> str:
    if not span[1]:
        return ""
    return f" (from {span[1]} to {span[2]})" if exact else f" ({span[1]} to {span[2]})"


def _other_units(span: float, unit) -> str:
    """The length units that would make ``span`` plausible."""
    table = UNITS["length"]
    if unit not in table:
        return "a unit slip?"
    alts = [f'"{u}" makes it {_m(span * f / table[unit])}' for u, f in table.items()
            if u != unit and SIZE_MIN_M <= span * f / table[unit] <= SIZE_LARGE_M]
    return (f"were the lengths typed in another unit? (units.length = {', '.join(alts)})"
            if alts else "a unit or decimal-point slip?")


#: Earth's standard gravity (m/s^2): a magnitude that is it times a power of ten is a slip
G_EARTH = 9.80665


def _earth_power(g: float) -> int:
    """k != 0 where ``g`` (m/s^2) is Earth's gravity times 10^k to within 1% (981 is 1e2:
    cm/s^2), else 0."""
    k = round(math.log10(g / G_EARTH))
    return k if k and abs(g / 10.0**k / G_EARTH - 1.0) < 0.01 else 0


def _gravity_units(g: float, unit: str) -> str:
    """How a gravity outside the planets' range may have been meant: a unit that makes it
    Earth's, else Earth's times a power of ten (cm/s^2, which has no name here), else the
    units that bring it into the planets' range."""
    table = UNITS["acceleration"]
    earth = [u for u, f in table.items()
             if u != unit and abs(g * f / table[unit] / G_EARTH - 1.0) < 0.01]
    if earth:
        return (f'typed in another unit? (units.acceleration = "{earth[0]}" makes it '
                f"{g * table[earth[0]] / table[unit]:.4g} m/s^2)")
    if power := _earth_power(g):
        unit_slip = ", or cm/s^2 (no unit here: give it in m/s^2)" if power == 2 else ""
        return f"it is Earth's 9.81 m/s^2 times 1e{power:+d}: a decimal slip{unit_slip}?"
    alts = [f'units.acceleration = "{u}" makes it {g * f / table[unit]:.4g} m/s^2'
            for u, f in table.items() if u != unit and G_LOW <= g * f / table[unit] <= G_HIGH]
    return f"typed in another unit? ({', '.join(alts)})" if alts else "a unit or decimal slip?"


# -- LaTeX ----------------------------------------------------------------------------------------

@functools.lru_cache(maxsize=1024)
def _latex_problem(shown: str) -> str | None:
    """Why the display name ``shown`` would not show in the report, or None (fine, or no
    matplotlib to ask).

    matplotlib's mathtext parses a subset of LaTeX that holds everything a symbol name needs
    (Greek letters, sub- and superscripts, \\mathrm, \\text, accents); imported only here, for a
    description with a [symbols] table. Answers are kept: a description is validated several
    times per command, and parsing its names each time cost about 18 ms per load.
    """
    parser = _parser()
    if parser is None:
        return None
    try:
        out = parser.parse(f"${shown}$")
    except ValueError as exc:
        return _reason(str(exc))
    if not out.glyphs and not out.rects:
        return "it shows nothing"
    return None


@functools.lru_cache(maxsize=1)
def _parser():
    try:
        from matplotlib.mathtext import MathTextParser
    except ImportError:  # a hard dependency; without it, only the checks above
        return None
    return MathTextParser("path")


def _reason(text: str) -> str:
    """mathtext's message without the echo of the input and the character position."""
    last = text.strip().splitlines()[-1] if text.strip() else "mathtext refused it"
    last = re.sub(r"^\w*(Exception|Error): ", "", last)
    last = re.sub(r"\s*\(at char \d+\).*$", "", last)
    return re.sub(r", found '.*'$", "", last).strip() or "mathtext refused it"
