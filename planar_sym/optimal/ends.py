"""The ends of an optimal move as the Python API takes them (``optimal_move``): each checked,
as its integrated coordinates or as a pose on a closed chain's loops, and an angle beyond a
turn warned about (degrees typed as radians)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError, warn_caller
from ..model.robot import Robot


def move_ends(robot: Robot, q_start, q_end, own: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """``q_start`` and ``q_end`` as the integrated coordinates ``own`` (rad; m at a slider),
    each given as them or as every coordinate (a closed chain's on its loops); InputError
    naming the end otherwise."""
    a0, a1 = (_end(robot, q, name, own) for q, name in ((q_start, "q_start"), (q_end, "q_end")))
    warn_turns(robot, own, q_start=a0, q_end=a1)
    return a0, a1


def _end(robot: Robot, q, name: str, own: list[int]) -> np.ndarray:
    """The integrated coordinates of an end state given as them or as every coordinate."""
    try:
        arr = np.asarray(q, dtype=float).ravel()
    except (TypeError, ValueError):  # numpy's "could not convert string to float: 'a'"
        raise InputError(f"{name} must be numbers (rad; m at a slider), got {q!r}") from None
    if len(arr) == robot.n:
        if robot.is_closed_chain and np.abs(robot.constraint(arr)).max() > 1e-9:
            raise InputError(f"{name} is off {robot.name}'s loops (|Phi| = "
                             f"{np.abs(robot.constraint(arr)).max():.3g} m): give the actuated "
                             "coordinates, or a pose on the loops")
        arr = arr[own]
    if len(arr) != len(own) or not np.all(np.isfinite(arr)):
        what = (f"its actuated coordinates, or {robot.n} for a pose on its loops"
                if robot.is_closed_chain else "one per coordinate")
        raise InputError(f"{name} must be {len(own)} finite value{'s' * (len(own) > 1)} for "
                         f"{robot.name} ({what}), got {np.asarray(q).tolist()}")
    return arr


def warn_turns(robot, coords, **values) -> None:
    """Warn once (at the caller's line) where an array of ``values`` (name -> rad, m at a
    slider, one per coordinate of ``coords``) puts a revolute coordinate beyond a turn:
    degrees typed as radians, the rule a description's and a study's angles follow, on a
    Python route (a trial: optimal_move from [30, 60] to [90, -45] meant in degrees planned a
    60 rad swing without a word)."""
    for what, array in values.items():
        for k, (i, v) in enumerate(zip(coords, np.ravel(array))):
            if robot.coordinate_units[i] == "rad" and abs(v) > 2.0 * np.pi:
                warn_caller(f"{robot.name}: {what}[{k}] = {v:g} rad ({robot.coordinates[i]}) "
                            f"is {abs(v) / (2.0 * np.pi):.3g} turns: were the angles typed in "
                            "degrees? (the Python API takes radians: np.radians)")
                return
