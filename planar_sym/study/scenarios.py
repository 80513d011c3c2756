"""The seed's scenarios by name (pinned down in SCENARIOS.md), run into tables of results.

Each scenario states its inputs in the seed's own units (mm, deg, rad, s); they are converted to
SI here, at the boundary, and converted back only for the output columns that say so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..dynamics.inverse import torque_split
from ..errors import InputError
from ..model.robot import Robot, load
from ..motion.ik import inverse_kinematics
from ..motion.profiles import JointTrajectory, cubic
from .result import Result


@dataclass(frozen=True)
class Scenario:
    name: str
    robot: str
    kind: str  # "forward", "joint" (joint-space trajectory) or "task" (task-space + IK)
    summary: str
    x0: tuple[float, ...] = ()  # seed units: task (mm, mm, rad) or joints (deg)
    dx: tuple[float, ...] = ()
    duration_s: float = 1.0
    extra: dict = field(default_factory=dict)


SCENARIOS: dict[str, Scenario] = {s.name: s for s in [
    Scenario("serial_2dof_free_swing", "serial_2dof", "forward",
             "S1: 2-DOF arm released from q1 = -60 deg, zero torque, 1 s (seed Fig. 14)",
             x0=(-60.0, 0.0), duration_s=1.0),
    Scenario("serial_2dof_joint_move", "serial_2dof", "joint",
             "S2: 2-DOF arm, joint 1 from 0 to 90 deg in 10 s, cubic (seed Fig. 20)",
             x0=(0.0, 0.0), dx=(90.0, 0.0), duration_s=10.0),
    Scenario("serial_2dof_cartesian_move", "serial_2dof", "task",
             "S3: 2-DOF arm, tip from (100, 100) mm by -200 mm in x in 5 s (seed Fig. 22)",
             x0=(100.0, 100.0), dx=(-200.0, 0.0), duration_s=5.0),
    Scenario("serial_3dof_cartesian_move", "serial_3dof", "task",
             "S4: 3-DOF arm, tool from (100, 120) mm, phi = pi/2, by -200 mm in x in 5 s "
             "(seed Fig. 25)",
             x0=(100.0, 120.0, np.pi / 2), dx=(-200.0, 0.0, 0.0), duration_s=5.0),
    *[Scenario(f"{robot}_move_{axis}", robot, "task",
               f"{tag}: {label}, end-effector P from ({x0[0]:g}, {x0[1]:g}) mm by +50 mm in "
               f"{axis} in 2 s ({fig})", x0=x0, dx=dx, duration_s=2.0)
      for robot, tag, label, fig, x0 in [
          ("five_bar_type1", "S5", "5-bar Type I", "seed Fig. 2.29", (60.852, 154.665)),
          ("five_bar_type2", "S6", "5-bar Type II", "seed Fig. 32", (100.0, 128.0))]
      for axis, dx in (("x", (50.0, 0.0)), ("y", (0.0, 50.0)))],
    *[Scenario(f"parallel_3rrr_move_{axis}", "parallel_3rrr", "task",
               f"S7: 3-RRR parallel robot, platform centre from (0, 0) mm by +50 mm in {axis} "
               "in 2 s, phi = 0 (seed Fig. 35)", x0=(0.0, 0.0, 0.0), dx=dx, duration_s=2.0)
      for axis, dx in (("x", (50.0, 0.0, 0.0)), ("y", (0.0, 50.0, 0.0)))],
]}

DEFAULT_SAMPLES = {"forward": 1001, "joint": 201, "task": 201}


def task_to_si(robot: Robot, x_seed: np.ndarray) -> np.ndarray:
    """Seed task units (mm, mm[, rad]) to SI (m, m[, rad])."""
    scale = np.array([1e-3 if n != "phi" else 1.0 for n in robot.task_names])
    return np.asarray(x_seed, dtype=float) * scale


def task_columns(robot: Robot, x_si: np.ndarray) -> dict[str, np.ndarray]:
    return {(f"{n}_rad" if n == "phi" else f"{n}_mm"): (x_si[:, i] if n == "phi"
                                                        else x_si[:, i] * 1e3)
            for i, n in enumerate(robot.task_names)}


def get(name: str) -> Scenario:
    if name not in SCENARIOS:
        raise InputError(f"unknown scenario {name!r}; known: {', '.join(SCENARIOS)}")
    return SCENARIOS[name]


def joint_motion(sc: Scenario, robot: Robot, t: np.ndarray) -> tuple[JointTrajectory,
                                                                      np.ndarray]:
    """Joint trajectory and task coordinates (SI) of an inverse-dynamics scenario."""
    if sc.kind == "joint":
        tr = cubic(np.radians(sc.x0), np.radians(sc.dx), sc.duration_s, t)
        jt = JointTrajectory(t, tr.x, tr.xd, tr.xdd)
        x, _, _ = robot.task(jt.q)
        return jt, x
    tr = cubic(task_to_si(robot, sc.x0), task_to_si(robot, sc.dx), sc.duration_s, t)
    return inverse_kinematics(robot, tr), tr.x


def run(name: str, samples: int | None = None) -> Result:
    """Run one scenario; ``samples`` evenly spaced samples over its duration."""
    sc = get(name)
    n_samples = DEFAULT_SAMPLES[sc.kind] if samples is None else samples
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 2:
        raise InputError(f"--samples must be an integer >= 2 (got {samples})")
    robot = load(sc.robot)
    t = np.linspace(0.0, sc.duration_s, n_samples)
    if sc.kind == "forward":
        return _forward(sc, robot, t)
    jt, x = joint_motion(sc, robot, t)
    cols = {"t": t, **task_columns(robot, x)}
    if robot.is_closed_chain:
        return _closed(sc, robot, jt, cols)
    tau = robot.inverse_dynamics(jt.q, jt.qd, jt.qdd)
    cols.update({f"q{i + 1}": jt.q[:, i] for i in range(robot.n)})
    cols.update({f"tau{i + 1}": tau[:, i] for i in range(robot.n)})
    return Result(sc.name, sc.summary, cols, kind="torques",
                  split=torque_split(robot, jt.q, jt.qd, jt.qdd))


def _closed(sc: Scenario, robot: Robot, jt: JointTrajectory, cols: dict) -> Result:
    """Actuated angles (the seed's absolute angles, rad), torques, then the cut-joint forces."""
    tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=jt.t_s)
    for k, i in enumerate(robot.actuated):
        cols[f"q{k + 1}"] = jt.q[:, i]
    for k in range(len(robot.actuated)):
        cols[f"tau{k + 1}"] = tau[:, k]
    for k, loop in enumerate(robot.loops):
        cols[f"fx_{loop}_n"] = lam[:, 2 * k]
        cols[f"fy_{loop}_n"] = lam[:, 2 * k + 1]
    drift = float(np.max(np.abs(robot.constraint(jt.q))))
    note = (f"actuated joints {', '.join(robot.coordinates[i] for i in robot.actuated)}; "
            f"loop residual max |Phi| = {drift:.1e} m; f*: force on the cut joint's parent body")
    return Result(sc.name, sc.summary, cols, kind="torques", note=note,
                  split=torque_split(robot, jt.q, jt.qd, jt.qdd, t=jt.t_s))


