"""Sweeps: one study (or atlas) per design, its figures collected in one table.

Parameters go to the compiled code per call, never through a new ``Robot`` per design:

* **inverse-dynamics studies whose motion the varied parameters do not change** (masses,
  inertias, centres of gravity, gravity, and lengths a joint-space move of a tree does not
  use): the motion is solved once, and the generated inverse dynamics runs once per design in
  one C loop over the designs (``Caller.designs``, the GIL released), reducing each design's
  samples to its peak and RMS as it goes;
* **lengths that move the joints** (the inverse kinematics, a closed chain's passive joints):
  the study's own motion code runs per design, on one robot per worker whose parameter vector
  is set in place, and the inverse dynamics again in one C loop per batch of designs;
* **simulations, controlled runs and atlases**: the study (or atlas) runs per design on that
  worker robot.

Designs are split into batches that run on local threads by default (the C loops release the
GIL), or on any ``concurrent.futures``-style executor: a ``ProcessPoolExecutor``, or a
``dask.distributed.Client`` for a cluster. A robot travels to another process by reference
(``Robot.__reduce__``) and each worker process compiles it once into its own cache. A design
that fails (a target out of reach, a singular pose) is reported with its own message; a batch
whose worker fails is reported with the worker's error, and every finished design is kept.
"""

from __future__ import annotations

import math
import os
import warnings
from concurrent.futures import Executor, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, PlanarSymError
from ..model.robot import COND_LIMIT, Robot
from ..study import spec as specs
from ..study.result import coordinate_column
from .designs import DesignSpace, design_space

#: designs per batch where the motion is shared (one C loop each): large enough that the
#: Python around a batch is a few per cent, small enough to spread over cores
FAST_BATCH = 4096


@dataclass
class SweepResult:
    """The sweep's table: ``columns`` (name -> (D,) array, units in the names), the varied
    parameters first (``varied``, the columns of the parameters named in ``parameters``),
    then the figures; ``failed`` maps a design's index to why it has no figures (NaN in its
    row); ``route`` says how the designs were evaluated.

    Values are SI, the unit in each column's name (``m_link2_kg``, ``a2_m``, ``peak_tau1_n_m`` in
    N*m, ``max_abs_e1_rad`` in rad, ``final_work_j`` in J); ``D`` is the
    number of designs. ``study`` names the study swept; ``note`` sums the run up (designs,
    sampling, route, failures).
    """

    study: str
    columns: dict[str, np.ndarray]
    varied: tuple[str, ...]
    parameters: tuple[str, ...] = ()
    failed: dict[int, str] = field(default_factory=dict)
    route: str = ""
    note: str = ""

    def __len__(self) -> int:
        return len(next(iter(self.columns.values())))

    @property
    def figures(self) -> tuple[str, ...]:
        """The names of the figure columns (every column but the varied parameters')."""
        return tuple(k for k in self.columns if k not in self.varied)

    def csv_text(self) -> str:
        """The table as CSV; a failed design's figures are empty and ``error`` says why."""
        names = list(self.columns) + (["error"] if self.failed else [])
        lines = [",".join(names)]
        for k in range(len(self)):
            row = ["" if not np.isfinite(v[k]) else f"{v[k]:.12g}" for v in self.columns.values()]
            if self.failed:
                row.append('"' + self.failed.get(k, "").replace('"', "'") + '"')
            lines.append(",".join(row))
        return "\n".join(lines) + "\n"

    def write_csv(self, path: str | os.PathLike) -> Path:
        """Write ``csv_text()`` to ``path``, whole or not at all; returns the path."""
        from ..files import atomic_files

        path = Path(path)
        with atomic_files([path]) as (tmp,):
            tmp.write_text(self.csv_text())
        return path


