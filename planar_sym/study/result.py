"""Scenario results as labelled columns, written to CSV and PNG without half-written files."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_files


@dataclass(frozen=True)
class Result:
    """Columns (name -> (N,) array) of one scenario; names carry units (``t`` in s).

    ``kind`` says what the main figure shows: ``"angles"`` (joint angles, deg) or
    ``"torques"`` (N*m). ``split`` holds the actuated torques split into parts (keys of
    ``dynamics.inverse.SPLIT_PARTS``: inertial ``M qdd``, velocity ``C qd``, gravity ``g``), each
    (N, actuated) in N*m, summing to the torques; it is not written to the CSV.
    """

    name: str
    summary: str
    columns: dict[str, np.ndarray]
    kind: str
    note: str = ""
    split: dict[str, np.ndarray] = field(default_factory=dict)

    def table(self) -> np.ndarray:
        return np.column_stack(list(self.columns.values()))

    def peak(self, prefix: str) -> dict[str, float]:
        """Largest magnitude of each column starting with ``prefix`` (e.g. 'tau')."""
        return {k: float(np.max(np.abs(v))) for k, v in self.columns.items()
                if k.startswith(prefix) and k[len(prefix):].isdigit()}

    def csv_text(self) -> str:
        header = ",".join(self.columns)
        rows = "\n".join(",".join(f"{v:.17g}" for v in row) for row in self.table())
        return header + "\n" + rows + "\n"

    def plot(self, split: bool = False):
        """The result's matplotlib Figure (for notebooks): the seed-like plot, or the split.

        Parameters
        ----------
        split : bool
            False: joint angles (deg) or torques (N*m) against time (s). True: each actuated
            torque (N*m) with its parts ``M qdd``, ``C qd`` and ``g``.
        """
        from ..outputs.plots import figure, split_figure

        if not split:
            return figure(self)
        if not self.split:
            raise InputError(f"{self.name} has no torque split")
        return split_figure(self)


def write(result: Result, out_dir: Path, split: bool = False) -> list[Path]:
    """Write ``<name>.csv`` and ``<name>.png`` (and ``<name>_split.png``); all or nothing.

    Parameters
    ----------
    result : Result
    out_dir : Path
        Created if missing.
    split : bool
        Also write the torque-split figure.

    Returns
    -------
    list of Path
        The files written.
    """
    from ..outputs.plots import save_figure

    out_dir = Path(out_dir)
    targets = [out_dir / f"{result.name}.csv", out_dir / f"{result.name}.png"]
    if split:
        targets.append(out_dir / f"{result.name}_split.png")
    with atomic_files(targets) as temps:
        temps[0].write_text(result.csv_text())
        save_figure(result, temps[1])
        if split:
            save_figure(result, temps[2], split=True)
    return targets