def _forward(sc: Scenario, robot: Robot, t: np.ndarray) -> Result:
    from ..dynamics.forward import simulate

    sim = simulate(robot, np.radians(sc.x0), np.zeros(robot.n), (0.0, sc.duration_s), t_eval=t)
    cols = {"t": t}
    cols.update({f"q{i + 1}": sim.q[:, i] for i in range(robot.n)})
    cols.update({f"qd{i + 1}": sim.qd[:, i] for i in range(robot.n)})
    cols["energy_j"] = sim.energy_j
    note = f"energy drift {sim.energy_drift:.2e} (relative), {sim.method} rtol {sim.rtol:g}"
    # the free swing has tau = 0: its split shows how M qdd, C qd and g balance each other
    qdd = robot.forward_dynamics(sim.q, sim.qd, sim.tau)
    return Result(sc.name, sc.summary, cols, kind="angles", note=note,
                  split=torque_split(robot, sim.q, sim.qd, qdd))


def motion(name: str, samples: int) -> tuple[Robot, np.ndarray, np.ndarray]:
    """Every joint's angle over a scenario, for pictures.

    Parameters
    ----------
    name : str
        Scenario name.
    samples : int
        Evenly spaced samples over the scenario's duration, >= 2.

    Returns
    -------
    robot : Robot
    t : ndarray, shape (samples,)
        Time (s).
    q : ndarray, shape (samples, n)
        Every coordinate (rad): simulated for forward dynamics, and for inverse dynamics the
        full joint trajectory, passive joints of closed chains included.
    """
    sc = get(name)
    if not isinstance(samples, (int, np.integer)) or samples < 2:
        raise InputError(f"the number of frames must be an integer >= 2 (got {samples})")
    robot = load(sc.robot)
    t = np.linspace(0.0, sc.duration_s, samples)
    if sc.kind == "forward":
        from ..dynamics.forward import simulate

        sim = simulate(robot, np.radians(sc.x0), np.zeros(robot.n), (0.0, sc.duration_s),
                       t_eval=t)
        return robot, t, sim.q
    return robot, t, joint_motion(sc, robot, t)[0].q