def sweep(study, vary: dict, *, sample: str = "grid", count: int | None = None, seed: int = 0,
          executor: Executor | None = None, workers: int | None = None,
          batch: int | None = None, atlas: dict | None = None) -> SweepResult:
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

    Returns
    -------
    SweepResult
        Figures per design: for inverse dynamics ``peak_tau<k>_n_m`` and ``rms_tau<k>_n_m``
        per actuator (``_n`` for a force), for a closed chain ``peak_f_<cut>_n`` (the largest
        cut-joint force) and ``max_cond_phi_p`` (its worst passive-constraint conditioning); for
        simulations and control the same torque figures where there are torques, the largest
        tracking error and the energy figures.
    """
    from ..study.run import load_study, robot_of

    st = load_study(study)
    robot = robot_of(st)
    space = design_space(robot, vary, sample=sample, count=count, seed=seed)
    if workers is not None and (not isinstance(workers, (int, np.integer)) or workers < 1):
        raise InputError(f"workers must be an integer >= 1 (got {workers!r})")
    if batch is not None and (not isinstance(batch, (int, np.integer)) or batch < 1):
        raise InputError(f"batch must be an integer >= 1 (got {batch!r})")
    route, shared = _route(st, robot, space, atlas)
    n_workers = workers or os.cpu_count() or 1
    # at least one batch per worker (four where each design is slow), at most FAST_BATCH
    per = 1 if route == "shared motion" else 4
    size = batch or max(1, min(FAST_BATCH, math.ceil(len(space) / (per * n_workers))))
    jobs = [_Job(robot, st, space.P[k:k + size], k, route, shared, atlas)
            for k in range(0, len(space), size)]
    own = executor is None
    pool = ThreadPoolExecutor(n_workers) if own else executor
    try:
        outs = _gather(pool, jobs)
    finally:
        if own:
            pool.shutdown()
    return _table(st, space, route, jobs, outs)


# -- routes ------------------------------------------------------------------------------------
def kinematic_parameters(robot: Robot, space: str) -> set[str]:
    """Parameters that move the joints of a motion in ``space`` ("task" or "joint"): those the
    task point's coordinates depend on (task space), and the loop equations' (closed chains).
    Found by evaluating the compiled functions with each parameter changed, at random poses."""
    names = [par.name for par in robot.parameter_list]
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (4, robot.n))
    args = {"q": q, "qd": np.zeros_like(q)}
    quantities = ([("task", "x")] if space == "task" and robot.task_names else []) + (
        [("constraint", "phi")] if robot.is_closed_chain else [])
    moved = np.zeros(len(names), dtype=bool)
    for quantity, output in quantities:
        fn = robot.library.functions[quantity]
        ins = {name: args[name] for name, _ in fn.spec.inputs if name != "p"}
        base = fn(len(q), {**ins, "p": robot.p})[output]
        for k in range(len(names)):
            p = robot.p.copy()
            p[k] = p[k] * 1.5 + 0.1
            moved[k] |= bool(np.any(fn(len(q), {**ins, "p": p})[output] != base))
    return {n for n, m in zip(names, moved) if m}


def _route(st: specs.Study, robot: Robot, space: DesignSpace, atlas) -> tuple[str, tuple]:
    """How the designs are evaluated, and the motion they share (if they do)."""
    if atlas is not None:
        return "atlas", ()
    if st.kind != "inverse":
        return "per design", ()
    if not hasattr(robot.tree_inverse_dynamics, "designs"):  # exact path, or no C extension
        return "per design", ()
    moving = kinematic_parameters(robot, st.motion.space) & set(space.names)
    if moving:
        return "motion per design", ()
    from ..study.motion import joint_motion

    if not robot.is_closed_chain:
        robot._refuse_passive_joints()
    jt, _ = joint_motion(st, robot)
    return "shared motion", (jt.q, jt.qd, jt.qdd, jt.t_s)


@dataclass
class _Job:
    robot: Robot
    study: specs.Study
    P: np.ndarray
    start: int
    route: str
    shared: tuple
    atlas: dict | None


@dataclass
class _Out:
    figures: dict[str, np.ndarray]
    failed: dict[int, str]


def _gather(pool, jobs: list[_Job]) -> list[_Out | BaseException]:
    """Each batch's figures, or the exception its worker raised (the others are kept)."""
    futures = []
    for job in jobs:
        try:
            futures.append(pool.submit(_run_job, job))
        except Exception as exc:  # noqa: BLE001 - a refused submission loses only its batch
            futures.append(exc)
    outs: list[_Out | BaseException] = []
    for fut in futures:
        if isinstance(fut, BaseException):
            outs.append(fut)
            continue
        try:
            outs.append(fut.result())
        except Exception as exc:  # noqa: BLE001 - reported with the batch's designs
            outs.append(exc)
    return outs


def _run_job(job: _Job) -> _Out:
    if job.route == "shared motion":
        return _shared(job)
    robot = Robot(job.robot.name, job.robot.library, job.robot.p.copy(), exact=job.robot.exact)
    if job.route == "motion per design":
        return _motion_per_design(job, robot)
    return _per_design(job, robot)


