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

A control study has two parameter sets: the controller's model (the robot with the study's
``[parameters]``) and the plant (the model with ``[control.plant]`` on top). ``on`` says which
the designs change: both (default), the model only, or the plant only; the table has the
plant's value of every varied parameter beside the model's (``plant_<name>_<unit>``).

For a robot with actuator models (``[joints.actuator]``), an inverse-dynamics sweep also has the
motor side per actuator, at each design's own gear ratio N (a swept ``gear_<joint>`` included),
as ``study.sizing.size`` computes it for one run: peak and RMS motor torque (tau / N; the RMS by
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
from ..study.sizing import RPM
from .designs import DesignSpace, design_space, unit_suffix

#: designs per batch where the motion is shared (one C loop each): large enough that the
#: Python around a batch is a few per cent, small enough to spread over cores
FAST_BATCH = 4096
#: designs per numpy pass of the motor-side figures (their torques at every sample, designs x
#: samples x coordinates): a few hundred keep a pass in cache
MOTOR_CHUNK = 256
#: which parameter set of a control study the designs change
ON = ("both", "model", "plant")


@dataclass
class SweepResult:
    """The sweep's table: ``columns`` (name -> (D,) array, units in the names), the varied
    parameters first (``varied``, the columns of the parameters named in ``parameters``),
    then the figures; ``failed`` maps a design's index to why it has no figures (NaN in its
    row); ``route`` says how the designs were evaluated.

    Values are SI, the unit in each column's name (``m_link2_kg``, ``a2_m``, ``peak_tau1_n_m`` in
    N*m, ``max_abs_e1_rad`` in rad, ``final_work_j`` in J); ``D`` is the
    number of designs. ``study`` names the study swept; ``note`` sums the run up (designs,
    sampling, route, what was varied on which parameter set, failures). For a control study the
    varied columns are the controller's model's values (``m_link2_kg``) then the plant's
    (``plant_m_link2_kg``), and ``on`` says which of the two the designs changed ("both",
    "model" or "plant"; "both" for any other study, which has one robot).
    """

    study: str
    columns: dict[str, np.ndarray]
    varied: tuple[str, ...]
    parameters: tuple[str, ...] = ()
    failed: dict[int, str] = field(default_factory=dict)
    route: str = ""
    note: str = ""
    on: str = "both"

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
          batch: int | None = None, atlas: dict | None = None,
          on: str = "both") -> SweepResult:
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
        For a control study: the designs change the controller's model and the plant
        (default; a varied parameter that ``[control.plant]`` sets takes the design's value
        there too), the model only (the plant keeps the study's plant), or the plant only (the
        controller keeps the study's model). Any other study has one robot: only "both".

    Returns
    -------
    SweepResult
        Figures per design: for inverse dynamics ``peak_tau<k>_n_m`` and ``rms_tau<k>_n_m``
        per actuator (``_n`` for a force), for a closed chain ``peak_f_<cut>_n`` (the largest
        cut-joint force) and ``max_cond_phi_p`` (its worst passive-constraint conditioning); for
        simulations and control the same torque figures where there are torques, the largest
        tracking error and the energy figures. With actuator models (``[joints.actuator]``),
        inverse-dynamics and control sweeps add per actuator ``peak_motor_tau<k>_n_m``,
        ``rms_motor_tau<k>_n_m``, ``peak_motor_speed<k>_rpm`` and ``peak_power<k>_w``.
    """
    from ..study.run import load_study, robot_of

    st = load_study(study)
    if not isinstance(on, str) or on not in ON:
        raise InputError(f"on must be 'both', 'model' or 'plant' (got {on!r})")
    robot = robot_of(st)
    if on != "both" and (st.kind != "control" or atlas is not None):
        what = ("an atlas sweep runs on one robot" if atlas is not None else
                f"{st.name} is a study of kind = \"{st.kind}\": one robot, no plant")
        raise InputError(f"on = {on!r} is for control studies (a controller's model and a "
                         f"plant): {what}; leave on = 'both'")
    space, plant_P = _designs(st, robot, vary, on, sample=sample, count=count, seed=seed,
                              control=atlas is None and st.kind == "control")
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
        outs = _gather(pool, jobs)
    finally:
        if own:
            pool.shutdown()
    return _table(st, robot, space, plant_P, on, route, jobs, outs)


# -- the two parameter sets of a control study -------------------------------------------------
def _designs(st: specs.Study, robot: Robot, vary: dict, on: str, *, sample: str,
             count: int | None, seed: int, control: bool) -> tuple[DesignSpace, np.ndarray | None]:
    """The designs' model parameter vectors (``space.P``: what the worker robot is set to) and,
    for a control study, the plant's (D, n_p). Each set a design changes is checked as a
    design of its own base: the study's robot, or the study's plant (``[control.plant]``)."""
    from ..study.parameters import with_overrides

    if not control:
        return design_space(robot, vary, sample=sample, count=count, seed=seed), None
    plant = with_overrides(robot, st.control.plant, f"{st.path or st.name}: control.plant")
    if on == "plant":
        try:
            space = design_space(plant, vary, sample=sample, count=count, seed=seed)
        except InputError as exc:
            raise InputError(f"the plant: {exc}") from None
        plant_P = space.P
        model = np.tile(robot.p, (len(space), 1))
        values = model[:, [_index(robot, n) for n in space.names]]
        return DesignSpace(space.names, space.units, values, model, space.sample), plant_P
    space = design_space(robot, vary, sample=sample, count=count, seed=seed)
    if on == "model":
        return space, np.tile(plant.p, (len(space), 1))
    # both: the plant's other [control.plant] values stay; the varied ones are the design's
    plant_P = np.tile(plant.p, (len(space), 1))
    for k, name in enumerate(space.names):
        plant_P[:, _index(robot, name)] = space.values[:, k]
    if not np.array_equal(plant_P, space.P):  # the plant is a design of its own base too
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a unit slip was said once, for the model
            try:
                design_space(plant, vary, sample=sample, count=count, seed=seed)
            except InputError as exc:
                raise InputError(f"the plant: {exc}") from None
    return space, plant_P


def _index(robot: Robot, name: str) -> int:
    return [par.name for par in robot.parameter_list].index(name)


def _plant_overrides(robot: Robot, p: np.ndarray, plant: np.ndarray) -> dict:
    """A design's ``[control.plant]``: every parameter where the plant differs from the model,
    in SI with its SI unit (so that ``to_si`` multiplies by exactly 1)."""
    return {par.name: (float(plant[k]), par.unit) for k, par in enumerate(robot.parameter_list)
            if plant[k] != p[k]}


def _on_note(st: specs.Study, robot: Robot, space: DesignSpace, plant_P: np.ndarray,
             on: str) -> str:
    """What the designs changed on which parameter set, and what the other one kept."""
    names = ", ".join(space.names)
    if on == "both":
        replaced = [n for n in space.names if n in st.control.plant]
        extra = (f" ([control.plant]'s {', '.join(replaced)} replaced by the design's)"
                 if replaced else "")
        return f"{names} varied on the controller's model and the plant{extra}"
    units = {par.name: par.unit for par in robot.parameter_list}
    kept = plant_P[0] if on == "model" else space.P[0]
    held = ", ".join(f"{n} = {kept[_index(robot, n)]:.6g} {units[n]}" for n in space.names)
    if on == "model":
        return f"{names} varied on the controller's model only: the plant keeps {held}"
    return f"{names} varied on the plant only: the controller's model keeps {held}"


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
    plant: np.ndarray | None = None  # a control study's plant parameter vectors (D, n_p)


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


# -- the motor side ------------------------------------------------------------------------------
def has_drives(robot: Robot) -> bool:
    """Whether the description models an actuator (``[joints.actuator]``: a gear, a rotor or
    friction). Without one every gear ratio is 1 and the motor figures would repeat the joint's."""
    return any(d.modelled for d in robot.drive_train.drives)


def gear_ratios(robot: Robot, P: np.ndarray) -> np.ndarray:
    """Each design's gear ratio per actuator, shape (D, actuated), dimensionless (motor rad per
    joint rad, per m at a slider): its ``gear_<joint>`` parameter where the robot has one (what
    the compiled code and ``DriveTrain.of`` use), else the description's figure (1 without an
    actuator model). ``P``: the designs' parameter vectors, shape (D, parameters), SI."""
    names = [par.name for par in robot.parameter_list]
    out = np.empty((len(P), len(robot.actuated)))
    for k, drive in enumerate(robot.drive_train.drives):
        key = f"gear_{drive.joint}"
        out[:, k] = P[:, names.index(key)] if key in names else drive.gear_ratio
    return out


def motor_columns(i: int) -> tuple[str, str, str, str]:
    """The motor-side figure columns of coordinate ``i`` (0-based): peak and RMS motor torque
    (N*m, also behind a slider's screw), peak motor speed (rpm), peak power (W)."""
    return (f"peak_motor_tau{i + 1}_n_m", f"rms_motor_tau{i + 1}_n_m",
            f"peak_motor_speed{i + 1}_rpm", f"peak_power{i + 1}_w")


def _trapezoid_weights(t: np.ndarray) -> np.ndarray:
    """w with w @ v**2 = the mean square of v(t) by the trapezoidal rule over t (``sizing``'s
    RMS); the plain mean over one sample or no time span."""
    span = t[-1] - t[0] if len(t) > 1 else 0.0
    if span <= 0:
        return np.full(len(t), 1.0 / len(t))
    dt = np.diff(t)
    w = np.zeros(len(t))
    w[:-1] += dt / 2
    w[1:] += dt / 2
    return w / span


def _motor_figures(robot: Robot, fn, P: np.ndarray, motion: tuple, t: np.ndarray,
                   joint: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Motor-side figures of the designs ``P`` along ``motion`` (q, qd, qdd: (N, n) shared or
    (D, N, n) per design): the torques again at every sample, ``MOTOR_CHUNK`` designs at a
    time, for the trapezoidal RMS and the peak power |tau qd| (a per-sample product the C
    loop's reduction cannot give); the peak motor torque from the joint's peak (``joint``)."""
    closed = robot.is_closed_chain
    q, qd, qdd = motion
    per_design = q.ndim == 3
    D, act = len(P), list(robot.actuated)
    ratios = gear_ratios(robot, P)
    w = _trapezoid_weights(t)
    ms, power = np.empty((D, len(act))), np.empty((D, len(act)))
    for s in range(0, D, MOTOR_CHUNK):
        sl = slice(s, s + MOTOR_CHUNK)
        args = (q[sl], qd[sl], qdd[sl]) if per_design else (q, qd, qdd)
        out = fn.designs(P[sl], *args)
        tau = out[0] if closed else out  # closed: the actuated torques; tree: every coordinate
        for k, i in enumerate(act):
            tk = tau[:, :, k if closed else i]  # (d, N), strided: each product below is new
            p = tk * args[1][..., i]  # the product sizing takes: tau * qd
            power[sl, k] = np.abs(p, out=p).max(axis=1)
            ms[sl, k] = np.square(tk) @ w
    speed = np.abs(qd[..., act]).max(axis=-2)  # (actuated,) shared, (D, actuated) per design
    figs = {}
    for k, i in enumerate(act):
        peak_t, rms_t, peak_w, peak_p = motor_columns(i)
        peak = joint["peak_" + coordinate_column("tau", i, robot.coordinate_units[i])]
        figs[peak_t] = peak / ratios[:, k]
        figs[rms_t] = np.sqrt(ms[:, k]) / ratios[:, k]
        figs[peak_w] = speed[..., k] * ratios[:, k] * RPM
        figs[peak_p] = power[:, k]
    return figs


def _shared(job: _Job) -> _Out:
    robot = job.robot
    q, qd, qdd, t = job.shared
    closed = robot.is_closed_chain
    fn = robot._closed_inverse_dynamics if closed else robot.tree_inverse_dynamics
    stats = fn.designs(job.P, q, qd, qdd, reduce=True)
    figs = _torque_figures(robot, stats, closed)
    if has_drives(robot):
        figs.update(_motor_figures(robot, fn, job.P, (q, qd, qdd), t, figs))
    return _Out(figs, _singular(figs, job.start))


def _motion_per_design(job: _Job, robot: Robot) -> _Out:
    """The study's own motion code per design (its IK, its loops), then one C loop over the
    batch's designs for the inverse dynamics."""
    from ..study.motion import joint_motion

    D, closed = len(job.P), robot.is_closed_chain
    motions, failed, t = [], {}, None
    for k, p in enumerate(job.P):
        robot.p[:] = p
        try:
            jt, _ = joint_motion(job.study, robot)
            motions.append((jt.q, jt.qd, jt.qdd))
            t = jt.t_s  # the study's sample times: every design's
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
        if has_drives(robot):
            sub.update(_motor_figures(robot, fn, job.P[ok], (q, qd, qdd), t, sub))
        for name, v in sub.items():
            figs[name] = np.full(D, np.nan)
            figs[name][ok] = v
        for k, why in _singular(sub, 0).items():
            failed[job.start + ok[k]] = why
    return _Out(figs, failed)


def _per_design(job: _Job, robot: Robot) -> _Out:
    """Simulations, controlled runs, atlases (or the exact path): the whole run per design."""
    from dataclasses import replace

    rows, failed = [], {}
    for k, p in enumerate(job.P):
        robot.p[:] = p
        st = job.study
        if job.plant is not None:  # a control study: the design's plant over its model
            st = replace(st, control=replace(st.control, plant=_plant_overrides(
                robot, p, job.plant[k])))
        try:
            rows.append(_atlas_figures(robot, job.atlas) if job.route == "atlas"
                        else run_figures(st, robot))
        except PlanarSymError as exc:
            failed[job.start + k] = str(exc)
            rows.append(None)
    names = list(dict.fromkeys(n for r in rows if r for n in r))
    figs = {n: np.array([np.nan if r is None else r.get(n, np.nan) for r in rows]) for n in names}
    return _Out(figs, failed)


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


def _atlas_figures(robot: Robot, options: dict) -> dict[str, float]:
    from .atlas import atlas

    return {k: float(v) for k, v in atlas(robot, **options).summary().items()  # not labels
            if isinstance(v, (bool, int, float, np.bool_, np.number))}


def _table(st: specs.Study, robot: Robot, space: DesignSpace, plant_P: np.ndarray | None,
           on: str, route: str, jobs: list[_Job], outs: list) -> SweepResult:
    D = len(space)
    columns = space.columns()
    if plant_P is not None:  # the plant's value of every varied parameter, beside the model's
        for name, unit in zip(space.names, space.units):
            columns[f"plant_{name}_{unit_suffix(unit)}"] = plant_P[:, _index(robot, name)]
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
    if plant_P is not None:
        note += "; " + _on_note(st, robot, space, plant_P, on)
    if failed:
        note += f"; {len(failed)} failed"
    if lost:
        first = next(k for k, why in failed.items() if why.startswith("worker error"))
        warnings.warn(f"{lost} of {D} designs were lost to worker errors (first: design {first}, "
                      f"{failed[first]}); the other designs' figures are kept", RuntimeWarning,
                      stacklevel=3)
    return SweepResult(st.name, columns, varied, space.names, dict(sorted(failed.items())),
                       route, note, on)

