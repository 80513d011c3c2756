"""Scenario results as labelled columns, written to CSV and PNG without half-written files."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class Result:
    """Columns (name -> (N,) array) of one scenario; names carry units (``t`` in s).

    ``plot`` says what the figure shows: ``"angles"`` (joint angles, deg) or ``"torques"``.
    """

    name: str
    summary: str
    columns: dict[str, np.ndarray]
    plot: str
    note: str = ""

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


def write(result: Result, out_dir: Path) -> list[Path]:
    """Write ``<name>.csv`` and ``<name>.png`` into ``out_dir``; all or nothing."""
    from .plots import save_figure

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    targets = [out_dir / f"{result.name}.csv", out_dir / f"{result.name}.png"]
    temps: list[str] = []
    try:
        for target in targets:
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=out_dir)
            os.close(fd)
            temps.append(tmp)
        Path(temps[0]).write_text(result.csv_text())
        save_figure(result, Path(temps[1]))
        for tmp, target in zip(temps, targets):
            os.chmod(tmp, 0o644)
            os.replace(tmp, target)
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return targets
