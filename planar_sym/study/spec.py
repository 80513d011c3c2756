"""Study files: everything one run needs, as data (TOML), read and checked all at once.

.. code:: toml

    title = "5-bar Type I, P 30 mm diagonally in 1.5 s"
    robot = "five_bar_type1"       # built-in name, a description file (.toml) or a generated folder
    kind = "inverse"               # "inverse": torques along a motion; "forward": simulate;
                                   # "control": track the motion under a controller
                                   # ([control], [events]: see study/control_spec.py);
                                   # "optimal": the best move between two states
                                   # ([optimal]: see study/optimal_spec.py), run, or
                                   # tracked under its [control] law

    [units]                        # of this file's numbers; default m and rad (time is in s)
    length = "mm"
    angle = "deg"

    [parameters]                   # overrides: a number in the description's units, or "0.5 kg"
    m_L_Link1 = 0.5

    [constants]                    # optional: names for the expressions below
    side = 30.0

    [motion]                       # kind = "inverse"
    space = "task"                 # "task" (x, y[, phi]) or "joint" (every joint of a tree,
                                   # the actuated joints of a closed chain)
    profile = "cubic"              # cubic | quintic | trapezoid | via | table
    start = [60.852, 154.665]
    by = ["side", "side"]          # or end = [...]; any number may be an expression
    duration = 1.5                 # s
    samples = 201

    [simulation]                   # kind = "forward"
    q0 = [-60.0, 0.0]              # every coordinate
    duration = 1.0
    torque = "zero"                # "zero", a constant [...] (N*m), a CSV of t_s, tau<k>_n_m
                                   # { file = "t.csv", interpolation = "linear" }, or a profile
                                   # { profile = "cubic", start = [...], end = [...], duration }

    [optimise]                     # kind = "inverse": time the motion's path as fast as
    torque_limit = [0.5, 0.1]      # these N*m (N) per motor allow (default: the description's
                                   # torque_limit), rest to rest; speed_limit = [...] per
                                   # coordinate in the file's units per s (optional)

    [outputs]
    csv = true                     # and plot, split, animation ("gif" / "mp4"), frames

Paths (a description file, a table) are relative to the study file. Every problem is reported
at once, naming the file, the field and the value; nothing is run then.

Every number may be typed as an expression in a string (``"30*cos(45*deg)"``, ``"side/2"``;
the rules: ``planar_sym.expressions``), at the places ``NUMBERS`` names; a ``[parameters]`` or
``[control.plant]`` string is an expression optionally followed by its unit (``"2*0.3 kg"``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

from ..expressions import ExpressionError, quantity
from ..model.units import factor
from .checks import Checker, StudyError, finite
from .control_spec import (
    CONTROL_INTEGERS,
    ControlSpec,
    EventsSpec,
    TorqueInput,
    parse_control,
    parse_events,
    parse_torque,
)
from .optimal_spec import OPTIMAL_INTEGERS, OptimalSpec, parse_optimal

KINDS = ("inverse", "forward", "control", "optimal")
#: ``motion.space``: task coordinates (x, y[, phi]) or joint coordinates
SPACES = ("task", "joint")
PROFILES = ("cubic", "quintic", "trapezoid", "via", "table")
SOLVERS = ("auto", "seed", "newton")
METHODS = ("dopri5", "cvodes", "idas", "DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
ANIMATIONS = ("gif", "mp4")
#: bounds that keep a typo from asking for a huge or empty run
MAX_SAMPLES = 1_000_000
MAX_DURATION_S = 1e6
MAX_FRAMES = 2000
#: where a study takes integers: (default, lowest, highest), as ``NUMBERS`` is laid out
INTEGERS = {
    "motion": {"samples": (201, 2, MAX_SAMPLES)},
    "simulation": {"samples": (1001, 2, MAX_SAMPLES)},
    "outputs": {"frames": (60, 2, MAX_FRAMES)},
    "control": CONTROL_INTEGERS,
    "optimal": OPTIMAL_INTEGERS,
}

_TOP = {"title", "robot", "kind", "units", "parameters", "motion", "simulation", "outputs", "notes",
        "control", "events", "optimise", "optimal", "constants"}
_OPTIMISE = {"torque_limit", "speed_limit"}
_UNITS = {"length", "angle"}
_MOTION = {"space", "profile", "start", "by", "end", "duration", "samples", "v_max", "a_max",
           "times", "points", "file", "ik", "start_pose"}
_SIMULATION = {"q0", "qd0", "duration", "samples", "torque", "method", "rtol", "atol"}
_OUTPUTS = {"csv", "plot", "split", "animation", "frames"}
#: a torque input: a list of constants or a profile table (a string, "zero", is no number)
_TORQUE = (1, {"start": 1, "end": 1, "duration": 0})
#: where a study takes numbers, for ``expressions.numbers``: 0 a number, 1 a list of numbers, 2
#: a list of such lists, a tuple either; a string there is an expression. Integers (samples,
#: frames) are not numbers here; [parameters] and [control.plant] are read by ``parameters``.
NUMBERS = {
    "motion": {"start": 1, "by": 1, "end": 1, "duration": 0, "v_max": 1, "a_max": 1,
               "times": 1, "points": 2, "start_pose": 1},
    "simulation": {"q0": 1, "qd0": 1, "duration": 0, "rtol": 0, "atol": 0, "torque": _TORQUE},
    "control": {"kp": (0, 1), "kd": (0, 1), "natural_frequency_hz": 0, "damping": 0,
                "duration": 0, "start_error": 1, "rtol": 0, "atol": 0, "torque": _TORQUE,
                "q_weight": (0, 1), "r_weight": (0, 1)},
    "events": {"joint_limits": {"*": 1}},
    "optimise": {"torque_limit": 1, "speed_limit": 1},
    "optimal": {"start": 1, "end": 1, "duration": 0, "torque_limit": 1, "speed_limit": 1},
}


@dataclass(frozen=True)
class Motion:
    """The move of an inverse-dynamics study, in the file's units (converted when run)."""

    space: str
    profile: str
    start: tuple[float, ...] = ()
    by: tuple[float, ...] | None = None
    end: tuple[float, ...] | None = None
    duration_s: float | None = None
    samples: int = 201
    v_max: tuple[float, ...] | None = None
    a_max: tuple[float, ...] | None = None
    times_s: tuple[float, ...] | None = None
    points: tuple[tuple[float, ...], ...] | None = None
    table: Path | None = None
    ik: str = "auto"
    start_pose: tuple[float, ...] | None = None


