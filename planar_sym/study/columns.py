"""Columns and notes every kind of study shares: task coordinates as the seed writes them, and
which coordinate is which."""

from __future__ import annotations

import numpy as np

from ..model.robot import Robot


def task_columns(robot: Robot, x_si: np.ndarray) -> dict[str, np.ndarray]:
    """Task coordinates as the seed writes them: x, y in mm, phi in rad."""
    x_si = np.asarray(x_si).reshape(len(x_si), -1)
    return {(f"{n}_rad" if n == "phi" else f"{n}_mm"): (x_si[:, i] if n == "phi"
                                                        else x_si[:, i] * 1e3)
            for i, n in enumerate(robot.task_names)}


def coordinates_note(robot: Robot) -> str:
    marks = [f"q{i + 1} = {name}{' (prismatic, m)' if u == 'm' else ''}"
             f"{' (actuated)' if i in robot.actuated else ''}"
             for i, (name, u) in enumerate(zip(robot.coordinates, robot.coordinate_units))]
    return "coordinates: " + ", ".join(marks)
