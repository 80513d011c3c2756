"""A robot under control, simulated in C: the plant, the controller, the input tables and the
events in one compiled loop (``_integrate.c``), no Python per step.

``simulate_controlled`` is the entry point; its result is a ``Simulation`` (``run_result``,
also named ``ControlledRun``), the type an open-loop run has, with its control fields set. The
controller's model is ``robot`` (its parameters are the nominal ones); ``plant`` is the robot
that moves (the same description, perhaps other parameters: a model error). Closed chains run
in segments re-projected onto the loops, as free simulations do (``forward_closed``).

The C side (the struct the loop reads, its entry points) is ``engine_c``; the inputs' checks
are ``engine_inputs``.
"""

from __future__ import annotations

import ctypes
from dataclasses import replace

import numpy as np

from ..errors import InputError, SimulationError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal
from ..progress import ambient, watching
from .engine_c import MAX_EVENTS_LOGGED, _array, _functions, _Setup, control_values
from .engine_inputs import check_controller, engine_reference, engine_torque
from .events import Event, actuator_events, joint_limit_events, output_events
from .laws import Controller
from .run_result import Simulation
from .segments import run_segments
from .watched import call_watched

# the C side and the checks are named here too, where they used to live
__all__ = ["LOOP_EVENT", "MAX_EVENTS_LOGGED", "ControlledRun", "assembly_changes",
           "check_controller", "control_values", "simulate_controlled"]

#: the name a controlled run's type had: ``Simulation`` itself
ControlledRun = Simulation
LOOP_EVENT = "the loops could not stay assembled"


def simulate_controlled(robot: Robot, controller: Controller, t_span, *,
                        reference: JointTrajectory | Signal | None = None,
                        plant: Robot | None = None, q0=None, qd0=None, project: bool = False,
                        torque=None,
                        t_eval=None, joint_limits: dict | None = None,
                        on_joint_limit: str = "stop", on_actuator_limit: str = "continue",
                        method: str = "dopri5", rtol: float = 1e-10, atol: float = 1e-12,
                        max_steps: int = 10_000_000, progress=None) -> Simulation:
    """Simulate ``plant`` (default: ``robot``) under ``controller`` over ``t_span`` (s).

    Parameters
    ----------
    robot : Robot
        The controller's model: its parameters are the nominal ones.
    controller : Controller
        From ``planar_sym.control.controller``: the law, its gains, and whether torques are
        clipped at the actuator limits of the description (``[joints.actuator]``).
    reference : JointTrajectory or Signal
        What to track: a JointTrajectory (every coordinate, e.g. ``Robot.inverse_kinematics``
        or a study's motion; interpolated by quintic Hermite polynomials through its samples),
        or a Signal over the actuated coordinates (rad or m). Must cover ``t_span``.
    plant : Robot, optional
        The robot that moves: the same description with other parameters (a model error).
    q0, qd0 : array, optional
        Initial state, every coordinate (rad or m; /s); default: the reference's first sample.
        A closed chain's must be on the plant's loops, or ``project``.
    project : bool
        Closed chains: solve the passive joints of ``q0``, ``qd0`` from the actuated ones on
        the plant's loops (Newton from ``q0``'s passive values, which pick the assembly mode),
        as ``simulate``'s ``project``; ``initial_correction_rad`` says how far they moved.
    torque : None, (actuated,) array or Signal
        Input torques added to the controller's (N*m or N): constant, or a Signal of time
        (``signals.from_table``); the only input of controller "none".
    joint_limits : dict, optional
        {coordinate name or index: (lower, upper)} in rad or m: events.
    on_joint_limit, on_actuator_limit : "stop" or "continue"
        What an event does. Actuator limits are those of the description.
    method : "dopri5" (C, default), "cvodes" or "idas" (SUNDIALS through CasADi)
    progress : callable, optional
        ``progress(t_s, t_end_s)`` while the compiled loop runs (see ``simulate``).

    Returns
    -------
    Simulation
        The run (``ControlledRun`` is the same type) with its control fields set: ``q_ref``,
        ``qd_ref``, ``tau_cmd`` and the applied ``tau`` on the actuated coordinates, ``work_j``,
        ``friction_j``, ``controller``, ``events``. Raises InputError for bad input, including
        an event that fires at the start.
    """
    from .forward_closed import CONTROLLED_HINT, start_state
    from .integrate import check_tolerances, time_grid

    if not isinstance(robot, Robot):
        raise InputError(f"simulate_controlled needs a Robot (planar_sym.load), got "
                         f"{type(robot).__name__}")
    if not isinstance(controller, Controller):
        raise InputError("controller: make one with planar_sym.control.controller(kind, kp, kd)")
    if progress is not None:  # read from there by the C loop's call
        with watching(progress):
            return simulate_controlled(
                robot, controller, t_span, reference=reference, plant=plant, q0=q0, qd0=qd0,
                project=project, torque=torque, t_eval=t_eval, joint_limits=joint_limits,
                on_joint_limit=on_joint_limit, on_actuator_limit=on_actuator_limit,
                method=method, rtol=rtol, atol=atol, max_steps=max_steps)
    plant = robot if plant is None else plant
    if not isinstance(plant, Robot) or plant.name != robot.name:
        raise InputError(f"the plant must be the same robot as the controller's model "
                         f"({robot.name}), perhaps with other parameters (with_parameters)")
    check_controller(robot, controller)
    na = len(robot.actuated)
    if controller.kp and len(controller.kp) != na:  # one gain for every joint
        controller = replace(controller, kp=controller.kp * na, kd=controller.kd * na)
    check_tolerances(rtol, atol)
    t = time_grid(t_span, t_eval)
    t0, t1 = float(t_span[0]), float(t_span[1])
    n = robot.n
    ref = engine_reference(robot, reference, controller, t0, t1)
    u = engine_torque(torque, na, t0, t1)
    if q0 is None:
        if isinstance(reference, JointTrajectory):
            q0 = reference.q[0] if reference.t_s[0] == t0 else None
            qd0 = reference.qd[0] if qd0 is None and q0 is not None else qd0
        elif ref is not None and na == n:
            q0, qd0 = ref(t0)[0], (ref(t0, 1)[0] if qd0 is None else qd0)
        if q0 is None:
            raise InputError("give q0 (every coordinate): the reference does not say where "
                             "the passive joints start")
    q0, qd0, moved = start_state(plant, q0, qd0, project, hint=CONTROLLED_HINT)
    run = run_checked(robot, plant, controller, ref, u, q0, qd0, t0, t, joint_limits,
                      on_joint_limit, on_actuator_limit, method, rtol, atol, max_steps)
    return replace(run, initial_correction_rad=moved) if moved else run


