"""Run a study: load its robot, apply its parameters, make its motion (or simulation), and return
typed series (``dynamics.series.Series``: quantity, unit, coordinate or joint) in a ``Result``.

Their columns (one header row in the CSV, the names made from the series): ``t_s``; the task
coordinates (``x_mm``, ``y_mm``, ``phi_rad``); every joint coordinate ``q<k>_rad`` with its
rate ``qd<k>_rad_s`` and, for inverse dynamics, acceleration ``qdd<k>_rad_s2`` (k numbers the
robot's coordinates, passive joints of closed chains included); the torque at each actuated
coordinate ``tau<k>_n_m`` (same k); for closed chains the reaction force at each cut joint
``fx_<joint>_n``, ``fy_<joint>_n`` (N, world axes, on the cut joint's parent body); for inverse
dynamics (the series ``dynamics.along.inverse_series`` makes, as tau and f* above) every joint's
load (``jfx_<joint>_n``, ``jfy_<joint>_n``, ``jload_<joint>_n``, ``jm_<joint>_n_m``,
``jfn_<joint>_n``, the parent body on the child body) and the power ``p<k>_w``; for forward
dynamics ``energy_j``.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..dynamics.along import inverse_along, inverse_series
from ..dynamics.inverse import split_along
from ..errors import InputError, LibraryError
from ..model.locate import load
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from . import spec as specs
from .builtin import find as find_builtin
from .columns import coordinates_note as _coordinates_note
from .columns import task_series
from .motion import initial_state, joint_motion, timed_motion
from .parameters import with_overrides
from .result import Result, Series


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
    try:
        robot = load(study.robot)
    except LibraryError as exc:  # the study file and field that named it
        if not study.path:
            raise
        raise LibraryError(f"{study.path}: robot: {exc}") from None
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
        Typed series, their columns named with units (see the module docstring).
    """
    st = load_study(study)
    if samples is not None and (not isinstance(samples, (int, np.integer)) or samples < 2):
        raise InputError(f"samples must be an integer >= 2 (got {samples})")
    failed = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            robot = robot_of(st)  # the study's robot, loaded before it runs
            result = run_on(st, robot, samples)
        except BaseException as exc:  # noqa: BLE001 - re-raised below, after the warnings
            failed = exc
    for w in caught:  # as they were given, now under the caller's filters
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    if failed is not None:
        raise failed
    said = tuple(dict.fromkeys(str(w.message) for w in caught
                               if issubclass(w.category, RuntimeWarning)))
    return replace(result, warnings=said) if said else result


def run_on(st: specs.Study, robot: Robot, samples: int | None = None) -> Result:
    """Run ``st`` on ``robot`` as it is (its parameters, not the study's overrides): what a
    sweep calls once per design, on one robot whose parameter vector it sets in place."""
    if st.kind == "forward":
        return _forward(st, robot, samples)
    if st.kind == "optimal" and st.control is None:  # run as an inverse study runs its motion
        from .optimal_run import plan_motion

        # a tree with a passive joint: the solver's nodes (between them the joint is not
        # free), the move itself
        nodes = not (robot.is_closed_chain or len(robot.actuated) == robot.n)
        jt, x, move, timing = plan_motion(st, robot, None if nodes else samples)
        if nodes:
            return _nodes(st, robot, jt, x, move, timing)
    elif st.kind in ("control", "optimal"):
        from .control_run import run_control

        return run_control(st, robot, samples, plant_of(st, robot))
    else:
        jt, x, timing = timed_motion(st, robot, samples)
    return _inverse(st, robot, jt, x, timing)


def plant_of(st: specs.Study, robot: Robot) -> Robot | None:
    """The machine a control study's controller moves: ``robot`` (the controller's model) with
    the values ``[control.plant]`` sets (checked SI), or None where it sets none."""
    if st.control is None or not st.control.plant:
        return None
    return with_overrides(robot, st.control.plant, f"{st.path or st.name}: control.plant")


