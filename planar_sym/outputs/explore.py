"""An interactive view of a robot in a notebook: sliders move it, its torques and joint loads follow.

``explore(robot)`` shows sliders for the actuated joints (or, with ``task=True``, for the task
point x, y and phi), the robot drawn at that pose (``outputs.drawing.Scene``, the drawing every
picture of the package uses), and the actuated torques and every joint's load at that pose
under the chosen joint rates and accelerations (text boxes, default 0: the static torques,
gravity only), all updated live.

The computation is plain code, testable without a front end: ``pose_report`` (a pose from the
actuated joints), ``task_report`` (a pose from the task point, by inverse kinematics) and
``ExploreState`` (the pose shown, continued from one move to the next so a closed chain keeps
its assembly mode and an arm its working mode) return a ``PoseReport``; the widget only wires
sliders to them. A pose that cannot be reached is a report with a ``message``, never an
exception: the widget shows that message and keeps drawing the last pose reached.

Units shown: angles in deg, lengths in mm (the drawing's unit), torques in N*m (N at a slider),
forces in N; every array of a report is SI (rad, m, N*m, N).

Only ``explore`` imports ipywidgets and matplotlib, when it is called.
"""

from __future__ import annotations

import dataclasses
import html
import textwrap
from dataclasses import dataclass

import numpy as np

from ..dynamics.reactions import JointLoads, joint_loads
from ..errors import InputError, PlanarSymError
from ..model.loops import COND_WARN
from ..model.robot import Robot

#: how a coordinate is shown, by its SI unit: (factor from SI, unit shown)
SHOWN = {"rad": (180.0 / np.pi, "deg"), "m": (1e3, "mm")}
#: task coordinates shown: x, y in mm, phi in deg
TASK_SHOWN = {"x": (1e3, "mm"), "y": (1e3, "mm"), "phi": (180.0 / np.pi, "deg")}
#: a task move is followed by inverse kinematics through samples at most this far apart (m; rad
#: for phi), so Newton's continuation and its branch check see a smooth motion
TASK_STEP_M = 0.002
TASK_STEP_RAD = 0.02


@dataclass(frozen=True)
class PoseReport:
    """What ``explore`` shows at one pose: the pose, its torques and every joint's load (SI).

    Attributes
    ----------
    robot : str
        The robot's name.
    q, qd, qdd : ndarray, shape (n,)
        Every coordinate (rad; m at a slider), its rate (rad/s; m/s) and acceleration
        (rad/s^2; m/s^2), passive joints included (from the loops for a closed chain). When the
        pose asked for was not reached (``reached`` False), the last pose reached.
    reached : bool
        Whether ``q`` is the pose asked for.
    tau : ndarray, shape (actuated,), or None
        The actuated joints' torques (N*m; N at a slider), ``robot.actuated`` order; None when
        they could not be computed (``message`` says why).
    loads : JointLoads or None
        Every joint's load at this one sample (arrays of shape (1, joints, 2) and (1, joints)):
        the force F (N) and couple M (N*m) the parent body exerts on the child.
    cut_forces : ndarray, shape (2 * loops,), or None
        A closed chain's lambda (N, world x and y per cut joint); None for a tree.
    task : ndarray, shape (n_task,), or None
        The task point x, y (m) and orientation phi (rad) at ``q``; None without a task point.
    loop_residual_m : float or None
        A closed chain's largest |Phi(q)| (m); None for a tree.
    condition : float or None
        A closed chain's 1-norm condition number of the passive-joint constraint Jacobian
        Phi_p at ``q`` (dimensionless; large near a singular pose); None for a tree.
    message : str
        Empty when all is shown; else why the pose was not reached or the torques not computed.
    """

    robot: str
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    reached: bool
    tau: np.ndarray | None
    loads: JointLoads | None
    cut_forces: np.ndarray | None
    task: np.ndarray | None
    loop_residual_m: float | None
    condition: float | None
    message: str

    @property
    def ok(self) -> bool:
        """True when the pose asked for was reached and its torques computed."""
        return not self.message

    def pose_rows(self, robot: Robot) -> list[tuple[str, str]]:
        """(name, value with unit) of every coordinate (deg; mm at a slider), marking the
        actuated ones, then the task point (mm, deg) and a closed chain's loop residual (m)."""
        rows = []
        for k, (name, unit) in enumerate(zip(robot.coordinates, robot.coordinate_units)):
            scale, shown = SHOWN[unit]
            role = "actuated" if k in robot.actuated else "passive"
            rows.append((f"q{k + 1} {name} ({role})", f"{self.q[k] * scale:.3f} {shown}"))
        if self.task is not None:
            for name, value in zip(robot.task_names, self.task):
                scale, shown = TASK_SHOWN[name]
                rows.append((f"task {name}", f"{value * scale:.3f} {shown}"))
        if self.loop_residual_m is not None:
            rows.append(("loop residual max|Phi|", f"{self.loop_residual_m:.2g} m"))
        if self.condition is not None and self.condition > COND_WARN:
            why = (f"Phi_p condition number {self.condition:.3g} (forces grow like 1 / the "
                   "distance)")
            rows.append(("near a singular pose", why))
        return rows

    def torque_rows(self, robot: Robot) -> list[tuple[str, str]]:
        """(actuated joint, torque with its unit: N*m, or N at a slider), one per actuator;
        empty when the torques could not be computed."""
        if self.tau is None:
            return []
        return [(f"tau {robot.coordinates[i]}",
                 f"{t:.6g} {'N' if robot.coordinate_units[i] == 'm' else 'N*m'}")
                for i, t in zip(robot.actuated, self.tau)]

    def load_rows(self) -> list[tuple[str, str, str, str, str, str]]:
        """One row per joint (tree joints, then cut joints): name, type, F_x, F_y, |F| (N, the
        parent body on the child, world axes) and the couple M (N*m); empty without loads."""
        if self.loads is None:
            return []
        ld = self.loads

        def num(v: float) -> str:  # rounding noise (a passive joint's 1e-17 N*m) shown as 0
            return "0" if abs(v) < 1e-12 else f"{v:.4g}"

        mag = ld.magnitude[0]
        return [(name, kind, num(ld.force[0, j, 0]), num(ld.force[0, j, 1]), num(mag[j]),
                 num(ld.couple[0, j])) for j, (name, kind) in enumerate(zip(ld.names, ld.types))]

    def text(self, robot: Robot) -> str:
        """The report as plain text: the message (if any), the pose, torques and loads."""
        lines = [f"! {self.message}"] if self.message else []
        lines += [f"{k}: {v}" for k, v in self.pose_rows(robot)]
        lines += [f"{k} = {v}" for k, v in self.torque_rows(robot)]
        rows = self.load_rows()
        if rows:
            lines.append(f"{'joint':<10} {'type':<10} {'Fx (N)':>10} {'Fy (N)':>10} "
                         f"{'|F| (N)':>10} {'M (N*m)':>10}")
            lines += [f"{r[0]:<10} {r[1]:<10} {r[2]:>10} {r[3]:>10} {r[4]:>10} {r[5]:>10}"
                      for r in rows]
        return "\n".join(lines)


