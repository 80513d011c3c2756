"""The seed's closed-form inverse kinematics, kept as checks of the generic solver.

Positions follow the seed's listings (elbow choice, ``th1 += 2 pi`` wrap, 2-DOF joint limits),
but take every length from the robot's own parameter vector, so that forward kinematics of the
solution returns the target to rounding. Closed chains report every coordinate as the 2 pi
representative nearest the drawn configuration, so trajectories are continuous. Where the seed
silently held its last solution outside the workspace, these raise WorkspaceError naming the
time and the target.
"""

from __future__ import annotations

import numpy as np

from ..errors import WorkspaceError
from ..model.robot import Robot
from .failures import Failures

#: a joint angle within this of a limit (rad) counts as on it: the seed's start poses sit
#: exactly on q1 = 0, where atan2 returns +-1e-17 and the seed's own check would flicker.
ANGLE_TOL_RAD = 1e-9


def _two_link(fails: Failures, px, py, a1, a2, elbow: float, wrap: bool = True,
              what: str = ""):
    """Seed's 2-link solution: th2 = elbow * acos(kappa), th1 from atan2 (wrapped to
    [0, 2 pi) as the serial listings do when ``wrap``). Unreachable samples are recorded in
    ``fails`` and computed with kappa clipped (as the seed does) so later checks still run."""
    kappa = (px**2 + py**2 - a1**2 - a2**2) / (2 * a1 * a2)
    fails.add(np.abs(kappa) > 1, lambda k: f"is outside the workspace ({what + ': ' if what else ''}"
                                           f"cos of the elbow angle would be {kappa[k]:.6g}, "
                                           "beyond +-1)")
    th2 = elbow * np.arccos(np.clip(kappa, -1.0, 1.0))
    delta = a1**2 + a2**2 + 2 * a1 * a2 * np.cos(th2)
    c1 = (px * (a1 + a2 * np.cos(th2)) + py * a2 * np.sin(th2)) / delta
    s1 = (-px * a2 * np.sin(th2) + py * (a1 + a2 * np.cos(th2))) / delta
    th1 = np.arctan2(s1, c1)
    if wrap:
        th1 = np.where(th1 < -ANGLE_TOL_RAD, th1 + 2 * np.pi, th1)  # seed: 0 < th < 360
    return th1, th2


def _params(robot: Robot, *names: str) -> list[float]:
    p = robot.parameters
    return [p.get(n, 0.0) for n in names]


def _check_on_axis(robot: Robot, *names: str) -> None:
    off = [n for n in names if robot.parameters.get(n, 0.0) != 0.0]
    if off:
        raise WorkspaceError(f"{robot.name}: the seed's closed-form IK assumes joints and tool on "
                             f"the link axes, but {', '.join(off)} are non-zero")


