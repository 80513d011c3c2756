"""Run a study: load its robot, apply its parameters, make its motion (or simulation), and return
labelled columns with units.

Columns (one header row in the CSV): ``t_s``; the task coordinates (``x_mm``, ``y_mm``,
``phi_rad``); every joint coordinate ``q<k>_rad`` with its rate ``qd<k>_rad_s`` and, for inverse
dynamics, acceleration ``qdd<k>_rad_s2`` (k numbers the robot's coordinates, passive joints of
closed chains included); the torque at each actuated coordinate ``tau<k>_n_m`` (same k); for
closed chains the reaction force at each cut joint ``fx_<joint>_n``, ``fy_<joint>_n`` (N, world
axes, on the cut joint's parent body); for forward dynamics ``energy_j``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..dynamics.inverse import torque_split
from ..errors import InputError
from ..model.robot import Robot, load
from ..motion.profiles import JointTrajectory, Trajectory, cubic
from . import spec as specs
from .builtin import find as find_builtin
from .parameters import to_si
from .result import Result


def load_study(study: str | Path | specs.Study) -> specs.Study:
    """A Study from itself, a study file, or a built-in study name."""
    if isinstance(study, specs.Study):
        return study
    text = str(study)
    if text.endswith(".toml") or "/" in text:
        return specs.load(Path(study))
    return specs.load(find_builtin(text))


def robot_of(study: specs.Study) -> Robot:
    """The study's robot with its parameter overrides applied (checked, SI)."""
    robot = load(study.robot)
    if study.parameters:
        where = f"{study.path}: parameters" if study.path else "parameters"
        robot = robot.with_parameters(**to_si(robot, study.parameters, where))
    return robot


def run(study: str | Path | specs.Study, samples: int | None = None) -> Result:
    """Run one study (a Study, a study file, or a built-in study name).

    Parameters
    ----------
    study : Study, str or Path
    samples : int, optional
        Overrides the study's number of evenly spaced samples (>= 2).

    Returns
    -------
    Result
        Columns with units in their names (see the module docstring).
    """
    st = load_study(study)
    if samples is not None and (not isinstance(samples, (int, np.integer)) or samples < 2):
        raise InputError(f"samples must be an integer >= 2 (got {samples})")
    robot = robot_of(st)
    if st.kind == "forward":
        return _forward(st, robot, samples)
    jt, x = joint_motion(st, robot, samples)
    return _inverse(st, robot, jt, x)


def joint_motion(st: specs.Study, robot: Robot, samples: int | None = None, *,
                 t: np.ndarray | None = None) -> tuple[JointTrajectory, np.ndarray | None]:
    """Every joint's motion (SI) of an inverse-dynamics study, and its task coordinates.

    At ``samples`` evenly spaced times (default the study's), or at the times ``t`` (s).
    """
    m = st.motion
    tr = trajectory(st, robot, samples) if t is None else profile_at(st, robot, np.asarray(t))
    if m.space == "task":
        from ..motion.ik import inverse_kinematics

        q_start = start_pose(st, robot)
        kw = {} if m.ik == "auto" and q_start is None else {"solver": m.ik, "q_start": q_start}
        jt = inverse_kinematics(robot, tr, **kw)  # TODO(helper-1 lands): always pass both
        return jt, tr.x
    if robot.is_closed_chain:
        from ..motion.closure import from_actuated

        guess = start_pose(st, robot)
        jt = from_actuated(robot, tr.t_s, tr.x, tr.xd, tr.xdd, q_guess=guess)
    else:
        jt = JointTrajectory(tr.t_s, tr.x, tr.xd, tr.xdd)
    return jt, (robot.task(jt.q)[0] if robot.task_names else None)


#: a start pose for the inverse kinematics only picks the assembly mode, so it may be typed
#: approximately; further off than this (m) it is not an assembled pose at all
START_POSE_GAP_M = 1e-3
#: the initial state of a simulation must be on the loops: this is the loops' own tolerance
#: (m), the forward dynamics' drift limit
STATE_GAP_M = 1e-9


