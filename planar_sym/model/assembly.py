"""Closing a closed chain's loops numerically from an approximate drawn pose (``assemble = true``
in a description), so nobody has to solve circle intersections by hand.

Each body keeps its shape (its points in its own frame, as given); the tree joints are placed
from ground outward (a child's joint point on its parent's), and Gauss-Newton with minimum-norm
steps moves the passive joints' angles until every cut joint's two points meet:

.. code:: text

    gap(theta) = r(parent point) - r(child point) at each cut joint,  J = d gap / d theta_passive
    theta_passive -= J^+ gap     until max |gap| < ASSEMBLY_TOL_M

The actuated joints keep the angles of the given pose, and starting from the given pose keeps
its assembly mode. No SymPy: shared by derive and the runtime.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

#: the loops are closed to this gap (m), far below the 1e-5 m a drawn pose must close to
ASSEMBLY_TOL_M = 1e-12
MAX_ITER = 60


@dataclass(frozen=True)
class Assembly:
    """What assembling changed: per joint the angle change (rad), per body point how far it
    moved (m), and the gap each loop had before (m)."""

    angle_change_rad: dict[str, float]
    point_moved_m: dict[str, float]
    gaps_before_m: dict[str, float]

    def report(self) -> str:
        lines = ["assembled the loops from the given pose:"]
        lines += [f"  loop {k}: gap {v * 1e3:.4g} mm closed" for k, v in self.gaps_before_m.items()]
        lines += [f"  joint {k}: angle changed by {math.degrees(v):+.4g} deg"
                  for k, v in self.angle_change_rad.items() if abs(v) > 1e-12]
        moved = sorted(self.point_moved_m.items(), key=lambda kv: -kv[1])
        lines += [f"  point {k} moved {v * 1e3:.4g} mm" for k, v in moved if v > 1e-12]
        return "\n".join(lines)


def _world(body, local) -> np.ndarray:
    c, s = math.cos(body.drawn_angle_rad), math.sin(body.drawn_angle_rad)
    return np.array(body.drawn_origin_m) + np.array([c * local[0] - s * local[1],
                                                     s * local[0] + c * local[1]])


def _place(bodies: dict, tree, angles: dict[str, float]) -> dict:
    """Bodies re-placed along the tree: child angle = parent angle + joint angle, child's joint
    point on the parent's."""
    out = dict(bodies)
    for j in tree:
        parent = out[j.parent]
        angle = parent.drawn_angle_rad + angles[j.name]
        anchor = _world(parent, parent.points_m[j.parent_point])
        c, s = math.cos(angle), math.sin(angle)
        local = out[j.child].points_m[j.child_point]
        origin = anchor - np.array([c * local[0] - s * local[1], s * local[0] + c * local[1]])
        out[j.child] = replace(out[j.child], drawn_angle_rad=angle,
                               drawn_origin_m=(float(origin[0]), float(origin[1])))
    return out


def _gaps(bodies: dict, loops) -> np.ndarray:
    return np.concatenate([_world(bodies[j.parent], bodies[j.parent].points_m[j.parent_point])
                           - _world(bodies[j.child], bodies[j.child].points_m[j.child_point])
                           for j in loops])


def assemble(bodies: dict, tree, loops) -> tuple[dict, Assembly] | tuple[None, str]:
    """The bodies with the loops closed, and what changed; or (None, why) when they cannot be.

    ``tree``: the tree joints, parents first; ``loops``: the cut joints. The starting angles are
    the given pose's relative frame angles.
    """
    angles = {j.name: bodies[j.child].drawn_angle_rad - bodies[j.parent].drawn_angle_rad
              for j in tree}
    start = dict(angles)
    free = [j.name for j in tree if j.type == "revolute" and not j.actuated]
    placed = _place(bodies, tree, angles)
    gap0 = _gaps(placed, loops)
    before = {j.name: float(np.hypot(*gap0[2 * k:2 * k + 2])) for k, j in enumerate(loops)}
    gap = gap0
    for _ in range(MAX_ITER):
        if np.max(np.abs(gap)) < ASSEMBLY_TOL_M or not free:
            break
        jac = np.empty((len(gap), len(free)))
        for c, name in enumerate(free):  # central differences: the gaps are smooth in angle
            h = 1e-7
            plus, minus = dict(angles), dict(angles)
            plus[name] += h
            minus[name] -= h
            jac[:, c] = (_gaps(_place(bodies, tree, plus), loops)
                         - _gaps(_place(bodies, tree, minus), loops)) / (2 * h)
        step = np.linalg.lstsq(jac, gap, rcond=None)[0]
        limit = 0.3  # rad: large steps jump to the other assembly mode
        step *= min(1.0, limit / max(np.max(np.abs(step)), 1e-300))
        for c, name in enumerate(free):
            angles[name] -= step[c]
        placed = _place(bodies, tree, angles)
        gap = _gaps(placed, loops)
    worst = int(np.argmax([np.hypot(*gap[2 * k:2 * k + 2]) for k in range(len(loops))]))
    if not np.max(np.abs(gap)) < ASSEMBLY_TOL_M:
        return None, (f"loop {loops[worst].name} cannot be closed from the given pose: its "
                      f"points stay {np.hypot(*gap[2 * worst:2 * worst + 2]) * 1e3:.4g} mm "
                      "apart (the links cannot reach, or the pose is far from an assembled one)")
    moved = {f"{b}.{p}": float(np.linalg.norm(_world(placed[b], xy) - _world(bodies[b], xy)))
             for b in bodies for p, xy in bodies[b].points_m.items()}
    change = {k: angles[k] - start[k] for k in angles}
    return placed, Assembly(change, moved, before)
