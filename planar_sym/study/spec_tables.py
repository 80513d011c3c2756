"""What a study file may hold: its kinds, its sections' keys and choices, the bounds of a run,
and where it takes integers (``INTEGERS``) and numbers (``NUMBERS``).

One table each, read by the study reader (``spec``, ``spec_sections``) and by the JSON Schema
built from them (``schema_study``), so the two cannot drift apart.
"""

from __future__ import annotations

from .control_spec import CONTROL_INTEGERS
from .optimal_spec import OPTIMAL_INTEGERS

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
