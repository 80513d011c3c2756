"""Run a study: load its robot, apply its parameters, make its motion (or simulation), and return
labelled columns with units.

Columns (one header row in the CSV): ``t_s``; the task coordinates (``x_mm``, ``y_mm``,
``phi_rad``); every joint coordinate ``q<k>_rad`` with its rate ``qd<k>_rad_s`` and, for inverse
dynamics, acceleration ``qdd<k>_rad_s2`` (k numbers the robot's coordinates, passive joints of
closed chains included); the torque at each actuated coordinate ``tau<k>_n_m`` (same k); for
closed chains the reaction force at each cut joint ``fx_<joint>_n``, ``fy_<joint>_n`` (N, world
axes, on the cut joint's parent body); for inverse dynamics every joint's load (``load_columns``:
``jfx_<joint>_n``, ``jfy_<joint>_n``, ``jload_<joint>_n``, ``jm_<joint>_n_m``, ``jfn_<joint>_n``,
the parent body on the child body); for forward dynamics ``energy_j``.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..dynamics.inverse import torque_split
from ..dynamics.reactions import JointLoads, joint_loads
from ..errors import InputError
from ..model.locate import load
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from . import spec as specs
from .builtin import find as find_builtin
from .columns import coordinates_note as _coordinates_note
from .columns import task_columns
from .motion import initial_state, joint_motion
from .parameters import with_overrides
from .result import Result, coordinate_column
from .sizing import size


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
        robot = with_overrides(robot, study.parameters, where)
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
    return run_on(st, robot_of(st), samples)


def run_on(st: specs.Study, robot: Robot, samples: int | None = None) -> Result:
    """Run ``st`` on ``robot`` as it is (its parameters, not the study's overrides): what a
    sweep calls once per design, on one robot whose parameter vector it sets in place."""
    if st.kind == "forward":
        return _forward(st, robot, samples)
    if st.kind == "control":
        from .control_run import run_control

        return run_control(st, robot, samples)
    jt, x = joint_motion(st, robot, samples)
    return _inverse(st, robot, jt, x)


def _inverse(st: specs.Study, robot: Robot, jt: JointTrajectory, x) -> Result:
    cols = {"t_s": jt.t_s}
    if x is not None:
        cols.update(task_columns(robot, x))
    units = robot.coordinate_units
    for kind, values in (("q", jt.q), ("qd", jt.qd), ("qdd", jt.qdd)):
        for i in range(robot.n):
            cols[coordinate_column(kind, i, units[i])] = values[:, i]
    if robot.is_closed_chain:
        tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=jt.t_s)
    else:
        tau, lam = robot.inverse_dynamics(jt.q, jt.qd, jt.qdd), None
    for k, i in enumerate(robot.actuated):
        cols[coordinate_column("tau", i, units[i])] = tau[:, k]
    for k, loop in enumerate(robot.loops):
        cols[f"fx_{loop}_n"] = lam[:, 2 * k]
        cols[f"fy_{loop}_n"] = lam[:, 2 * k + 1]
    cols.update(load_columns(joint_loads(robot, jt.q, jt.qd, jt.qdd, t=jt.t_s,
                                         inverse=(tau, lam))))
    note = _coordinates_note(robot)
    if robot.is_closed_chain:
        drift = float(np.max(np.abs(robot.constraint(jt.q))))
        note += (f"; loop residual max |Phi| = {drift:.1e} m; f*: force on the cut joint's "
                 "parent body")
    note += "; jf*, jm*: joint loads, parent on child (world axes; jload = |jf|)"
    solver = getattr(jt, "solver", "")
    if st.motion.space == "joint" and robot.is_closed_chain:
        solver = "passive joints from the loops (Newton, continued)"
    if solver:
        note += f"; {'inverse kinematics' if st.motion.space == 'task' else 'joints'}: {solver}"
    split = torque_split(robot, jt.q, jt.qd, jt.qdd, t=jt.t_s)
    sizing = size(robot, jt.t_s, jt.qd, tau)
    for k, i in enumerate(robot.actuated):  # the power each actuator delivers
        cols[f"p{i + 1}_w"] = tau[:, k] * jt.qd[:, i]
    over = [e for s in sizing for e in s.exceeded]
    if over:
        note += "; ACTUATOR LIMITS EXCEEDED: " + "; ".join(over)
    return Result(st.name, st.title, cols, kind="torques", note=note, split=split,
                  sizing=sizing,
                  robot=robot.name, solver=solver, actuated=robot.actuated)


def load_columns(loads: JointLoads) -> dict[str, np.ndarray]:
    """Every joint's load as columns: ``jfx_<joint>_n``, ``jfy_<joint>_n`` (N, world axes, the
    parent body on the child body), ``jload_<joint>_n`` (|F|, the bearing load); the reaction
    couple ``jm_<joint>_n_m`` (N*m) of welds and prismatic joints (a revolute joint's couple is
    its torque column, or 0 if passive); a prismatic joint's normal force ``jfn_<joint>_n``."""
    cols = {}
    load = loads.magnitude
    for i, (name, kind) in enumerate(zip(loads.names, loads.types)):
        cols[f"jfx_{name}_n"] = loads.force[:, i, 0]
        cols[f"jfy_{name}_n"] = loads.force[:, i, 1]
        cols[f"jload_{name}_n"] = load[:, i]
        if kind in ("weld", "prismatic"):
            cols[f"jm_{name}_n_m"] = loads.couple[:, i]
        if kind == "prismatic":
            cols[f"jfn_{name}_n"] = loads.normal[name]
    return cols


