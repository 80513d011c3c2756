"""The table a sweep returns (``sweep.sweep``): one row per design, its varied parameters then
its figures, SI with the unit in each column's name, and its CSV text.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


@dataclass
class SweepResult:
    """The sweep's table: ``columns`` (name -> (D,) array, units in the names), the varied
    parameters first (``varied``, the columns of the parameters named in ``parameters``),
    then the figures; ``failed`` maps a design's index to why it has no figures (NaN in its
    row); ``route`` says how the designs were evaluated.

    Values are SI, the unit in each column's name (``m_link2_kg``, ``a2_m``, ``peak_tau1_n_m`` in
    N*m, ``max_abs_e1_rad`` in rad, ``final_work_j`` in J); ``D`` is the
    number of designs. ``study`` names the study swept; ``note`` sums the run up (designs,
    sampling, route, what was varied on which parameter set, failures). For a control study the
    varied columns are the controller's model's values (``m_link2_kg``) then the plant's
    (``plant_m_link2_kg``), and ``on`` says which of the two the designs changed ("both",
    "model" or "plant"; "both" for any other study, which has one robot). ``info`` types every
    column (``figures.Figure``: its unit, and the statistic and quantity it is of).
    ``over_limits`` maps a design's index to the actuator limits it passes (its figures kept;
    the CSV's ``limits`` column).
    """

    study: str
    columns: dict[str, np.ndarray]
    varied: tuple[str, ...]
    parameters: tuple[str, ...] = ()
    failed: dict[int, str] = field(default_factory=dict)
    route: str = ""
    note: str = ""
    on: str = "both"
    info: dict = field(default_factory=dict)
    over_limits: dict[int, str] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(next(iter(self.columns.values())))

    @property
    def figures(self) -> tuple[str, ...]:
        """The names of the figure columns (every column but the varied parameters')."""
        return tuple(k for k in self.columns if k not in self.varied)

    def csv_text(self) -> str:
        """The table as CSV; a failed design's figures are empty and ``error`` says why; a
        design over an actuator limit says which in ``limits``."""
        texts = [(name, d) for name, d in (("limits", self.over_limits), ("error", self.failed))
                 if d]
        lines = [",".join([*self.columns, *(name for name, _ in texts)])]
        for k in range(len(self)):
            row = ["" if not np.isfinite(v[k]) else f"{v[k]:.12g}" for v in self.columns.values()]
            row += ['"' + d.get(k, "").replace('"', "'") + '"' for _, d in texts]
            lines.append(",".join(row))
        return "\n".join(lines) + "\n"

    def write_csv(self, path: str | os.PathLike) -> Path:
        """Write ``csv_text()`` to ``path``, whole or not at all; returns the path."""
        from ..files import atomic_files

        path = Path(path)
        with atomic_files([path]) as (tmp,):
            tmp.write_text(self.csv_text())
        return path
