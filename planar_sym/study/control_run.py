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

from dataclasses import replace

import numpy as np

from ..control.track import Tracked, Tracking, track
from ..dynamics.events import coordinate_index
from ..errors import InputError, warn_caller
from ..model.robot import Robot
from ..motion.signals import from_motion, from_table
from . import spec as specs
from .checks import StudyError
from .columns import coordinates_note, task_series
from .motion import check_width, coordinate_scale, joint_motion, warn_start_error, warn_turns
from .result import Result, Series, coordinate_column


def run_control(st: specs.Study, robot: Robot, samples: int | None = None,
                plant: Robot | None = None) -> Result:
    """Track the study's motion with ``robot`` as the controller's model and ``plant`` (the
    study's [control.plant] applied, by ``study.run``) as the machine that moves."""
    cs = st.control
    where = str(st.path or st.name)
    # the study read into one request in SI (its fields checked here, by name, every problem
    # at once: a trial's kp, kd and start_error of the wrong width came one run at a time,
    # kd never), then tracked
    problems: list[str] = []
    kp, kd = _collect(problems, (None, None), _given_gains, st, robot)
    start_error = _collect(problems, None, _start_error, st, robot)
    limits = _collect(problems, {}, _limits, st, robot)
    weights = {k: _collect(problems, None, _weights, st, robot, k)
               for k in ("q_weight", "r_weight")}
    _all_at_once(problems)
    tau, found = None, ""
    if st.kind == "optimal":  # the optimal move, with the torques that make it
        from .optimal_run import plan

        move, found = plan(st, robot)
        jt, tau = move.trajectory, move.tau
    else:
        jt, _ = joint_motion(st, robot)
    _warn_unheld(st, robot, jt)
    # one rule for every control study: a run cut short of its move stopped mid-move in silence
    move_s = float(jt.t_s[-1] - jt.t_s[0])
    if cs.duration_s is not None and cs.duration_s < move_s * (1 - 1e-9):
        raise InputError(f"{where}: control.duration {cs.duration_s:g} s ends before the "
                         f"move it tracks ({move_s:.4g} s): lengthen it, or leave it out (the "
                         "move's own duration)")
    # a torque input must cover the run: to the motion's end if no duration is given
    torque = torque_input(st, robot, cs.torque, cs.duration_s or float(jt.t_s[-1]),
                          "control.torque")
    done = track(robot, Tracking(
        motion=jt, law=cs.law, kp=kp, kd=kd, natural_frequency_hz=cs.natural_frequency_hz,
        damping=cs.damping, saturate=cs.saturate, samples=samples or cs.samples,
        duration_s=cs.duration_s, start_error=start_error, torque=torque, joint_limits=limits,
        on_joint_limit=st.events.on_joint_limit, on_actuator_limit=st.events.on_actuator_limit,
        plant=plant, method=cs.method, rtol=cs.rtol, atol=cs.atol, where=where,
        q_weight=weights["q_weight"], r_weight=weights["r_weight"],
        tau=tau))
    result = _result(st, robot, done)
    if found:  # what the move is: the plan the law tracks
        result = replace(result, note=f"{found}; {result.note}", timing=found)
    return result


def _collect(problems: list[str], default, check, *args):
    """``check(*args)``, or ``default`` with its problems added to ``problems``."""
    try:
        return check(*args)
    except StudyError as exc:
        problems.extend(exc.problems)
    except InputError as exc:
        problems.append(str(exc))
    return default


def _all_at_once(problems: list[str]) -> None:
    """One problem as it reads; several as one StudyError, each on its line."""
    if len(problems) == 1:
        raise InputError(problems[0])
    if problems:
        raise StudyError(problems)


