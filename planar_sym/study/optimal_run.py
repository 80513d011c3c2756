"""Run an optimal study (``kind = "optimal"``): find the move (``optimal_move``), then run it
as an inverse study runs its motion, or track it under the study's ``[control]`` law.

The move is piecewise quadratic in time (constant accelerations per interval), so it is
sampled exactly at any times; a closed chain's passive joints follow from its loops. A tree
with a passive joint (a cart-pole's pole) cannot be given an arbitrary motion, so its
result is the move itself: the solver's coordinates and torques at its nodes.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError, SimulationError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from . import spec as specs
from .motion import check_width, coordinate_scale, warn_turns

#: optimal_move's own turns warning (optimal.ends.warn_turns), which a study replaces by its own
API_TURNS = r".*were the angles typed in degrees\? \(the Python API takes radians"

if TYPE_CHECKING:  # the optimal layer is imported when a move is asked for
    from ..optimal.point_to_point import OptimalMove

#: the move found for a study on a robot's parameters: a study's run asks for it more than
#: once (its motion, its reference, the pictures); keyed by the study and the parameters
_FOUND: dict = {}


def plan(st: specs.Study, robot: Robot):
    """The study's optimal move (``OptimalMove``, SI) and a sentence saying what was found."""
    from ..optimal.point_to_point import optimal_move

    key = (repr(st.optimal), st.length_unit, st.angle_unit, robot.name, robot.p.tobytes())
    if key in _FOUND:
        return _FOUND[key]
    o, where = st.optimal, st.path or st.name
    act = list(robot.actuated)
    own = act if robot.is_closed_chain else list(range(robot.n))
    scale = coordinate_scale(st, robot)
    width = len(own)
    for fld, v in (("optimal.start", o.start), ("optimal.end", o.end)):
        if len(v) != robot.n:
            check_width(st, fld, v, width, "actuated joint" if robot.is_closed_chain
                        else "coordinate")
    # beyond a turn: the study's rule (its file, field and [units]), not the API's own
    any(warn_turns(st, robot, fld, v, range(robot.n) if len(v) == robot.n else own)
        for fld, v in (("optimal.start", o.start), ("optimal.end", o.end)))
    ends = [np.asarray(v) * (scale if len(v) == robot.n else scale[own])
            for v in (o.start, o.end)]
    speed = None
    if o.speed_limit is not None:
        check_width(st, "optimal.speed_limit", o.speed_limit, robot.n, "coordinate")
        speed = np.asarray(o.speed_limit) * scale
    limit = o.torque_limit
    if limit is not None and len(limit) not in (1, len(act)):
        check_width(st, "optimal.torque_limit", limit, len(act), "motor")
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=API_TURNS)
            move = optimal_move(robot, *ends, objective=o.objective, duration_s=o.duration_s,
                                torque_limit=limit, speed_limit=speed, intervals=o.intervals)
    except InputError as exc:
        raise InputError(f"{where}: optimal: {exc}") from None
    except SimulationError as exc:  # infeasible: named by the study and its own field names
        raise SimulationError(f"{where}: optimal: " + str(exc).replace(
            "lengthen duration_s", "lengthen optimal.duration")) from None
    s = move.solver
    kinds = {robot.coordinate_units[i] for i in act}  # "m": a slider's force, N
    unit = ("s" if o.objective == "time" else "J" if o.objective == "energy" else
            "N^2*s" if kinds == {"m"} else
            "N^2*m^2*s" if kinds == {"rad"} else "(N*m or N)^2*s")
    note = (f"optimal move ({o.objective}): {move.duration_s:.4g} s, objective "
            f"{move.objective:.6g} {unit}, peak |tau| "
            + ", ".join(f"{v:.4g} {'N' if robot.coordinate_units[i] == 'm' else 'N*m'}"
                        for v, i in zip(np.abs(move.tau).max(axis=0), act))
            + f"; IPOPT {s['iterations']} iterations, {s['status']}, constraint violation "
              f"{s['constraint_violation']:.1e}, {o.intervals} intervals")
    if len(_FOUND) > 32:
        _FOUND.clear()
    _FOUND[key] = (move, note)
    return move, note


def plan_motion(st: specs.Study, robot: Robot, samples: int | None = None,
                t: np.ndarray | None = None
                ) -> tuple[JointTrajectory, np.ndarray | None, OptimalMove, str]:
    """The move as a study's joint motion: at its nodes, at ``samples`` evenly spaced times,
    or at the times ``t`` (s) (``OptimalMove.sampled_at``); its task coordinates (None
    without a task); and the move itself with the sentence saying what was found (``plan``)."""
    move, note = plan(st, robot)
    jt = move.trajectory
    if t is not None or samples is not None:
        times = np.linspace(jt.t_s[0], jt.t_s[-1], samples) if t is None else t
        jt = move.sampled_at(robot, times)
    x = robot.task(jt.q)[0].reshape(len(jt.t_s), -1) if robot.task_names else None
    return jt, x, move, note