def _forward(st: specs.Study, robot: Robot, samples: int | None) -> Result:
    s = st.simulation
    t = np.linspace(0.0, s.duration_s, samples or s.samples)
    q0, qd0 = initial_state(st, robot)
    sim = _simulate(st, robot, q0, qd0, t)
    cols = {"t_s": t}
    if robot.task_names:
        cols.update(task_columns(robot, robot.task(sim.q)[0].reshape(len(t), -1)))
    for kind, values in (("q", sim.q), ("qd", sim.qd)):
        for i in range(robot.n):
            cols[coordinate_column(kind, i, robot.coordinate_units[i])] = values[:, i]
    if s.torque is not None:
        for k, i in enumerate(robot.actuated):
            cols[coordinate_column("tau", i, robot.coordinate_units[i])] = sim.tau[:, k]
    cols["energy_j"] = sim.energy_j
    drift = ("energy change (the actuators' friction dissipates it)" if robot.has_friction
             else "energy drift")
    if s.torque is not None:
        drift = "energy change (the input torques do work)"
    note = (f"{_coordinates_note(robot)}; {drift} {sim.energy_drift:.2e} (relative), "
            f"{sim.method} rtol {sim.rtol:g}")
    if s.torque is not None:
        note += "; input torques " + _input_note(s.torque)
    split = {}
    if not robot.is_closed_chain and s.torque is None:
        # tau = 0 in a free swing: the split shows how M qdd, C qd and g balance each other
        qdd = robot.forward_dynamics(sim.q, sim.qd, np.zeros_like(sim.q))
        split = torque_split(robot, sim.q, sim.qd, qdd)
    return Result(st.name, st.title, cols, kind="angles", note=note, split=split,
                  robot=robot.name, actuated=robot.actuated)


def _simulate(st: specs.Study, robot: Robot, q0, qd0, t):
    """A forward run through ``dynamics.forward.simulate``, the one entry point (constant
    torques in the C integrator, a table or a profile and SUNDIALS in the engine, SciPy with
    the table evaluated in Python). ``tau`` comes back on the actuated joints."""
    from ..dynamics.forward import simulate
    from .control_run import torque_input

    s = st.simulation
    u = torque_input(st, robot, s.torque, s.duration_s, "simulation.torque")
    sim = simulate(robot, q0, qd0, (0.0, s.duration_s), t_eval=t, torque=u,
                   method=s.method, rtol=s.rtol, atol=s.atol)
    act = list(robot.actuated)
    tau = sim.tau[:, act] if sim.tau.shape[1] == robot.n and len(act) < robot.n else sim.tau
    return replace(sim, tau=tau)  # on the actuated joints, as the engine gives them


def _input_note(tq) -> str:
    if tq.constant is not None:
        return "constant"
    if tq.profile is not None:
        return f"{tq.profile} profile over {tq.duration_s:g} s, then held"
    return f"from {tq.file.name}, {tq.interpolation} between rows"


def motion(study: str | Path | specs.Study, frames: int) -> tuple[Robot, np.ndarray, np.ndarray]:
    """Every joint's angle over a study at ``frames`` evenly spaced times, for pictures.

    Returns
    -------
    robot : Robot
    t : ndarray, shape (frames,)
        Time (s).
    q : ndarray, shape (frames, n)
        Every coordinate (rad): simulated for forward dynamics and control, and for inverse
        dynamics the full joint trajectory, passive joints of closed chains included.
    """
    robot, t, q, _ = motion_and_reference(study, frames)
    return robot, t, q


def motion_and_reference(study: str | Path | specs.Study, frames: int
                         ) -> tuple[Robot, np.ndarray, np.ndarray, np.ndarray | None]:
    """As ``motion``, and for a control study the reference of every coordinate (frames, n),
    else None: robot, t (frames,) in s, q (frames, n) in rad (m at a slider), reference in the
    same units."""
    st = load_study(study)
    if not isinstance(frames, (int, np.integer)) or frames < 2:
        raise InputError(f"the number of frames must be an integer >= 2 (got {frames})")
    robot = robot_of(st)
    if st.kind in ("forward", "control"):
        result = (_forward(st, robot, frames) if st.kind == "forward"
                  else run(st, samples=frames))
        q = np.column_stack([result.columns[coordinate_column("q", i, robot.coordinate_units[i])]
                             for i in range(robot.n)])
        return robot, result.columns["t_s"], q, result.reference
    jt, _ = joint_motion(st, robot, frames)
    return robot, jt.t_s, jt.q, None
