"""A robot under control, simulated in C: the plant, the controller, the input tables and the
events in one compiled loop (``_integrate.c``), no Python per step.

``simulate_controlled`` is the entry point; its result is a ``Simulation`` (``run_result``,
also named ``ControlledRun``), the type an open-loop run has, with its control fields set. The
controller's model is ``robot`` (its parameters are the nominal ones); ``plant`` is the robot
that moves (the same description, perhaps other parameters: a model error). Closed chains run
in segments re-projected onto the loops, as free simulations do (``forward_closed``).
"""

from __future__ import annotations

import ctypes
import functools
from dataclasses import replace

import numpy as np

from ..errors import InputError, SimulationError
from ..progress import ambient, watching
from ..model.arrays import as_state, as_vector
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal, from_motion
from .events import Event, EventSpec, actuator_events, joint_limit_events, output_events
from .integrate import check_torque
from .laws import Controller
from .run_result import Simulation, labels
from .segments import friction, run_segments
from .watched import call_watched

#: the name a controlled run's type had: ``Simulation`` itself
ControlledRun = Simulation
_P = ctypes.c_void_p
MAX_EVENTS_LOGGED = 256
LOOP_EVENT = "the loops could not stay assembled"


class _CSignal(ctypes.Structure):
    _fields_ = [("n_knots", ctypes.c_int), ("n_ch", ctypes.c_int), ("deg", ctypes.c_int),
                ("T", _P), ("c", _P)]


class _CControl(ctypes.Structure):  # mirrors Control in _integrate.c
    _fields_ = [("mode", ctypes.c_int), ("saturate", ctypes.c_int),
                ("kp", _P), ("kd", _P), ("p_nom", _P), ("tau_const", _P), ("lo", _P),
                ("hi", _P), ("fv", _P), ("fc", _P), ("vs", _P),
                ("gravity", _P), ("inverse", _P), ("closed_inverse", _P), ("jac", _P),
                ("bias", _P), ("ref", _CSignal), ("input", _CSignal),
                ("n_ev", ctypes.c_int), ("ev_kind", _P), ("ev_index", _P), ("ev_stop", _P),
                ("ev_value", _P), ("armed", _P), ("max_log", ctypes.c_int),
                ("n_log", ctypes.c_int), ("log_ev", _P), ("log_t", _P),
                ("stopped", ctypes.c_int), ("t_stop", ctypes.c_double), ("y_stop", _P),
                ("hint_ref", ctypes.c_int), ("hint_input", ctypes.c_int),
                ("gain", _P), ("x_ref", _P), ("u_ref", _P), ("sched", _CSignal),
                ("sched_v", _P), ("hint_sched", ctypes.c_int)]


def _array(a, dtype=float) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=dtype)


class _Setup:
    """The C Control struct and every array it points to (kept alive here)."""

    def __init__(self, robot: Robot, plant: Robot, ctl: Controller, ref: Signal | None,
                 torque: np.ndarray | Signal | None, events: list[EventSpec],
                 bound: np.ndarray):
        na, n = len(robot.actuated), robot.n
        lib = robot.library
        self.keep = []
        c = _CControl()
        c.mode = ctl.mode
        c.saturate = int(ctl.saturate and np.isfinite(bound).any())
        c.kp = self._ptr(ctl.kp or np.zeros(na))
        c.kd = self._ptr(ctl.kd or np.zeros(na))
        c.p_nom = self._ptr(robot.p)
        c.lo, c.hi = self._ptr(-bound), self._ptr(bound)
        c.gain = self._ptr(ctl.gain or np.zeros(1))
        c.x_ref = self._ptr(ctl.x_ref or np.zeros(1))
        c.u_ref = self._ptr(ctl.u_ref or np.zeros(1))
        if ctl.schedule is not None:  # a time-varying LQR: x_ref, u_ref and K of time
            c.sched = self._signal(ctl.schedule)
            self.sched_v = np.zeros(ctl.schedule.channels)
            c.sched_v = self.sched_v.ctypes.data
        fv, fc, vs = friction(plant)
        c.fv, c.fc, c.vs = self._ptr(fv), self._ptr(fc), self._ptr(vs)
        if isinstance(torque, Signal):
            c.input = self._signal(torque)
        elif torque is not None:
            c.tau_const = self._ptr(torque)
        if ref is not None:
            c.ref = self._signal(ref)
        for slot, quantity in (("gravity", "gravity"), ("inverse", "inverse_dynamics"),
                               ("closed_inverse", "closed_inverse_dynamics"),
                               ("jac", "constraint_jacobian"), ("bias", "constraint_bias")):
            if quantity in lib.manifest["functions"]:
                setattr(c, slot, lib.address(quantity))
        c.n_ev = len(events)
        c.ev_kind = self._ptr([e.kind for e in events], np.intc)
        c.ev_index = self._ptr([e.index for e in events], np.intc)
        c.ev_stop = self._ptr([int(e.stop) for e in events], np.intc)
        c.ev_value = self._ptr([e.value for e in events])
        self.armed = _array(np.ones(max(len(events), 1)), np.intc)
        c.armed = self.armed.ctypes.data
        c.max_log = MAX_EVENTS_LOGGED
        self.log_ev = np.zeros(MAX_EVENTS_LOGGED, dtype=np.intc)
        self.log_t = np.zeros(MAX_EVENTS_LOGGED)
        c.log_ev, c.log_t = self.log_ev.ctypes.data, self.log_t.ctypes.data
        self.y_stop = np.zeros(2 * n + 2)
        c.y_stop = self.y_stop.ctypes.data
        self.c = c
        self.act = _array(robot.actuated, np.intc)
        self.bound = bound

    def _ptr(self, a, dtype=float) -> int:
        arr = _array(a if len(a) else [0], dtype)
        self.keep.append(arr)
        return arr.ctypes.data

    def _signal(self, s: Signal) -> _CSignal:
        out = _CSignal()
        out.n_knots, out.n_ch, out.deg = len(s.knots_s), s.channels, s.degree
        out.T, out.c = self._ptr(s.knots_s), self._ptr(s.coefficients.ravel())
        return out


