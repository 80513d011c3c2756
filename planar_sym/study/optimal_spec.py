"""The ``[optimal]`` section of a study (``kind = "optimal"``): the best rest-to-rest move
between two states (``planar_sym.optimal_move``: direct collocation, CasADi Opti and IPOPT),
which the study then runs as an inverse study runs its motion, or tracks under its
``[control]`` law (a swing-up then balance: ``law = "lqr"``).

.. code:: toml

    [optimal]
    start = [0.0, -90.0]       # every coordinate of a tree, a closed chain's actuated ones
    end = [0.0, 90.0]          # (file's units: length for a slider, angle for a hinge)
    objective = "effort"       # or "time" (needs torque_limit), or "energy" (electrical:
                               # each motor's torque_constant and winding_resistance)
    duration = 2.0             # s ("effort", "energy"; "time" finds it)
    intervals = 100            # the collocation grid
    torque_limit = [0.2]       # N*m (N at a slider) per motor (default: the description's)
    speed_limit = [2.0, 720.0] # per coordinate, file's units per s (optional)
"""

from __future__ import annotations

from dataclasses import dataclass

from ..optimal.point_to_point import OBJECTIVES
from .checks import Checker

_OPTIMAL = {"start", "end", "objective", "duration", "intervals", "torque_limit",
            "speed_limit"}
MAX_INTERVALS = 10_000
#: integers of [optimal]: (default, lowest, highest)
OPTIMAL_INTEGERS = {"intervals": (100, 2, MAX_INTERVALS)}


@dataclass(frozen=True)
class OptimalSpec:
    """The move to find, in the file's units (converted when run)."""

    start: tuple[float, ...]
    end: tuple[float, ...]
    objective: str = "effort"
    duration_s: float | None = None
    intervals: int = 100
    torque_limit: tuple[float, ...] | None = None
    speed_limit: tuple[float, ...] | None = None


def parse_optimal(c: Checker, tbl: dict) -> OptimalSpec | None:
    c.keys(tbl, _OPTIMAL, "optimal.")
    start = c.vector(tbl, "start", "optimal.start", required=True)
    end = c.vector(tbl, "end", "optimal.end", required=True)
    if start is not None and end is not None and len(start) != len(end):
        # which of the two is wrong is the robot's to say: both are named
        c.err("optimal.end", f"has {len(end)} value{'s' * (len(end) != 1)} and optimal.start "
                             f"{len(start)}: both need one per coordinate (a closed chain's: "
                             "per actuated joint, or a whole pose)")
    objective = c.choice(tbl, "objective", "optimal.objective", OBJECTIVES, "effort")
    duration = None
    if objective in ("effort", "energy"):
        duration = c.number(tbl, "duration", "optimal.duration", positive=True, limit=1e6)
    elif objective == "time" and "duration" in tbl:
        c.err("optimal.duration", "not used by objective = \"time\" (the time is what it "
                                  "finds)")
    intervals = c.integer(tbl, "intervals", "optimal.intervals", *OPTIMAL_INTEGERS["intervals"])
    limits = {}
    for key in ("torque_limit", "speed_limit"):
        v = c.vector(tbl, key, f"optimal.{key}")
        if v is not None and not all(x > 0 for x in v):
            c.err(f"optimal.{key}", f"must be positive (got {list(v)})")
        limits[key] = v
    if None in (start, end, objective) or (objective != "time" and duration is None):
        return None
    return OptimalSpec(start, end, objective, duration, intervals, **limits)
