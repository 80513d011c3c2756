"""The JSON Schema of a study file, built from the study validators' own tables (``spec``,
``control_spec``, ``optimal_spec``) with one described entry per key (``schema_parts``).

The tables are read through the ``spec`` module at each build, so the schema follows what
``spec`` holds then.
"""

from __future__ import annotations

from ..model.units import SI, UNITS
from ..optimal.point_to_point import OBJECTIVES
from . import control_spec as ctl
from . import optimal_spec as opt
from . import spec
from .schema_parts import (
    BOOL,
    DRAFT,
    EXPRESSION,
    INT,
    NOTES,
    NUM,
    STRING,
    TEXT,
    SchemaDrift,
    _constants,
    _enum,
    _number,
    _table,
)

#: the sections each study kind requires and those it refuses, as ``spec.parse`` has them; a
#: kind = "optimal" study takes [events] only with its [control]
KIND_SECTIONS = {
    "inverse": (("motion",), ("simulation", "control", "events", "optimal")),
    "forward": (("simulation",), ("motion", "control", "events", "optimise", "optimal")),
    "control": (("motion", "control"), ("simulation", "optimise", "optimal")),
    "optimal": (("optimal",), ("motion", "simulation", "optimise")),
}


def _torque(shape) -> dict:
    """Input torques (``NUMBERS``: a list, or a profile table): "zero", constants, a CSV file
    or a profile."""
    listed, profile = shape
    file = _table("torque (a file)", ctl.TORQUE_FILE_KEYS, {
        "file": (TEXT, "A CSV of t_s and tau<k>_n_m (N*m or N), relative to this study file."),
        "interpolation": (_enum(ctl.INTERPOLATIONS, "linear"),
                          "How the table is read between its rows (default linear)."),
    }, required=["file"])
    ramp = _table("torque (a profile)", ctl.TORQUE_PROFILE_KEYS, {
        "profile": (_enum(ctl.TORQUE_PROFILES), "The shape from start to end."),
        "start": (NUM, "Torques at the start, N*m (N at a slider), one per motor."),
        "end": (NUM, "Torques at the end, N*m (N), one per motor."),
        "duration": (NUM, "Duration of the change, s (> 0); then end holds."),
    }, profile, required=sorted(ctl.TORQUE_PROFILE_KEYS))
    return {"anyOf": [{"const": "zero"}, _number(listed, pair=False), file, ramp]}


def _parameters(what: str) -> tuple[dict, str]:
    return ({"type": "object", "additionalProperties": EXPRESSION},
            (f"{what}: name = a number in the description's units, or a string with an "
             "expression and a unit (\"0.5 kg\", \"2*0.3 kg\", \"90.992 kg*mm^2\")."))


