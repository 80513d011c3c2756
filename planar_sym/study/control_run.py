"""Run a control study (``kind = "control"``): the study's motion is the reference, the
controller tracks it on the plant in the compiled loop, and the result carries the tracking
errors, the commanded and applied torques, the events and the energy balance.

Series (``dynamics.series.Series``, named here by their columns), besides those of a
simulation (``t_s``, task coordinates, ``q<k>``, ``qd<k>``):
``q<k>_ref_rad`` and ``e<k>_rad`` (reference and error q_ref - q, actuated coordinates);
``x_ref_mm``, ``y_ref_mm`` (``phi_ref_rad``) and ``e_task_mm`` (distance of the tool from its
reference); ``tau_cmd<k>_n_m`` (the controller's) and ``tau<k>_n_m`` (applied, after
saturation); ``p<k>_w``; ``energy_j`` (the plant's), ``work_j`` (int tau . qd dt),
``friction_j`` (int D . qd dt) and ``balance_j`` = energy - energy(0) - (work - friction),
which is zero up to the integrator's accuracy.
"""

from __future__ import annotations

import numpy as np

from ..control import controller as make_controller
from ..control.laws import bandwidth_gains
from ..dynamics.engine import simulate_controlled
from ..dynamics.events import coordinate_index
from ..dynamics.inverse import split_along
from ..dynamics.run_result import Simulation
from ..errors import InputError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal, from_motion, from_table
from . import spec as specs
from .columns import coordinates_note, task_series
from .motion import check_width, coordinate_scale, joint_motion
from .parameters import with_overrides
from .result import Result, Series, coordinate_column
from .sizing import size

#: a reference that ends moving cannot be held: its end rates must be this small (SI/s)
REST_TOL = 1e-9


def run_control(st: specs.Study, robot: Robot, samples: int | None = None) -> Result:
    cs = st.control
    where = str(st.path or st.name)
    plant = robot
    if cs.plant:
        plant = with_overrides(robot, cs.plant, f"{where}: control.plant")
    jt, _ = joint_motion(st, robot)
    t_end = cs.duration_s or float(jt.t_s[-1])
    ref_full = _reference(jt, t_end, where)
    act = list(robot.actuated)
    ref = Signal(ref_full.knots_s, np.ascontiguousarray(ref_full.coefficients[:, act]))
    ctl = make_controller(cs.law, *_gains(st, robot, jt), width=len(act), saturate=cs.saturate)
    q0, qd0 = _start(st, robot, jt)
    t = np.linspace(0.0, t_end, samples or cs.samples)
    limits = _limits(st, robot)
    run = simulate_controlled(
        robot, ctl, (0.0, t_end), reference=ref, plant=plant, q0=q0, qd0=qd0,
        torque=torque_input(st, robot, st.control.torque, t_end, "control.torque"), t_eval=t, joint_limits=limits,
        on_joint_limit=st.events.on_joint_limit, on_actuator_limit=st.events.on_actuator_limit,
        method=cs.method, rtol=cs.rtol, atol=cs.atol)
    return _result(st, robot, plant, run, ref_full)


def _reference(jt: JointTrajectory, t_end: float, where: str) -> Signal:
    """Every coordinate's reference as quintic Hermite polynomials; held after its end."""
    ref = from_motion(jt.t_s, jt.q, jt.qd, jt.qdd)
    if t_end > jt.t_s[-1] + 1e-12:
        moving = np.max(np.abs(jt.qd[-1]))  # (a cubic ends with an acceleration: held, it jumps)
        if moving > REST_TOL:
            raise InputError(f"{where}: control.duration {t_end:g} s outlasts the motion "
                             f"({jt.t_s[-1]:g} s), which ends moving ({moving:.3g} per s): "
                             "the reference cannot be held; end the motion at rest or shorten "
                             "control.duration")
        ref = ref.hold_until(t_end)
    return ref


def _gains(st: specs.Study, robot: Robot, jt: JointTrajectory):
    """(kp, kd) SI: as given, or from the natural frequency w and damping zeta: computed
    torque Kp = w^2, Kd = 2 zeta w; PD the same times each actuated joint's effective inertia
    at the start (for a closed chain, of the motion reduced to the actuated joints)."""
    cs = st.control
    na = len(robot.actuated)
    if cs.law == "none":
        return None, None
    if cs.kp is not None:
        for key, v in (("control.kp", cs.kp), ("control.kd", cs.kd)):
            if len(v) != 1:
                check_width(st, key, v, na, "actuated joint (or 1 for all)")
        return np.broadcast_to(cs.kp, (na,)), np.broadcast_to(cs.kd, (na,))
    return bandwidth_gains(robot, cs.law, jt.q[0], cs.natural_frequency_hz, cs.damping)


def _start(st: specs.Study, robot: Robot, jt: JointTrajectory):
    """On the reference, or off it by ``control.start_error`` on the actuated joints (the
    loops then give the passive joints)."""
    q0, qd0 = jt.q[0].copy(), jt.qd[0].copy()
    err = st.control.start_error
    if err is None:
        return q0, qd0
    act = list(robot.actuated)
    check_width(st, "control.start_error", err, len(act), "actuated joint")
    q0[act] += np.array(err) * coordinate_scale(st, robot)[act]
    if robot.is_closed_chain:
        from ..motion.closure import complete_rates, solve_passive

        q0 = solve_passive(robot, q0[act][None], q_guess=jt.q[0])[0]
        qd, _ = complete_rates(robot, q0[None], qd0[act][None], np.zeros((1, len(act))))
        qd0 = qd[0]
    return q0, qd0