@functools.cache
def _functions():
    """The C entry points, their argument types declared once per process."""
    from .integrate import helper

    lib = helper()
    run = lib.planar_sym_dopri5_ctl
    run.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_int, _P, _P, _P, _P,
                    ctypes.POINTER(_CControl), ctypes.c_double, _P, ctypes.c_int, _P,
                    ctypes.c_double, ctypes.c_double, ctypes.c_longlong, _P, _P, _P]
    run.restype = ctypes.c_int
    ev = lib.planar_sym_control_eval
    ev.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int, _P, _P, ctypes.POINTER(_CControl),
                   ctypes.c_longlong, _P, _P, _P, _P, _P]
    ev.restype = ctypes.c_int
    return run, ev


def control_values(robot: Robot, setup: _Setup, t: np.ndarray, y: np.ndarray):
    """Commanded and applied torques (N, actuated) and event values (N, events) at states
    ``y`` (N, 2n) and times ``t`` (s), from the compiled controller."""
    _, ev = _functions()
    na, n_ev = len(robot.actuated), setup.c.n_ev
    t, y = _array(t), _array(y[:, :2 * robot.n])
    cmd, app = np.empty((len(t), na)), np.empty((len(t), na))
    g = np.empty((len(t), max(n_ev, 1)))
    rc = ev(robot.n, robot.n_constraints, na, setup.act.ctypes.data, robot.p.ctypes.data, ctypes.byref(setup.c), len(t), t.ctypes.data,
            y.ctypes.data, cmd.ctypes.data, app.ctypes.data, g.ctypes.data)
    if rc:
        raise SimulationError(f"{robot.name}: the controller failed at t = {t[rc - 1]:.6g} s "
                              "(a singular pose of the controller's model?)")
    return cmd, app, g[:, :n_ev]


def check_controller(robot: Robot, ctl: Controller) -> None:
    """Refuse a law the robot cannot carry out."""
    if ctl.kind == "computed_torque" and not robot.is_closed_chain \
            and len(robot.actuated) != robot.n:
        passive = [robot.coordinates[i] for i in range(robot.n) if i not in robot.actuated]
        raise InputError(f"{robot.name}: computed-torque control needs every coordinate "
                         f"actuated or set by the loops; {', '.join(passive)} "
                         f"{'is' if len(passive) == 1 else 'are'} passive (underactuated): "
                         "use controller \"pd\"")
    if robot.is_closed_chain and robot.n - len(robot.actuated) != robot.n_constraints:
        raise InputError(f"{robot.name}: control of a closed chain needs as many passive "
                         f"coordinates ({robot.n - len(robot.actuated)}) as loop equations "
                         f"({robot.n_constraints})")
    na, n = len(robot.actuated), robot.n
    if ctl.kind == "lqr" and ctl.schedule is not None and \
            ctl.schedule.channels != 2 * n + na + 2 * n * na:
        raise InputError(f"{robot.name}: this time-varying LQR law was designed for another "
                         "robot (make it with planar_sym.tvlqr on this one)")
    if ctl.kind == "lqr" and ctl.schedule is None and len(ctl.gain) != 2 * n * na:
        raise InputError(f"{robot.name}: this LQR law was designed for another robot (make "
                         "it with planar_sym.lqr on this one)")
    for k in (ctl.kp, ctl.kd):
        if k and len(k) not in (1, len(robot.actuated)):
            raise InputError(f"{robot.name}: {len(k)} gains for {len(robot.actuated)} "
                             "actuated joints")


