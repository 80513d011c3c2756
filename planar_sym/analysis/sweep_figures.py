"""A sweep's figures per design: the compiled loop's reductions as peak and RMS torque columns
(and the singular designs among them), one run's figures (peaks, RMS, tracking errors, work,
the motor side), an atlas's summary."""

from __future__ import annotations

import numpy as np

from ..model.loops import COND_LIMIT
from ..model.robot import Robot
from ..study import spec as specs
from ..study.result import coordinate_column
from .sweep_motor import has_drives, motor_columns


def torque_figures(robot: Robot, stats: np.ndarray, closed: bool) -> dict[str, np.ndarray]:
    """Peak and RMS per actuator from the C loop's (D, components, 3) min/max/mean-square;
    for a closed chain also the largest cut-joint force and the worst conditioning."""
    figs = {}
    na = len(robot.actuated)
    for k, i in enumerate(robot.actuated):
        c = k if closed else i
        name = coordinate_column("tau", i, robot.coordinate_units[i])
        figs[f"peak_{name}"] = np.maximum(-stats[:, c, 0], stats[:, c, 1])
        figs[f"rms_{name}"] = np.sqrt(stats[:, c, 2])
    if closed:
        for k, loop in enumerate(robot.loops):  # lambda's components: fx, fy per cut
            fx, fy = (np.maximum(-stats[:, na + 2 * k + j, 0], stats[:, na + 2 * k + j, 1])
                      for j in (0, 1))
            figs[f"peak_fx_{loop}_n"] = fx
            figs[f"peak_fy_{loop}_n"] = fy
        figs["max_cond_phi_p"] = stats[:, na + robot.n_constraints, 1]
    return figs


def singular_designs(figs: dict[str, np.ndarray], start: int) -> dict[int, str]:
    cond = figs.get("max_cond_phi_p")
    if cond is None:
        return {}
    bad = ~(cond <= COND_LIMIT)
    return {start + int(k): f"singular pose on the move: the passive-joint constraint Jacobian "
            f"Phi_p has condition number {cond[k]:.3g} > {COND_LIMIT:g}" for k in np.flatnonzero(bad)}


def run_figures(st: specs.Study, robot: Robot) -> dict[str, float]:
    """One run's figures: peak and RMS of every torque column; for a controlled run the
    largest tracking error of every coordinate and of the task point, and the work done; with
    actuator models, the motor side of the run's sizing (``Result.sizing``: the plant's, under
    control)."""
    from ..study.run import run_on

    res = run_on(st, robot)
    figs = {}
    for name, v in res.torques().items():
        figs[f"peak_{name}"] = float(np.max(np.abs(v)))
        figs[f"rms_{name}"] = float(np.sqrt(np.mean(v**2)))
    for name, v in res.columns.items():
        if name.startswith(("fx_", "fy_")):
            figs[f"peak_{name}"] = float(np.max(np.abs(v)))
        elif name.startswith("e") and name[1:2].isdigit() or name == "e_task_mm":
            figs[f"max_abs_{name}"] = float(np.max(np.abs(v)))
        elif name in ("work_j", "friction_j"):
            figs[f"final_{name}"] = float(v[-1])
        elif name == "energy_j":
            figs["energy_change_j"] = float(v[-1] - v[0])
    if has_drives(robot):
        for a in res.sizing:
            peak_t, rms_t, peak_w, peak_p = motor_columns(a.coordinate)
            figs[peak_t] = a.peak_motor_torque_n_m
            figs[rms_t] = a.rms_motor_torque_n_m
            figs[peak_w] = a.peak_motor_speed_rpm
            figs[peak_p] = a.peak_power_w
    return figs


def atlas_figures(robot: Robot, options: dict) -> dict[str, float]:
    from .atlas import atlas

    return {k: float(v) for k, v in atlas(robot, **options).summary().items()  # not labels
            if isinstance(v, (bool, int, float, np.bool_, np.number))}