def _limits(st: specs.Study, robot: Robot) -> dict:
    """Joint limits in SI, keyed by coordinate index; ``q<k>`` or the joint's name."""
    scale = coordinate_scale(st, robot)
    out = {}
    for key, (lo, hi) in st.events.joint_limits.items():
        try:
            i = coordinate_index(robot, key)
        except InputError as exc:
            raise InputError(f"{st.path or st.name}: events.joint_limits.{key}: {exc}") from None
        out[i] = (lo * scale[i], hi * scale[i])
    return out


def torque_input(st: specs.Study, robot: Robot, tq, t_end: float, fld: str):
    """Input torques on the actuated joints (N*m or N) from a study's TorqueInput: None, a
    constant vector, or a Signal (a table read as stated, a profile then held)."""
    na = len(robot.actuated)
    if tq is None:
        return None
    if tq.constant is not None:
        check_width(st, fld, tq.constant, na, "actuated joint")
        return np.array(tq.constant)
    if tq.profile is not None:
        from ..motion.profiles_by_name import make_profile

        for key, v in (("start", tq.start), ("end", tq.end)):
            check_width(st, f"{fld}.{key}", v, na, "actuated joint")
        knots = np.linspace(0.0, tq.duration_s, 3)
        tr = make_profile(tq.profile, t_s=knots, start=tq.start, end=tq.end,
                          duration_s=tq.duration_s)
        return from_motion(knots, tr.x, tr.xd, tr.xdd).hold_until(t_end)
    from ..motion.tables import read_table

    names = [coordinate_column("tau", i, robot.coordinate_units[i]) for i in robot.actuated]
    times, values = read_table(tq.file, names)
    sig = from_table(times, values, tq.interpolation)
    sig.covers(0.0, t_end, f"{tq.file}: the torque table")
    return sig


def _result(st: specs.Study, robot: Robot, plant: Robot, run: Simulation,
            ref_full: Signal) -> Result:
    t = run.t_s
    units = robot.coordinate_units
    data = [Series("t", "s", t)]
    q_ref_full = ref_full(t)
    if robot.task_names:
        x = robot.task(run.q)[0].reshape(len(t), -1)
        x_ref = robot.task(q_ref_full)[0].reshape(len(t), -1)
        data += task_series(robot, x) + task_series(robot, x_ref, "_ref")
        xy = [i for i, nm in enumerate(robot.task_names) if nm != "phi"]
        data.append(Series("e_task", "mm",
                           np.linalg.norm(x_ref[:, xy] - x[:, xy], axis=1) * 1e3))
    # the run's own series (the same code names a Simulation's columns), in the CSV's order
    data += run.series("q") + run.series("qd")
    error = run.error
    for k, i in enumerate(robot.actuated):
        data += [run.get("q_ref", i), Series.of_coordinate("e", i, units[i], error[:, k])]
    for k, i in enumerate(robot.actuated):
        data += [run.get("tau_cmd", i), run.get("tau", i),
                 Series("p", "W", run.tau[:, k] * run.qd[:, i], index=i)]
    data += [run.get("energy"), run.get("work"), run.get("friction"),
             Series("balance", "J",
                    run.energy_j - run.energy_j[0] - (run.work_j - run.friction_j))]
    ctl = run.controller
    gains = ""
    if ctl.kind != "none":
        kpu, kdu = ctl.gain_units(units[robot.actuated[0]])
        gains = (f" Kp {', '.join(f'{v:.4g}' for v in ctl.kp)} {kpu}, Kd "
                 f"{', '.join(f'{v:.4g}' for v in ctl.kd)} {kdu}")
    law = {"pd": "PD + gravity compensation", "computed_torque": "computed torque",
           "none": "open loop"}[ctl.kind]
    err = np.max(np.abs(run.error), axis=0)
    note = (f"{coordinates_note(robot)}; {law}{gains}; max |error| "
            + ", ".join(f"e{i + 1} {v:.3g} {units[i]}" for i, v in zip(robot.actuated, err))
            + "; final |error| " + ", ".join(f"e{i + 1} {abs(v):.3g} {units[i]}" for i, v in
                                             zip(robot.actuated, run.error[-1]))
            + f"; energy balance residual {run.balance_residual:.2e} (relative); {run.method} "
              f"rtol {run.rtol:g}")
    if st.control.plant:
        note += "; plant parameters differ: " + ", ".join(sorted(st.control.plant))
    if robot.is_closed_chain:
        note += f"; loop residual max |Phi| = {run.constraint_drift_m:.1e} m"
    if run.events:
        note += "; EVENTS: " + "; ".join(str(e) for e in run.events)
    sizing = size(plant, t, run.qd, run.tau)
    # the applied torques split along the motion the plant made (its own dynamics)
    split = split_along(plant, run.q, run.qd, run.tau, t=run.t_s)
    return Result(st.name, st.title, data, kind="control", note=note, split=split,
                  robot=robot.name,
                  actuated=robot.actuated, sizing=sizing, reference=q_ref_full,
                  events=run.events)
