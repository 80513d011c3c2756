"""The computation behind ``explore``, plain code testable without a front end.

``pose_report`` (a pose from the actuated joints), ``task_report`` (a pose from the task point,
by inverse kinematics) and ``ExploreState`` (the pose shown, continued from one move to the
next so a closed chain keeps its assembly mode and an arm its working mode) return a
``PoseReport``. A pose that cannot be reached is a report with a ``message``, never an
exception.
"""

from __future__ import annotations

import numpy as np

from ..dynamics.reactions import joint_loads
from ..errors import InputError, PlanarSymError
from ..model.robot import Robot
from .explore_report import PoseReport, shown, task_shown

#: a task move is followed by inverse kinematics through samples at most this far apart (m; rad
#: for phi), so Newton's continuation and its branch check see a smooth motion
TASK_STEP_M = 0.002
TASK_STEP_RAD = 0.02


def _rates(robot: Robot, values, name: str) -> np.ndarray:
    """The actuated joints' rates or accelerations as a vector (actuated,), SI; default 0."""
    n_act = len(robot.actuated)
    if values is None:
        return np.zeros(n_act)
    try:
        arr = np.asarray(values, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        arr = np.full(1, np.nan)
    if arr.shape != (n_act,) or not np.all(np.isfinite(arr)):
        raise InputError(f"{robot.name}: {name} must be {n_act} finite numbers, one per "
                         f"actuated joint ({', '.join(robot.coordinates[i] for i in robot.actuated)})"
                         f", got {np.asarray(values).tolist()}")
    return arr


def _start(robot: Robot, q_previous) -> np.ndarray:
    q = np.array(robot.q_drawn if q_previous is None else q_previous, dtype=float).reshape(-1)
    if q.shape != (robot.n,) or not np.all(np.isfinite(q)):
        raise InputError(f"{robot.name}: q_previous must be {robot.n} finite coordinates "
                         f"(rad; m at a slider), got {np.asarray(q_previous).tolist()}")
    return q


def _shown(robot: Robot, indices, values) -> str:
    """``A = 120 deg, E = 60 deg``: coordinates (SI) as the sliders show them."""
    out, coordinate = [], shown(robot)
    for i, v in zip(indices, values):
        scale, unit = coordinate[robot.coordinate_units[i]]
        out.append(f"{robot.coordinates[i]} = {v * scale:.4g} {unit}")
    return ", ".join(out)


def _at(robot: Robot, q: np.ndarray, qd_act: np.ndarray, qdd_act: np.ndarray, reached: bool,
        message: str = "") -> PoseReport:
    """The report at a pose ``q`` (n,) already on the loops: rates, torques, loads (SI)."""
    act = list(robot.actuated)
    task = robot.task(q)[0].reshape(-1) if robot.task_names else None
    residual = condition = lam = tau = loads = None
    qd, qdd = np.zeros(robot.n), np.zeros(robot.n)
    qd[act], qdd[act] = qd_act, qdd_act
    try:
        if robot.is_closed_chain:
            from ..motion.closure import complete_rates

            residual = float(np.max(np.abs(robot.constraint(q))))
            jac = np.reshape(robot.constraint_jacobian(q), (robot.n_constraints, robot.n))
            condition = float(np.linalg.cond(jac[:, list(robot.passive)], 1))
            qd_all, qdd_all = complete_rates(robot, q[None], qd_act[None], qdd_act[None])
            qd, qdd = qd_all[0], qdd_all[0]
            tau_act, lam = robot.closed_chain_inverse_dynamics(q[None], qd[None], qdd[None])
            inverse = (tau_act, lam)
            tau, lam = tau_act[0], lam[0]
        else:
            tau_all = np.reshape(robot.inverse_dynamics(q[None], qd[None], qdd[None]),
                                 (1, robot.n))
            inverse = (tau_all, None)
            tau = tau_all[0, act]
        loads = joint_loads(robot, q[None], qd[None], qdd[None], inverse=inverse)
    except PlanarSymError as exc:
        message = message or f"No torques at this pose: {exc}"
        tau = loads = lam = None
    return PoseReport(robot.name, q, qd, qdd, reached, tau, loads, lam, task, residual,
                      condition, message)


def pose_report(robot: Robot, q_actuated, qd=None, qdd=None, q_previous=None) -> PoseReport:
    """The pose, torques and joint loads with the actuated joints at ``q_actuated``.

    Parameters
    ----------
    robot : Robot
    q_actuated : array_like, shape (actuated,)
        The actuated joints' coordinates (rad; m at a slider), ``robot.actuated`` order.
    qd, qdd : array_like, shape (actuated,), optional
        Their rates (rad/s; m/s) and accelerations (rad/s^2; m/s^2); default 0, the static
        torques (gravity only). A closed chain's passive rates follow from the loops.
    q_previous : array_like, shape (n,), optional
        The pose (rad; m) the move starts from, default the drawn configuration ``q_drawn``.
        A tree keeps its passive joints (if any) there; a closed chain's passive joints are
        continued from it along the loops (``motion.closure.solve_passive``), so the assembly
        mode is the one of ``q_previous``.

    Returns
    -------
    PoseReport
        With ``message`` empty when all went well. A pose outside the workspace (the loops
        cannot be closed, or only in another assembly mode, or at a singular pose) is not an
        exception: the report holds ``q_previous``, ``reached`` False and the reason.
    """
    q_prev = _start(robot, q_previous)
    act = list(robot.actuated)
    try:
        qa = np.asarray(q_actuated, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        qa = np.full(1, np.nan)
    if qa.shape != (len(act),) or not np.all(np.isfinite(qa)):
        raise InputError(f"{robot.name}: q_actuated must be {len(act)} finite numbers (rad; m "
                         f"at a slider), one per actuated joint, got "
                         f"{np.asarray(q_actuated).tolist()}")
    qd_act, qdd_act = _rates(robot, qd, "qd"), _rates(robot, qdd, "qdd")
    if not robot.is_closed_chain:
        q = q_prev.copy()
        q[act] = qa
        return _at(robot, q, qd_act, qdd_act, True)
    from ..motion.closure import solve_passive

    try:
        q = solve_passive(robot, np.vstack([q_prev[act], qa]), q_prev)[-1]
    except PlanarSymError as exc:
        why = (f"Outside the workspace: {_shown(robot, act, qa)} cannot be reached from the "
               f"last pose ({_shown(robot, act, q_prev[act])}) in its assembly mode; the last "
               f"pose reached is shown. (Details: {exc})")
        return _at(robot, q_prev, qd_act, qdd_act, False, why)
    return _at(robot, q, qd_act, qdd_act, True)


def task_report(robot: Robot, x, qd=None, qdd=None, q_previous=None) -> PoseReport:
    """The pose, torques and joint loads with the task point at ``x``, by inverse kinematics.

    Parameters
    ----------
    robot : Robot
        With a task that fixes its coordinates (``robot.task_names``: x, y and maybe phi).
    x : array_like, shape (n_task,)
        The task point x, y (m) and orientation phi (rad), ``robot.task_names`` order.
    qd, qdd : array_like, shape (actuated,), optional
        The actuated joints' rates (rad/s; m/s) and accelerations (rad/s^2; m/s^2), default 0.
    q_previous : array_like, shape (n,), optional
        The pose (rad; m) the move starts from, default ``robot.q_drawn``: Newton is continued
        from it along a straight line of the task point (``planar_sym.inverse_kinematics`` with
        ``q_start``), so the working and assembly modes are those of ``q_previous``.

    Returns
    -------
    PoseReport
        A target out of reach (or beyond a singular pose, or a singular start pose) gives
        ``reached`` False, ``q_previous`` and the reason in ``message``, not an exception.
    """
    from ..motion.ik import inverse_kinematics
    from ..motion.profiles import cubic

    if not robot.task_names:
        raise InputError(f"{robot.name} has no task point (its description has no [task]): "
                         "explore its actuated joints instead (task=False)")
    q_prev = _start(robot, q_previous)
    nt = len(robot.task_names)
    target = np.asarray(x, dtype=float).reshape(-1)
    if target.shape != (nt,) or not np.all(np.isfinite(target)):
        raise InputError(f"{robot.name}: x must be {nt} finite numbers "
                         f"({', '.join(robot.task_names)}: m, rad), got {np.asarray(x).tolist()}")
    qd_act, qdd_act = _rates(robot, qd, "qd"), _rates(robot, qdd, "qdd")
    task = task_shown(robot)
    asked = ", ".join(f"{n} = {v * task[n][0]:.4g} {task[n][1]}"
                      for n, v in zip(robot.task_names, target))
    from ..motion.newton import check_square, start_pose

    try:
        check_square(robot)
        start_pose(robot, q_prev)
    except PlanarSymError as exc:
        why = (f"No task-space move from the pose shown: it picks no working mode, or the task "
               f"does not fix the joints (explore with task=True needs q_start in the mode "
               f"wanted, e.g. with the elbow bent). (Details: {exc})")
        return _at(robot, q_prev, qd_act, qdd_act, False, why)
    try:
        start = robot.task(q_prev)[0].reshape(-1)
        step = target - start
        lengths = np.abs(step[:2]).max() / TASK_STEP_M
        turns = abs(step[2]) / TASK_STEP_RAD if nt > 2 else 0.0
        samples = 5 + int(np.ceil(max(lengths, turns)))
        motion = cubic(start, step, 1.0, np.linspace(0.0, 1.0, samples))
        q = inverse_kinematics(robot, motion, solver="newton", q_start=q_prev).q[-1]
    except PlanarSymError as exc:
        why = (f"Out of reach: the task point cannot go to {asked} from the last pose in its "
               f"working mode; the last pose reached is shown. (Details: {exc})")
        return _at(robot, q_prev, qd_act, qdd_act, False, why)
    return _at(robot, q, qd_act, qdd_act, True)


class ExploreState:
    """The pose ``explore`` shows, moved by its sliders and continued from move to move.

    Parameters
    ----------
    robot : Robot
    q_start : array_like, shape (n,), optional
        The first pose (rad; m at a slider), default ``robot.q_drawn``; its assembly (closed
        chain) and working (task moves) modes are kept.

    Attributes
    ----------
    robot : Robot
    q : ndarray, shape (n,)
        The last pose reached, every coordinate (rad; m): where the next move starts.
    qd, qdd : ndarray, shape (actuated,)
        The actuated joints' rates (rad/s; m/s) and accelerations (rad/s^2; m/s^2) the torques
        are computed under (default 0: static torques).
    report : PoseReport
        The report of the last move (or of the start pose).
    """

    def __init__(self, robot: Robot, q_start=None):
        self.robot = robot
        self.q = _start(robot, q_start)
        n_act = len(robot.actuated)
        self.qd, self.qdd = np.zeros(n_act), np.zeros(n_act)
        self.report = self.move_actuated(self.q[list(robot.actuated)])

    def _keep(self, report: PoseReport) -> PoseReport:
        if report.reached:
            self.q = report.q
        self.report = report
        return report

    def move_actuated(self, q_actuated) -> PoseReport:
        """Move the actuated joints to ``q_actuated`` (actuated,) in rad (m at a slider):
        ``pose_report`` from the last pose reached."""
        return self._keep(pose_report(self.robot, q_actuated, self.qd, self.qdd, self.q))

    def move_task(self, x) -> PoseReport:
        """Move the task point to ``x`` (n_task,): x, y in m, phi in rad: ``task_report`` from
        the last pose reached (its working mode kept)."""
        return self._keep(task_report(self.robot, x, self.qd, self.qdd, self.q))

    def set_rates(self, qd=None, qdd=None) -> PoseReport:
        """New actuated rates ``qd`` (actuated,) in rad/s and accelerations ``qdd`` (actuated,)
        in rad/s^2 (m/s, m/s^2 at a slider; None keeps the current ones); the report at the
        last pose reached under them."""
        if qd is not None:
            self.qd = _rates(self.robot, qd, "qd")
        if qdd is not None:
            self.qdd = _rates(self.robot, qdd, "qdd")
        last = self.report
        # a move out of reach stays reported (its slider still says where it was asked to go)
        return self._keep(_at(self.robot, self.q, self.qd, self.qdd, last.reached,
                              "" if last.reached else last.message))
