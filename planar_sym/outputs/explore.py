"""An interactive view of a robot in a notebook: sliders move it, its torques and joint loads follow.

``explore(robot)`` shows sliders for the actuated joints (or, with ``task=True``, for the task
point x, y and phi), the robot drawn at that pose (``outputs.drawing.Scene``, the drawing every
picture of the package uses), and the actuated torques and every joint's load at that pose
under the chosen joint rates and accelerations (text boxes, default 0: the static torques,
gravity only), all updated live.

The computation is plain code, testable without a front end (``explore_state``):
``pose_report`` (a pose from the actuated joints), ``task_report`` (a pose from the task point,
by inverse kinematics) and ``ExploreState`` (the pose shown, continued from one move to the
next so a closed chain keeps its assembly mode and an arm its working mode) return a
``PoseReport`` (``explore_report``); the widget here only wires sliders to them. A pose that
cannot be reached is a report with a ``message``, never an exception: the widget shows that
message and keeps drawing the last pose reached.

Units shown: angles in deg, lengths in the unit the robot is typed in (the drawing's), torques in N*m (N at a slider),
forces in N; every array of a report is SI (rad, m, N*m, N).

Only ``explore`` imports ipywidgets and matplotlib, when it is called.
"""

from __future__ import annotations

import dataclasses
import html
import textwrap

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from .explore_report import LOAD_HEADER, PoseReport, report_html, shown, task_shown
from .explore_state import ExploreState, _shown, pose_report, task_report

#: decimals a length slider reads to, by the robot's length unit: 0.1 mm in each
SLIDER_DIGITS = {"mm": 1, "cm": 2, "m": 4}

__all__ = [
    "LOAD_HEADER",
    "ExploreState",
    "Explorer",
    "PoseReport",
    "explore",
    "pose_figure",
    "pose_report",
    "report_html",
    "shown",
    "task_report",
    "task_shown",
]


def pose_figure(robot: Robot, desc, q, title: str = "", limits=None):
    """The robot drawn at one pose ``q`` (n,), rad (m at a slider): ``drawing.Scene`` on a
    6 x 4.5 in Figure in the robot's length unit; ``limits`` ((x0, x1), (y0, y1)) in that
    unit widen the view to hold them (so a moving robot's view does not jump). Returns the
    Figure."""
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
        Whether the sliders move the task point (x, y in the robot's length unit, phi in deg)
        instead of the actuated joints (deg; the length unit at a slider).
    sliders : dict of str to ipywidgets.FloatSlider
        By actuated joint name (or task coordinate name).
    qd, qdd : dict of str to ipywidgets.FloatText
        By actuated joint name: its rate (deg/s; length unit/s at a slider) and acceleration
        (deg/s^2; length unit/s^2).
    picture : ipywidgets.Image
        The robot drawn at the pose shown (PNG).
    readout : ipywidgets.HTML
        The message, torques, pose and joint loads (``report_html``).
    widget : ipywidgets.Box
        All of it, laid out: what a notebook displays.
    """

    def __init__(self, robot: Robot, task: bool = False, q_start=None):
        import ipywidgets as w

        from ..model.described import described

        if task and not robot.task_names:
            raise InputError(f"{robot.name} has no task point (its description has no [task]):"
                             " explore its actuated joints instead (task=False)")
        self.robot, self.task = robot, task
        self._desc = described(robot)
        self.state = ExploreState(robot, q_start)
        self._limits = None
        q0 = self.state.q
        style = {"description_width": "initial"}
        layout = w.Layout(width="420px")
        coordinate, task_units = shown(robot), task_shown(robot)
        low, high = (np.array(c) * coordinate["m"][0] for c in self._extent(q0))
        span = float(max(high - low))
        # a length slider reads to 0.1 mm in any unit, steps a thousandth of the robot's size
        digits = SLIDER_DIGITS[robot.length_unit]

        def length(share: float) -> tuple[float, float, int]:
            """(half range, step, decimals) of a length slider: ``share`` of the span."""
            return share * span, max(round(span / 1000, digits + 2), 10.0 ** -(digits + 2)), \
                digits

        self.sliders = {}
        if task:
            x0 = self.state.report.task
            for name, v in zip(robot.task_names, x0):
                scale, unit = task_units[name]
                half, step, digits = (180.0, 0.5, 1) if name == "phi" else length(0.6)
                self.sliders[name] = w.FloatSlider(
                    value=v * scale, min=round(v * scale - half, digits),
                    max=round(v * scale + half, digits), step=step,
                    description=f"task {name} ({unit})", style=style, layout=layout,
                    readout_format=f".{digits}f")
        else:
            for i in robot.actuated:
                name, unit = robot.coordinates[i], robot.coordinate_units[i]
                scale, unit_shown = coordinate[unit]
                v = q0[i] * scale
                half, step, digits = (180.0, 0.5, 1) if unit == "rad" else length(0.5)
                self.sliders[name] = w.FloatSlider(
                    value=v, min=round(v - half, digits), max=round(v + half, digits),
                    step=step, description=f"{name} ({unit_shown})", style=style,
                    layout=layout, readout_format=f".{digits}f")
        self.qd, self.qdd = {}, {}
        small = w.Layout(width="210px")
        for i in robot.actuated:
            name, unit = robot.coordinates[i], coordinate[robot.coordinate_units[i]][1]
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
            task = task_shown(self.robot)
            self.state.move_task([v / task[n][0] for n, v in zip(self.sliders, values)])
        else:
            self.state.move_actuated(
                [v / shown(self.robot)[self.robot.coordinate_units[i]][0]
                 for i, v in zip(self.robot.actuated, values)])
        self._show()

    def _on_rates(self, _change=None) -> None:
        units = [shown(self.robot)[self.robot.coordinate_units[i]][0] for i in self.robot.actuated]
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

    Sliders for the actuated joints (deg; at a slider the length unit the robot is typed in)
    or, with ``task=True``, for the task point x, y (in that unit) and phi (deg), solved by inverse kinematics from the pose shown (its
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
