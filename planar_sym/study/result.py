"""Study results: typed series (quantity, unit, coordinate or joint), named as columns whose
names carry their units only at the output edge (CSV, NPZ, DataFrame), and the torque split."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

# a coordinate's column names are the dynamics layer's (a Simulation names its columns too)
from ..dynamics.columns import coordinate_column
from ..dynamics.series import Series, columns_of, one, select

__all__ = ["Result", "Series", "coordinate_column"]


@dataclass(frozen=True)
class Result:
    """One study run as typed series (``data``: ``dynamics.series.Series``, each (N,) with its
    quantity, unit and coordinate or joint); the CSV's columns are made from them, each name
    carrying its unit (``t_s``, ``q1_rad``, ``qd1_rad_s``, ``tau1_n_m``, ``fx_C_n``,
    ``energy_j``, ...).

    ``kind`` says what the main figure shows: ``"angles"`` (joint angles), ``"torques"``, or
    ``"control"`` (reference against actual, tracking errors, commanded and applied torques).
    ``split`` holds the actuated torques split into parts (keys of
    ``dynamics.inverse.SPLIT_PARTS``: inertial ``M qdd``, velocity ``C qd``, gravity ``g``, the
    drive train's friction ``D(qd)`` and rotors), each (N, actuated) in N*m, summing to the
    torques; it is not written to the CSV. ``solver`` names
    the inverse kinematics that ran; ``actuated`` the actuated coordinates (0-based); ``sizing``
    one ``dynamics.sizing.ActuatorSizing`` per actuator (peaks, RMS, power, energy, limits
    exceeded with the time), inverse dynamics only.

    Attributes
    ----------
    name : str
        The study's name (the CSV and figure file names).
    summary : str
        Its title, one line.
    data : tuple of Series
        Every series, in the CSV's column order, ``t`` (s) first; SI but for the task
        coordinates x, y in mm. Read them with ``series`` and ``get``; ``columns`` names them.
    kind : str
        ``"angles"``, ``"torques"`` or ``"control"``.
    note : str
        What the figure's footnote says: coordinates, solver, drift, limits exceeded.
    split : dict of str to ndarray
        The torque split, each part (N, actuated) in N*m.
    robot : str
        The robot's name.
    solver : str
        The inverse kinematics that ran ("" if none).
    actuated : tuple of int
        The actuated coordinates (0-based).
    sizing : tuple of ActuatorSizing
        What each actuator must deliver (inverse dynamics and control), () otherwise.
    reference : ndarray, shape (N, n), or None
        Control studies: every coordinate's reference at ``t_s`` (rad; m at a slider).
    events : tuple of Event
        Control studies: what happened along the run (name, time in s, stopped).
    warnings : tuple of str
        What the run warned about (a likely unit slip in a parameter, a pose near a singular
        one): shown on the page and in the notebook, carried in the metadata.
    timing : str
        An ``[optimise]`` study: how its path was timed (the time reached, the limits), else "".
    """

    name: str
    summary: str
    data: tuple[Series, ...]
    kind: str
    note: str = ""
    split: dict[str, np.ndarray] = field(default_factory=dict)
    robot: str = ""
    solver: str = ""
    actuated: tuple[int, ...] = ()
    #: what each actuator must deliver (inverse dynamics; ``dynamics.sizing``), () otherwise
    sizing: tuple = ()
    #: control studies: every coordinate's reference at ``t_s`` (N, n; rad or m), to draw
    reference: np.ndarray | None = None
    #: control studies: what happened along the run (``control.Event``: name, time, stopped)
    events: tuple = ()
    #: the run's warnings, each a sentence (also shown on stderr as they happened)
    warnings: tuple[str, ...] = ()
    #: an [optimise] study: how its path was timed ("" otherwise)
    timing: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "data", tuple(self.data))
        columns_of(self.data)  # refuses two series of one column name

    @cached_property
    def columns(self) -> dict[str, np.ndarray]:
        """Column name (with its unit) -> values, each (N,), SI as the name says (x, y in mm):
        the ``column`` of every series in ``data``, ``t_s`` first. Made from the series: the
        output edge (CSV, NPZ, DataFrame)."""
        return columns_of(self.data)

    def series(self, quantity: str | None = None, index: int | None = None,
               joint: str | None = None) -> tuple[Series, ...]:
        """The series of ``quantity`` (every one if None: ``"q"``, ``"tau"``, ``"jload"``,
        ...), of coordinate ``index`` (0-based) and of ``joint`` where given, in column order;
        each (N,) in its own ``unit``."""
        return select(self.data, quantity, index, joint)

    def get(self, quantity: str, index: int | None = None, joint: str | None = None) -> Series:
        """The one series of ``quantity`` (at coordinate ``index``, 0-based, or ``joint``),
        shape (N,), in its ``unit``; KeyError if there is none or more than one."""
        return one(self.data, quantity, index, joint)

    def table(self) -> np.ndarray:
        """Every column side by side, shape (N, columns), SI as the column names say."""
        return np.column_stack([s.values for s in self.data])

    def torques(self) -> dict[str, np.ndarray]:
        """The applied torques (series ``"tau"``), each (N,) in N*m (a prismatic joint's force
        in N), keyed by column name, in coordinate order."""
        return {s.column: s.values for s in self.series("tau")}

    def angles(self) -> dict[str, np.ndarray]:
        """The joint coordinates (series ``"q"``), each (N,) in rad (a slider's in m), keyed by
        column name, in coordinate order."""
        return {s.column: s.values for s in self.series("q")}

    def peak_torques(self) -> dict[str, float]:
        """Largest magnitude (N*m, or N for a force) of each torque, keyed ``tau<k>``."""
        return {s.stem: float(np.max(np.abs(s.values))) for s in self.series("tau")}

    def peak_torques_with_units(self) -> dict[str, tuple[float, str]]:
        """``peak_torques`` with each one's unit, the series' own: ``tau<k>`` -> (peak,
        ``"N*m"``, or ``"N"`` for a slider's force)."""
        return {s.stem: (float(np.max(np.abs(s.values))), s.unit) for s in self.series("tau")}

    def csv_text(self) -> str:
        """The columns as CSV text: one header row of names with units, then one row per
        sample (17 significant digits)."""
        header = ",".join(self.columns)
        rows = "\n".join(",".join(f"{v:.17g}" for v in row) for row in self.table())
        return header + "\n" + rows + "\n"

    def metadata(self) -> dict[str, str]:
        """What the NPZ and the DataFrame's ``attrs`` carry besides the columns: study, robot,
        summary, kind, solver, note, and the warnings (one per line; empty if none)."""
        return {"study": self.name, "robot": self.robot, "summary": self.summary,
                "kind": self.kind, "solver": self.solver, "note": self.note,
                "warnings": "\n".join(self.warnings), "writer": "planar-sym"}

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
