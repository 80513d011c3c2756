"""An experiment read from a CSV: the table ``planar-sym run`` writes, or any with its columns.

.. code:: text

    t_s, q1_rad, q2_deg, ..., tau1_n_m, tau2_n, ...        positions and torques (required)
    qd1_rad_s, ..., qdd1_rad_s2, ...                         rates and accelerations (optional)

Positions of every coordinate (a closed chain's actuated ones will do) with ``_rad``, ``_deg``,
``_m`` or ``_mm``; torques of the actuated coordinates with ``_n_m`` or ``_n``. Where every
rate and acceleration is given in SI (``_rad_s``, ``_rad_s2``; ``_m_s``, ``_m_s2``) they are
used as they are; otherwise positions and torques are filtered and differentiated
(``data.experiment``).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from ..errors import InputError, warn_caller
from ..model.robot import Robot
from ..motion.tables import read_table
from .data import Experiment, experiment

#: a median time step above this (s) is no dynamic experiment (a rate below 2 Hz)
SLOWEST_S = 0.5
_COORD = re.compile(r"^(q|qd|qdd|tau)(\d+)_")


def read_experiment(robot: Robot, path: str | Path, cutoff_hz: float | None = None,
                    filtered: bool = False) -> Experiment:
    """The experiment in ``path`` (see the module docstring); ``filtered=True`` filters and
    differentiates even where rates and accelerations are given."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8-sig") as f:
            header = [h.strip() for h in next(csv.reader(f), [])]
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror})") from None
    slide = [u == "m" for u in robot.coordinate_units]

    def names(kind: str, i: int) -> list[str]:
        return {"q": [f"q{i + 1}_m", f"q{i + 1}_mm"] if slide[i] else
                [f"q{i + 1}_rad", f"q{i + 1}_deg"],
                "qd": [f"qd{i + 1}_m_s" if slide[i] else f"qd{i + 1}_rad_s"],
                "qdd": [f"qdd{i + 1}_m_s2" if slide[i] else f"qdd{i + 1}_rad_s2"],
                "tau": [f"tau{i + 1}_n" if slide[i] else f"tau{i + 1}_n_m"]}[kind]

    def present(kind: str, coords) -> bool:
        return all(any(n in header for n in names(kind, i)) for i in coords)

    other = sorted({h for h in header if (m := _COORD.match(h)) and int(m[2]) > robot.n})
    if other:  # a 2-link arm's run fitted to a pendulum gave a 2 % residual and no word
        warn_caller(f"{path}: columns {', '.join(other)} are of coordinates {robot.name} does "
                    f"not have (it has {robot.n}): data of another robot?")
    every, act = range(robot.n), list(robot.actuated)
    for i in every:  # q1_rad beside q1_deg: the first was read and the other ignored
        both = [n for n in names("q", i) if n in header]
        if len(both) > 1:
            raise InputError(f"{path}: columns {' and '.join(both)} both give coordinate "
                             f"{i + 1}: keep one")
    q_coords = every if present("q", every) or not robot.is_closed_chain else act
    columns = [names("q", i) for i in q_coords] + [names("tau", i) for i in act]
    t, values = read_table(path, columns)  # every problem of the file at once, SI
    step = float(np.median(np.diff(t)))
    if step > SLOWEST_S:  # milliseconds under t_s were fitted, then blamed on an inertia
        raise InputError(f"{path}: column t_s: samples {step:.4g} s apart ({1 / step:.3g} Hz): "
                         "far too slow to identify dynamics from; are the times in ms? (the "
                         "column is in s)")
    nq = len(q_coords)
    q, tau = values[:, :nq], values[:, nq:]
    if not filtered and present("qd", every) != present("qdd", every):
        given, missing = ("rates", "accelerations") if present("qd", every) else (
            "accelerations", "rates")
        warn_caller(f"{path}: {given} are given without {missing} (both are needed to use "
                    "them): left unused, both filtered and differentiated from the positions")
    if not filtered and present("qd", every) and present("qdd", every):
        rates = _plain_columns(path, header, [names("qd", i)[0] for i in every]
                               + [names("qdd", i)[0] for i in every])
        ex = experiment(robot, t, q, tau, rates[:, :robot.n], rates[:, robot.n:],
                        name=str(path))
        return Experiment(ex.t_s, ex.q, ex.qd, ex.qdd, ex.tau, ex.name,
                          (*ex.notes, "rates and accelerations as given in the file"))
    return experiment(robot, t, q, tau, cutoff_hz=cutoff_hz, name=str(path))


def _plain_columns(path: Path, header: list[str], wanted: list[str]) -> np.ndarray:
    """Columns already in SI (rates, accelerations), as floats; InputError naming a bad cell."""
    idx = [header.index(w) for w in wanted]
    rows = []
    with path.open(newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        next(reader)
        for line, row in enumerate(reader, start=2):
            if not row or not any(c.strip() for c in row):
                continue
            try:
                rows.append([float(row[i]) for i in idx])
            except (ValueError, IndexError):
                raise InputError(f"{path}: line {line}: a rate or acceleration is missing or "
                                 "not a number") from None
    return np.array(rows)