def _study() -> dict:
    n, ints = spec.NUMBERS, spec.INTEGERS
    if n["control"]["torque"] != n["simulation"]["torque"]:
        raise SchemaDrift("[simulation] and [control] read torque inputs differently")
    torque = _torque(n["simulation"]["torque"])
    length = "[units] (length; angle for a hinge or phi)"
    units = _table("units", spec._UNITS, {
        q: (_enum(UNITS[q], SI[q]), (f"Unit of every {q} typed in this file (default {SI[q]}); "
                                     "times are in s.")) for q in spec._UNITS})
    motion = _table("motion", spec._MOTION, {
        "space": (_enum(spec.SPACES), ("task: start, by and end are task coordinates (x, y[, "
                                       "phi]); joint: every joint of a tree, the actuated "
                                       "joints of a closed chain.")),
        "profile": (_enum(spec.PROFILES, "cubic"),
                    ("cubic (default) or quintic from start by (or to end) in duration; "
                     "trapezoid (v_max, a_max); via (times, points); table (file).")),
        "start": (NUM, f"Where the move starts, in {length}."),
        "by": (NUM, f"The displacement from start, in {length}; give by or end, not both."),
        "end": (NUM, f"Where the move ends, in {length}; give by or end, not both."),
        "duration": (NUM, ("Duration, s (> 0); optional for trapezoid (as fast as v_max and "
                           "a_max allow).")),
        "samples": (INT, "Number of samples of the move."),
        "v_max": (NUM, "trapezoid: the speed limit per coordinate, [units] per s (> 0)."),
        "a_max": (NUM, ("trapezoid: the acceleration limit per coordinate, [units] per s^2 "
                        "(> 0).")),
        "times": (NUM, "via: the times of the via points, s, from 0, increasing."),
        "points": (NUM, f"via: the via points, one list per time, in {length}."),
        "file": (TEXT, "table: a CSV of t_s and the coordinates, relative to this study file."),
        "ik": (_enum(spec.SOLVERS, "auto"), ("space = 'task' only: the inverse-kinematics "
                                             "solver (default auto).")),
        "start_pose": (NUM, ("Joint coordinates near the start, in [units], choosing the "
                             "assembly (working) mode.")),
    }, n["motion"], ints["motion"], required=["space"])
    simulation = _table("simulation", spec._SIMULATION, {
        "q0": (NUM, "The start: every coordinate, in [units]."),
        "qd0": (NUM, "The start speeds, [units] per s (default 0)."),
        "duration": (NUM, "Duration, s (> 0)."),
        "samples": (INT, "Number of output samples."),
        "torque": ({**torque}, ("Input torques: 'zero' (default), constants [N*m or N, one per "
                                "motor], a CSV { file, interpolation } or a profile { profile, "
                                "start, end, duration }.")),
        "method": (_enum(spec.METHODS, "dopri5"), "The integrator (default dopri5)."),
        "rtol": (NUM, "Relative tolerance of the integrator (> 0)."),
        "atol": (NUM, "Absolute tolerance of the integrator (> 0)."),
    }, n["simulation"], ints["simulation"], required=["q0", "duration"])
    outputs = _table("outputs", spec._OUTPUTS, {
        "csv": (BOOL, "Write the results as CSV (default true)."),
        "plot": (BOOL, "Draw the plots (default true)."),
        "split": (BOOL, "One plot per quantity (default false)."),
        "animation": ({"enum": [False, True, *spec.ANIMATIONS]},
                      "An animation: false (default), true (a GIF) or the format."),
        "frames": (INT, "Frames of the animation."),
    }, None, ints["outputs"])
    control = _table("control", ctl._CONTROL, {
        "law": (_enum(ctl.LAWS), ("pd: PD + gravity compensation; computed_torque; lqr: "
                                  "time-varying LQR along the motion (q_weight, r_weight); "
                                  "none: open loop (needs torque).")),
        "kp": (NUM, ("Proportional gains, SI: N*m/rad (N/m) for pd, 1/s^2 for "
                     "computed_torque; one number for every joint or one per actuated joint; "
                     "with kd, instead of natural_frequency_hz.")),
        "kd": (NUM, ("Derivative gains, SI: N*m*s/rad (N*s/m) for pd, 1/s for computed_torque; "
                     "one number or one per actuated joint.")),
        "natural_frequency_hz": (NUM, ("Gains from a bandwidth, Hz (> 0), instead of kp and "
                                       "kd.")),
        "damping": (NUM, "Damping ratio with natural_frequency_hz (default 1)."),
        "saturate": (BOOL, "Clip at the description's actuator limits (default true)."),
        "duration": (NUM, "Duration, s (default: the motion's; the reference then holds)."),
        "samples": (INT, "Number of output samples."),
        "start_error": (NUM, "Start off the reference: one per actuated joint, in [units]."),
        "torque": ({**torque}, ("Input torques added to the controller's, N*m (N): constants, "
                                "a CSV { file, interpolation } or a profile; required by law = "
                                "'none'.")),
        "method": (_enum(ctl.CONTROL_METHODS, "dopri5"), "The integrator (default dopri5)."),
        "rtol": (NUM, "Relative tolerance of the integrator (> 0)."),
        "atol": (NUM, "Absolute tolerance of the integrator (> 0)."),
        "plant": _parameters("The plant's parameters where they differ from the model's (a "
                             "model error)"),
        "q_weight": (NUM, ("lqr: state weights, SI, 2n values (coordinates, then speeds), >= 0; "
                           "or one number.")),
        "r_weight": (NUM, "lqr: input weights, SI, one per motor, >= 0; or one number."),
    }, n["control"], ints["control"], required=["law"])
    events = _table("events", ctl._EVENTS, {
        "joint_limits": ({"type": "object", "additionalProperties": _number(
            n["events"]["joint_limits"]["*"], pair=True)},
            "Joint limits, coordinate = [lower, upper] in [units] (angle, length)."),
        "on_joint_limit": (_enum(ctl.ON_LIMIT, "stop"), ("At a joint limit: stop (default) or "
                                                         "continue.")),
        "on_actuator_limit": (_enum(ctl.ON_LIMIT, "continue"),
                              "At an actuator limit: continue (default) or stop."),
    }, n["events"])
    optimise = _table("optimise", spec._OPTIMISE, {
        "torque_limit": (NUM, ("Torque limits, N*m (N at a slider), one per motor, > 0 "
                               "(default: the description's torque_limit).")),
        "speed_limit": (NUM, "Speed limits per coordinate, [units] per s, > 0 (optional)."),
    }, n["optimise"])
    optimal = _table("optimal", opt._OPTIMAL, {
        "start": (NUM, (f"The start state (at rest): every coordinate of a tree, a closed "
                        f"chain's actuated ones, in {length}.")),
        "end": (NUM, f"The end state (at rest), in {length}."),
        "objective": (_enum(OBJECTIVES, "effort"),
                      ("effort (default: in the given duration), energy (the motors' "
                       "electrical energy in the given duration: each motor's "
                       "torque_constant and winding_resistance) or time (the fastest; needs "
                       "torque limits).")),
        "duration": (NUM, "Duration, s (> 0): objective = 'effort' or 'energy' only."),
        "intervals": (INT, "Intervals of the collocation grid."),
        "torque_limit": (NUM, ("Torque limits, N*m (N at a slider), one per motor, > 0 "
                               "(default: the description's).")),
        "speed_limit": (NUM, "Speed limits per coordinate, [units] per s, > 0 (optional)."),
    }, n["optimal"], ints["optimal"], required=["start", "end"])
    top = _table("", spec._TOP, {
        "title": (STRING, "A one-line title (default: the file's name)."),
        "robot": (TEXT, ("A built-in robot's name, a description file (.toml) or a generated "
                         "folder; a path is relative to this study file.")),
        "kind": (_enum(spec.KINDS), ("inverse: the torques along a motion; forward: simulate "
                                     "from a start; control: track the motion under a "
                                     "controller; optimal: the best move between two "
                                     "states.")),
        "units": (units, ("The units of this file's numbers: length and angle (default m and "
                          "rad); times are in s, gains and torques SI.")),
        "parameters": _parameters("Overrides of the robot's parameters"),
        "motion": (motion, "The move: kind = 'inverse' or 'control'."),
        "simulation": (simulation, "The run: kind = 'forward'."),
        "outputs": (outputs, "What to write."),
        "notes": NOTES,
        "control": (control, ("The controller: kind = 'control' (or 'optimal', to track the "
                              "move found).")),
        "events": (events, "Events and what each does, with [control]."),
        "optimise": (optimise, ("kind = 'inverse': time the motion's path as fast as these "
                                "limits allow, rest to rest.")),
        "optimal": (optimal, ("The best rest-to-rest move between two states: kind = "
                              "'optimal'.")),
        "constants": _constants(),
    }, n, required=["robot", "kind"], **_by_kind())
    return {"$schema": DRAFT, "title": "planar-sym study",
            "description": "One run of a robot: inverse dynamics along a motion, a forward "
                           "simulation, control in the loop or an optimal move "
                           "(planar_sym.study.spec). Numbers are in the file's [units] and "
                           "may be expressions in strings.", **top}


def _by_kind() -> dict:
    """``KIND_SECTIONS`` as one chain of if/then/else on ``kind`` (no allOf at the top: taplo
    would then complete no key there)."""
    if set(KIND_SECTIONS) != set(spec.KINDS):
        raise SchemaDrift(f"KIND_SECTIONS has {sorted(KIND_SECTIONS)}, spec.KINDS "
                          f"{sorted(spec.KINDS)}")
    chain: dict = {}
    for kind in reversed(spec.KINDS):
        requires, refuses = KIND_SECTIONS[kind]
        then: dict = {"required": list(requires), "properties": dict.fromkeys(refuses, False)}
        if kind == "optimal":
            then.update({"if": {"not": {"required": ["control"]}},
                         "then": {"properties": {"events": False}}})
        branch = {"if": {"properties": {"kind": {"const": kind}}, "required": ["kind"]},
                  "then": then}
        if chain:
            branch["else"] = chain
        chain = branch
    return chain