def simulate_controlled(robot: Robot, controller: Controller, t_span, *,
                        reference: JointTrajectory | Signal | None = None,
                        plant: Robot | None = None, q0=None, qd0=None, torque=None,
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
        A closed chain's must be on the loops.
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
    from .forward_closed import initial_state
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
                torque=torque, t_eval=t_eval, joint_limits=joint_limits,
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
    n, na, act = robot.n, len(robot.actuated), list(robot.actuated)
    ref = _reference(robot, reference, controller)
    if ref is not None:
        ref.covers(t0, t1, "the reference motion")
    u = _torque_input(torque, na, t0, t1)
    if q0 is None:
        if isinstance(reference, JointTrajectory):
            q0 = reference.q[0] if reference.t_s[0] == t0 else None
            qd0 = reference.qd[0] if qd0 is None and q0 is not None else qd0
        elif ref is not None and na == n:
            q0, qd0 = ref(t0)[0], (ref(t0, 1)[0] if qd0 is None else qd0)
        if q0 is None:
            raise InputError("give q0 (every coordinate): the reference does not say where "
                             "the passive joints start")
    q0, qd0 = as_state(q0, qd0, n)
    if robot.is_closed_chain:
        q0, qd0 = initial_state(plant, q0, qd0, False)
    specs = joint_limit_events(robot, joint_limits, on_joint_limit)
    act_specs, bound = actuator_events(plant, on_actuator_limit)
    specs += act_specs
    setup = _Setup(robot, plant, controller, ref, u, specs, bound)
    y0 = np.concatenate([q0, qd0, [0.0, 0.0]])
    _, _, g0 = control_values(robot, setup, np.array([t0]), y0[None])
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
        events = [Event(specs[k].name, float(tt), bool(stops) and specs[k].stop
                        and tt == min(stops)) for k, tt in found if not stops or tt <= min(stops)]
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
    cmd, app, _ = control_values(robot, setup, t_out, ys)
    kin, pot = plant.energy(q, qd)
    q_ref, qd_ref = _held(controller, ref, t_out, n, act)
    if q_ref is None:  # open loop: no reference, no error
        q_ref, qd_ref = q[:, act], qd[:, act]
    return Simulation(t_out, q, qd, app, kin, pot, method, rtol, atol, n_rhs, drift,
                      **labels(robot), q_ref=q_ref, qd_ref=qd_ref, tau_cmd=cmd,
                      work_j=ys[:, 2 * n], friction_j=ys[:, 2 * n + 1], controller=controller,
                      events=tuple(sorted(events, key=lambda e: e.time_s)))


def _held(ctl: Controller, ref: Signal | None, t: np.ndarray, n: int, act: list[int]):
    """The actuated coordinates' reference and its rate at ``t`` (each (N, actuated)): the
    tracked motion's, or the state an LQR law holds (of time along a TVLQR's motion); None
    for an open-loop run."""
    if ref is not None:
        return ref(t), ref(t, 1)
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


def _reference(robot: Robot, reference, ctl: Controller) -> Signal | None:
    na = len(robot.actuated)
    if ctl.kind == "lqr":  # it holds its own state; a reference would not be used
        if reference is not None:
            raise InputError("controller \"lqr\" holds the state it was designed about "
                             "and takes no reference motion")
        return None
    if reference is None:
        if ctl.kind != "none":
            raise InputError(f"controller {ctl.kind!r} needs a reference motion to track")
        return None
    if isinstance(reference, JointTrajectory):
        act = list(robot.actuated)
        return from_motion(reference.t_s, reference.q[:, act], reference.qd[:, act],
                           reference.qdd[:, act])
    if isinstance(reference, Signal):
        if reference.channels != na:
            raise InputError(f"the reference has {reference.channels} channels; "
                             f"{robot.name} has {na} actuated joints")
        return reference
    raise InputError("reference: a JointTrajectory (every coordinate) or a Signal over the "
                     f"actuated joints (got {type(reference).__name__})")


def _torque_input(torque, na: int, t0: float, t1: float):
    if torque is None or isinstance(torque, Signal):
        if isinstance(torque, Signal):
            check_torque(torque, na)  # its width, by simulate's rule
            torque.covers(t0, t1, "the torque table")
        return torque
    if callable(torque):
        raise InputError("a torque function of time runs in Python; in the compiled loop give "
                         "a table (planar_sym.motion.signals.from_table) or a constant")
    return as_vector("torque", torque, na)


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
