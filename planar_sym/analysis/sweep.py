"""Sweeps: one study (or atlas) per design, its figures collected in one table.

Parameters go to the compiled code per call, never through a new ``Robot`` per design:

* **inverse-dynamics studies whose motion the varied parameters do not change** (masses,
  inertias, centres of gravity, gravity, and lengths a joint-space move of a tree does not
  use): the motion is solved once, and the generated inverse dynamics runs once per design in
  one C loop over the designs (``Caller.designs``, the GIL released), reducing each design's
  samples to its peak and RMS as it goes;
* **lengths that move the joints** (the inverse kinematics, a closed chain's passive joints):
  the study's own motion code runs per design, on the robot with that design's parameters
  (the same compiled code; its columns checked at once beforehand), and the inverse dynamics
  again in one C loop per batch of designs;
* **simulations, controlled runs and atlases**: the study (or atlas) runs per design on the
  robot with that design's parameters.

A control study has two parameter sets: the controller's model (the robot with the study's
``[parameters]``) and the plant (the model with ``[control.plant]`` on top). ``on`` says which
the designs change: both (default), the model only, or the plant only; the table has the
plant's value of every varied parameter beside the model's (``plant_<name>_<unit>``).

For a robot with actuator models (``[joints.actuator]``), an inverse-dynamics sweep also has the
motor side per actuator, at each design's own gear ratio N (a swept ``gear_<joint>`` included),
as ``dynamics.sizing.size`` computes it for one run: peak and RMS motor torque (tau / N; the RMS by
the trapezoidal rule over time), peak motor speed (N max|qd|, rpm) and peak power max|tau qd|
(W). These need every sample: the C loop's per-design min/max/mean square cannot give them, so
the shared-motion route makes a second pass over the designs in chunks of ``MOTOR_CHUNK``, each
chunk's torques (designs x samples) reduced in numpy.

Designs are split into batches that run on local threads by default (the C loops release the
GIL), or on any ``concurrent.futures``-style executor: a ``ProcessPoolExecutor``, or a
``dask.distributed.Client`` for a cluster. A robot travels to another process by reference
(``Robot.__reduce__``) and each worker process compiles it once into its own cache. A design
that fails (a target out of reach, a singular pose) is reported with its own message; a batch
whose worker fails is reported with the worker's error, and every finished design is kept.

Here the designs are split into batches and gathered into the table; the routes and a batch's
run are ``sweep_routes``, the table's type ``sweep_result``.
"""

from __future__ import annotations

import math
import os
import warnings
from concurrent.futures import Executor, ThreadPoolExecutor

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from ..study import spec as specs
from .designs import DesignSpace
from .figures import named, parameter_figure
from .sweep_plant import ON, on_note, parameter_index, plant_designs
from .sweep_result import SweepResult
from .sweep_routes import _Job, _Out, _route, _run_job, kinematic_parameters

# the result type and the routes are named here too, where they used to live
__all__ = ["FAST_BATCH", "ON", "SweepResult", "kinematic_parameters", "sweep"]

#: designs per batch where the motion is shared (one C loop each): large enough that the
#: Python around a batch is a few per cent, small enough to spread over cores
FAST_BATCH = 4096


def sweep(study, vary: dict, *, sample: str = "grid", count: int | None = None, seed: int = 0,
          executor: Executor | None = None, workers: int | None = None,
          batch: int | None = None, atlas: dict | None = None,
          on: str = "both", progress=None) -> SweepResult:
    """Run ``study`` once per design and collect its figures.

    Parameters
    ----------
    study : Study, str or Path
        A study (its robot, with the study's own ``[parameters]``, is the base design).
    vary : dict
        Parameter name -> values in SI: a list, ``(low, high, count)`` on a grid, or
        ``(low, high)`` with ``sample="random"`` (see ``designs.design_space``).
    sample, count, seed
        Grid (every combination) or ``count`` random designs drawn with ``seed``.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Where batches run; default ``workers`` local threads (default: every core).
    batch : int, optional
        Designs per batch (default ``FAST_BATCH`` where the motion is shared, else enough for
        four batches per worker).
    atlas : dict, optional
        Run ``analysis.atlas.atlas(robot, **atlas)`` per design instead of the study, and
        collect its summary (workspace area, worst dexterity, ...). ``study`` then only names
        the robot and its parameters.
    on : {"both", "model", "plant"}
        For a control study (or an optimal one with ``[control]``): the designs change the
        controller's model and the plant
        (default; a varied parameter that ``[control.plant]`` sets takes the design's value
        there too), the model only (the plant keeps the study's plant), or the plant only (the
        controller keeps the study's model). Any other study has one robot: only "both".
    progress : callable, optional
        Called as ``progress(done, total)`` with the numbers of designs done and in all after
        each batch (in the batches' order; ``planar_sym.progress.Meter``).

    Returns
    -------
    SweepResult
        Figures per design: for inverse dynamics ``peak_tau<k>_n_m`` and ``rms_tau<k>_n_m``
        per actuator (``_n`` for a force), for a closed chain ``peak_f_<cut>_n`` (the largest
        cut-joint force) and ``max_cond_phi_p`` (its worst passive-constraint conditioning); for
        simulations and control the same torque figures where there are torques, the largest
        tracking error and the energy figures. With actuator models (``[joints.actuator]``),
        inverse-dynamics and control sweeps add per actuator ``peak_motor_tau<k>_n_m``,
        ``rms_motor_tau<k>_n_m``, ``peak_motor_speed<k>_rpm`` and ``peak_power<k>_w``. RMS
        figures are time averages (the trapezoidal rule, as ``dynamics.sizing``). A design
        that passes a limit of its actuators (joint torque, motor torque, motor speed; a
        controlled run's actuator and joint-limit events) is named in ``over_limits``, its
        figures kept, and a warning says how many.
    """
    from ..study.run import load_study, robot_of

    st = load_study(study)
    if not isinstance(on, str) or on not in ON:
        raise InputError(f"on must be 'both', 'model' or 'plant' (got {on!r})")
    robot = robot_of(st)
    # a control study, or an optimal one tracked by [control]: a controller's model and a plant
    # (the optimal one's plant was left out: every design ran on the study's plant, silently)
    controlled = st.control is not None and atlas is None
    if on != "both" and not controlled:
        what = ("an atlas sweep runs on one robot" if atlas is not None else
                f"{st.name} is a study of kind = \"{st.kind}\": one robot, no plant")
        raise InputError(f"on = {on!r} is for control studies (a controller's model and a "
                         f"plant): {what}; leave on = 'both'")
    space, plant_P = plant_designs(st, robot, vary, on, sample=sample, count=count, seed=seed,
                              control=controlled)
    if workers is not None and (not isinstance(workers, (int, np.integer)) or workers < 1):
        raise InputError(f"workers must be an integer >= 1 (got {workers!r})")
    if batch is not None and (not isinstance(batch, (int, np.integer)) or batch < 1):
        raise InputError(f"batch must be an integer >= 1 (got {batch!r})")
    route, shared = _route(st, robot, space, atlas)
    n_workers = workers or os.cpu_count() or 1
    # at least one batch per worker (four where each design is slow), at most FAST_BATCH
    per = 1 if route == "shared motion" else 4
    size = batch or max(1, min(FAST_BATCH, math.ceil(len(space) / (per * n_workers))))
    jobs = [_Job(robot, st, space.P[k:k + size], k, route, shared, atlas,
                 None if plant_P is None else plant_P[k:k + size])
            for k in range(0, len(space), size)]
    own = executor is None
    pool = ThreadPoolExecutor(n_workers) if own else executor
    try:
        outs = _gather(pool, jobs, progress)
    finally:
        if own:
            pool.shutdown()
    return _table(st, robot, space, plant_P, on, route, jobs, outs)


