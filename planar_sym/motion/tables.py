"""CSV tables of a motion or a torque input: a header row whose names carry their units, then
numbers; every problem reported at once, naming the file, the line and the column.

Units by suffix, converted to SI: ``_s`` (s), ``_m``, ``_mm`` (m), ``_rad``, ``_deg`` (rad),
``_n_m`` (N*m), ``_n`` (N). A table needs a ``t_s`` column, at least 2 rows, and strictly
increasing times.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ..errors import InputError

#: column suffix -> factor to SI
SUFFIXES = {"_s": 1.0, "_mm": 1e-3, "_m": 1.0, "_deg": math.pi / 180.0, "_rad": 1.0,
            "_n_m": 1.0, "_n": 1.0}


def to_si(column: str) -> float:
    """The SI factor of a column named with a unit suffix (the longest matching one)."""
    for suffix in sorted(SUFFIXES, key=len, reverse=True):
        if column.endswith(suffix):
            return SUFFIXES[suffix]
    raise InputError(f"column {column!r} has no unit suffix ({', '.join(SUFFIXES)})")


def read_table(path: str | Path, columns: list[str] | list[list[str]]
               ) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and the named columns (SI) of a CSV table.

    Parameters
    ----------
    path : str or Path
    columns : list
        The columns wanted, in order; each entry a name, or a list of names that mean the same
        quantity in other units (``["x_mm", "x_m"]``): the first present is taken.

    Returns
    -------
    times : ndarray, shape (K,)
    values : ndarray, shape (K, len(columns))
    """
    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text (CSV) file") from None
    rows = [r for r in rows if any(cell.strip() for cell in r)]
    if not rows:
        raise InputError(f"{path}: empty: a header row (t_s, ...) and at least 2 rows of numbers")
    header = [h.strip() for h in rows[0]]
    problems = []
    wanted = [[c] if isinstance(c, str) else list(c) for c in columns]
    chosen = []
    for options in [["t_s"], *wanted]:
        found = next((c for c in options if c in header), None)
        if found is None:
            problems.append(f"{path}: missing column {' or '.join(options)} (the header has "
                            f"{', '.join(header)})")
        chosen.append(found)
    data = []
    for line, row in enumerate(rows[1:], start=2):
        values = []
        for name in chosen:
            if name is None:
                continue
            col = header.index(name)
            cell = row[col].strip() if col < len(row) else ""
            try:
                v = float(cell)
            except ValueError:
                problems.append(f"{path}: line {line}, column {name}: not a number ({cell!r})")
                v = math.nan
            else:
                if not math.isfinite(v):
                    problems.append(f"{path}: line {line}, column {name}: must be finite "
                                    f"({cell!r})")
            values.append(v)
        data.append(values)
    if len(data) < 2:
        problems.append(f"{path}: needs at least 2 rows of numbers (has {len(data)})")
    if not problems:
        t = np.array([r[0] for r in data])
        for k in range(1, len(t)):
            if not t[k] > t[k - 1]:
                what = "repeated" if t[k] == t[k - 1] else "not increasing"
                problems.append(f"{path}: line {k + 2}: time {t[k]:g} s {what} (line {k + 1} "
                                f"has {t[k - 1]:g} s)")
    if problems:
        raise InputError(problems[0] if len(problems) == 1 else
                         "invalid table:\n  " + "\n  ".join(problems))
    arr = np.array(data)
    scale = np.array([to_si(c) for c in chosen])
    arr = arr * scale
    return arr[:, 0], arr[:, 1:]
