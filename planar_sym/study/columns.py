"""Series and notes every kind of study shares: task coordinates as the seed writes them, and
which coordinate is which."""

from __future__ import annotations

import numpy as np

from ..dynamics.series import Series
from ..model.robot import Robot


def task_series(robot: Robot, x_si: np.ndarray, suffix: str = "") -> list[Series]:
    """Task coordinates as the seed writes them (``x_si``: shape (N, task), SI): x, y in mm,
    phi in rad; quantities ``x``, ``y``, ``phi`` (``x_ref``, ... with ``suffix="_ref"``)."""
    x_si = np.asarray(x_si).reshape(len(x_si), -1)
    return [Series(f"{n}{suffix}", "rad", x_si[:, i]) if n == "phi"
            else Series(f"{n}{suffix}", "mm", x_si[:, i] * 1e3)
            for i, n in enumerate(robot.task_names)]


def coordinates_note(robot: Robot) -> str:
    """Which joint each q<k> is, a slide marked prismatic; no unit here: the columns' names and
    the plots' axes carry theirs (a trial read "m" in a plot's note beside its mm axis)."""
    marks = [f"q{i + 1} = {name}{' (prismatic)' if u == 'm' else ''}"
             f"{' (actuated)' if i in robot.actuated else ''}"
             for i, (name, u) in enumerate(zip(robot.coordinates, robot.coordinate_units))]
    return "coordinates: " + ", ".join(marks)
