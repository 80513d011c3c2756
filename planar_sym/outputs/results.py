"""A study's result on disk: ``<name>.csv`` and its figures, written whole or not at all."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..files import atomic_files
from ..study.result import Result
from .plots import save_figure


def write(result: Result, out_dir: Path, split: bool = False, csv: bool = True,
          plot: bool = True, npz: bool = False) -> list[Path]:
    """Write ``<name>.csv``, ``<name>.png``, (``split``) ``<name>_split.png`` and (``npz``)
    ``<name>.npz``; all or nothing.

    Parameters
    ----------
    result : Result
    out_dir : Path
        Created if missing; must not be a file.
    split : bool
        Also write the torque-split figure.
    csv, plot : bool
        Write the table, the main figure.
    npz : bool
        Write the table's columns as NPZ too (float64 bit for bit, with the study's and the
        robot's names: ``Result.save_npz``).

    Returns
    -------
    list of Path
        The files written.
    """
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir} is a file, not a folder")
    if split and not result.split:
        raise InputError(f"{result.name} has no torque split")
    targets = []
    if csv:
        targets.append(out_dir / f"{result.name}.csv")
    if plot:
        targets.append(out_dir / f"{result.name}.png")
    if split:
        targets.append(out_dir / f"{result.name}_split.png")
    if npz:
        targets.append(out_dir / f"{result.name}.npz")
    with atomic_files(targets) as temps:
        it = iter(temps)
        if csv:
            next(it).write_text(result.csv_text())
        if plot:
            save_figure(result, next(it))
        if split:
            save_figure(result, next(it), split=True)
        if npz:
            result.save_npz(next(it))
    return targets