def _nodes(st: specs.Study, robot: Robot, jt: JointTrajectory, x, move, found: str) -> Result:
    """An optimal move of a tree with a passive joint, at the solver's nodes: its motion and
    its torques, no joint loads (between the nodes the passive joint is not free)."""
    data = _motion_series(robot, jt, x)
    data += coordinate_series(robot, "tau", move.tau, robot.actuated)
    data += [Series("p", "W", move.tau[:, k] * jt.qd[:, i], index=i)
             for k, i in enumerate(robot.actuated)]
    passive = ", ".join(robot.coordinates[i] for i in range(robot.n)
                        if i not in robot.actuated)
    note = (f"{_coordinates_note(robot)}; {found}; the solver's nodes and torques (qdd: each "
            f"interval's, constant; {passive} passive: no joint loads, and no torque there "
            "at a node): add [control] to run it on the robot")
    return Result(st.name, st.title, data, kind="torques", note=note, robot=robot.name,
                  actuated=robot.actuated, timing=found)


def _motion_series(robot: Robot, jt: JointTrajectory, x) -> list[Series]:
    """A joint motion's series, in a result's order: ``t`` (s), the task coordinates ``x``
    ((N, task) SI, or None: ``task_series``), then every coordinate's ``q``, ``qd``, ``qdd``."""
    data = [Series("t", "s", jt.t_s)]
    if x is not None:
        data += task_series(robot, x)
    for kind, values in (("q", jt.q), ("qd", jt.qd), ("qdd", jt.qdd)):
        data += coordinate_series(robot, kind, values)
    return data


def coordinate_series(robot: Robot, quantity: str, values: np.ndarray,
                      on=None) -> list[Series]:
    """``quantity`` (``"q"``, ``"qd"``, ``"qdd"``, ``"tau"``, ...) of every coordinate (``values``
    shape (N, n)), or of those ``on`` lists (0-based; ``values`` then (N, len(on))), each
    (N,) in its unit: rad, rad/s, rad/s^2, N*m (m, m/s, m/s^2, N at a slider)."""
    on = range(robot.n) if on is None else on
    units = robot.coordinate_units
    return [Series.of_coordinate(quantity, i, units[i], values[:, k]) for k, i in enumerate(on)]


def _inverse(st: specs.Study, robot: Robot, jt: JointTrajectory, x, timing: str = "") -> Result:
    # the motion's own series and note first; then the inverse dynamics, which gives its own
    data = _motion_series(robot, jt, x)
    note = _coordinates_note(robot) + (f"; {timing}" if timing else "")
    inv = inverse_along(robot, jt.t_s, jt.q, jt.qd, jt.qdd)
    data += inverse_series(robot, inv)
    if inv.loop_residual_m is not None:
        note += (f"; loop residual max |Phi| = {inv.loop_residual_m:.1e} m; f*: force on the "
                 "cut joint's parent body")
    note += "; jf*, jm*: joint loads, parent on child (world axes; jload = |jf|)"
    if any(d.modelled for d in robot.drive_train.drives):
        note += ("; jm at a geared joint: the link-side couple (tau less friction and rotor), "
                 "what the gearbox and bearing carry")
    solver = getattr(jt, "solver", "")
    space = st.motion.space if st.motion else "joint"  # an optimal move is in joint space
    if space == "joint" and robot.is_closed_chain:
        solver = "passive joints from the loops (Newton, continued)"
    if solver:
        note += f"; {'inverse kinematics' if space == 'task' else 'joints'}: {solver}"
    over = [e for s in inv.sizing for e in s.exceeded]
    if over:
        note += "; ACTUATOR LIMITS EXCEEDED: " + "; ".join(over)
    return Result(st.name, st.title, data, kind="torques", note=note, split=inv.split,
                  sizing=inv.sizing,
                  robot=robot.name, solver=solver, actuated=robot.actuated, timing=timing)


