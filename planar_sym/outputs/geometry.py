"""Where a mechanism's points are, for its pictures: world positions of every body point and
centre of gravity over a motion, from the compiled body frames (``Robot.frames``) and the
description's body-frame points; which joint is actuated, passive or a loop's cut; the names
points are shown by; a plate's outline. No matplotlib here: ``drawing.Scene`` draws them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.description import GROUND, Description


@dataclass(frozen=True)
class Geometry:
    """World positions (m) of a robot over N configurations.

    ``points[(body, point)]`` and ``cgs[body]`` are arrays of shape (N, 2); ground points are
    repeated at every sample.
    """

    points: dict[tuple[str, str], np.ndarray]
    cgs: dict[str, np.ndarray]
    #: every body's frame angle (rad), shape (N,); the ground's is 0
    angles: dict[str, np.ndarray] | None = None

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower-left and upper-right corners (m) of everything, the world origin included."""
        xy = np.concatenate([a for a in (*self.points.values(), *self.cgs.values())]
                            + [np.zeros((1, 2))])
        return xy.min(axis=0), xy.max(axis=0)


def to_world(frames: np.ndarray, local) -> np.ndarray:
    """Body-frame point(s) ``local`` (m) to world (m) for frames (N, 3): x, y (m), angle (rad)."""
    c, s = np.cos(frames[:, 2]), np.sin(frames[:, 2])
    x, y = local
    return np.column_stack([frames[:, 0] + c * x - s * y, frames[:, 1] + s * x + c * y])


def geometry(desc: Description, body_names, frames: np.ndarray) -> Geometry:
    """Every named point and centre of gravity in world coordinates.

    Parameters
    ----------
    desc : Description
        Gives body-frame points and centres of gravity (m).
    body_names : sequence of str
        Body order of ``frames`` (``Robot.body_names``).
    frames : ndarray, shape (N, bodies, 3) or (bodies, 3)
        ``Robot.frames(q)``: origin (m) and angle (rad) of every body frame.
    """
    frames = np.asarray(frames, dtype=float).reshape(-1, len(body_names), 3)
    n = len(frames)
    points = {(GROUND, p): np.tile(xy, (n, 1))
              for p, xy in desc.bodies[GROUND].points_m.items()}
    cgs, angles = {}, {GROUND: np.zeros(n)}
    for k, name in enumerate(body_names):
        body = desc.bodies[name]
        points.update({(name, p): to_world(frames[:, k], xy) for p, xy in body.points_m.items()})
        cgs[name] = to_world(frames[:, k], body.cg_m)
        angles[name] = frames[:, k, 2]
    return Geometry(points, cgs, angles)


def joint_roles(desc: Description) -> list[tuple[str, tuple[str, str], str]]:
    """(name, (body, point) where it is drawn, role) of every revolute joint.

    Role is ``"actuated"``, ``"passive"`` or ``"cut"`` (a loop-closing joint); welds are not
    joints a reader needs to see: the welded body is drawn instead; prismatic joints are drawn
    as sliders (``Scene._sliders``).
    """
    out = []
    for j in (*desc.tree_joints, *desc.loop_joints):
        if j.type == "revolute":
            role = "cut" if j.closes_loop else "actuated" if j.actuated else "passive"
            out.append((j.name, (j.parent, j.parent_point), role))
    return out


def point_labels(desc: Description) -> dict[tuple[str, str], str]:
    """Label of every named point that is not a joint location.

    A point's own name where it is unique in the robot, ``body.point`` where several bodies
    have a point of that name (every link has a CS1).
    """
    at_joint = {(j.parent, j.parent_point) for j in (*desc.tree_joints, *desc.loop_joints)}
    at_joint |= {(j.child, j.child_point) for j in (*desc.tree_joints, *desc.loop_joints)}
    names = [p for b in desc.bodies.values() for p in b.points_m]
    return {(b.name, p): (p if names.count(p) == 1 else f"{b.name}.{p}")
            for b in desc.bodies.values() for p in b.points_m if (b.name, p) not in at_joint}


def outline(points: dict[str, tuple[float, float]]) -> tuple[list[str], bool]:
    """Drawing order of a body's points and whether they enclose an area.

    A body whose points (nearly) lie on a line is a link: its points sorted along it. Otherwise
    the convex hull (monotone chain), drawn as a plate; points inside it are not corners.
    """
    names = list(points)
    xy = np.array([points[p] for p in names])
    if len(names) < 3:
        return names, False
    d = xy[:, None, :] - xy[None, :, :]
    i, j = np.unravel_index(np.argmax(np.hypot(d[..., 0], d[..., 1])), d.shape[:2])
    axis = (xy[j] - xy[i]) / np.linalg.norm(xy[j] - xy[i])
    along = (xy - xy[i]) @ axis
    off = np.abs((xy - xy[i]) @ np.array([-axis[1], axis[0]]))
    if off.max() < 0.1 * along.max():  # thin: a (possibly slightly bent) link, not a plate
        return [names[k] for k in np.argsort(along)], False
    order = sorted(range(len(names)), key=lambda k: tuple(xy[k]))
    hull: list[int] = []
    for seq in (order, order[::-1]):
        start = len(hull)
        for k in seq:
            while len(hull) >= start + 2 and _cross(xy[hull[-2]], xy[hull[-1]], xy[k]) <= 0:
                hull.pop()
            hull.append(k)
        hull.pop()  # the last of each half is the first of the other
    return [names[k] for k in hull], True


def _cross(o, a, b) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))
