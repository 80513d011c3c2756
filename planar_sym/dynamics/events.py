"""Events along a controlled run: a joint reaching its limit, an actuator asked for more
than it can give, a loop that cannot stay assembled; each found to the integrator's accuracy
and reported with its time.

Each event is a function of the state that is positive while all is well (``kind``):

.. code:: text

    0  q_i - lower          joint i at its lower limit
    1  upper - q_i          joint i at its upper limit
    2  limit - |tau_cmd_a|  actuator a commanded beyond its torque (force) limit
    3  limit - |qd_i|       joint i faster than its motor allows (motor limit / gear ratio)

The C integrator locates a sign change within a step by bisection on its dense output.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

ACTIONS = ("stop", "continue")


@dataclass(frozen=True)
class EventSpec:
    """One event function: kind (above), index (coordinate, or actuator for kind 2),
    value (SI), whether it stops the run, and its name in reports.

    Attributes
    ----------
    kind : int
        0 lower joint limit, 1 upper joint limit, 2 actuator torque (force) limit, 3 joint
        speed limit (the module's table).
    index : int
        The coordinate (0-based), or for kind 2 the actuator (position in ``actuated``).
    value : float
        The limit in SI: rad or m (kinds 0, 1), N*m or N (2), rad/s or m/s (3).
    stop : bool
        Whether the run stops when the event fires.
    name : str
        What is reported, e.g. "joint joint2 reached its upper limit 3.05 rad (175 deg)".
    """

    kind: int
    index: int
    value: float
    stop: bool
    name: str


@dataclass(frozen=True)
class Event:
    """An event that happened: its ``name``, time ``time_s`` (s), and whether the run
    ``stopped`` there."""

    name: str
    time_s: float
    stopped: bool

    def __str__(self) -> str:
        return f"{self.name} at t = {self.time_s:.6g} s{' (run stopped)' if self.stopped else ''}"


def joint_limit_events(robot, limits: dict, action: str) -> list[EventSpec]:
    """Events for ``limits`` {coordinate (``coordinate_index``): (lower, upper)} in SI (rad
    or m)."""
    _check_action("on_joint_limit", action)
    out = []
    for key, bounds in (limits or {}).items():
        i = coordinate_index(robot, key)
        name = robot.coordinates[i]
        try:
            lo, hi = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise InputError(f"joint limit of {name}: give [lower, upper] (got {bounds!r})") \
                from None
        if not (np.isfinite(lo) and np.isfinite(hi)) or lo >= hi:
            raise InputError(f"joint limit of {name}: need finite lower < upper (got "
                             f"[{lo:g}, {hi:g}])")
        unit = robot.coordinate_units[i]
        out += [EventSpec(0, i, lo, action == "stop",
                          f"joint {name} reached its lower limit {_shown(lo, unit)}"),
                EventSpec(1, i, hi, action == "stop",
                          f"joint {name} reached its upper limit {_shown(hi, unit)}")]
    return out


def actuator_events(robot, action: str) -> tuple[list[EventSpec], np.ndarray]:
    """Events for every actuator limit the description gives, and the joint-side torque bound
    per actuated coordinate (inf where none): what saturation clips at.

    Returns the event specs and the bounds, shape (actuated,), in N*m (N at a slider).
    """
    _check_action("on_actuator_limit", action)
    params = robot.parameters
    out, bound = [], np.full(len(robot.actuated), np.inf)
    for a, act in enumerate(robot.actuators):
        ratio = params.get(f"gear_{act['joint']}", act["gear_ratio"])
        joint = act["joint"]
        motor = (None if act["motor_torque_limit"] is None
                 else act["motor_torque_limit"] * ratio)
        limits = [v for v in (act["torque_limit"], motor) if v is not None]
        if limits:
            bound[a] = min(limits)
            what = "force" if act["unit"] == "N" else "torque"
            # which side: the joint's (a trial read 10 N*m beside the motor's 0.2 N*m limit)
            side = (f" at the joint (the motor's {act['motor_torque_limit']:.4g} N*m x N = "
                    f"{ratio:.4g})" if bound[a] == motor and ratio != 1.0 else "")
            out.append(EventSpec(2, a, bound[a], action == "stop",
                                 f"actuator {joint} commanded beyond its {what} limit "
                                 f"{bound[a]:.4g} {act['unit']}{side}"))
        if act["motor_speed_limit_rad_s"] is not None:
            v = act["motor_speed_limit_rad_s"] / ratio
            unit = "m/s" if act["unit"] == "N" else "rad/s"
            out.append(EventSpec(3, act["coordinate"], v, action == "stop",
                                 f"joint {joint} faster than its motor's limit ({v:.4g} {unit} "
                                 "at the joint)"))
    return out, bound


def _shown(v: float, unit: str) -> str:
    """A limit in SI, and an angle also in degrees (as study files give them)."""
    return f"{v:.6g} {unit}" + (f" ({np.degrees(v):.6g} deg)" if unit == "rad" else "")


def _check_action(field: str, action: str) -> None:
    if action not in ACTIONS:
        raise InputError(f"{field} must be \"stop\" or \"continue\" (got {action!r})")


def coordinate_index(robot, key) -> int:
    """A coordinate named by its 0-based index, its joint's name, or ``q<k>`` (1-based, as
    in the CSV columns)."""
    if isinstance(key, (int, np.integer)) and not isinstance(key, bool):
        if 0 <= key < robot.n:
            return int(key)
    elif key in robot.coordinates:
        return robot.coordinates.index(key)
    elif isinstance(key, str) and key[:1] == "q" and key[1:].isdigit() \
            and 1 <= int(key[1:]) <= robot.n:
        return int(key[1:]) - 1
    raise InputError(f"joint limit for {key!r}: not a coordinate of {robot.name} (q1..q{robot.n}"
                     f", or {', '.join(robot.coordinates)})")


def output_events(g: np.ndarray, t: np.ndarray) -> list[tuple[int, float]]:
    """Events seen on the output grid (the SUNDIALS route), from the event values ``g`` of shape
    (N, events) at the output times ``t`` (N,) in s: (event, time in s) of each one's first
    crossing from positive to not positive, its time found by linear interpolation. An event
    already past at the first sample (logged at the start by the engine) counts from when it
    has recovered, as the compiled route's events do."""
    out = []
    for k in range(g.shape[1]):
        down = np.nonzero((g[:-1, k] > 0) & (g[1:, k] <= 0))[0]
        if len(down):
            j = int(down[0]) + 1
            frac = g[j - 1, k] / (g[j - 1, k] - g[j, k])
            out.append((k, t[j - 1] + frac * (t[j] - t[j - 1])))
    return out
