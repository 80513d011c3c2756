"""Study results: labelled columns whose names carry their units, and the torque split."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

#: the column holding a coordinate's torque: tau<k>_n_m, k numbering the robot's coordinates
#: (a prismatic joint's force: tau<k>_n)
TORQUE = re.compile(r"^tau(\d+)_n(_m)?$")
#: a coordinate's angle column (a prismatic joint's displacement: q<k>_m)
ANGLE = re.compile(r"^q(\d+)_(rad|m)$")

#: column suffixes of a coordinate by its unit: value, rate, acceleration, torque or force
SUFFIXES = {"rad": ("rad", "rad_s", "rad_s2", "n_m"), "m": ("m", "m_s", "m_s2", "n")}


def coordinate_column(kind: str, k: int, unit: str) -> str:
    """The column name of coordinate ``k`` (0-based) for ``kind`` ``q``, ``qd``, ``qdd`` or
    ``tau``, its unit in the name: ``q1_rad``, ``qd2_m_s``, ``tau1_n_m``, ``tau2_n`` (a
    prismatic joint's force)."""
    suffix = SUFFIXES[unit][("q", "qd", "qdd", "tau").index(kind)]
    return f"{kind}{k + 1}_{suffix}"


@dataclass(frozen=True)
class Result:
    """Columns (name -> (N,) array) of one study run; each name carries its unit (``t_s``,
    ``q1_rad``, ``qd1_rad_s``, ``tau1_n_m``, ``fx_C_n``, ``energy_j``, ...).

    ``kind`` says what the main figure shows: ``"angles"`` (joint angles), ``"torques"``, or
    ``"control"`` (reference against actual, tracking errors, commanded and applied torques).
    ``split`` holds the actuated torques split into parts (keys of
    ``dynamics.inverse.SPLIT_PARTS``: inertial ``M qdd``, velocity ``C qd``, gravity ``g``), each
    (N, actuated) in N*m, summing to the torques; it is not written to the CSV. ``solver`` names
    the inverse kinematics that ran; ``actuated`` the actuated coordinates (0-based); ``sizing``
    one ``study.sizing.ActuatorSizing`` per actuator (peaks, RMS, power, energy, limits
    exceeded with the time), inverse dynamics only.
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
    #: what each actuator must deliver (inverse dynamics; ``study.sizing``), () otherwise
    sizing: tuple = ()
    #: control studies: every coordinate's reference at ``t_s`` (N, n; rad or m), to draw
    reference: np.ndarray | None = None
    #: control studies: what happened along the run (``control.Event``: name, time, stopped)
    events: tuple = ()

    def table(self) -> np.ndarray:
        return np.column_stack(list(self.columns.values()))

    def torques(self) -> dict[str, np.ndarray]:
        """The torque columns (N*m), in coordinate order."""
        return {k: v for k, v in self.columns.items() if TORQUE.match(k)}

    def angles(self) -> dict[str, np.ndarray]:
        """The joint-angle columns (rad), in coordinate order."""
        return {k: v for k, v in self.columns.items() if ANGLE.match(k)}

    def peak_torques(self) -> dict[str, float]:
        """Largest magnitude (N*m, or N for a force) of each torque column, keyed ``tau<k>``."""
        return {k.split("_")[0]: float(np.max(np.abs(v)))
                for k, v in self.torques().items()}

    def csv_text(self) -> str:
        header = ",".join(self.columns)
        rows = "\n".join(",".join(f"{v:.17g}" for v in row) for row in self.table())
        return header + "\n" + rows + "\n"
