"""Track a joint motion: one typed request (``Tracking``, SI) in, the run and what it asked of
the actuators out. A control study is this request read from a file; the API builds it
directly. ``track`` makes the reference (quintic Hermite through the motion's samples, held
at rest after its end), the gains (given, or from a bandwidth), the start state (off the
reference on the actuated joints, the loops giving a closed chain's passive joints), runs the
engine, and splits and sizes the applied torques along the motion the plant made."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..dynamics.engine import simulate_controlled
from ..dynamics.inverse import split_along
from ..dynamics.run_result import Simulation
from ..dynamics.sizing import ActuatorSizing, size
from ..errors import InputError
from ..model.arrays import as_vector
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal, from_motion
from .laws import bandwidth_gains, controller

#: a reference that ends moving cannot be held: its end rates must be this small (SI/s)
REST_TOL = 1e-9


@dataclass(frozen=True)
class Tracking:
    """What to track and how (SI: rad or m, s, N*m or N).

    Attributes
    ----------
    motion : JointTrajectory
        Every coordinate's samples: the reference (a study's joint motion,
        ``inverse_kinematics``, ``from_actuated``).
    law : str
        ``"pd"`` (PD + gravity compensation), ``"computed_torque"``, ``"lqr"`` (time-varying
        LQR along the motion, its torques from the inverse dynamics, then LQR about its end:
        ``tvlqr``) or ``"none"``.
    kp, kd : ndarray, shape (actuated,), or None
        The gains (``controller``'s units), or None to set them from ``natural_frequency_hz``
        and ``damping`` (``bandwidth_gains`` at the motion's start).
    natural_frequency_hz, damping : float
        The closed loop's bandwidth (Hz) and damping ratio, when no gains are given.
    saturate : bool
        Clip torques at the description's actuator limits.
    samples : int
        Output samples, evenly spaced from 0 to the run's end.
    duration_s : float or None
        The run's length (s); past the motion's end the reference is held, so the motion must
        end at rest. Default: the motion's end.
    start_error : ndarray, shape (actuated,), or None
        The start's offset from the reference on the actuated joints (rad; m at a slider).
    torque : None, ndarray (actuated,) or Signal
        Input torques added to the controller's (N*m; N at a slider).
    joint_limits : dict
        {coordinate name or index: (lower, upper)} in rad (m): events.
    on_joint_limit, on_actuator_limit : str
        What an event does: ``"stop"`` or ``"continue"``.
    plant : Robot or None
        The robot that moves, if not the controller's model (a model error).
    method : str
        ``"dopri5"`` (C), ``"cvodes"`` or ``"idas"`` (SUNDIALS).
    rtol, atol : float
        The integrator's tolerances.
    where : str
        Prefixes messages (a study names its file); empty from the API.
    q_weight, r_weight : array or None
        ``"lqr"`` only: the weights on the state error and the torques (``lqr``'s, SI).
    tau : ndarray (samples, actuated) or None
        ``"lqr"`` only: the torques that make the motion (N*m; N at a slider), e.g. an
        optimal move's; default the inverse dynamics along it (a robot whose every joint is
        actuated or set by the loops).
    """

    motion: JointTrajectory
    law: str = "pd"
    kp: np.ndarray | None = None
    kd: np.ndarray | None = None
    natural_frequency_hz: float | None = None
    damping: float = 1.0
    saturate: bool = True
    samples: int = 201
    duration_s: float | None = None
    start_error: np.ndarray | None = None
    torque: object = None
    joint_limits: dict = field(default_factory=dict)
    on_joint_limit: str = "stop"
    on_actuator_limit: str = "continue"
    plant: Robot | None = None
    method: str = "dopri5"
    rtol: float = 1e-10
    atol: float = 1e-12
    where: str = ""
    q_weight: object = None
    r_weight: object = None
    tau: np.ndarray | None = None


@dataclass(frozen=True)
class Tracked:
    """A tracking run.

    Attributes
    ----------
    run : Simulation
        The engine's run (``error``, ``tau_cmd``, ``tau``, energies, events).
    reference : Signal
        Every coordinate's reference, a function of time (s).
    split : dict of str to ndarray
        The applied torques' parts along the motion the plant made, each (N, actuated).
    sizing : tuple of ActuatorSizing
        What each actuator delivered.
    x, x_ref : ndarray, shape (N, task), or None
        The task coordinates (m; rad for phi) and their reference at the run's samples; None
        for a robot without a task.
    """

    run: Simulation
    reference: Signal
    split: dict
    sizing: tuple[ActuatorSizing, ...]
    x: np.ndarray | None
    x_ref: np.ndarray | None


def track(robot: Robot, req: Tracking) -> Tracked:
    """Run ``req`` with ``robot`` as the controller's model (see the module docstring)."""
    jt = req.motion
    if not isinstance(jt, JointTrajectory):
        raise InputError(f"{req.where or 'Tracking'}: motion must be a JointTrajectory (every "
                         "coordinate: inverse_kinematics, from_actuated), got "
                         f"{type(jt).__name__}")
    t_end = req.duration_s or float(jt.t_s[-1])
    ref_full = reference(jt, t_end, req.where)
    act = list(robot.actuated)
    error = None if req.start_error is None else as_vector(
        "start_error", req.start_error, len(act))  # one value per actuated joint
    ref = Signal(ref_full.knots_s, np.ascontiguousarray(ref_full.coefficients[:, act]))
    kp, kd = req.kp, req.kd
    if req.law == "lqr":
        ctl = _tvlqr(robot, req)
    elif req.law != "none" and kp is None:
        if req.natural_frequency_hz is None:
            raise InputError(f"{req.where or 'Tracking'}: law {req.law!r} needs gains kp and kd, "
                             "or natural_frequency_hz (and damping) to set them")
        kp, kd = bandwidth_gains(robot, req.law, jt.q[0], req.natural_frequency_hz, req.damping)
    if req.law != "lqr":
        ctl = controller(req.law, kp, kd, width=len(act), saturate=req.saturate)
    # the start: on the reference, or off it on the actuated joints; a closed chain's passive
    # joints and rates from the plant's loops (a plant of other lengths than the model's is
    # not on the reference's: refused once, with a hint to give start_error, which it had)
    q0, qd0 = jt.q[0].copy(), jt.qd[0].copy()
    if error is not None:
        q0[act] += error
    plant = req.plant or robot
    run = simulate_controlled(
        robot, ctl, (0.0, t_end), reference=None if req.law == "lqr" else ref, plant=plant,
        q0=q0, qd0=qd0, project=robot.is_closed_chain,
        torque=req.torque, t_eval=np.linspace(0.0, t_end, req.samples),
        joint_limits=req.joint_limits, on_joint_limit=req.on_joint_limit,
        on_actuator_limit=req.on_actuator_limit, method=req.method, rtol=req.rtol,
        atol=req.atol)
    # the applied torques split along the motion the plant made (its own dynamics)
    split = split_along(plant, run.q, run.qd, run.tau, t=run.t_s)
    sizing = size(plant, run.t_s, run.qd, run.tau)
    x = x_ref = None
    if robot.task_names:
        # the tool where the plant's geometry puts it (the model's put a plant with a 33 cm
        # upper arm 30 mm off, reported 0.8 mm from its path); its path as the model planned it
        x = plant.task(run.q)[0].reshape(len(run.t_s), -1)
        x_ref = robot.task(ref_full(run.t_s))[0].reshape(len(run.t_s), -1)
    return Tracked(run, ref_full, split, sizing, x, x_ref)


def _tvlqr(robot: Robot, req: Tracking):
    """The time-varying LQR law along ``req.motion`` (its torques given or from the inverse
    dynamics), LQR about its end after it."""
    from .tvlqr import tvlqr

    jt, where = req.motion, (req.where + ": " if req.where else "")
    if req.q_weight is None or req.r_weight is None:
        raise InputError(f"{where}law \"lqr\" needs q_weight and r_weight")
    try:
        return tvlqr(robot, jt, req.tau, q_weight=req.q_weight,
                     r_weight=req.r_weight).controller(req.saturate)
    except InputError as exc:
        raise InputError(f"{where}{exc}") from None


def reference(jt: JointTrajectory, t_end: float, where: str) -> Signal:
    """Every coordinate's reference as quintic Hermite polynomials; held after its end."""
    ref = from_motion(jt.t_s, jt.q, jt.qd, jt.qdd)
    if t_end > jt.t_s[-1] + 1e-12:
        moving = np.max(np.abs(jt.qd[-1]))  # (a cubic ends with an acceleration: held, it jumps)
        if moving > REST_TOL:  # a study names its file and field, the API its argument
            fld = "control.duration" if where else "duration_s"
            raise InputError(f"{where + ': ' if where else ''}{fld} {t_end:g} s outlasts the "
                             f"motion ({jt.t_s[-1]:g} s), which ends moving ({moving:.3g} per "
                             f"s): the reference cannot be held; end the motion at rest or "
                             f"shorten {fld}")
        ref = ref.hold_until(t_end)
    return ref
