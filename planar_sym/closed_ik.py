"""The seed's closed-form inverse kinematics of the closed chains, in this package's coordinates.

Lengths come from the robot's parameter vector (the description's own geometry), so forward
kinematics of the solution returns the target to rounding. Every coordinate is reported as the
2 pi representative nearest the drawn configuration, so trajectories are continuous.
"""

from __future__ import annotations

import numpy as np

from .dynamics import Robot
from .kinematics import Failures, _two_link


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


CLOSED_IK_SOLVERS = {
    "five_bar_type1": ik_five_bar_type1,
    "five_bar_type2": ik_five_bar_type2,
    "parallel_3rrr": ik_parallel_3rrr,
}
