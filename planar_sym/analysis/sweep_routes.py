"""How a sweep evaluates its designs, by route: which route a study takes (``_route``), and
one batch of designs (``_Job``) run on it (``_run_job``) into its figures (``_Out``).

Routes: "shared motion" (the motion solved once, the inverse dynamics in one C loop over the
batch), "motion per design" (the study's motion code per design, then that C loop), and "per
design" or "atlas" (the whole run per design). A batch travels to a worker (a thread, a
process, a cluster), so a job holds all it needs and a failing design is a message, not an
exception.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..dynamics.sizing import rms_weights
from ..errors import PlanarSymError
from ..model.robot import Robot
from ..study import spec as specs
from .designs import DesignSpace
from .sweep_figures import atlas_figures, run_figures_and_limits, singular_designs, torque_figures
from .sweep_limits import over_limits
from .sweep_motor import gear_ratios, has_drives, motor_figures, peak_torque
from .sweep_plant import plant_overrides


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
    if st.kind != "inverse" or st.optimise is not None:
        # an [optimise] study's timing depends on each design's dynamics: its own run each
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
    figures: dict  # Figure -> (designs,) values
    failed: dict[int, str]
    over: dict[int, str] = field(default_factory=dict)  # design -> the limits it passes


def _run_job(job: _Job) -> _Out:
    if job.route == "shared motion":
        return _shared(job)
    robot = job.robot
    if job.route == "motion per design":
        return _motion_per_design(job, robot)
    return _per_design(job, robot)


def _design(robot: Robot, p: np.ndarray) -> Robot:
    """The robot with one design's parameter vector (SI): its columns passed the same rules at
    once (``model.parameters.failing``) when the design space was made."""
    return robot.with_values(robot.parameters.with_vector(p, checked=True))


def _shared(job: _Job) -> _Out:
    robot = job.robot
    q, qd, qdd, t = job.shared
    closed = robot.is_closed_chain
    fn = robot._closed_inverse_dynamics if closed else robot.tree_inverse_dynamics
    stats = fn.designs(job.P, q, qd, qdd, reduce=True, weights=rms_weights(t))
    figs = torque_figures(robot, stats, closed)
    if has_drives(robot):
        figs.update(motor_figures(robot, fn, job.P, (q, qd, qdd), t, figs))
    return _Out(figs, singular_designs(figs, job.start),
                _limits(robot, job.P, figs, qd, job.start))


def _limits(robot: Robot, P: np.ndarray, figs: dict, qd: np.ndarray, start: int
            ) -> dict[int, str]:
    """The designs (numbered from ``start``) whose peaks pass an actuator limit."""
    act = list(robot.actuated)
    peak = np.column_stack([figs[peak_torque(robot, i)] for i in act])
    found = over_limits(robot, gear_ratios(robot, P), peak, np.abs(qd[..., act]).max(axis=-2))
    return {start + k: why for k, why in found.items()}


def _motion_per_design(job: _Job, robot: Robot) -> _Out:
    """The study's own motion code per design (its IK, its loops), then one C loop over the
    batch's designs for the inverse dynamics."""
    from ..study.motion import joint_motion

    D, closed = len(job.P), robot.is_closed_chain
    motions, failed, t = [], {}, None
    for k, p in enumerate(job.P):
        design = _design(robot, p)
        try:
            jt, _ = joint_motion(job.study, design)
            motions.append((jt.q, jt.qd, jt.qdd))
            t = jt.t_s  # the study's sample times: every design's
        except PlanarSymError as exc:
            failed[job.start + k] = str(exc)
            motions.append(None)
    ok = [k for k, m in enumerate(motions) if m is not None]
    figs = {}
    if ok:
        q, qd, qdd = (np.ascontiguousarray(np.stack([motions[k][j] for k in ok]))
                      for j in range(3))
        fn = robot._closed_inverse_dynamics if closed else robot.tree_inverse_dynamics
        sub = torque_figures(robot, fn.designs(job.P[ok], q, qd, qdd, reduce=True,
                                               weights=rms_weights(t)), closed)
        if has_drives(robot):
            sub.update(motor_figures(robot, fn, job.P[ok], (q, qd, qdd), t, sub))
        for name, v in sub.items():
            figs[name] = np.full(D, np.nan)
            figs[name][ok] = v
        for k, why in singular_designs(sub, 0).items():
            failed[job.start + ok[k]] = why
        over = {job.start + ok[k]: why
                for k, why in _limits(robot, job.P[ok], sub, qd, 0).items()}
    return _Out(figs, failed, over if ok else {})


def _per_design(job: _Job, robot: Robot) -> _Out:
    """Simulations, controlled runs, atlases (or the exact path): the whole run per design."""
    from dataclasses import replace

    rows, failed, over = [], {}, {}
    for k, p in enumerate(job.P):
        design = _design(robot, p)
        st = job.study
        if job.plant is not None:  # a control study: the design's plant over its model
            st = replace(st, control=replace(st.control, plant=plant_overrides(
                design, p, job.plant[k])))
        try:
            if job.route == "atlas":
                rows.append(atlas_figures(design, job.atlas))
            else:
                figs, passed = run_figures_and_limits(st, design)
                rows.append(figs)
                if passed:
                    over[job.start + k] = passed
        except PlanarSymError as exc:
            failed[job.start + k] = str(exc)
            rows.append(None)
    names = list(dict.fromkeys(n for r in rows if r for n in r))
    figs = {n: np.array([np.nan if r is None else r.get(n, np.nan) for r in rows]) for n in names}
    return _Out(figs, failed, over)
