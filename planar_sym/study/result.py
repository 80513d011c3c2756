"""Study results: labelled columns whose names carry their units, and the torque split."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

# a coordinate's column names are the dynamics layer's (a Simulation names its columns too)
from ..dynamics.columns import SUFFIXES, coordinate_column

__all__ = ["ANGLE", "SUFFIXES", "TORQUE", "Result", "coordinate_column"]

#: the column holding a coordinate's torque: tau<k>_n_m, k numbering the robot's coordinates
#: (a prismatic joint's force: tau<k>_n)
TORQUE = re.compile(r"^tau(\d+)_n(_m)?$")
#: a coordinate's angle column (a prismatic joint's displacement: q<k>_m)
ANGLE = re.compile(r"^q(\d+)_(rad|m)$")



@dataclass(frozen=True)
class Result:
    """Columns (name -> (N,) array) of one study run; each name carries its unit (``t_s``,
    ``q1_rad``, ``qd1_rad_s``, ``tau1_n_m``, ``fx_C_n``, ``energy_j``, ...).

    ``kind`` says what the main figure shows: ``"angles"`` (joint angles), ``"torques"``, or
    ``"control"`` (reference against actual, tracking errors, commanded and applied torques).
    ``split`` holds the actuated torques split into parts (keys of
    ``dynamics.inverse.SPLIT_PARTS``: inertial ``M qdd``, velocity ``C qd``, gravity ``g``, the
    drive train's friction ``D(qd)`` and rotors), each (N, actuated) in N*m, summing to the
    torques; it is not written to the CSV. ``solver`` names
    the inverse kinematics that ran; ``actuated`` the actuated coordinates (0-based); ``sizing``
    one ``study.sizing.ActuatorSizing`` per actuator (peaks, RMS, power, energy, limits
    exceeded with the time), inverse dynamics only.

    Attributes
    ----------
    name : str
        The study's name (the CSV and figure file names).
    summary : str
        Its title, one line.
    columns : dict of str to ndarray
        Column name (with its unit) -> values, shape (N,), SI; ``t_s`` first.
    kind : str
        ``"angles"``, ``"torques"`` or ``"control"``.
    note : str
        What the figure's footnote says: coordinates, solver, drift, limits exceeded.
    robot : str
        The robot's name.
    reference : ndarray, shape (N, n), or None
        Control studies: every coordinate's reference at ``t_s`` (rad; m at a slider).
    events : tuple of Event
        Control studies: what happened along the run (name, time in s, stopped).
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
        """Every column side by side, shape (N, columns), SI as the column names say."""
        return np.column_stack(list(self.columns.values()))

    def torques(self) -> dict[str, np.ndarray]:
        """The torque columns, each (N,) in N*m (a prismatic joint's force in N), in
        coordinate order."""
        return {k: v for k, v in self.columns.items() if TORQUE.match(k)}

    def angles(self) -> dict[str, np.ndarray]:
        """The joint-coordinate columns, each (N,) in rad (a slider's in m), in coordinate
        order."""
        return {k: v for k, v in self.columns.items() if ANGLE.match(k)}

    def peak_torques(self) -> dict[str, float]:
        """Largest magnitude (N*m, or N for a force) of each torque column, keyed ``tau<k>``."""
        return {k.split("_")[0]: float(np.max(np.abs(v)))
                for k, v in self.torques().items()}

    def peak_torques_with_units(self) -> dict[str, tuple[float, str]]:
        """``peak_torques`` with each one's unit: ``tau<k>`` -> (peak, ``"N*m"``, or ``"N"`` for
        a slider's force)."""
        units = {k.split("_")[0]: ("N" if k.endswith("_n") else "N*m") for k in self.torques()}
        return {k: (v, units[k]) for k, v in self.peak_torques().items()}

    def csv_text(self) -> str:
        """The columns as CSV text: one header row of names with units, then one row per
        sample (17 significant digits)."""
        header = ",".join(self.columns)
        rows = "\n".join(",".join(f"{v:.17g}" for v in row) for row in self.table())
        return header + "\n" + rows + "\n"

    def metadata(self) -> dict[str, str]:
        """What the NPZ and the DataFrame's ``attrs`` carry besides the columns: study, robot,
        summary, kind, solver, note."""
        return {"study": self.name, "robot": self.robot, "summary": self.summary,
                "kind": self.kind, "solver": self.solver, "note": self.note,
                "writer": "planar-sym"}

    def to_dataframe(self):
        """The columns as a pandas DataFrame, one per column in order, names with units,
        ``t_s`` a column (not the index: ``df.to_csv(index=False)`` has the CSV's header);
        ``attrs`` = ``metadata()``. Needs pandas (``pip install pandas``)."""
        from ..dynamics.columns import dataframe

        return dataframe(self.columns, self.metadata())

    def save_npz(self, path):
        """Write the columns (each (N,), float64 bit for bit) and ``metadata()`` to the NPZ
        file ``path``, whole or not at all; returns the Path. Read back with ``np.load`` or
        ``planar_sym.dynamics.columns.load_npz``."""
        from ..dynamics.columns import save_npz

        return save_npz(path, self.columns, self.metadata())