def _forward(st: specs.Study, robot: Robot, samples: int | None) -> Result:
    s = st.simulation
    t = np.linspace(0.0, s.duration_s, samples or s.samples)
    inputs = "" if s.torque is None else "; input torques " + _input_note(s.torque)
    q0, qd0, project = initial_state(st, robot)
    sim = _simulate(st, robot, q0, qd0, t, project)
    # the run's own series (the same code names a Simulation's columns), in the CSV's order
    data = [Series("t", "s", t)]
    x = robot.task(sim.q)[0].reshape(len(t), -1) if robot.task_names else None
    if x is not None:
        data += task_series(robot, x)
    data += sim.series("q") + sim.series("qd")
    if s.torque is not None:
        data += sim.series("tau")
    data.append(sim.get("energy"))
    drift = ("energy change (the actuators' friction dissipates it)" if robot.has_friction
             else "energy drift")
    if s.torque is not None:
        drift = "energy change (the input torques do work)"
    balance = ""
    if sim.balance_residual is not None and (robot.has_friction or s.torque is not None):
        # what the change should be: the work put in less the friction loss, both integrated
        balance = (f"; energy balance E - E0 - (W - F) {sim.balance_residual:.2e} (relative; "
                   f"friction loss {sim.friction_j[-1]:.3g} J)")
    note = (f"{_coordinates_note(robot)}; {drift} {sim.energy_drift:.2e} (relative){balance}, "
            f"{sim.method} rtol {sim.rtol:g}{inputs}")
    split = {}
    if not robot.is_closed_chain and s.torque is None:
        # tau = 0 in a free swing: the split shows how M qdd, C qd and g balance each other
        split = split_along(robot, sim.q, sim.qd, np.zeros((len(t), len(robot.actuated))))
    return Result(st.name, st.title, data, kind="angles", note=note, split=split,
                  robot=robot.name, actuated=robot.actuated)


def _simulate(st: specs.Study, robot: Robot, q0, qd0, t, project: bool):
    """A forward run through ``dynamics.forward.simulate``, the one entry point (constant
    torques in the C integrator, a table or a profile and SUNDIALS in the engine, SciPy with
    the table evaluated in Python). ``tau`` comes back on the actuated joints."""
    from ..dynamics.forward import simulate
    from .control_run import torque_input

    s = st.simulation
    u = torque_input(st, robot, s.torque, s.duration_s, "simulation.torque")
    sim = simulate(robot, q0, qd0, (0.0, s.duration_s), t_eval=t, torque=u,
                   method=s.method, rtol=s.rtol, atol=s.atol, project=project)
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
        The machine that moved: a control study's plant (its ``[control.plant]`` values).
    t : ndarray, shape (frames,)
        Time (s).
    q : ndarray, shape (frames, n)
        Every coordinate (rad): simulated for forward dynamics and control, and for inverse
        dynamics the full joint trajectory, passive joints of closed chains included.
    """
    robot, t, q, _ = motion_and_reference(study, frames)
    return robot, t, q


def motion_and_reference(study: str | Path | specs.Study, frames: int
                         ) -> tuple[Robot, np.ndarray, np.ndarray,
                                    tuple[Robot, np.ndarray] | None]:
    """As ``motion``, and for a control study its reference: the controller's model and every
    coordinate's reference (frames, n), else None. robot (the plant that moved), t (frames,)
    in s, q (frames, n) in rad (m at a slider), the reference in the same units."""
    st = load_study(study)
    if not isinstance(frames, (int, np.integer)) or frames < 2:
        raise InputError(f"the number of frames must be an integer >= 2 (got {frames})")
    robot = robot_of(st)
    if st.kind in ("forward", "control") or (st.kind == "optimal" and st.control):
        result = (_forward(st, robot, frames) if st.kind == "forward"
                  else run(st, samples=frames))
        q = np.column_stack([result.get("q", index=i).values for i in range(robot.n)])
        ref = None if result.reference is None else (robot, result.reference)
        return plant_of(st, robot) or robot, result.get("t").values, q, ref
    if st.kind == "optimal":
        from .optimal_run import plan_motion

        jt, *_ = plan_motion(st, robot, frames)
        return robot, jt.t_s, jt.q, None
    if st.optimise is None:
        jt, _ = joint_motion(st, robot, frames)
        return robot, jt.t_s, jt.q, None
    # timed on the study's own samples, then drawn at evenly spaced times
    from scipy.interpolate import CubicHermiteSpline

    jt, _, _ = timed_motion(st, robot)
    t = np.linspace(jt.t_s[0], jt.t_s[-1], frames)
    return robot, t, CubicHermiteSpline(jt.t_s, jt.q, jt.qd)(t), None