def run_checked(robot: Robot, plant: Robot, controller: Controller, ref: Signal | None, u,
                q0: np.ndarray, qd0: np.ndarray, t0: float, t: np.ndarray,
                joint_limits: dict | None,
                on_joint_limit: str, on_actuator_limit: str, method: str, rtol: float,
                atol: float, max_steps: int) -> Simulation:
    """``simulate_controlled`` on inputs checked already, by it or by ``forward.simulate``
    (the open-loop law "none"): the reference ``ref`` a Signal over the actuated coordinates
    covering the run (or None), the input ``u`` None, (actuated,) N*m or a Signal covering the
    run, the state ``q0``, ``qd0`` (n,) at the start ``t0`` (s; a closed chain's on the
    loops), the output times ``t`` (N,) in s and the tolerances; events and the run here."""
    n, act = robot.n, list(robot.actuated)
    specs = joint_limit_events(robot, joint_limits, on_joint_limit)
    act_specs, bound = actuator_events(plant, on_actuator_limit)
    specs += act_specs
    setup = _Setup(robot, plant, controller, ref, u, specs, bound)
    y0 = np.concatenate([q0, qd0, [0.0, 0.0]])
    g0 = control_values(robot, setup, np.array([t0]), y0[None])[2]
    at_start = []
    for k, s in enumerate(specs):
        if g0[0, k] > 0:
            continue
        if s.stop:  # a run that would stop before it starts is a mistake in its input
            raise InputError(f"an event fires at t = {t0:g} s, before the run starts: {s.name}"
                             f" (give a start inside the limits, or a reference that starts "
                             "there)")
        setup.armed[k] = 0  # already past it: logged once, fires again after it recovers
        at_start.append(Event(s.name, t0, False))
    if method in ("cvodes", "idas"):
        from .sundials import integrate as sundials

        ys, t_out, n_rhs, drift, loop_event = sundials(robot, plant, setup, controller, ref, u,
                                                       y0, t, method, rtol, atol)
        found = output_events(control_values(robot, setup, t_out, ys)[2], t_out)
        stops = [tt for k, tt in found if specs[k].stop]
        if stops:  # the run ends at the last sample before the first stop event
            keep = t_out < min(stops)
            ys, t_out = ys[keep], t_out[keep]
        events = [Event(specs[k].name, float(tt), bool(stops and specs[k].stop
                                                      and tt == min(stops)))
                  for k, tt in found if not stops or tt <= min(stops)]
    elif method == "dopri5":
        ys, t_out, n_rhs, drift, loop_event = _dopri5(robot, plant, setup, y0, t, rtol, atol,
                                                      max_steps)
        events = [Event(specs[int(k)].name, float(tt), bool(specs[int(k)].stop))
                  for k, tt in zip(setup.log_ev[:setup.c.n_log], setup.log_t[:setup.c.n_log])]
        if setup.c.stopped:  # only the first stop event stops; later ones never happened
            first = min(e.time_s for e in events if e.stopped)
            events = [e if e.time_s <= first else Event(e.name, e.time_s, False)
                      for e in events if e.time_s <= first]
    else:
        raise InputError(f"unknown method {method!r}; known: dopri5, cvodes, idas")
    events = at_start + events
    if loop_event is not None:
        events.append(Event(LOOP_EVENT + f" ({loop_event[1]})", loop_event[0], True))
    q, qd = ys[:, :n], ys[:, n:2 * n]
    if robot.is_closed_chain:
        events += assembly_changes(plant, t_out, q)
    cmd, app, _, q_ref, qd_ref = control_values(robot, setup, t_out, ys)
    if q_ref is None:  # the state an LQR law holds, or none
        q_ref, qd_ref = _held(controller, t_out, n, act)
    if q_ref is None:  # open loop: no reference, no error
        q_ref, qd_ref = q[:, act], qd[:, act]
    # the plant's energies; its labels are the model's (the same description)
    return Simulation.of_robot(plant, t_out, q, qd, app, method, rtol, atol, n_rhs,
                               constraint_drift_m=drift, q_ref=q_ref, qd_ref=qd_ref,
                               tau_cmd=cmd, work_j=ys[:, 2 * n], friction_j=ys[:, 2 * n + 1],
                               controller=controller,
                               events=tuple(sorted(events, key=lambda e: e.time_s)))


