"""Inverse-kinematics failures: every check records its failing samples, the earliest is
reported, naming the time and the target in the task's units (mm, rad)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import WorkspaceError
from ..model.robot import Robot


def _describe(robot: Robot, x: np.ndarray) -> str:
    parts = []
    for name, v in zip(robot.task_names, x):
        parts.append(f"{name} = {v:.6g} rad" if name == "phi" else f"{name} = {v * 1e3:.6g} mm")
    return "(" + ", ".join(parts) + ")"


class Failures:
    """Collects failing samples of every IK check, then reports the earliest of them all."""

    def __init__(self, robot: Robot, t: np.ndarray, x: np.ndarray):
        self.robot, self.t, self.x = robot, t, x
        self.found: list[tuple[int, str]] = []

    def add(self, bad: np.ndarray, why: Callable[[int], str]) -> None:
        if bad.any():
            k = int(np.argmax(bad))
            self.found.append((k, why(k)))

    def raise_earliest(self) -> None:
        if self.found:
            k, why = min(self.found, key=lambda f: f[0])
            raise WorkspaceError(f"{self.robot.name}: target {_describe(self.robot, self.x[k])} "
                                 f"at t = {self.t[k]:.6g} s (sample {k}) {why}")