def ik_serial_2dof(robot: Robot, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Seed listing: elbow down (th2 = +acos), joint limits 0 <= th1 <= pi, pi/6 <= th2 <= 5pi/6."""
    _check_on_axis(robot, "py_link1_CS2", "py_link2_CS2")
    a1, a2 = _params(robot, "px_link1_CS2", "px_link2_CS2")
    fails = Failures(robot, t, x)
    th1, th2 = _two_link(fails, x[:, 0], x[:, 1], a1, a2, +1.0)
    tol = ANGLE_TOL_RAD
    fails.add((th1 < -tol) | (th1 > np.pi + tol),
              lambda k: f"violates the joint limit 0 <= q1 <= 180 deg "
                        f"(q1 = {np.degrees(th1[k]):.6g} deg)")
    fails.add((th2 < np.pi / 6 - tol) | (th2 > 5 * np.pi / 6 + tol),
              lambda k: f"violates the joint limit 30 <= q2 <= 150 deg "
                        f"(q2 = {np.degrees(th2[k]):.6g} deg)")
    fails.raise_earliest()
    return np.column_stack([th1, th2])


def ik_serial_3dof(robot: Robot, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Seed listing: wrist p = x - a3 (cos phi, sin phi), elbow down, q3 = phi - q1 - q2.

    The seed's listing is cut off after q1; ``q3 = phi - q1 - q2`` completes it.
    """
    _check_on_axis(robot, "py_link1_CS2", "py_link2_CS2", "py_link3_CS2")
    a1, a2, a3 = _params(robot, "px_link1_CS2", "px_link2_CS2", "px_link3_CS2")
    phi = x[:, 2]
    px, py = x[:, 0] - a3 * np.cos(phi), x[:, 1] - a3 * np.sin(phi)
    fails = Failures(robot, t, x)
    th1, th2 = _two_link(fails, px, py, a1, a2, +1.0)
    fails.raise_earliest()
    return np.column_stack([th1, th2, phi - th1 - th2])


def _nearest(q: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return ref + (q - ref + np.pi) % (2 * np.pi) - np.pi


def _rot(angle: np.ndarray, v: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    c, s = np.cos(angle), np.sin(angle)
    return c * v[0] - s * v[1], s * v[0] + c * v[1]


def _five_bar(robot: Robot, t, x, left_elbow: float) -> np.ndarray:
    """Seed listing, generalised to the description's points.

    Left arm A-B-P: th3 = left_elbow * acos(k1) (Type I: -1, Type II: +1), th2 by atan2.
    Right arm E-D-C with C = P - R(th2 + th3) (P - C in L_Link2's frame): th4 = +acos(k2).
    Coordinates (A, B, E, D) = (th2, th3, th5, th4): A and E absolute, B and D relative.
    """
    p = robot.parameters
    ax, ay = p.get("px_ground_A", 0.0), p.get("py_ground_A", 0.0)
    ex, ey = p.get("px_ground_E", 0.0), p.get("py_ground_E", 0.0)
    l2 = p["px_L_Link1_CS2"]
    l36 = p["px_L_Link2_CS3"]  # |BP|: L_Link2's frame points from B at P
    cb = (p.get("px_L_Link2_CS2", 0.0) - l36, p.get("py_L_Link2_CS2", 0.0))  # C - P, body frame
    l5, l4 = p["px_R_Link1_CS2"], p["px_R_Link2_CS2"]
    fails = Failures(robot, t, x)
    th2, th3 = _two_link(fails, x[:, 0] - ax, x[:, 1] - ay, l2, l36, left_elbow, wrap=False,
                         what="left arm")
    dx, dy = _rot(th2 + th3, cb)
    cx, cy = x[:, 0] + dx - ex, x[:, 1] + dy - ey
    th5, th4 = _two_link(fails, cx, cy, l5, l4, +1.0, wrap=False, what="right arm")
    fails.raise_earliest()
    return _nearest(np.column_stack([th2, th3, th5, th4]), robot.q_drawn)


def ik_five_bar_type1(robot: Robot, t, x) -> np.ndarray:
    return _five_bar(robot, t, x, -1.0)


def ik_five_bar_type2(robot: Robot, t, x) -> np.ndarray:
    return _five_bar(robot, t, x, +1.0)


def ik_parallel_3rrr(robot: Robot, t, x) -> np.ndarray:
    """Seed listing per leg: d = p + R(phi) b_i - A_i, e1 = -2 l1 d_y, e2 = -2 l1 d_x,
    e3 = |d|^2 + l1^2 - l2^2, th_i = 2 atan((-e1 - sqrt(e1^2 + e2^2 - e3^2)) / (e3 - e2)).

    Coordinates (A1, elbow1, B1, A2, elbow2, A3, elbow3): A_i the seed's th_i, elbow_i the
    distal link's angle relative to the proximal one, B1 the platform's relative to distal 1.
    """
    p = robot.parameters
    phi = x[:, 2]
    cols = []
    fails = Failures(robot, t, x)
    for i in (1, 2, 3):
        a = (p.get(f"px_ground_A{i}", 0.0), p.get(f"py_ground_A{i}", 0.0))
        b = (p.get(f"px_platform_CS{i}", 0.0), p.get(f"py_platform_CS{i}", 0.0))
        l1, l2 = p[f"px_Link{i}_1_CS2"], p[f"px_Link{i}_2_CS2"]
        bx, by = _rot(phi, b)
        dx, dy = x[:, 0] + bx - a[0], x[:, 1] + by - a[1]
        e1, e2, e3 = -2 * l1 * dy, -2 * l1 * dx, dx**2 + dy**2 + l1**2 - l2**2
        disc = e1**2 + e2**2 - e3**2
        fails.add(disc < 0, lambda k, i=i, disc=disc: (
            f"is outside the workspace (leg {i} cannot reach: e1^2 + e2^2 - e3^2 = "
            f"{disc[k]:.3g} < 0)"))
        th = 2 * np.arctan((-e1 - np.sqrt(np.maximum(disc, 0.0))) / (e3 - e2))
        psi = np.arctan2(dy - l1 * np.sin(th), dx - l1 * np.cos(th))  # distal link angle
        cols += [th, psi - th]
        if i == 1:
            cols.append(phi - psi)
    fails.raise_earliest()
    return _nearest(np.column_stack(cols), robot.q_drawn)


SEED_SOLVERS = {
    "serial_2dof": ik_serial_2dof,
    "serial_3dof": ik_serial_3dof,
    "five_bar_type1": ik_five_bar_type1,
    "five_bar_type2": ik_five_bar_type2,
    "parallel_3rrr": ik_parallel_3rrr,
}