def _torque_figures(robot: Robot, stats: np.ndarray, closed: bool) -> dict[str, np.ndarray]:
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


def _singular(figs: dict[str, np.ndarray], start: int) -> dict[int, str]:
    cond = figs.get("max_cond_phi_p")
    if cond is None:
        return {}
    bad = ~(cond <= COND_LIMIT)
    return {start + int(k): f"singular pose on the move: the passive-joint constraint Jacobian "
            f"Phi_p has condition number {cond[k]:.3g} > {COND_LIMIT:g}" for k in np.flatnonzero(bad)}


def _shared(job: _Job) -> _Out:
    robot = job.robot
    q, qd, qdd, _ = job.shared
    closed = robot.is_closed_chain
    fn = robot._closed_inverse_dynamics if closed else robot.tree_inverse_dynamics
    stats = fn.designs(job.P, q, qd, qdd, reduce=True)
    figs = _torque_figures(robot, stats, closed)
    return _Out(figs, _singular(figs, job.start))


def _motion_per_design(job: _Job, robot: Robot) -> _Out:
    """The study's own motion code per design (its IK, its loops), then one C loop over the
    batch's designs for the inverse dynamics."""
    from ..study.motion import joint_motion

    D, closed = len(job.P), robot.is_closed_chain
    motions, failed = [], {}
    for k, p in enumerate(job.P):
        robot.p[:] = p
        try:
            jt, _ = joint_motion(job.study, robot)
            motions.append((jt.q, jt.qd, jt.qdd))
        except PlanarSymError as exc:
            failed[job.start + k] = str(exc)
            motions.append(None)
    ok = [k for k, m in enumerate(motions) if m is not None]
    figs: dict[str, np.ndarray] = {}
    if ok:
        q, qd, qdd = (np.ascontiguousarray(np.stack([motions[k][j] for k in ok]))
                      for j in range(3))
        fn = robot._closed_inverse_dynamics if closed else robot.tree_inverse_dynamics
        sub = _torque_figures(robot, fn.designs(job.P[ok], q, qd, qdd, reduce=True), closed)
        for name, v in sub.items():
            figs[name] = np.full(D, np.nan)
            figs[name][ok] = v
        for k, why in _singular(sub, 0).items():
            failed[job.start + ok[k]] = why
    return _Out(figs, failed)


def _per_design(job: _Job, robot: Robot) -> _Out:
    """Simulations, controlled runs, atlases (or the exact path): the whole run per design."""
    rows, failed = [], {}
    for k, p in enumerate(job.P):
        robot.p[:] = p
        try:
            rows.append(_atlas_figures(robot, job.atlas) if job.route == "atlas"
                        else run_figures(job.study, robot))
        except PlanarSymError as exc:
            failed[job.start + k] = str(exc)
            rows.append(None)
    names = list(dict.fromkeys(n for r in rows if r for n in r))
    figs = {n: np.array([np.nan if r is None else r.get(n, np.nan) for r in rows]) for n in names}
    return _Out(figs, failed)


def run_figures(st: specs.Study, robot: Robot) -> dict[str, float]:
    """One run's figures: peak and RMS of every torque column; for a controlled run the
    largest tracking error of every coordinate and of the task point, and the work done."""
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
    return figs


def _atlas_figures(robot: Robot, options: dict) -> dict[str, float]:
    from .atlas import atlas

    return {k: float(v) for k, v in atlas(robot, **options).summary().items()  # not labels
            if isinstance(v, (bool, int, float, np.bool_, np.number))}


def _table(st: specs.Study, space: DesignSpace, route: str, jobs: list[_Job],
           outs: list) -> SweepResult:
    D = len(space)
    columns = space.columns()
    varied = tuple(columns)
    failed: dict[int, str] = {}
    figs: dict[str, np.ndarray] = {}
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
    for k in failed:  # a failed design has no figures, whatever part of it was computed
        for v in figs.values():
            v[k] = np.nan
    columns.update(figs)
    note = f"{D} designs ({space.sample}), {route}"
    if failed:
        note += f"; {len(failed)} failed"
    if lost:
        first = next(k for k, why in failed.items() if why.startswith("worker error"))
        warnings.warn(f"{lost} of {D} designs were lost to worker errors (first: design {first}, "
                      f"{failed[first]}); the other designs' figures are kept", RuntimeWarning,
                      stacklevel=3)
    return SweepResult(st.name, columns, varied, space.names, dict(sorted(failed.items())),
                       route, note)

