"""One entry point for the study layer: a motion profile named by a string.

.. code:: text

    kind        needs                                   duration
    cubic       start, end (or by), duration_s          duration_s
    quintic     start, end (or by), duration_s          duration_s
    trapezoid   start, end (or by), v_max, a_max        duration_s, or the minimum time
                [duration_s]                            (trapezoid_duration)
    via         via_times, via_points                   via_times[0] .. via_times[-1]
    table       table_times, table_values               table_times[0] .. table_times[-1]

An argument the named kind does not use is refused (naming it), so a mistyped study cannot
pass silently; so is an unknown kind (listing the known ones).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from . import _checks
from .profiles import Trajectory, _floats, cubic
from .smooth import quintic, trapezoid, trapezoid_duration
from .splines import _knots, table, via

#: the profiles a study can name
KINDS = ("cubic", "quintic", "trapezoid", "via", "table")

_USES = {"cubic": {"start", "end", "by", "duration_s"},
         "quintic": {"start", "end", "by", "duration_s"},
         "trapezoid": {"start", "end", "by", "duration_s", "v_max", "a_max"},
         "via": {"via_times", "via_points"},
         "table": {"table_times", "table_values"}}
_NEEDS = {"cubic": ("start", "duration_s"), "quintic": ("start", "duration_s"),
          "trapezoid": ("start", "v_max", "a_max"), "via": ("via_times", "via_points"),
          "table": ("table_times", "table_values")}


def _check(kind: str, given: dict) -> None:
    if not isinstance(kind, str) or kind not in KINDS:
        raise InputError(f"unknown motion profile {kind!r}: the known ones are "
                         f"{', '.join(KINDS)}")
    unused = sorted(k for k, v in given.items() if v is not None and k not in _USES[kind])
    if unused:
        raise InputError(f"a {kind} profile does not take {', '.join(unused)} (it takes "
                         f"{', '.join(sorted(_USES[kind]))})")
    missing = [k for k in _NEEDS[kind] if given.get(k) is None]
    if kind in ("cubic", "quintic", "trapezoid") \
            and (given.get("end") is None) == (given.get("by") is None):
        missing.append("end or by (exactly one)")
    if missing:
        raise InputError(f"a {kind} profile needs {', '.join(missing)}")


def _step(start, end, by) -> np.ndarray:
    if by is not None:
        return by
    start, end = _floats("start", start), _floats("end", end)
    if start.shape != end.shape:
        raise InputError(f"start and end must have the same length (got {start.size} and "
                         f"{end.size})")
    return end - start


def profile_span(kind: str, *, start=None, end=None, by=None, duration_s=None, v_max=None,
                 a_max=None, via_times=None, via_points=None, table_times=None,
                 table_values=None) -> tuple[float, float]:
    """First and last time (s) of the profile ``make_profile`` would build, for sampling.

    .. code:: text

        cubic, quintic:  (0, duration_s)
        trapezoid:       (0, duration_s) or (0, trapezoid_duration(end - start, v_max, a_max))
        via, table:      (times[0], times[-1])

    Takes the arguments of ``make_profile`` except ``t_s``; checks them the same way.
    """
    _check(kind, {k: v for k, v in locals().items() if k not in ("kind", "t_s")})
    if kind in ("via", "table"):
        times, _ = _knots(*((via_times, via_points) if kind == "via"
                            else (table_times, table_values)), kind)
        return float(times[0]), float(times[-1])
    if duration_s is not None or kind != "trapezoid":
        return 0.0, _checks.duration(duration_s)
    return 0.0, trapezoid_duration(_step(start, end, by), v_max, a_max)


def make_profile(kind: str, *, t_s, start=None, end=None, by=None, duration_s=None,
                 v_max=None, a_max=None, via_times=None, via_points=None, table_times=None,
                 table_values=None) -> Trajectory:
    """The motion profile named ``kind``, sampled at ``t_s``.

    .. code:: text

        cubic      -> cubic(start, end - start, duration_s, t_s)      (the seed's coeff_3rd)
        quintic    -> quintic(start, end - start, duration_s, t_s)
        trapezoid  -> trapezoid(start, end - start, t_s, v_max=, a_max=, duration_s=)
        via        -> via(via_times, via_points, t_s)
        table      -> table(table_times, table_values, t_s)
        (``by`` instead of ``end`` is passed as the displacement unchanged)

    Parameters
    ----------
    kind : str
        One of ``KINDS``: cubic, quintic, trapezoid, via, table.
    t_s : array_like, shape (N,)
        Evaluation times (s) inside ``profile_span(kind, ...)``.
    start, end, by : array_like, shape (channels,)
        Start and end, or start and displacement, SI (m or rad): cubic, quintic, trapezoid.
    duration_s : float
        Duration (s): cubic, quintic; trapezoid optional (None: the minimum time).
    v_max, a_max : float or array_like, shape (channels,)
        Trapezoid limits, per s and per s^2.
    via_times, via_points : array_like, shapes (K,) and (K, channels)
        Via points (SI) and their times (s), strictly increasing, K >= 2.
    table_times, table_values : array_like, shapes (K,) and (K, channels)
        A table (e.g. from ``read_table``): times (s) and positions (SI).

    Returns
    -------
    Trajectory
        ``x``, ``xd``, ``xdd`` of shape (N, channels), exact derivatives.
    """
    _check(kind, {k: v for k, v in locals().items() if k not in ("kind", "t_s")})
    if kind == "via":
        return via(via_times, via_points, t_s)
    if kind == "table":
        return table(table_times, table_values, t_s)
    dx = _step(start, end, by)
    if kind == "cubic":
        return cubic(start, dx, duration_s, t_s)
    if kind == "quintic":
        return quintic(start, dx, duration_s, t_s)
    return trapezoid(start, dx, t_s, v_max=v_max, a_max=a_max, duration_s=duration_s)