def _gather(pool, jobs: list[_Job], progress=None) -> list[_Out | BaseException]:
    """Each batch's figures, or the exception its worker raised (the others are kept);
    ``progress(designs done, designs)`` after each batch."""
    futures = []
    for job in jobs:
        try:
            futures.append(pool.submit(_run_job, job))
        except Exception as exc:  # noqa: BLE001 - a refused submission loses only its batch
            futures.append(exc)
    outs: list[_Out | BaseException] = []
    done, total = 0, sum(len(job.P) for job in jobs)
    for job, fut in zip(jobs, futures):
        done += len(job.P)
        if isinstance(fut, BaseException):
            outs.append(fut)
        else:
            try:
                outs.append(fut.result())
            except Exception as exc:  # noqa: BLE001 - reported with the batch's designs
                outs.append(exc)
        if progress is not None:
            progress(done, total)
    return outs


def _table(st: specs.Study, robot: Robot, space: DesignSpace, plant_P: np.ndarray | None,
           on: str, route: str, jobs: list[_Job], outs: list) -> SweepResult:
    D = len(space)
    columns = space.columns()
    info = {f.name: f for f in map(parameter_figure, space.names, space.units)}
    if plant_P is not None:  # the plant's value of every varied parameter, beside the model's
        for name, unit in zip(space.names, space.units):
            f = parameter_figure(name, unit, "plant_")
            columns[f.name], info[f.name] = plant_P[:, parameter_index(robot, name)], f
    varied = tuple(columns)
    failed: dict[int, str] = {}
    over: dict[int, str] = {}
    figs = {}
    lost = 0
    for job, out in zip(jobs, outs):
        sl = slice(job.start, job.start + len(job.P))
        if isinstance(out, BaseException):
            why = f"worker error: {type(out).__name__}: {out}"
            failed.update({k: why for k in range(sl.start, sl.stop)})
            lost += len(job.P)
            continue
        for name, v in out.figures.items():
            figs.setdefault(name, np.full(D, np.nan))[sl] = v
        failed.update(out.failed)
        over.update(out.over)
    for k in failed:  # a failed design has no figures, whatever part of it was computed
        for v in figs.values():
            v[k] = np.nan
    values, kinds = named(figs)
    columns.update(values)
    note = f"{D} designs ({space.sample}), {route}"
    if plant_P is not None:
        note += "; " + on_note(st, robot, space, plant_P, on)
    over = {k: why for k, why in sorted(over.items()) if k not in failed}
    if over:
        note += f"; {len(over)} over an actuator limit"
        first = next(iter(over))
        warnings.warn(f"{len(over)} of {D} designs pass an actuator limit (first: design "
                      f"{first}, {over[first]}): see the table's limits column "
                      "(SweepResult.over_limits)", RuntimeWarning, stacklevel=3)
    if failed:
        note += f"; {len(failed)} failed"
    if lost:
        first = next(k for k, why in failed.items() if why.startswith("worker error"))
        warnings.warn(f"{lost} of {D} designs were lost to worker errors (first: design {first}, "
                      f"{failed[first]}); the other designs' figures are kept", RuntimeWarning,
                      stacklevel=3)
    return SweepResult(st.name, columns, varied, space.names, dict(sorted(failed.items())),
                       route, note, on, {**info, **kinds}, over)
