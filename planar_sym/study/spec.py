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

Here the file is read (``load``, ``parse``); beside it are the tables of what it may hold
(``spec_tables``), the typed study (``spec_types``) and the reader of each section
(``spec_sections``).
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

from .checks import StudyError
from .control_spec import parse_control, parse_events
from .optimal_spec import parse_optimal
from .spec_sections import StudyChecker
from .spec_tables import (
    _MOTION,
    _OPTIMISE,
    _OUTPUTS,
    _SIMULATION,
    _TOP,
    _TORQUE,
    _UNITS,
    ANIMATIONS,
    INTEGERS,
    KINDS,
    MAX_DURATION_S,
    MAX_FRAMES,
    MAX_SAMPLES,
    METHODS,
    NUMBERS,
    PROFILES,
    SOLVERS,
    SPACES,
)
from .spec_types import Motion, Optimise, Outputs, Simulation, Study

# the tables and types live beside this module; they are named here too, where they used to
# be defined, so ``spec.NUMBERS`` or ``spec.Study`` keep working
__all__ = ["ANIMATIONS", "INTEGERS", "KINDS", "MAX_DURATION_S", "MAX_FRAMES", "MAX_SAMPLES",
           "METHODS", "NUMBERS", "PROFILES", "SOLVERS", "SPACES", "_MOTION", "_OPTIMISE",
           "_OUTPUTS", "_SIMULATION", "_TOP", "_TORQUE", "_UNITS", "Motion", "Optimise",
           "Outputs", "Simulation", "Study", "load", "parse"]


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
    data = copy.deepcopy(data)  # a misspelt key is moved to the key it nearly is (Checker.keys)
    c = StudyChecker(path)
    if "robot" not in data and {"bodies", "joints"} & set(data):  # one message, not ten
        where = f"{path}: " if path is not None else ""
        raise StudyError([(f"{where}a robot description, not a study: a study names its robot "
                           "(robot = \"<this file>\") and says what to do with it (kind, "
                           "[motion]...); `planar-sym move` runs one move of a robot without a "
                           "study")])
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