@dataclass(frozen=True)
class Simulation:
    """The run of a forward-dynamics study, in the file's units."""

    q0: tuple[float, ...]
    duration_s: float
    qd0: tuple[float, ...] | None = None
    samples: int = 1001
    torque: TorqueInput | None = None
    method: str = "dopri5"
    rtol: float = 1e-11
    atol: float = 1e-12


@dataclass(frozen=True)
class Optimise:
    """Time the motion's path as fast as the limits allow (``planar_sym.time_optimal``):
    torque limits in N*m (N at a slider) per motor, None for the description's; speed limits
    per coordinate in the file's units per s, None for none."""

    torque_limit: tuple[float, ...] | None = None
    speed_limit: tuple[float, ...] | None = None


@dataclass(frozen=True)
class Outputs:
    csv: bool = True
    plot: bool = True
    split: bool = False
    animation: str | None = None
    frames: int = 60


@dataclass(frozen=True)
class Study:
    """One study: a robot, its parameter overrides, and a motion (or a simulation)."""

    name: str
    title: str
    robot: str  # a built-in name, or an absolute path (description file or generated folder)
    kind: str  # "inverse" or "forward"
    length_unit: str = "m"
    angle_unit: str = "rad"
    parameters: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    motion: Motion | None = None
    simulation: Simulation | None = None
    outputs: Outputs = Outputs()
    path: Path | None = None
    control: ControlSpec | None = None
    events: EventsSpec | None = None
    optimise: Optimise | None = None
    optimal: OptimalSpec | None = None

    @property
    def length_si(self) -> float:
        return factor("length", self.length_unit)

    @property
    def angle_si(self) -> float:
        return factor("angle", self.angle_unit)


