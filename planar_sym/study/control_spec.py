"""The ``[control]`` and ``[events]`` sections of a study (``kind = "control"``): a law, its
gains, the plant's parameters and the run; the events and what each does.

.. code:: toml

    [control]
    law = "computed_torque"        # "pd" (PD + gravity compensation), "computed_torque", "none",
                                   # "lqr" (time-varying LQR along the motion, then LQR about
                                   # its end: q_weight = [...] (2n, SI), r_weight = [...])
    natural_frequency_hz = 4.0     # gains from a bandwidth (and damping, default 1) ...
    # kp = [400.0, 400.0]          # ... or given (one number: every joint): PD in N*m/rad,
                                   # computed torque in 1/s^2
    # kd = [40.0, 40.0]            #               PD in N*m*s/rad, computed torque in 1/s
    saturate = true                # clip at the description's actuator limits
    duration = 2.0                 # s (default: the motion's; the reference then holds)
    samples = 501
    start_error = [5.0, -5.0]      # start off the reference, actuated joints (file's units)
    torque = { file = "disturbance.csv", interpolation = "linear" }  # added input torques
    method = "dopri5"              # or "cvodes", "idas" (SUNDIALS through CasADi)

    [control.plant]                # the plant's parameters where they differ (a model error)
    m_L_Link2 = "0.6 kg"

    [events]
    joint_limits = { q1 = [-170.0, 170.0] }   # file's angle (length) unit
    on_joint_limit = "stop"        # or "continue"
    on_actuator_limit = "continue" # or "stop"
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from .checks import Checker, finite

LAWS = ("pd", "computed_torque", "lqr", "none")
CONTROL_METHODS = ("dopri5", "cvodes", "idas")
INTERPOLATIONS = ("hold", "linear", "cubic", "pchip")
TORQUE_PROFILES = ("cubic", "quintic")
#: what ``on_joint_limit`` and ``on_actuator_limit`` may do
ON_LIMIT = ("stop", "continue")
#: the two tables an input torque may be: a CSV file, or a profile
TORQUE_FILE_KEYS = {"file", "interpolation"}
TORQUE_PROFILE_KEYS = {"profile", "start", "end", "duration"}
#: integers of [control]: (default, lowest, highest)
CONTROL_INTEGERS = {"samples": (501, 2, 1_000_000)}
_CONTROL = {"law", "kp", "kd", "natural_frequency_hz", "damping", "saturate", "duration",
            "samples", "start_error", "torque", "method", "rtol", "atol", "plant", "q_weight",
            "r_weight"}
_EVENTS = {"joint_limits", "on_joint_limit", "on_actuator_limit"}
MAX_FREQUENCY_HZ = 1e4


@dataclass(frozen=True)
class TorqueInput:
    """Input torques (N*m or N) added to the controller's: a constant, a CSV table read as
    ``interpolation`` says, or a profile from ``start`` to ``end`` over ``duration_s``."""

    constant: tuple[float, ...] | None = None
    file: Path | None = None
    interpolation: str = "linear"
    profile: str | None = None
    start: tuple[float, ...] | None = None
    end: tuple[float, ...] | None = None
    duration_s: float | None = None


@dataclass(frozen=True)
class ControlSpec:
    law: str
    kp: tuple[float, ...] | None = None
    kd: tuple[float, ...] | None = None
    natural_frequency_hz: float | None = None
    damping: float = 1.0
    saturate: bool = True
    duration_s: float | None = None
    samples: int = 501
    start_error: tuple[float, ...] | None = None
    torque: TorqueInput | None = None
    method: str = "dopri5"
    rtol: float = 1e-10
    atol: float = 1e-12
    plant: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    q_weight: tuple[float, ...] | None = None
    r_weight: tuple[float, ...] | None = None
    saturate_asked: bool = False  # the file says saturate = true (not only the default)


@dataclass(frozen=True)
class EventsSpec:
    joint_limits: dict[str, tuple[float, float]] = field(default_factory=dict)
    on_joint_limit: str = "stop"
    on_actuator_limit: str = "continue"


def parse_control(c: Checker, tbl: dict, parameters) -> ControlSpec | None:
    """``parameters``: the checker's parser of a parameters table (shared with [parameters])."""
    c.keys(tbl, _CONTROL, "control.")
    law = c.choice(tbl, "law", "control.law", LAWS)
    # one number for every joint, or one per actuated joint
    kp, kd = (c.vector({k: [tbl[k]] if _number(tbl.get(k)) else tbl.get(k)}, k, f"control.{k}")
              for k in ("kp", "kd"))
    freq = None
    if "natural_frequency_hz" in tbl:
        freq = c.number(tbl, "natural_frequency_hz", "control.natural_frequency_hz",
                        positive=True, limit=MAX_FREQUENCY_HZ)
    damping = c.number(tbl, "damping", "control.damping", positive=True, limit=100.0,
                       default=1.0)
    if law in ("pd", "computed_torque"):
        given = (kp is not None or kd is not None, "natural_frequency_hz" in tbl)
        if given == (False, False):
            c.err("control", f"law {law!r} needs gains: natural_frequency_hz = ... (and "
                             "damping), or kp = [...] and kd = [...]")
        elif all(given):
            c.err("control", "give natural_frequency_hz or kp and kd, not both")
        elif given[0] and (("kp" in tbl) != ("kd" in tbl)):
            c.err("control", "give both kp and kd")
    elif law in ("none", "lqr"):
        for key in ("kp", "kd", "natural_frequency_hz", "damping"):
            if key in tbl:
                c.err(f"control.{key}", f"not used by law = \"{law}\"" + (
                    " (open loop)" if law == "none" else ": give q_weight and r_weight"))
    weights = {}
    for key in ("q_weight", "r_weight"):
        weights[key] = c.vector({key: [tbl[key]] if _number(tbl.get(key)) else tbl.get(key)},
                                key, f"control.{key}", required=law == "lqr")
        if law != "lqr" and key in tbl:
            c.err(f"control.{key}", "only for law = \"lqr\"")
        elif weights[key] is not None and min(weights[key]) < 0:
            c.err(f"control.{key}", f"must be >= 0 (got {list(weights[key])})")
    for key, vec in (("kp", kp), ("kd", kd)):
        if vec is not None and min(vec) < 0:
            c.err(f"control.{key}", f"must be >= 0: a negative gain pushes the joint away from "
                                    f"its reference (got {list(vec)})")
    duration = None
    if "duration" in tbl:
        duration = c.number(tbl, "duration", "control.duration", positive=True, limit=1e6)
    samples = c.integer(tbl, "samples", "control.samples", *CONTROL_INTEGERS["samples"])
    start_error = c.vector(tbl, "start_error", "control.start_error")
    method = c.choice(tbl, "method", "control.method", CONTROL_METHODS, "dopri5")
    rtol = c.number(tbl, "rtol", "control.rtol", positive=True, default=1e-10)
    atol = c.number(tbl, "atol", "control.atol", positive=True, default=1e-12)
    saturate = c.flag(tbl, "saturate", "control.saturate", True)
    plant = parameters(c.table(tbl, "plant"), "control.plant")
    torque = parse_torque(c, tbl.get("torque"), "control.torque")
    if law == "none" and torque is None:
        c.err("control.torque", "law = \"none\" (open loop) needs input torques")
    if None in (law, method, rtol, atol, damping):
        return None
    return ControlSpec(law, kp, kd, freq, damping, saturate, duration, samples, start_error,
                       torque, method, rtol, atol, plant, weights["q_weight"],
                       weights["r_weight"], saturate_asked=bool(saturate and "saturate" in tbl))


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def parse_torque(c: Checker, raw, fld: str) -> TorqueInput | None:
    if raw is None or raw == "zero":
        return None
    if isinstance(raw, list):
        vec = c.vector({"t": raw}, "t", fld)
        return TorqueInput(constant=vec) if vec is not None else None
    if isinstance(raw, dict) and "file" in raw:
        c.keys(raw, TORQUE_FILE_KEYS, f"{fld}.")
        path = c.file(raw["file"], f"{fld}.file")
        interp = c.choice(raw, "interpolation", f"{fld}.interpolation", INTERPOLATIONS,
                          "linear")
        return TorqueInput(file=path, interpolation=interp or "linear") if path else None
    if isinstance(raw, dict) and "profile" in raw:
        c.keys(raw, TORQUE_PROFILE_KEYS, f"{fld}.")
        prof = c.choice(raw, "profile", f"{fld}.profile", TORQUE_PROFILES)
        start = c.vector(raw, "start", f"{fld}.start", required=True)
        end = c.vector(raw, "end", f"{fld}.end", required=True)
        dur = c.number(raw, "duration", f"{fld}.duration", positive=True, limit=1e6)
        if start is not None and end is not None and len(start) != len(end):
            c.err(f"{fld}.end", f"must have {len(start)} values like {fld}.start")
            return None
        if None in (prof, start, end, dur):
            return None
        return TorqueInput(profile=prof, start=start, end=end, duration_s=dur)
    c.err(fld, "must be \"zero\", a list of constant torques (N*m or N), { file = \"t.csv\", "
               "interpolation = \"linear\" } or { profile = \"cubic\", start = [...], end = "
               f"[...], duration = ... }} (got {raw!r:.80})")
    return None


def parse_events(c: Checker, tbl: dict) -> EventsSpec:
    c.keys(tbl, _EVENTS, "events.")
    limits = {}
    raw = tbl.get("joint_limits", {})
    if not isinstance(raw, dict):
        c.err("events.joint_limits", f"must be a table {{ q1 = [lower, upper] }} (got {raw!r})")
        raw = {}
    for name, v in raw.items():
        fld = f"events.joint_limits.{name}"
        if (not isinstance(v, list) or len(v) != 2
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and finite(x)
                           for x in v)):
            c.err(fld, f"must be [lower, upper], two finite numbers (got {v!r})")
        elif not v[0] < v[1]:
            c.err(fld, f"lower must be below upper (got {v!r})")
        else:
            limits[name] = (float(v[0]), float(v[1]))
    on_joint = c.choice(tbl, "on_joint_limit", "events.on_joint_limit", ON_LIMIT, "stop")
    on_act = c.choice(tbl, "on_actuator_limit", "events.on_actuator_limit", ON_LIMIT,
                      "continue")
    return EventsSpec(limits, on_joint or "stop", on_act or "continue")