def _warn_unheld(st: specs.Study, robot: Robot, jt) -> None:
    """Warn where the study asks what the law cannot do, and would otherwise pass in silence:
    ``saturate = true`` on joints with no actuator limit to clip at (a trial's cart-pole pushed
    0.273 N against its study's 0.2 N), and a reference moving a tree's passive joint, which a
    PD or computed-torque law does not hold (the pole told to turn 45 degrees fell to 211)."""
    where = f"{st.path or st.name}"
    if st.control.saturate_asked:
        free = [d.joint for d in robot.drive_train.drives
                if d.torque_limit is None and d.motor_torque_limit is None]
        if free:
            warn_caller(f"{where}: control.saturate = true, but {', '.join(free)} "
                        f"{'has' if len(free) == 1 else 'have'} no actuator limit to clip at "
                        "(torque_limit or motor_torque_limit under the description's "
                        "[joints.actuator]): not clipped")
    if st.control.law in ("pd", "computed_torque") and not robot.is_closed_chain:
        moved = [robot.coordinates[i] for i in range(robot.n) if i not in robot.actuated
                 and np.ptp(jt.q[:, i]) > 1e-9 * max(1.0, float(np.abs(jt.q[:, i]).max()))]
        if moved:
            warn_caller(f"{where}: the motion moves the passive {', '.join(moved)}, which law "
                        f"\"{st.control.law}\" does not hold (it drives the actuated joints "
                        "only): the passive coordinates go where the dynamics take them; law "
                        "\"lqr\" feeds them back")


def _weights(st: specs.Study, robot: Robot, key: str):
    """``control.q_weight`` or ``r_weight`` of law "lqr": one number (every state or torque)
    or one per state (2 per coordinate the law holds) or per motor, checked by name."""
    v = getattr(st.control, key)
    if v is None or len(v) == 1:
        return None if v is None else v[0]
    held = len(robot.actuated) if robot.is_closed_chain else robot.n
    width, what = ((2 * held, "state (q then qd of each coordinate the law holds)")
                   if key == "q_weight" else (len(robot.actuated), "actuated joint"))
    check_width(st, f"control.{key}", v, width, what + " (or 1 for all)")
    return v


def _given_gains(st: specs.Study, robot: Robot):
    """(kp, kd) SI as the study gives them, each (actuated,); (None, None) for the law "none"
    or when a natural frequency sets them (``control.track``: computed torque Kp = w^2,
    Kd = 2 zeta w; PD the same times each actuated joint's effective inertia at the start)."""
    cs = st.control
    na = len(robot.actuated)
    if cs.law == "none" or cs.kp is None:
        return None, None
    problems: list[str] = []
    for key, v in (("control.kp", cs.kp), ("control.kd", cs.kd)):
        if len(v) != 1:
            _collect(problems, None, check_width, st, key, v, na,
                     "actuated joint (or 1 for all)")
    _all_at_once(problems)
    return np.broadcast_to(cs.kp, (na,)), np.broadcast_to(cs.kd, (na,))


def _start_error(st: specs.Study, robot: Robot):
    """``control.start_error`` on the actuated joints in SI, or None."""
    err = st.control.start_error
    if err is None:
        return None
    act = list(robot.actuated)
    check_width(st, "control.start_error", err, len(act), "actuated joint")
    warn_start_error(st, robot, err)
    return np.array(err) * coordinate_scale(st, robot)[act]


def _limits(st: specs.Study, robot: Robot) -> dict:
    """Joint limits in SI, keyed by coordinate index; ``q<k>`` or the joint's name."""
    scale = coordinate_scale(st, robot)
    out, problems = {}, []
    for key, (lo, hi) in st.events.joint_limits.items():
        try:
            i = coordinate_index(robot, key)
        except InputError as exc:
            problems.append(f"{st.path or st.name}: events.joint_limits.{key}: {exc}")
            continue
        # limits typed in degrees in a radian study fired "at t = 0 s" with no file or field
        warn_turns(st, robot, f"events.joint_limits.{key}", (lo, hi), (i, i))
        out[i] = (lo * scale[i], hi * scale[i])
    _all_at_once(problems)
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


