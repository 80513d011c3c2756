"""A study's motion in SI: the profile sampled in time, its joint motion (inverse kinematics in
task space, the loops for a closed chain's passive joints), and checked start poses and states.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from ..model.description.types import ANGLE_TURN_RAD
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory, Trajectory
from ..motion.profiles_by_name import make_profile, profile_span
from . import spec as specs


def joint_motion(st: specs.Study, robot: Robot, samples: int | None = None, *,
                 t: np.ndarray | None = None) -> tuple[JointTrajectory, np.ndarray | None]:
    """Every joint's motion (SI) of an inverse-dynamics study, and its task coordinates.

    At ``samples`` evenly spaced times (default the study's), or at the times ``t`` (s).
    """
    m = st.motion
    if m.space != "task":
        coords = robot.actuated if robot.is_closed_chain else range(robot.n)
        any(warn_turns(st, robot, f"motion.{key}", getattr(m, key, None), coords)
            for key in ("start", "by", "end"))  # one warning for one slip
    tr = trajectory(st, robot, samples) if t is None else profile_at(st, robot, np.asarray(t))
    q_start = start_pose(st, robot)  # picks the assembly (and working) mode
    if m.space == "task":
        from ..errors import WorkspaceError
        from ..motion.ik import inverse_kinematics

        try:
            jt = inverse_kinematics(robot, tr, solver=m.ik, q_start=q_start)
        except WorkspaceError as exc:
            # 100 meant in mm, read in the default m, is a target 100 m away: say which unit
            far = st.length_si == 1.0 and np.max(np.abs(m.start)) > MM_LIKE_M
            if not far:
                raise
            raise WorkspaceError(f"{exc}; the study's lengths are in m ([units] length, "
                                 f"default m): were they typed in mm? ([units] length = "
                                 f"\"mm\")") from None
        return jt, tr.x
    if robot.is_closed_chain:
        from ..motion.closure import from_actuated

        jt = from_actuated(robot, tr.t_s, tr.x, tr.xd, tr.xdd, q_guess=q_start)
    else:
        jt = JointTrajectory(tr.t_s, tr.x, tr.xd, tr.xdd)
    return jt, (robot.task(jt.q)[0] if robot.task_names else None)


def timed_motion(st: specs.Study, robot: Robot, samples: int | None = None
                 ) -> tuple[JointTrajectory, np.ndarray | None, str]:
    """``joint_motion``, and with ``[optimise]`` its path timed as fast as the limits allow
    (``planar_sym.time_optimal``: the same samples at new times); a note says what was done
    ("" without ``[optimise]``)."""
    jt, x = joint_motion(st, robot, samples)
    if st.optimise is None:
        return jt, x, ""
    from ..optimal.time_optimal import time_optimal

    speed = st.optimise.speed_limit
    if speed is not None:
        if len(speed) != robot.n:
            raise InputError(f"{st.path or st.name}: optimise.speed_limit: {robot.name} needs "
                             f"{robot.n} values, one per coordinate (got {len(speed)})")
        speed = np.asarray(speed) * coordinate_scale(st, robot)
    limit = st.optimise.torque_limit
    if limit is not None and len(limit) not in (1, len(robot.actuated)):
        raise InputError(f"{st.path or st.name}: optimise.torque_limit: {robot.name} needs "
                         f"{len(robot.actuated)} values, one per motor (got {len(limit)})")
    fast = time_optimal(robot, jt, limit, speed)
    new = fast.trajectory
    x = robot.task(new.q)[0] if robot.task_names else None
    units = ", ".join("N" if robot.coordinate_units[i] == "m" else "N*m" for i in robot.actuated)
    note = (f"time-optimal: {fast.duration_s:.4g} s (the motion as given: "
            f"{jt.t_s[-1] - jt.t_s[0]:.4g} s) under |tau| <= "
            f"{', '.join(f'{v:g}' for v in fast.limits)} ({units}); a torque on its limit at "
            f"{int(fast.on_limit.sum())} of {len(fast.on_limit)} samples")
    if fast.speed_limits is not None:  # (left out, a trial read a torque-bound move 23 % on)
        speeds = ", ".join(f"{v:.4g}" for v in fast.speed_limits)
        vunits = ", ".join("m/s" if u == "m" else "rad/s" for u in robot.coordinate_units)
        note += (f", a speed on its limit (|qd| <= {speeds} ({vunits})) at "
                 f"{int(fast.on_speed_limit.sum())}")
    return new, x, note


#: a start pose for the inverse kinematics only picks the assembly mode, so it may be typed
#: approximately; further off than this (m) it is not an assembled pose at all
START_POSE_GAP_M = 1e-3
#: the initial state of a simulation must be on the loops: this is the loops' own tolerance
#: (m), the forward dynamics' drift limit
STATE_GAP_M = 1e-9


#: a task start farther than this (m) in a study read in metres, and out of reach: likely mm
MM_LIKE_M = 10.0


def warn_turns(st: specs.Study, robot: Robot, fld: str, values, coords,
                limit: float = ANGLE_TURN_RAD, beyond: str = "one") -> bool:
    """Warn where a joint angle typed in radians (the default) exceeds ``limit`` (a turn), as
    the description does for its drawn angles: 360 meant in degrees ran 57 turns in a second.
    True when it warned."""
    if values is None or st.angle_si != 1.0:
        return False
    for k, (i, v) in enumerate(zip(coords, values)):
        if robot.coordinate_units[i] == "rad" and abs(v) > limit:
            warnings.warn(f"{st.path or st.name}: {fld}[{k}] = {v:g} rad is "
                          f"{abs(v) / ANGLE_TURN_RAD:.3g} turns (a warning beyond {beyond}): "
                          f"were the angles typed in degrees? ([units] angle = \"deg\" makes "
                          f"it {v:g} deg)", RuntimeWarning, stacklevel=4)
            return True
    return False


def warn_start_error(st: specs.Study, robot: Robot, values) -> None:
    """``control.start_error`` beyond a quarter turn in radians: a start error is a nudge off
    the reference (a trial typed [2, -2] meaning degrees: the controller started 115 degrees
    off)."""
    warn_turns(st, robot, "control.start_error", values, robot.actuated, ANGLE_TURN_RAD / 4,
                "a quarter")


def coordinate_scale(st: specs.Study, robot: Robot) -> np.ndarray:
    """SI factor of each coordinate as a study file gives it: its length unit for a prismatic
    joint, its angle unit for a revolute one."""
    return np.array([st.length_si if u == "m" else st.angle_si for u in robot.coordinate_units])


def start_pose(st: specs.Study, robot: Robot) -> np.ndarray | None:
    """``motion.start_pose`` in rad; a closed chain's must be roughly assembled."""
    if st.motion.start_pose is None:
        return None
    check_width(st, "motion.start_pose", st.motion.start_pose, robot.n, "coordinate")
    warn_turns(st, robot, "motion.start_pose", st.motion.start_pose, range(robot.n))
    q = np.array(st.motion.start_pose) * coordinate_scale(st, robot)
    _check_loops(st, robot, "motion.start_pose", q, START_POSE_GAP_M)
    return q


def initial_state(st: specs.Study, robot: Robot) -> tuple[np.ndarray, np.ndarray, bool]:
    """(q0, qd0, project): every coordinate's start in rad and rad/s. A closed chain's q0 is
    every coordinate, on the loops, or its actuated joints only: the passive ones are then left
    to the simulation to solve (``project`` True: ``dynamics.forward.simulate`` continues the
    drawn pose along the loops, so in its assembly mode, and takes their rates from qd0's), and
    are returned at the drawn pose, their rates 0."""
    s, scale = st.simulation, coordinate_scale(st, robot)
    n_act = len(robot.actuated)
    short = robot.is_closed_chain and len(s.q0) == n_act
    warn_turns(st, robot, "simulation.q0", s.q0, robot.actuated if short else range(robot.n))
    if short:
        act = list(robot.actuated)
        qda = np.zeros(n_act) if s.qd0 is None else np.array(s.qd0)
        check_width(st, "simulation.qd0", qda, n_act, "actuated joint")
        # passive coordinates at the drawn pose are no guess to simulate(project=True): it
        # reaches them from the drawn pose along the loops, in its assembly mode (Newton
        # straight from the drawn passive angles could close the other one)
        q0, qd0 = np.array(robot.q_drawn, dtype=float), np.zeros(robot.n)
        q0[act], qd0[act] = np.array(s.q0) * scale[act], qda * scale[act]
        return q0, qd0, True
    what = "coordinate (or actuated joint, for a closed chain)" if robot.is_closed_chain \
        else "coordinate"
    check_width(st, "simulation.q0", s.q0, robot.n, what)
    q0 = np.array(s.q0) * scale
    qd0 = np.zeros(robot.n) if s.qd0 is None else np.array(s.qd0)
    check_width(st, "simulation.qd0", qd0, robot.n, "coordinate")
    qd0 = qd0 * scale
    _check_loops(st, robot, "simulation.q0", q0, STATE_GAP_M)
    if robot.is_closed_chain:
        rate = np.abs(robot.constraint_jacobian(q0).reshape(robot.n_constraints, robot.n) @ qd0)
        if np.max(rate) > STATE_GAP_M:
            raise InputError(f"{st.path or st.name}: simulation.qd0 breaks the loops: "
                             f"Phi_q qd0 = {np.max(rate):.3g} m/s (limit {STATE_GAP_M:g}); give "
                             f"the actuated joints' rates only ({n_act} values) and the loops "
                             "give the rest")
    return q0, qd0, False


def _check_loops(st, robot: Robot, fld: str, q: np.ndarray, limit: float) -> None:
    if not robot.is_closed_chain:
        return
    gap = np.abs(robot.constraint(q)).reshape(-1, 2)
    worst = int(np.argmax(np.max(gap, axis=1)))
    if gap.max() > limit:
        na = len(robot.actuated)
        hint = (f"; give the actuated joints only ({na} value{'s' * (na > 1)}) and the loops "
                "give the rest" if fld == "simulation.q0" else "")
        raise InputError(f"{st.path or st.name}: {fld} does not close the loop at cut joint "
                         f"{robot.loops[worst]}: the joint's two points are "
                         f"{np.hypot(*gap[worst]) * 1e3:.4g} mm apart (limit "
                         f"{limit * 1e3:g} mm){hint}")


def channel_scale(st: specs.Study, robot: Robot) -> np.ndarray:
    """SI factor of each motion channel: lengths for x, y and prismatic joints; angles for phi
    and revolute joints."""
    m = st.motion
    if m.space == "task":
        return np.array([st.angle_si if n == "phi" else st.length_si for n in robot.task_names])
    coords = robot.actuated if robot.is_closed_chain else range(robot.n)
    # a joint move is in the file's angle unit, a prismatic joint's in its length unit
    return np.array([st.length_si if robot.coordinate_units[i] == "m" else st.angle_si
                     for i in coords])


def trajectory(st: specs.Study, robot: Robot, samples: int | None = None) -> Trajectory:
    """The study's motion profile at its evenly spaced samples, in SI."""
    t0, t1 = span(st, robot)
    return profile_at(st, robot, np.linspace(t0, t1, samples or st.motion.samples))


def span(st: specs.Study, robot: Robot) -> tuple[float, float]:
    """First and last time (s) of the motion: from 0 to its duration, which is given or set by
    the profile (the via points' last time, the table's rows, the trapezoid's limits)."""
    if st.motion.duration_s is not None:
        return 0.0, st.motion.duration_s
    return profile_span(st.motion.profile, **_profile_args(st, robot))


def duration(st: specs.Study, robot: Robot) -> float:
    """The motion's duration (s)."""
    t0, t1 = span(st, robot)
    return t1 - t0


def _what(st: specs.Study, robot: Robot) -> str:
    if st.motion.space == "task":
        return "task coordinate (" + ", ".join(robot.task_names) + ")"
    return "actuated joint" if robot.is_closed_chain else "joint"


def _start_and_by(st: specs.Study, robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    m, scale = st.motion, channel_scale(st, robot)
    check_width(st, "motion.start", m.start, len(scale), _what(st, robot))
    start = np.array(m.start) * scale
    return start, (np.array(m.by) * scale if m.by is not None else np.array(m.end) * scale - start)


def table_columns(st: specs.Study, robot: Robot) -> list[list[str]]:
    """The CSV columns a table motion needs, each with the unit suffixes it may carry."""
    if st.motion.space == "task":
        return [[f"{n}_rad", f"{n}_deg"] if n == "phi" else [f"{n}_mm", f"{n}_m"]
                for n in robot.task_names]
    coords = robot.actuated if robot.is_closed_chain else range(robot.n)
    return [[f"q{i + 1}_m", f"q{i + 1}_mm"] if robot.coordinate_units[i] == "m"
            else [f"q{i + 1}_rad", f"q{i + 1}_deg"] for i in coords]


def _table(st: specs.Study, robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    from ..motion.tables import read_table

    return read_table(st.motion.table, table_columns(st, robot))


def _profile_args(st: specs.Study, robot: Robot) -> dict:
    """The study's motion as ``make_profile``'s arguments, in SI."""
    m, scale = st.motion, channel_scale(st, robot)
    if m.profile == "via":
        check_width(st, "motion.points[0]", m.points[0], len(scale), _what(st, robot))
        return {"via_times": m.times_s, "via_points": np.array(m.points) * scale}
    if m.profile == "table":
        times, values = _table(st, robot)
        return {"table_times": times, "table_values": values}
    start, by = _start_and_by(st, robot)
    args = {"start": start, "by": by, "duration_s": m.duration_s}
    if m.profile == "trapezoid":
        args.update(v_max=np.array(m.v_max) * scale, a_max=np.array(m.a_max) * scale)
    return args


def profile_at(st: specs.Study, robot: Robot, t: np.ndarray | None) -> Trajectory:
    """The study's motion profile at times ``t`` (s), in SI; ``t = None``: at its ends. The
    cubic is the seed's coeff_3rd bit for bit (``by`` goes through unchanged)."""
    if t is None:
        t = np.array(span(st, robot))
    return make_profile(st.motion.profile, t_s=t, **_profile_args(st, robot))


def check_width(st, fld: str, values, width: int, what: str) -> None:
    if len(values) and not width and what.startswith(("task coordinate", "actuated joint")):
        why = ("has no task point (no [task] in its description): move its joints instead "
               '(space = "joint")' if what.startswith("task") else
               "has no actuated joint (every joint is passive): nothing takes a torque; mark "
               "the driven joint actuated = true in its description")
        raise InputError(f"{st.path or st.name}: {fld}: {st.robot} {why} (got {len(values)} "
                         f"value{'' if len(values) == 1 else 's'})")
    if len(values) != width:
        raise InputError(f"{st.path or st.name}: {fld}: {st.robot} needs {width} "
                         f"value{'' if width == 1 else 's'}, one per {what} (got {len(values)})")