LOAD_HEADER = ("joint", "type", "F_x (N)", "F_y (N)", "|F| (N)", "couple M (N*m)")


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
    out = []
    for i, v in zip(indices, values):
        scale, unit = SHOWN[robot.coordinate_units[i]]
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
    shown = ", ".join(f"{n} = {v * TASK_SHOWN[n][0]:.4g} {TASK_SHOWN[n][1]}"
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
        why = (f"Out of reach: the task point cannot go to {shown} from the last pose in its "
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


def report_html(report: PoseReport, robot: Robot) -> str:
    """A report as an HTML fragment: the message (red, if any), the torques, the pose and
    every joint's load, each value with its unit (deg, mm, N*m, N)."""
    from .notebook import _STYLE, _table

    parts = [f'<div class="planar-sym">{_STYLE}']
    if report.message:
        parts.append(f'<p style="color:#b00020"><b>{html.escape(report.message)}</b></p>')
    torques = report.torque_rows(robot)
    if torques:
        parts.append(f"<b>torques</b> (qd, qdd as set; N*m, N at a slider){_table(torques)}")
    parts.append(f"<b>pose</b>{_table(report.pose_rows(robot))}")
    loads = report.load_rows()
    if loads:
        parts.append("<b>joint loads</b> (the parent body on the child, world axes)"
                     f"{_table(loads, header=LOAD_HEADER)}")
    parts.append("</div>")
    return "".join(parts)


def pose_figure(robot: Robot, desc, q, title: str = "", limits=None):
    """The robot drawn at one pose ``q`` (n,), rad (m at a slider): ``drawing.Scene`` on a
    6 x 4.5 in Figure in mm; ``limits`` ((x0, x1), (y0, y1)) in mm widen the view to hold
    them (so a moving robot's view does not jump). Returns the Figure."""
    from .drawing import Scene, geometry
    from .plots import new_figure, tight

    geo = geometry(desc, robot.body_names, robot.frames(np.asarray(q, dtype=float)[None, :]))
    fig = new_figure((6.5, 4.5))
    ax = fig.add_subplot()
    Scene(ax, desc, geo, labels=True)
    if limits is not None:
        (x0, x1), (y0, y1) = limits
        (a0, a1), (b0, b1) = ax.get_xlim(), ax.get_ylim()
        ax.set_xlim(min(x0, a0), max(x1, a1))
        ax.set_ylim(min(y0, b0), max(y1, b1))
    ax.set_title("\n".join(line for part in title.split("\n")
                           for line in textwrap.wrap(part, 90)), fontsize=8)
    tight(fig)
    return fig


class Explorer:
    """The interactive view ``explore`` returns: its widgets, and the state they move.

    Shown by a notebook cell like a widget (the ``widget`` box). Setting a slider's ``value``
    from code moves the robot as dragging it does (tests, scripted demos).

    Parameters
    ----------
    robot : Robot
    task : bool
        Sliders for the task point instead of the actuated joints.
    q_start : array_like, shape (n,), optional
        The first pose (rad; m at a slider), default ``robot.q_drawn``.

    Attributes
    ----------
    robot : Robot
        The robot explored.
    state : ExploreState
        The pose shown and the rates set (SI).
    task : bool
        Whether the sliders move the task point (x, y in mm, phi in deg) instead of the
        actuated joints (deg; mm at a slider).
    sliders : dict of str to ipywidgets.FloatSlider
        By actuated joint name (or task coordinate name).
    qd, qdd : dict of str to ipywidgets.FloatText
        By actuated joint name: its rate (deg/s; mm/s at a slider) and acceleration (deg/s^2;
        mm/s^2).
    picture : ipywidgets.Image
        The robot drawn at the pose shown (PNG).
    readout : ipywidgets.HTML
        The message, torques, pose and joint loads (``report_html``).
    widget : ipywidgets.Box
        All of it, laid out: what a notebook displays.
    """

    def __init__(self, robot: Robot, task: bool = False, q_start=None):
        import ipywidgets as w

        from ..model.description import load as load_description

        if robot.description_file is None:
            raise InputError(f"{robot.name}: no description at hand to draw it (the generated "
                             "folder has no description.toml)")
        if task and not robot.task_names:
            raise InputError(f"{robot.name} has no task point (its description has no [task]):"
                             " explore its actuated joints instead (task=False)")
        self.robot, self.task = robot, task
        self._desc = load_description(robot.description_file)
        self.state = ExploreState(robot, q_start)
        self._limits = None
        q0 = self.state.q
        style = {"description_width": "initial"}
        layout = w.Layout(width="420px")
        low, high = (np.array(c) * 1e3 for c in self._extent(q0))
        span = float(max(high - low))
        self.sliders = {}
        if task:
            x0 = self.state.report.task
            for name, v in zip(robot.task_names, x0):
                scale, unit = TASK_SHOWN[name]
                half = 180.0 if name == "phi" else 0.6 * span
                step = 0.5 if name == "phi" else max(round(span / 1000, 3), 0.001)
                self.sliders[name] = w.FloatSlider(
                    value=v * scale, min=round(v * scale - half, 1),
                    max=round(v * scale + half, 1), step=step,
                    description=f"task {name} ({unit})", style=style, layout=layout,
                    readout_format=".1f")
        else:
            for i in robot.actuated:
                name, unit = robot.coordinates[i], robot.coordinate_units[i]
                scale, shown = SHOWN[unit]
                v = q0[i] * scale
                half = 180.0 if unit == "rad" else 0.5 * span
                step = 0.5 if unit == "rad" else max(round(span / 1000, 3), 0.001)
                self.sliders[name] = w.FloatSlider(
                    value=v, min=round(v - half, 1), max=round(v + half, 1), step=step,
                    description=f"{name} ({shown})", style=style, layout=layout,
                    readout_format=".1f")
        self.qd, self.qdd = {}, {}
        small = w.Layout(width="210px")
        for i in robot.actuated:
            name, unit = robot.coordinates[i], SHOWN[robot.coordinate_units[i]][1]
            self.qd[name] = w.FloatText(value=0.0, description=f"qd {name} ({unit}/s)",
                                        style=style, layout=small)
            self.qdd[name] = w.FloatText(value=0.0, description=f"qdd {name} ({unit}/s^2)",
                                         style=style, layout=small)
        self.picture = w.Image(format="png")
        self.readout = w.HTML()
        for s in self.sliders.values():
            s.observe(self._on_move, names="value")
        for box in (*self.qd.values(), *self.qdd.values()):
            box.observe(self._on_rates, names="value")
        rates = w.VBox([w.HTML("<b>joint rates and accelerations</b> (default 0: static "
                               "torques, gravity only)"),
                        *(w.HBox([self.qd[n], self.qdd[n]]) for n in self.qd)])
        what = "task point" if task else "actuated joints"
        controls = w.VBox([w.HTML(f"<b>{html.escape(robot.name)}</b>: {what}"),
                           *self.sliders.values(), rates, self.readout])
        self.widget = w.HBox([self.picture, controls])
        if task:  # a move of nothing: says at once whether the start pose picks a working mode
            self.state.move_task(self.state.report.task)
        self._show()

    # -- wiring -----------------------------------------------------------------------------
    def _extent(self, q) -> tuple[np.ndarray, np.ndarray]:
        from .drawing import geometry

        return geometry(self._desc, self.robot.body_names,
                        self.robot.frames(np.asarray(q)[None, :])).extent()

    def _on_move(self, _change=None) -> None:
        values = [s.value for s in self.sliders.values()]
        if self.task:
            self.state.move_task([v / TASK_SHOWN[n][0] for n, v in zip(self.sliders, values)])
        else:
            self.state.move_actuated(
                [v / SHOWN[self.robot.coordinate_units[i]][0]
                 for i, v in zip(self.robot.actuated, values)])
        self._show()

    def _on_rates(self, _change=None) -> None:
        units = [SHOWN[self.robot.coordinate_units[i]][0] for i in self.robot.actuated]
        qd = [b.value / s for b, s in zip(self.qd.values(), units)]
        qdd = [b.value / s for b, s in zip(self.qdd.values(), units)]
        try:
            self.state.set_rates(qd, qdd)
        except InputError as exc:  # a box holding inf or nan: said in the view, rates kept
            self.readout.value = report_html(dataclasses.replace(self.report, message=str(exc)),
                                             self.robot)
            return
        self._show()

    def _show(self) -> None:
        from .notebook import png_bytes

        report = self.state.report
        title = f"{self.robot.name}: " + _shown(self.robot, range(self.robot.n), report.q)
        if not report.reached:
            title += "\n(the last pose reached: the one asked for is out of reach)"
        fig = pose_figure(self.robot, self._desc, report.q, title, self._limits)
        ax = fig.axes[0]
        self._limits = (ax.get_xlim(), ax.get_ylim())
        self.picture.value = png_bytes(fig)
        self.readout.value = report_html(report, self.robot)

    # -- display ----------------------------------------------------------------------------
    @property
    def report(self) -> PoseReport:
        """The report shown (``state.report``)."""
        return self.state.report

    def _repr_mimebundle_(self, **kwargs):
        return self.widget._repr_mimebundle_(**kwargs)


def explore(robot: Robot | str, task: bool = False, q_start=None) -> Explorer:
    """An interactive view of a robot in a notebook: sliders move it, torques and loads follow.

    Sliders for the actuated joints (deg; mm at a slider) or, with ``task=True``, for the task
    point x, y (mm) and phi (deg), solved by inverse kinematics from the pose shown (its
    working mode kept); a closed chain's passive joints follow through the loops from the pose
    shown (its assembly mode kept). Text boxes set the actuated joints' rates (deg/s) and
    accelerations (deg/s^2), default 0: the static torques, gravity only. Shown live: the
    robot drawn, the actuated torques (N*m; N at a slider), the pose and every joint's load
    (force in N, couple in N*m). A pose out of reach shows a message in the view, and the last
    pose reached.

    Parameters
    ----------
    robot : Robot or str
        A robot, or a name ``planar_sym.load`` takes.
    task : bool
        Sliders for the task point instead of the actuated joints.
    q_start : array_like, shape (n,), optional
        The first pose, every coordinate (rad; m at a slider); default ``robot.q_drawn``. Its
        assembly and working modes are kept (give one with the elbow bent for task moves of an
        arm drawn stretched out, where the drawn pose is singular).

    Returns
    -------
    Explorer
        Displayed by a notebook cell; ``sliders``, ``qd``, ``qdd`` set from code work too, and
        ``report`` (a ``PoseReport``) holds the numbers shown. The computation alone, without
        widgets: ``pose_report``, ``task_report``, ``ExploreState``.

    Raises
    ------
    ImportError
        Without ipywidgets: ``pip install ipywidgets`` (or the ``notebook`` extra,
        ``pip install 'planar-sym[notebook]'``).
    """
    try:
        import ipywidgets  # noqa: F401
    except ImportError as exc:
        raise ImportError("planar_sym.explore needs ipywidgets: pip install ipywidgets (or "
                          "the notebook extra: pip install 'planar-sym[notebook]')") from exc
    if isinstance(robot, str):
        from ..model.locate import load

        robot = load(robot)
    return Explorer(robot, task=task, q_start=q_start)