def start_pose(st: specs.Study, robot: Robot) -> np.ndarray | None:
    """``motion.start_pose`` in rad; a closed chain's must be roughly assembled."""
    if st.motion.start_pose is None:
        return None
    _check_width(st, "motion.start_pose", st.motion.start_pose, robot.n, "coordinate")
    q = np.array(st.motion.start_pose) * st.angle_si
    _check_loops(st, robot, "motion.start_pose", q, START_POSE_GAP_M)
    return q


def initial_state(st: specs.Study, robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """(q0, qd0) in rad and rad/s. A closed chain's q0 is every coordinate, on the loops, or
    its actuated joints only: the loops then give the passive ones (Newton from the drawn
    pose), and qd0 (actuated joints too) the passive rates."""
    s = st.simulation
    n_act = len(robot.actuated)
    if robot.is_closed_chain and len(s.q0) == n_act:
        from ..motion.closure import complete_rates, solve_passive

        qa = np.array(s.q0) * st.angle_si
        qda = np.zeros(n_act) if s.qd0 is None else np.array(s.qd0) * st.angle_si
        _check_width(st, "simulation.qd0", qda, n_act, "actuated joint")
        q0 = solve_passive(robot, qa[None])[0]
        qd0, _ = complete_rates(robot, q0[None], qda[None], np.zeros((1, n_act)))
        return q0, qd0[0]
    what = "coordinate (or actuated joint, for a closed chain)" if robot.is_closed_chain \
        else "coordinate"
    _check_width(st, "simulation.q0", s.q0, robot.n, what)
    q0 = np.array(s.q0) * st.angle_si
    qd0 = np.zeros(robot.n) if s.qd0 is None else np.array(s.qd0) * st.angle_si
    _check_width(st, "simulation.qd0", qd0, robot.n, "coordinate")
    _check_loops(st, robot, "simulation.q0", q0, STATE_GAP_M)
    if robot.is_closed_chain:
        rate = np.abs(robot.constraint_jacobian(q0).reshape(robot.n_constraints, robot.n) @ qd0)
        if np.max(rate) > STATE_GAP_M:
            raise InputError(f"{st.path or st.name}: simulation.qd0 breaks the loops: "
                             f"Phi_q qd0 = {np.max(rate):.3g} m/s (limit {STATE_GAP_M:g}); give "
                             f"the actuated joints' rates only ({n_act} values) and the loops "
                             "give the rest")
    return q0, qd0


def _check_loops(st, robot: Robot, fld: str, q: np.ndarray, limit: float) -> None:
    if not robot.is_closed_chain:
        return
    gap = np.abs(robot.constraint(q)).reshape(-1, 2)
    worst = int(np.argmax(np.max(gap, axis=1)))
    if gap.max() > limit:
        hint = (f"; give the actuated joints only ({len(robot.actuated)} values) and the "
                "loops give the rest" if fld == "simulation.q0" else "")
        raise InputError(f"{st.path or st.name}: {fld} does not close the loop at cut joint "
                         f"{robot.loops[worst]}: the joint's two points are "
                         f"{np.hypot(*gap[worst]) * 1e3:.4g} mm apart (limit "
                         f"{limit * 1e3:g} mm){hint}")


def channel_scale(st: specs.Study, robot: Robot) -> np.ndarray:
    """SI factor of each motion channel: lengths for x, y; angles for phi and joints."""
    m = st.motion
    if m.space == "task":
        return np.array([st.angle_si if n == "phi" else st.length_si for n in robot.task_names])
    width = len(robot.actuated) if robot.is_closed_chain else robot.n
    return np.full(width, st.angle_si)


def trajectory(st: specs.Study, robot: Robot, samples: int | None = None) -> Trajectory:
    """The study's motion profile at its evenly spaced samples, in SI."""
    return profile_at(st, robot, np.linspace(0.0, duration(st, robot), samples or st.motion.samples))


def duration(st: specs.Study, robot: Robot) -> float:
    """The motion's duration (s): given, or set by the profile (via points, table, trapezoid)."""
    m = st.motion
    if m.duration_s is not None:
        return m.duration_s
    return float(profile_at(st, robot, None).t_s[-1])


def profile_at(st: specs.Study, robot: Robot, t: np.ndarray | None) -> Trajectory:
    """The study's motion profile at times ``t`` (s), in SI; ``t = None``: at its own knots."""
    m = st.motion
    scale = channel_scale(st, robot)
    what = ("task coordinates (" + ", ".join(robot.task_names) + ")" if m.space == "task" else
            "actuated joints" if robot.is_closed_chain else "joints")
    if m.profile in ("cubic", "quintic", "trapezoid"):
        _check_width(st, "motion.start", m.start, len(scale), what)
        start = np.array(m.start) * scale
        by = (np.array(m.by) * scale if m.by is not None
              else np.array(m.end) * scale - start)
        if m.profile == "cubic":  # the seed's form, bit for bit
            return cubic(start, by, m.duration_s, np.array([0.0, m.duration_s]) if t is None else t)
    return _profile(m, scale, t)


def _profile(m: specs.Motion, scale: np.ndarray, t) -> Trajectory:
    raise InputError(f"profile {m.profile!r} is not available yet")


def _check_width(st, fld: str, values, width: int, what: str) -> None:
    if len(values) != width:
        raise InputError(f"{st.path or st.name}: {fld}: {st.robot} needs {width} values, one per "
                         f"{what} (got {len(values)})")


def _inverse(st: specs.Study, robot: Robot, jt: JointTrajectory, x) -> Result:
    cols = {"t_s": jt.t_s}
    if x is not None:
        cols.update(task_columns(robot, x))
    for i in range(robot.n):
        cols[f"q{i + 1}_rad"] = jt.q[:, i]
    for i in range(robot.n):
        cols[f"qd{i + 1}_rad_s"] = jt.qd[:, i]
    for i in range(robot.n):
        cols[f"qdd{i + 1}_rad_s2"] = jt.qdd[:, i]
    if robot.is_closed_chain:
        tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=jt.t_s)
    else:
        tau, lam = robot.inverse_dynamics(jt.q, jt.qd, jt.qdd), None
    for k, i in enumerate(robot.actuated):
        cols[f"tau{i + 1}_n_m"] = tau[:, k]
    for k, loop in enumerate(robot.loops):
        cols[f"fx_{loop}_n"] = lam[:, 2 * k]
        cols[f"fy_{loop}_n"] = lam[:, 2 * k + 1]
    note = _coordinates_note(robot)
    if robot.is_closed_chain:
        drift = float(np.max(np.abs(robot.constraint(jt.q))))
        note += (f"; loop residual max |Phi| = {drift:.1e} m; f*: force on the cut joint's "
                 "parent body")
    solver = getattr(jt, "solver", "")
    if st.motion.space == "joint" and robot.is_closed_chain:
        solver = "passive joints from the loops (Newton, continued)"
    if solver:
        note += f"; {'inverse kinematics' if st.motion.space == 'task' else 'joints'}: {solver}"
    split = torque_split(robot, jt.q, jt.qd, jt.qdd, t=jt.t_s)
    return Result(st.name, st.title, cols, kind="torques", note=note, split=split,
                  robot=robot.name, solver=solver, actuated=robot.actuated)


