"""CSV tables of a motion or a torque input: a header row whose names carry their units, then
numbers; every problem reported at once, naming the file, the line and the column.

Units by suffix, converted to SI (``SUFFIXES``):

=========  ===========  ==============
suffix     unit         factor to SI
=========  ===========  ==============
``_s``     s            1
``_m``     m            1
``_mm``    mm           1e-3 (to m)
``_rad``   rad          1
``_deg``   deg          pi / 180 (to rad)
``_n_m``   N*m          1
``_n``     N            1
=========  ===========  ==============

A table needs a ``t_s`` column, at least 2 rows, and strictly increasing times. Blank lines are
skipped (line numbers still count them); a UTF-8 byte-order mark (Excel) is ignored.
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


#: problems listed in one error (the count says how many there are in all)
MAX_LISTED = 20


def to_si(column: str) -> float:
    """The SI factor of a column named with a unit suffix (the longest matching one).

    .. code:: text

        value_SI = value * to_si(name):  "x_mm" -> 1e-3,  "q1_deg" -> pi / 180,  "t_s" -> 1

    Raises InputError for a name without a known suffix, listing the known ones.
    """
    for suffix in sorted(SUFFIXES, key=len, reverse=True):
        if column.endswith(suffix) and len(column) > len(suffix):
            return SUFFIXES[suffix]
    raise InputError(f"column {column!r} has no unit suffix ({', '.join(SUFFIXES)})")


def _rows(path: Path) -> list[tuple[int, list[str]]]:
    """(line number, cells) of each non-blank line."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.reader(f)
            rows, start = [], 1
            for cells in reader:
                if any(c.strip() for c in cells):
                    rows.append((start, cells))
                start = reader.line_num + 1
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text (CSV) file") from None
    except csv.Error as exc:
        raise InputError(f"{path}: not a CSV file ({exc})") from None
    return rows


def read_table(path: str | Path, columns: list[str] | list[list[str]]
               ) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and the named columns (SI) of a CSV table with a header row.

    .. code:: text

        t_s, x_mm, q1_deg          <- header: names with unit suffixes (see SUFFIXES)
        0.0, 100.0, 30.0           -> times_s[0] = 0.0,  values[0] = [0.1, 0.5236]
        0.5, 120.0, 35.0

    Every problem is collected, then raised as one InputError listing them (the first
    ``MAX_LISTED``, then how many more), each naming the file and, where it has one, the line
    and the column: a missing column (naming the columns the header has), a repeated column
    name, a column without a unit suffix, a cell that is not a number or is empty, a value
    that is not finite, a row with more cells than the header, a time that repeats or goes
    back (naming both lines), fewer than 2 rows.

    Parameters
    ----------
    path : str or Path
        The CSV file (UTF-8, comma separated).
    columns : list
        The columns wanted besides ``t_s``, in order; each entry a name, or a list of names
        that mean the same quantity in other units (``["x_mm", "x_m"]``): the first present
        is taken.

    Returns
    -------
    times_s : ndarray, shape (K,)
        The ``t_s`` column, strictly increasing, K >= 2.
    values : ndarray, shape (K, len(columns))
        The columns, converted to SI by their suffixes.
    """
    path = Path(path)
    rows = _rows(path)
    if not rows:
        raise InputError(f"{path}: empty: a header row (t_s, ...) and at least 2 rows of numbers")
    header_line, header = rows[0][0], [h.strip() for h in rows[0][1]]
    named_cells = [h for h in header if h]
    for sep, what in ((";", "semicolons"), ("\t", "tabs")):
        if len(named_cells) == 1 and sep in named_cells[0]:  # one message, not one per column
            raise InputError(f"{path}: line {header_line}: the header {named_cells[0]!r} is one "
                             f"column: the table's columns are separated by {what}; separate "
                             "them by commas (a CSV file)")
    problems = []
    for name in sorted({h for h in header if h and header.count(h) > 1}):
        problems.append(f"{path}: line {header_line}: column {name} appears "
                        f"{header.count(name)} times in the header")
    wanted = [[c] if isinstance(c, str) else list(c) for c in columns]
    chosen = []
    for options in [["t_s"], *wanted]:
        found = next((c for c in options if c in header), None)
        if found is None:
            problems.append(f"{path}: missing column {' or '.join(options)} (the header has "
                            f"{', '.join(h for h in header if h) or 'no names'})")
        else:
            try:
                to_si(found)
            except InputError as exc:
                problems.append(f"{path}: line {header_line}: {exc}")
        chosen.append(found)
    named = len(header)
    while named and not header[named - 1]:
        named -= 1
    data, lines = [], []
    for line, cells in rows[1:]:
        extra = [c for c in cells[named:] if c.strip()]
        if extra:
            problems.append(f"{path}: line {line}: {len(cells)} cells, but the header names "
                            f"{named} columns (extra: {', '.join(extra)})")
        values = []
        for name in chosen:
            if name is None:
                continue
            col = header.index(name)
            cell = cells[col].strip() if col < len(cells) else ""
            try:
                v = float(cell)
            except ValueError:
                what = "empty" if not cell else f"not a number ({cell!r})"
                problems.append(f"{path}: line {line}, column {name}: {what}")
                v = math.nan
            else:
                if not math.isfinite(v):
                    problems.append(f"{path}: line {line}, column {name}: must be finite "
                                    f"({cell!r})")
                    v = math.nan
            values.append(v)
        data.append(values)
        lines.append(line)
    if len(data) < 2:
        problems.append(f"{path}: needs at least 2 rows of numbers (has {len(data)})")
    if chosen[0] is not None:
        last = None  # (line, time) of the latest row with a valid time
        order = []
        for line, values in zip(lines, data):
            t = values[0]
            if math.isnan(t):
                continue
            if last is not None and not t > last[1]:
                what = "repeated" if t == last[1] else "not increasing"
                order.append(f"{path}: line {line}: time {t:g} s {what} (line {last[0]} "
                             f"has {last[1]:g} s)")
            else:
                last = (line, t)
        if len(order) > MAX_LISTED:  # one mistake (rows reversed, or unsorted): one message
            order = [(f"{path}: column {chosen[0]}: {len(order)} of {len(data)} rows are not "
                      f"later than the rows before them ({order[0].split(': ', 1)[1]}): sort "
                      "the rows by time")]
        problems += order
    if len(problems) == 1:
        raise InputError(problems[0])
    if problems:
        more = len(problems) - MAX_LISTED
        listed = problems[:MAX_LISTED] + ([f"... and {more} more"] if more > 0 else [])
        raise InputError(f"invalid table ({len(problems)} problems):\n  " + "\n  ".join(listed))
    arr = np.array(data, dtype=float) * np.array([to_si(c) for c in chosen])
    return arr[:, 0], arr[:, 1:]
