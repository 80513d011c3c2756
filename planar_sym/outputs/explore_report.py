"""What ``explore`` shows at one pose, as numbers and rows: ``PoseReport`` and its HTML.

A report holds SI arrays (rad, m, N*m, N); its rows and ``report_html`` show them as the
sliders do: angles in deg, lengths in the robot's own unit (the drawing's), torques in N*m (N at a slider),
forces in N.
"""

from __future__ import annotations

import html
from dataclasses import dataclass

import numpy as np

from ..dynamics.reactions import JointLoads
from ..model.length_unit import per_metre
from ..model.loops import COND_WARN
from ..model.robot import Robot

DEG = (180.0 / np.pi, "deg")


def shown(robot: Robot) -> dict[str, tuple[float, str]]:
    """How a coordinate is shown, by its SI unit: (factor from SI, unit shown): angles in deg,
    lengths in the unit the robot's description is typed in (its drawing's)."""
    return {"rad": DEG, "m": (per_metre(robot.length_unit), robot.length_unit)}


def task_shown(robot: Robot) -> dict[str, tuple[float, str]]:
    """How the task coordinates are shown: x, y as the robot's lengths, phi in deg."""
    length = shown(robot)["m"]
    return {"x": length, "y": length, "phi": DEG}


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
        """(name, value with unit) of every coordinate (deg; the robot's length unit at a
        slider), marking the actuated ones, then the task point and a closed chain's loop
        residual (m)."""
        rows, coordinate, task = [], shown(robot), task_shown(robot)
        for k, (name, unit) in enumerate(zip(robot.coordinates, robot.coordinate_units)):
            scale, unit_shown = coordinate[unit]
            role = "actuated" if k in robot.actuated else "passive"
            rows.append((f"q{k + 1} {name} ({role})", f"{self.q[k] * scale:.3f} {unit_shown}"))
        if self.task is not None:
            for name, value in zip(robot.task_names, self.task):
                scale, unit_shown = task[name]
                rows.append((f"task {name}", f"{value * scale:.3f} {unit_shown}"))
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


def report_html(report: PoseReport, robot: Robot) -> str:
    """A report as an HTML fragment: the message (red, if any), the torques, the pose and
    every joint's load, each value with its unit (deg, the robot's length unit, N*m, N)."""
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
