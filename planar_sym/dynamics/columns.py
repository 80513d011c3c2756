"""Named sample columns (name -> (N,) array, the unit in the name: ``t_s``, ``q1_rad``,
``tau1_n_m``) as a pandas DataFrame or an NPZ file: the output edge of ``Simulation`` and the
study ``Result``, which hold typed ``series.Series`` and name them only here.

NPZ layout: one array per column under its own name (``np.load(path)["q1_rad"]``), in column
order, plus ``METADATA_KEY`` holding a JSON object as a 0-d unicode array (robot, study,
method, ...; read without ``allow_pickle``). ``load_npz`` gives both back.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_files
from .series import column_name, coordinate_unit

#: the NPZ entry holding the metadata (JSON text)
METADATA_KEY = "__metadata__"


def coordinate_column(kind: str, k: int, unit: str) -> str:
    """The column name of coordinate ``k`` (0-based) for ``kind`` ``q``, ``qd``, ``qdd`` or
    ``tau``, its unit in the name: ``q1_rad``, ``qd2_m_s``, ``tau1_n_m``, ``tau2_n`` (a
    prismatic joint's force). ``unit`` is the coordinate's: ``"rad"``, or ``"m"`` at a slider
    (``series.Series.column`` of the same series)."""
    return column_name(kind, coordinate_unit(kind, unit), k)


def dataframe(columns: dict[str, np.ndarray], metadata: dict[str, str]):
    """A pandas DataFrame of ``columns`` (copied), one per column in order, ``t_s`` a column
    (not the index, so ``df.to_csv(index=False)`` has the CSV's header); ``df.attrs`` holds
    ``metadata``. pandas is imported here only: ``import planar_sym`` never loads it."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("to_dataframe needs pandas, which is not installed: pip install "
                          "pandas (or write NPZ or CSV, which need nothing more)") from None
    df = pd.DataFrame({k: np.array(v, copy=True) for k, v in columns.items()})
    df.attrs.update(metadata)
    return df


def save_npz(path: str | Path, columns: dict[str, np.ndarray],
             metadata: dict[str, str]) -> Path:
    """Write ``columns`` and ``metadata`` to ``path`` (exactly that name), whole or not at all.

    Parameters
    ----------
    path : str or Path
        The file (``.npz`` by convention; no suffix is added). Its folder is created.
    columns : dict of str to ndarray
        Each (N,), stored as is (float64 bit for bit).
    metadata : dict of str to str
        Small text facts (robot, study, method), stored as JSON under ``METADATA_KEY``.

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"NPZ file {path} is a folder; give a file name such as "
                         f"{path / 'result.npz'}")
    if METADATA_KEY in columns:
        raise InputError(f"a column may not be named {METADATA_KEY!r} (the NPZ's metadata)")
    arrays = {k: np.asarray(v) for k, v in columns.items()}
    arrays[METADATA_KEY] = np.array(json.dumps(metadata, sort_keys=True))
    with atomic_files([path]) as (tmp,), open(tmp, "wb") as f:
        np.savez(f, **arrays)
    return path


def load_npz(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """(columns, metadata) of an NPZ written by ``save_npz``; columns in their saved order."""
    with np.load(Path(path), allow_pickle=False) as data:
        columns = {k: data[k] for k in data.files if k != METADATA_KEY}
        meta = json.loads(str(data[METADATA_KEY])) if METADATA_KEY in data.files else {}
    return columns, meta