def load(path: str | Path) -> Study:
    """Read and check a study file; raises StudyError listing every problem."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise StudyError([f"{path}: cannot read ({exc.strerror})"]) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise StudyError([f"{path}: not valid TOML: {exc}"]) from None
    return parse(data, path.stem, path)


def parse(data: dict, name: str, path: Path | None = None) -> Study:
    """A Study from a TOML table (``path`` names the file in messages and anchors paths)."""
    c = _Checker(path)
    c.keys(data, _TOP, "")
    data = c.expressions(data, NUMBERS)
    robot = c.string(data, "robot", "robot")
    kind = c.choice(data, "kind", "kind", KINDS)
    units = c.table(data, "units")
    c.keys(units, _UNITS, "units.")
    length = c.unit(units, "length", "m")
    angle = c.unit(units, "angle", "rad")
    params = c.parameters(c.table(data, "parameters"))
    motion = sim = control = events = optimal = None
    if kind == "optimal":
        optimal = parse_optimal(c, c.table(data, "optimal", required=True))
        for key, what in (("motion", "the move is what it finds"),
                          ("simulation", "it finds a move")):
            if key in data:
                c.err(key, f"not for kind = \"optimal\" ({what}: see [optimal])")
    elif "optimal" in data and kind is not None:
        c.err("optimal", f"only for kind = \"optimal\" (this study is \"{kind}\")")
    if kind in ("inverse", "control"):
        motion = c.motion(c.table(data, "motion", required=True))
        if "simulation" in data:
            c.err("simulation", f"only for kind = \"forward\" (this study is \"{kind}\")")
    elif kind == "forward":
        sim = c.simulation(c.table(data, "simulation", required=True))
        if "motion" in data:
            c.err("motion", "only for kind = \"inverse\" or \"control\" (this study is "
                            "\"forward\")")
    if kind == "control" or (kind == "optimal" and "control" in data):
        control = parse_control(c, c.table(data, "control", required=True), c.parameters)
        events = parse_events(c, c.table(data, "events"))
    elif kind is not None:
        for key in ("control", "events"):
            if key in data:
                c.err(key, f"only for kind = \"control\" or \"optimal\" (this study is "
                           f"\"{kind}\")")
    optimise = None
    if "optimise" in data:
        if kind == "inverse":
            optimise = c.optimise(c.table(data, "optimise"))
        elif kind is not None:
            c.err("optimise", f"only for kind = \"inverse\" (this study is \"{kind}\")")
    outputs = c.outputs(c.table(data, "outputs"))
    title = data.get("title", name)
    if not isinstance(title, str):
        c.err("title", f"must be a string (got {title!r})")
    c.done()
    return Study(name, str(title), c.robot_ref(robot), kind, length, angle, params, motion, sim,
                 outputs, path, control, events, optimise, optimal)


class _Checker(Checker):
    """The sections of a study file."""

    def robot_ref(self, robot: str | None) -> str:
        """A built-in name stays a name; a path is made absolute against the study file."""
        if robot is None or ("/" not in robot and not robot.endswith(".toml")):
            return robot or ""
        return str((self.base / robot).resolve())

    def parameters(self, tbl: dict, section: str = "parameters"
                   ) -> dict[str, tuple[float, str | None]]:
        out = {}
        for name, v in tbl.items():
            fld = f"{section}.{name}"
            if isinstance(v, str):  # "0.5 kg", "2*0.3 kg", "m1/2": the unit is checked later
                try:
                    out[name] = quantity(v, self.names)
                except ExpressionError as exc:
                    self.err(fld, str(exc))
                    continue
            elif isinstance(v, (int, float)) and not isinstance(v, bool):
                out[name] = (float(v), None)
            else:
                self.err(fld, f"must be a number, or a number and a unit such as \"0.5 kg\" "
                              f"(got {v!r})")
                continue
            if not finite(out[name][0]):
                self.err(fld, f"must be finite (got {v!r})")
                del out[name]
        return out

    def motion(self, m: dict) -> Motion | None:
        self.keys(m, _MOTION, "motion.")
        space = self.choice(m, "space", "motion.space", SPACES)
        profile = self.choice(m, "profile", "motion.profile", PROFILES, "cubic")
        ik = self.choice(m, "ik", "motion.ik", SOLVERS, "auto")
        samples = self.integer(m, "samples", "motion.samples", *INTEGERS["motion"]["samples"])
        start_pose = self.vector(m, "start_pose", "motion.start_pose")
        if space == "joint" and "ik" in m:
            self.err("motion.ik", "only for space = \"task\" (a joint-space motion needs no "
                                  "inverse kinematics)")
        kw: dict = {}
        shape = profile or ("via" if "points" in m else "table" if "file" in m else "cubic")
        if shape in ("cubic", "quintic", "trapezoid"):  # (an unknown profile: checked as cubic)
            kw["start"] = self.vector(m, "start", "motion.start", required=True) or ()
            by, end = self.vector(m, "by", "motion.by"), self.vector(m, "end", "motion.end")
            if (by is None) == (end is None) and "by" not in m and "end" not in m:
                self.err("motion", "give the displacement `by = [...]` or the end `end = [...]`")
            elif "by" in m and "end" in m:
                self.err("motion", "give `by` or `end`, not both")
            for key, vec in (("by", by), ("end", end)):
                if vec is not None and kw["start"] and len(vec) != len(kw["start"]):
                    self.err(f"motion.{key}", f"must have {len(kw['start'])} values like "
                                              f"motion.start (got {len(vec)})")
            kw.update(by=by, end=end)
            if shape == "trapezoid":
                kw["v_max"] = self.vector(m, "v_max", "motion.v_max", required=True)
                kw["a_max"] = self.vector(m, "a_max", "motion.a_max", required=True)
                for key in ("v_max", "a_max"):
                    if kw[key] is not None and min(kw[key]) <= 0:
                        self.err(f"motion.{key}", f"must be > 0 (got {list(kw[key])})")
                if "duration" in m:
                    kw["duration_s"] = self.number(m, "duration", "motion.duration",
                                                   positive=True, limit=MAX_DURATION_S)
            else:
                kw["duration_s"] = self.number(m, "duration", "motion.duration", positive=True,
                                               limit=MAX_DURATION_S)
        elif shape == "via":
            kw.update(self._via(m))
        elif shape == "table":
            if "file" not in m:
                self.err("motion.file", "missing: a CSV of t_s and the coordinates")
            else:
                kw["table"] = self.file(m["file"], "motion.file")
        if shape != "table" and "file" in m:
            self.err("motion.file", "only for profile = \"table\"")
        if None in (space, profile, ik):
            return None
        return Motion(space, profile, samples=samples, ik=ik, start_pose=start_pose, **kw)

    def _via(self, m: dict) -> dict:
        times = self.vector(m, "times", "motion.times", required=True)
        raw = m.get("points")
        points = None
        if not isinstance(raw, list) or not raw or not all(isinstance(p, list) for p in raw):
            self.err("motion.points", f"must be a list of points [[...], [...]] (got {raw!r:.80})")
        else:
            rows = [self.vector({"p": p}, "p", f"motion.points[{i}]") for i, p in enumerate(raw)]
            if all(r is not None for r in rows):
                if len({len(r) for r in rows}) != 1:
                    self.err("motion.points", "every point must have the same number of values")
                else:
                    points = tuple(rows)
        if times is not None:
            if any(b <= a for a, b in pairwise(times)) or times[0] != 0.0:
                self.err("motion.times", f"must start at 0 and increase (got {list(times)})")
            elif times[-1] > MAX_DURATION_S:
                self.err("motion.times", f"must end by {MAX_DURATION_S:g} s")
            if points is not None and len(points) != len(times):
                self.err("motion.points", f"{len(points)} points for {len(times)} times")
            if len(times) < 2:
                self.err("motion.times", "needs at least 2 via points")
        for key in ("start", "by", "end", "duration"):
            if key in m:
                self.err(f"motion.{key}", "not used by profile = \"via\" (the points and times "
                                          "give the motion)")
        return {"times_s": times, "points": points}

    def simulation(self, s: dict) -> Simulation | None:
        self.keys(s, _SIMULATION, "simulation.")
        q0 = self.vector(s, "q0", "simulation.q0", required=True)
        qd0 = self.vector(s, "qd0", "simulation.qd0")
        duration = self.number(s, "duration", "simulation.duration", positive=True,
                               limit=MAX_DURATION_S)
        samples = self.integer(s, "samples", "simulation.samples",
                               *INTEGERS["simulation"]["samples"])
        method = self.choice(s, "method", "simulation.method", METHODS, "dopri5")
        rtol = self.number(s, "rtol", "simulation.rtol", positive=True, default=1e-11)
        atol = self.number(s, "atol", "simulation.atol", positive=True, default=1e-12)
        torque = parse_torque(self, s.get("torque"), "simulation.torque")
        if q0 is not None and qd0 is not None and len(qd0) != len(q0):
            self.err("simulation.qd0", f"must have {len(q0)} values like simulation.q0 "
                                       f"(got {len(qd0)})")
        if None in (q0, duration, method, rtol, atol):
            return None
        return Simulation(q0, duration, qd0, samples, torque, method, rtol, atol)

    def optimise(self, o: dict) -> Optimise:
        self.keys(o, _OPTIMISE, "optimise.")
        limits = {}
        for key in sorted(_OPTIMISE):
            v = self.vector(o, key, f"optimise.{key}")
            if v is not None and not all(x > 0 for x in v):
                self.err(f"optimise.{key}", f"must be positive (got {list(v)})")
            limits[key] = v
        return Optimise(**limits)

    def outputs(self, o: dict) -> Outputs:
        self.keys(o, _OUTPUTS, "outputs.")
        anim = o.get("animation", False)
        if anim is True:
            anim = "gif"
        if anim is not False and anim not in ANIMATIONS:
            self.err("outputs.animation", f"must be false, true, \"gif\" or \"mp4\" (got {anim!r})")
            anim = False
        return Outputs(self.flag(o, "csv", "outputs.csv", True),
                       self.flag(o, "plot", "outputs.plot", True),
                       self.flag(o, "split", "outputs.split", False),
                       anim or None,
                       self.integer(o, "frames", "outputs.frames", *INTEGERS["outputs"]["frames"]))