def _held(ctl: Controller, t: np.ndarray, n: int, act: list[int]):
    """The state an LQR law holds on the actuated coordinates and its rate at ``t`` (each
    (N, actuated); of time along a TVLQR's motion); None for an open-loop run. (A tracking
    law's reference comes from the compiled controller, ``control_values``.)"""
    if ctl.kind != "lqr":
        return None, None
    x = (ctl.schedule(t)[:, :2 * n] if ctl.schedule is not None
         else np.broadcast_to(np.asarray(ctl.x_ref), (len(t), 2 * n)))
    return x[:, act].copy(), x[:, [n + i for i in act]].copy()


def assembly_changes(robot: Robot, t: np.ndarray, q: np.ndarray) -> list[Event]:
    """A closed chain that passes through a singular pose of its passive joints (det Phi_p = 0,
    where the actuators lose control of it) may come out in another assembly mode: found as a
    sign change of det Phi_p between output samples, reported with the two times.

    ``t`` (N,) are the output times (s), ``q`` (N, n) every coordinate there (rad; m at a
    slider).
    """
    act, n, m = list(robot.actuated), robot.n, robot.n_constraints
    pas = [i for i in range(n) if i not in act]
    jac = robot.constraint_jacobian(q).reshape(len(q), m, n)
    det = np.linalg.det(jac[:, :, pas])
    flips = np.nonzero(np.sign(det[1:]) * np.sign(det[0]) < 0)[0]
    if not len(flips):
        return []
    k = int(flips[0])
    return [Event(f"the mechanism passed through a singular pose (det Phi_p changed sign between "
                  f"t = {t[k]:.6g} and {t[k + 1]:.6g} s) and changed assembly mode", float(t[k + 1]),
                  False)]


def _dopri5(robot, plant, setup, y0, t, rtol, atol, max_steps):
    """The compiled loop: one C call (a tree) or one per segment (a closed chain)."""
    from .integrate import _DOPRI5_ERRORS

    run, _ = _functions()
    n, m = plant.n, plant.n_constraints
    fn = plant.library.address("constrained_terms" if m else "forward_dynamics")
    stats = np.zeros(4, dtype=np.int64)
    t_fail = ctypes.c_double()
    count = [0]

    def segment(tt: np.ndarray, y: np.ndarray):
        out = np.empty((len(tt), 2 * n + 2))
        rc = call_watched(lambda: run(
            1 if m else 0, n, m, len(setup.act), setup.act.ctypes.data, 0, plant.p.ctypes.data,
            fn, ctypes.byref(setup.c), float(tt[0]), _array(y).ctypes.data, len(tt),
            tt.ctypes.data, rtol, atol, max_steps, out.ctypes.data, stats.ctypes.data,
            ctypes.byref(t_fail)), t_fail, float(t[-1]), ambient())
        count[0] += int(stats[0])
        if rc and not (m and rc in (1, 2)):
            raise SimulationError(f"{robot.name}: integration failed at t = "
                                  f"{t_fail.value:.6g} s: {_DOPRI5_ERRORS.get(rc, rc)}")
        # a closed chain's KKT matrix singular: the loops cannot be closed there (an event)
        return out, int(stats[3]), (t_fail.value if rc else None)

    return run_segments(plant, setup, y0, t, segment, count)