def _forward(st: specs.Study, robot: Robot, samples: int | None) -> Result:
    from ..dynamics.forward import simulate

    s = st.simulation
    t = np.linspace(0.0, s.duration_s, samples or s.samples)
    q0, qd0 = initial_state(st, robot)
    sim = simulate(robot, q0, qd0, (0.0, s.duration_s), t_eval=t, torque=_torque(st, robot),
                   method=s.method, rtol=s.rtol, atol=s.atol)
    cols = {"t_s": t}
    if robot.task_names:
        cols.update(task_columns(robot, robot.task(sim.q)[0].reshape(len(t), -1)))
    for i in range(robot.n):
        cols[f"q{i + 1}_rad"] = sim.q[:, i]
    for i in range(robot.n):
        cols[f"qd{i + 1}_rad_s"] = sim.qd[:, i]
    cols["energy_j"] = sim.energy_j
    note = (f"{_coordinates_note(robot)}; energy drift {sim.energy_drift:.2e} (relative), "
            f"{sim.method} rtol {sim.rtol:g}")
    split = {}
    if not robot.is_closed_chain:
        # tau = 0 in a free swing: the split shows how M qdd, C qd and g balance each other
        qdd = robot.forward_dynamics(sim.q, sim.qd, sim.tau)
        split = torque_split(robot, sim.q, sim.qd, qdd)
    return Result(st.name, st.title, cols, kind="angles", note=note, split=split,
                  robot=robot.name, actuated=robot.actuated)