def _result(st: specs.Study, robot: Robot, done: Tracked) -> Result:
    run = done.run
    t = run.t_s
    units = robot.coordinate_units
    data = [Series("t", "s", t)]
    q_ref_full = done.reference(t)
    if done.x is not None:
        x, x_ref = done.x, done.x_ref
        data += task_series(robot, x) + task_series(robot, x_ref, "_ref")
        xy = [i for i, nm in enumerate(robot.task_names) if nm != "phi"]
        data.append(Series("e_task", "mm",
                           np.linalg.norm(x_ref[:, xy] - x[:, xy], axis=1) * 1e3))
    # the run's own series (the same code names a Simulation's columns), in the CSV's order
    data += run.series("q") + run.series("qd")
    error = run.error
    for k, i in enumerate(robot.actuated):
        data += [run.get("q_ref", i), Series.of_coordinate("e", i, units[i], error[:, k])]
    ctl = run.controller
    fed_back = _fed_back(robot, ctl, run)  # an LQR law's other coordinates (a pole)
    for i, e in fed_back.items():
        data.append(Series.of_coordinate("e", i, units[i], e))
    for k, i in enumerate(robot.actuated):
        data += [run.get("tau_cmd", i), run.get("tau", i),
                 Series("p", "W", run.tau[:, k] * run.qd[:, i], index=i)]
    data += [run.get("energy"), run.get("work"), run.get("friction"),
             Series("balance", "J",
                    run.energy_j - run.energy_j[0] - (run.work_j - run.friction_j))]
    gains = ""
    if ctl.kind == "lqr":
        cs = st.control
        gains = (" along the motion, then LQR about its end; q_weight "
                 f"{', '.join(f'{v:g}' for v in cs.q_weight)}, r_weight "
                 f"{', '.join(f'{v:g}' for v in cs.r_weight)} (SI)")
    elif ctl.kind != "none":
        kpu, kdu = ctl.gain_units(units[robot.actuated[0]])
        gains = (f" Kp {', '.join(f'{v:.4g}' for v in ctl.kp)} {kpu}, Kd "
                 f"{', '.join(f'{v:.4g}' for v in ctl.kd)} {kdu}")
    law = {"pd": "PD + gravity compensation", "computed_torque": "computed torque",
           "none": "open loop", "lqr": "time-varying LQR"}[ctl.kind]
    errors = dict(zip(robot.actuated, run.error.T)) | fed_back
    note = (f"{coordinates_note(robot)}; {law}{gains}; max |error| "
            + ", ".join(f"e{i + 1} {np.abs(e).max():.3g} {units[i]}"
                        for i, e in sorted(errors.items()))
            + "; final |error| " + ", ".join(f"e{i + 1} {abs(e[-1]):.3g} {units[i]}"
                                             for i, e in sorted(errors.items()))
            + f"; energy balance residual {run.balance_residual:.2e} (relative); {run.method} "
              f"rtol {run.rtol:g}")
    if st.control.plant:
        note += "; plant parameters differ: " + ", ".join(sorted(st.control.plant))
    if robot.is_closed_chain:
        note += f"; loop residual max |Phi| = {run.constraint_drift_m:.1e} m"
        moved = np.abs(run.q[0] - q_ref_full[0])
        moved[list(robot.actuated)] = 0.0  # (a start_error is the study's own)
        if moved.max() > 1e-9:  # the plant's loops are not the reference's (other lengths)
            i = int(np.argmax(moved))
            note += (f"; start: passive joints closed on the plant's loops ({robot.coordinates[i]}"
                     f" {moved[i]:.3g} {units[i]} from the reference)")
    if run.events:
        note += "; EVENTS: " + "; ".join(str(e) for e in run.events)
    return Result(st.name, st.title, data, kind="control", note=note, split=done.split,
                  robot=robot.name,
                  actuated=robot.actuated, sizing=done.sizing, reference=q_ref_full,
                  events=run.events)


def _fed_back(robot: Robot, ctl, run) -> dict[int, np.ndarray]:
    """The tracking error x_ref - q of the coordinates an LQR law feeds back besides the
    actuated ones (a tree's passive joints), keyed by coordinate (0-based)."""
    if ctl.kind != "lqr" or robot.is_closed_chain:
        return {}
    others = [i for i in range(robot.n) if i not in robot.actuated]
    ref = (ctl.schedule(run.t_s)[:, :robot.n] if ctl.schedule is not None
           else np.broadcast_to(np.asarray(ctl.x_ref[:robot.n]), run.q.shape))
    return {i: ref[:, i] - run.q[:, i] for i in others}
