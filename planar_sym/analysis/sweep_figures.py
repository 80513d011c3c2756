"""A sweep's figures per design: the compiled loop's reductions as peak and RMS torque columns
(and the singular designs among them), one run's figures (peaks, RMS, tracking errors, work,
the motor side), an atlas's summary. Each keyed by its typed ``figures.Figure`` (quantity,
unit, statistic), made from the run's series, never from column names."""

from __future__ import annotations

import numpy as np

from ..dynamics.series import coordinate_unit
from ..dynamics.sizing import rms
from ..model.loops import COND_LIMIT
from ..model.robot import Robot
from ..study import spec as specs
from .figures import COND, ENERGY_CHANGE, Figure
from .sweep_limits import run_over_limits
from .sweep_motor import has_drives, motor_figure_keys, peak_torque


def torque_figures(robot: Robot, stats: np.ndarray, closed: bool) -> dict[Figure, np.ndarray]:
    """Peak and RMS per actuator from the C loop's (D, components, 3) min/max/mean-square
    (each figure (D,), N*m or N at a slider; the mean square over time, weighted by
    ``sizing.rms_weights``); for a closed chain also the largest cut-joint force (N) and the
    worst conditioning."""
    figs = {}
    na = len(robot.actuated)
    for k, i in enumerate(robot.actuated):
        c = k if closed else i
        figs[peak_torque(robot, i)] = np.maximum(-stats[:, c, 0], stats[:, c, 1])
        unit = coordinate_unit("tau", robot.coordinate_units[i])
        figs[Figure.of("rms", "tau", unit, i)] = np.sqrt(stats[:, c, 2])
    if closed:
        for k, loop in enumerate(robot.loops):  # lambda's components: fx, fy per cut
            for j, quantity in enumerate(("fx", "fy")):
                figs[Figure.of("peak", quantity, "N", joint=loop)] = np.maximum(
                    -stats[:, na + 2 * k + j, 0], stats[:, na + 2 * k + j, 1])
        figs[COND] = stats[:, na + robot.n_constraints, 1]
    return figs


def singular_designs(figs: dict[Figure, np.ndarray], start: int) -> dict[int, str]:
    """The designs (numbered from ``start``) whose worst conditioning (``COND``, (D,)) passed
    ``COND_LIMIT``, each with why it failed."""
    cond = figs.get(COND)
    if cond is None:
        return {}
    bad = ~(cond <= COND_LIMIT)
    return {start + int(k): f"singular pose on the move: the passive-joint constraint Jacobian "
            f"Phi_p has condition number {cond[k]:.3g} > {COND_LIMIT:g}" for k in np.flatnonzero(bad)}


#: a run's series -> the figure a sweep keeps of it, by quantity
_RUN_STATISTIC = {"fx": "peak", "fy": "peak", "e": "max_abs", "e_task": "max_abs",
                  "work": "final", "friction": "final"}


def run_figures(st: specs.Study, robot: Robot) -> dict[Figure, float]:
    """One run's figures: peak and RMS of every torque (N*m, N at a slider; the RMS over time,
    ``sizing.rms``); the largest cut-joint forces (N); for a controlled run the largest tracking
    error of every coordinate (rad or m) and of the task point (mm), the work done and the
    friction loss (J); the energy change (J); with actuator models, the motor side of the run's
    sizing (``Result.sizing``: the plant's, under control)."""
    return run_figures_and_limits(st, robot)[0]


def run_figures_and_limits(st: specs.Study, robot: Robot) -> tuple[dict[Figure, float], str]:
    """``run_figures`` and the limits the run passed (``sweep_limits.run_over_limits``)."""
    from ..study.run import run_on

    res = run_on(st, robot)
    figs = {}
    t = res.get("t").values
    for s in res.series("tau"):
        figs[Figure.of_series("peak", s)] = float(np.max(np.abs(s.values)))
        figs[Figure.of_series("rms", s)] = rms(t, s.values)
    for s in res.series():
        statistic = _RUN_STATISTIC.get(s.quantity)
        v = s.values
        if statistic is not None:
            figs[Figure.of_series(statistic, s)] = float(v[-1] if statistic == "final"
                                                         else np.max(np.abs(v)))
        elif s.quantity == "energy":
            figs[ENERGY_CHANGE] = float(v[-1] - v[0])
    if has_drives(robot):
        for a in res.sizing:
            peak_t, rms_t, peak_w, peak_p = motor_figure_keys(a.coordinate)
            figs[peak_t] = a.peak_motor_torque_n_m
            figs[rms_t] = a.rms_motor_torque_n_m
            figs[peak_w] = a.peak_motor_speed_rpm
            figs[peak_p] = a.peak_power_w
    return figs, run_over_limits(res)


#: the atlas summary's figures that have a unit: (stem, unit)
ATLAS_UNITS = {"area_m2": ("area", "m^2"), "area_same_assembly_m2": ("area_same_assembly", "m^2"),
               "accel_m_s2": ("accel", "m/s^2"), "time_s": ("time", "s")}


def atlas_figures(robot: Robot, options: dict) -> dict[Figure, float]:
    """The atlas summary's numbers (``Atlas.summary``: areas in m^2, dexterity, counts), each
    with its unit (``ATLAS_UNITS``; a pure number otherwise)."""
    from .atlas import atlas

    return {Figure(k, *ATLAS_UNITS.get(k, (k, ""))): float(v)  # not labels
            for k, v in atlas(robot, **options).summary().items()
            if isinstance(v, (bool, int, float, np.bool_, np.number))}