def _torque(st: specs.Study, robot: Robot):
    """None (zero), a constant vector (N*m), or a function of time from a CSV table (linear)."""
    tq = st.simulation.torque
    width = len(robot.actuated) if robot.is_closed_chain else robot.n
    if tq is None:
        return None
    if isinstance(tq, tuple):
        _check_width(st, "simulation.torque", tq, width, "actuated joint")
        return np.array(tq)
    from ..motion.tables import read_table

    names = [f"tau{i + 1}_n_m" for i in (robot.actuated if robot.is_closed_chain
                                         else range(robot.n))]
    times, values = read_table(tq, names)
    lo, hi = times[0], times[-1]
    if lo > 0.0 or hi < st.simulation.duration_s:
        raise InputError(f"{tq}: the torque table covers {lo:g} to {hi:g} s, but the "
                         f"simulation runs from 0 to {st.simulation.duration_s:g} s")

    def tau(t: float) -> np.ndarray:
        return np.array([np.interp(t, times, values[:, k]) for k in range(width)])
    return tau


def task_columns(robot: Robot, x_si: np.ndarray) -> dict[str, np.ndarray]:
    """Task coordinates as the seed writes them: x, y in mm, phi in rad."""
    x_si = np.asarray(x_si).reshape(len(x_si), -1)
    return {(f"{n}_rad" if n == "phi" else f"{n}_mm"): (x_si[:, i] if n == "phi"
                                                        else x_si[:, i] * 1e3)
            for i, n in enumerate(robot.task_names)}


def _coordinates_note(robot: Robot) -> str:
    marks = [f"q{i + 1} = {name}{' (actuated)' if i in robot.actuated else ''}"
             for i, name in enumerate(robot.coordinates)]
    return "coordinates: " + ", ".join(marks)


def motion(study: str | Path | specs.Study, frames: int) -> tuple[Robot, np.ndarray, np.ndarray]:
    """Every joint's angle over a study at ``frames`` evenly spaced times, for pictures.

    Returns
    -------
    robot : Robot
    t : ndarray, shape (frames,)
        Time (s).
    q : ndarray, shape (frames, n)
        Every coordinate (rad): simulated for forward dynamics, and for inverse dynamics the
        full joint trajectory, passive joints of closed chains included.
    """
    st = load_study(study)
    if not isinstance(frames, (int, np.integer)) or frames < 2:
        raise InputError(f"the number of frames must be an integer >= 2 (got {frames})")
    robot = robot_of(st)
    if st.kind == "forward":
        result = _forward(st, robot, frames)
        q = np.column_stack([result.columns[f"q{i + 1}_rad"] for i in range(robot.n)])
        return robot, result.columns["t_s"], q
    jt, _ = joint_motion(st, robot, frames)
    return robot, jt.t_s, jt.q
