"""A controlled run's inputs checked before the compiled loop runs: the law against the robot
(``check_controller``), the reference as a Signal over the actuated joints, and the input
torques as a constant or a Signal.
"""

from __future__ import annotations

from ..errors import InputError
from ..model.arrays import as_vector
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal, from_motion
from .integrate import check_torque
from .laws import Controller


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
    if ctl.kind == "lqr" and ctl.schedule is None and (
            len(ctl.gain) != 2 * n * na or len(ctl.x_ref) != 2 * n
            or len(ctl.u_ref) != na):  # the C loop reads 2n and na values from them
        raise InputError(f"{robot.name}: this LQR law was designed for another robot (make "
                         "it with planar_sym.lqr on this one)")
    for k in (ctl.kp, ctl.kd):
        if k and len(k) not in (1, len(robot.actuated)):
            raise InputError(f"{robot.name}: {len(k)} gains for {len(robot.actuated)} "
                             "actuated joints")


def engine_reference(robot: Robot, reference, ctl: Controller, t0: float, t1: float
                     ) -> Signal | None:
    """The reference as the compiled loop takes it: None (law "lqr", or "none" without one), or
    a Signal over the actuated coordinates covering ``t0`` to ``t1`` (s), from a
    JointTrajectory (every coordinate) or a Signal of the actuated ones."""
    ref = _reference(robot, reference, ctl)
    if ref is not None:
        ref.covers(t0, t1, "the reference motion")
    return ref


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


def engine_torque(torque, na: int, t0: float, t1: float):
    """Input torques as the compiled loop takes them: None, a Signal of ``na`` channels covering
    ``t0`` to ``t1`` (s), or constant (na,) N*m (N at a slider); a function of time refused."""
    if torque is None or isinstance(torque, Signal):
        if isinstance(torque, Signal):
            check_torque(torque, na)  # its width, by simulate's rule
            torque.covers(t0, t1, "the torque table")
        return torque
    if callable(torque):
        raise InputError("a torque function of time runs in Python; in the compiled loop give "
                         "a table (planar_sym.motion.signals.from_table) or a constant")
    return as_vector("torque", torque, na)
