"""Study results: labelled columns whose names carry their units, and the torque split."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

#: the column holding a coordinate's torque: tau<k>_n_m, k numbering the robot's coordinates
TORQUE = re.compile(r"^tau(\d+)_n_m$")
#: a coordinate's angle column
ANGLE = re.compile(r"^q(\d+)_rad$")


@dataclass(frozen=True)
class Result:
    """Columns (name -> (N,) array) of one study run; each name carries its unit (``t_s``,
    ``q1_rad``, ``qd1_rad_s``, ``tau1_n_m``, ``fx_C_n``, ``energy_j``, ...).

    ``kind`` says what the main figure shows: ``"angles"`` (joint angles) or ``"torques"``.
    ``split`` holds the actuated torques split into parts (keys of
    ``dynamics.inverse.SPLIT_PARTS``: inertial ``M qdd``, velocity ``C qd``, gravity ``g``), each
    (N, actuated) in N*m, summing to the torques; it is not written to the CSV. ``solver`` names
    the inverse kinematics that ran; ``actuated`` the actuated coordinates (0-based).
    """

    name: str
    summary: str
    columns: dict[str, np.ndarray]
    kind: str
    note: str = ""
    split: dict[str, np.ndarray] = field(default_factory=dict)
    robot: str = ""
    solver: str = ""
    actuated: tuple[int, ...] = ()

    def table(self) -> np.ndarray:
        return np.column_stack(list(self.columns.values()))

    def torques(self) -> dict[str, np.ndarray]:
        """The torque columns (N*m), in coordinate order."""
        return {k: v for k, v in self.columns.items() if TORQUE.match(k)}

    def angles(self) -> dict[str, np.ndarray]:
        """The joint-angle columns (rad), in coordinate order."""
        return {k: v for k, v in self.columns.items() if ANGLE.match(k)}

    def peak_torques(self) -> dict[str, float]:
        """Largest magnitude (N*m) of each torque column, keyed ``tau<k>``."""
        return {k.removesuffix("_n_m"): float(np.max(np.abs(v)))
                for k, v in self.torques().items()}

    def csv_text(self) -> str:
        header = ",".join(self.columns)
        rows = "\n".join(",".join(f"{v:.17g}" for v in row) for row in self.table())
        return header + "\n" + rows + "\n"
