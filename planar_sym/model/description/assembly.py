"""Placing bodies along the tree from joint angles, and closing the loops numerically, so that
nobody has to solve circle intersections by hand (``pose = "joints"``, ``assemble = true``).

Each body keeps its shape (its points in its own frame). The tree is placed from ground outward:
a child's frame angle is its parent's plus the joint angle, and its joint point is put on the
parent's. The loops are then closed by Gauss-Newton with minimum-norm steps on the cut joints'
gaps, moving the passive joints' angles theta (the actuated ones keep the given angles):

.. math::

    g(\\theta) = [r_a - r_b]_{\\text{cut joints}},\\qquad
    \\frac{\\partial (r_a - r_b)}{\\partial \\theta_k}
        = [a \\in S_k]\\, (r_a - p_k)^{\\perp} - [b \\in S_k]\\, (r_b - p_k)^{\\perp},\\qquad
    \\Delta\\theta = -J^{+} g

with ``S_k`` the bodies beyond tree joint ``k``, ``p_k`` its position and ``(x, y)^perp =
(-y, x)`` (an exact Jacobian: the iteration converges quadratically). Steps are limited to
``MAX_STEP_RAD`` and halved until ``|g|`` decreases, so the iteration stays in the assembly mode
of the given pose. The actuated joints never move: the angles a user gives them are the
design's input, and a loop they put out of reach is refused (naming it), not closed by quietly
turning a motor. numpy only: shared by derive and the runtime.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..units import factor
from .types import CLOSURE_TOLERANCE_M, GROUND, Assembly, Body, Joint, slide_offset, wrap_angle

#: the loops are closed to this gap (m), far below the 1e-5 m a typed pose must close to
ASSEMBLY_TOL_M = 1e-12
#: a step never turns a joint by more than this (rad): larger steps jump assembly modes
MAX_STEP_RAD = 0.3
MAX_ITER = 100


def tree_angles(bodies: dict[str, Body], tree) -> dict[str, float]:
    """Every tree joint's coordinate as the bodies are placed: the angle of the child frame
    minus the parent's (rad), or for a prismatic joint the child point's distance along the axis
    from the parent point (m)."""
    return {j.name: slide_offset(bodies, j) if j.type == "prismatic" else
            bodies[j.child].drawn_angle_rad - bodies[j.parent].drawn_angle_rad for j in tree}


def place(bodies: dict[str, Body], tree, angles: dict[str, float]) -> dict[str, Body]:
    """The bodies placed along the tree from ground.

    Parameters
    ----------
    bodies : dict of str to Body
        Shapes (body-frame points); the ground's placement is kept, the others' replaced.
    tree : sequence of Joint
        Tree joints, parents before children.
    angles : dict of str to float
        Every tree joint's coordinate: child frame angle = parent frame angle + angle (rad);
        for a prismatic joint the child point's distance along the axis from the parent point
        (m), the child frame turned by the joint's fixed ``rel_angle_rad``.
    """
    out = dict(bodies)
    for j in tree:
        parent = out[j.parent]
        ax, ay = parent.world(parent.points_m[j.parent_point])
        if j.type == "prismatic":
            angle = parent.drawn_angle_rad + j.rel_angle_rad
            u = parent.direction(j.axis)
            ax, ay = ax + angles[j.name] * u[0], ay + angles[j.name] * u[1]
        else:
            angle = parent.drawn_angle_rad + angles[j.name]
        c, s = math.cos(angle), math.sin(angle)
        lx, ly = out[j.child].points_m[j.child_point]
        out[j.child] = replace(out[j.child], drawn_angle_rad=angle,
                               drawn_origin_m=(ax - (c * lx - s * ly), ay - (s * lx + c * ly)))
    return out


def place_at(bodies: dict[str, Body], tree, q) -> dict[str, Body]:
    """The bodies placed for coordinates ``q`` (revolute angles in rad, prismatic displacements
    from the drawn pose in m, tree order); welds keep their drawn relative angle. The forward
    kinematics the generated ``frames`` compute."""
    angles, k = tree_angles(bodies, tree), 0
    for j in tree:
        if j.type == "revolute":
            angles[j.name] = float(q[k])
        elif j.type == "prismatic":
            angles[j.name] += float(q[k])
        if j.moves:
            k += 1
    return place(bodies, tree, angles)


def _point(bodies: dict[str, Body], body: str, point: str) -> np.ndarray:
    return np.array(bodies[body].world(bodies[body].points_m[point]))


def _gaps(bodies: dict[str, Body], loops) -> np.ndarray:
    return np.concatenate([_point(bodies, j.parent, j.parent_point)
                           - _point(bodies, j.child, j.child_point) for j in loops])


def moved_by(tree) -> dict[str, set[str]]:
    """Bodies moved by each tree joint: its child and everything hanging from it."""
    out: dict[str, set[str]] = {}
    for j in reversed(tree):  # children's sets are complete before their parents'
        out[j.name] = {j.child}.union(*(out[k.name] for k in tree if k.parent == j.child))
    return out


def gap_jacobian(bodies, tree, loops, beyond, free) -> np.ndarray:
    """d gaps / d coordinates of the joints ``free`` (exact, see the module docstring; a
    prismatic joint moves the points beyond it along its axis)."""
    pivots = {j.name: _point(bodies, j.parent, j.parent_point) for j in tree}
    slides = {j.name: np.array(bodies[j.parent].direction(j.axis)) for j in tree
              if j.type == "prismatic"}
    jac = np.zeros((2 * len(loops), len(free)))
    for r, cut in enumerate(loops):
        a = _point(bodies, cut.parent, cut.parent_point)
        b = _point(bodies, cut.child, cut.child_point)
        for c, name in enumerate(free):
            sign = (cut.parent in beyond[name]) - (cut.child in beyond[name])
            if name in slides:
                jac[2 * r:2 * r + 2, c] = sign * slides[name]
                continue
            d = np.zeros(2)
            if cut.parent in beyond[name]:
                d += a - pivots[name]
            if cut.child in beyond[name]:
                d -= b - pivots[name]
            jac[2 * r:2 * r + 2, c] = (-d[1], d[0])
    return jac


def close_loops(bodies, tree, loops, start, free):
    """Gauss-Newton from ``start`` moving the joints ``free``: (angles, placed, gaps, steps)."""
    beyond = moved_by(tree)
    angles = dict(start)
    placed = place(bodies, tree, angles)
    gap = _gaps(placed, loops)
    steps = 0
    while free and steps < MAX_ITER and np.max(np.abs(gap)) > 1e-3 * ASSEMBLY_TOL_M:
        jac = gap_jacobian(placed, tree, loops, beyond, free)
        step = np.linalg.lstsq(jac, -gap, rcond=None)[0]  # minimum norm: least motion
        step *= min(1.0, MAX_STEP_RAD / max(np.max(np.abs(step)), 1e-300))
        norm, t = np.linalg.norm(gap), 1.0
        while t > 1e-6:  # halve until the gap shrinks: no overshoot into another mode
            trial = dict(angles)
            for c, name in enumerate(free):
                trial[name] += t * step[c]
            trial_placed = place(bodies, tree, trial)
            trial_gap = _gaps(trial_placed, loops)
            if np.linalg.norm(trial_gap) < norm:
                break
            t /= 2
        else:
            break  # a least-squares minimum (or rounding): no step reduces the gap
        angles, placed, gap = trial, trial_placed, trial_gap
        steps += 1
    return angles, placed, gap, steps


def sizes(bodies: dict[str, Body]) -> dict[str, float]:
    """Each body's size (the ground's too): the largest distance between two of its points (m);
    a body of a single point has none and is left out."""
    out = {}
    for name, body in bodies.items():
        pts = np.array(list(body.points_m.values()), dtype=float)
        size = float(np.max(np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))))
        if size > CLOSURE_TOLERANCE_M:
            out[name] = size
    return out


def median_size(bodies: dict[str, Body]) -> float:
    """The mechanism's size: the median of its bodies' and ground's sizes (m; 0 for none), the
    yardstick of a loop's gap that one body typed in another unit does not move."""
    values = list(sizes(bodies).values())
    return float(np.median(values)) if values else 0.0


def assemble(bodies: dict[str, Body], tree: list[Joint], loops: list[Joint],
             start: dict[str, float], reference: dict[str, Body], pose: str, unit: str = "m"):
    """The bodies with every loop closed from the given pose, and what changed.

    Parameters
    ----------
    bodies : dict of str to Body
        Shapes; placements are replaced.
    tree, loops : list of Joint
        Tree joints (parents first) and cut joints.
    start : dict of str to float
        The given pose: every tree joint's angle (rad).
    reference : dict of str to Body
        Where the description put the bodies (typed world points, or placed from ``start``):
        the points' displacements are measured from it.
    pose : str
        ``"world"`` or ``"joints"``, for the record.
    unit : str
        The description's length unit (``[units].length``): the messages and the record's
        report give lengths in it.

    Returns
    -------
    (dict of str to Body, Assembly) or (None, (str, str))
        The assembled bodies and the record; or, when the loops cannot be closed, None and
        (the worst loop's name, the message naming every loop left open and its gap).
    """
    revolute = [j for j in tree if j.moves]
    passive = [j.name for j in revolute if not j.actuated]
    gap0 = _gaps(place(bodies, tree, start), loops)
    angles, placed, gap, steps = close_loops(bodies, tree, loops, start, passive)
    norms = {j.name: float(np.hypot(*gap[2 * k:2 * k + 2])) for k, j in enumerate(loops)}
    if not np.max(np.abs(gap)) < ASSEMBLY_TOL_M:
        open_ = sorted((n for n in norms if norms[n] >= ASSEMBLY_TOL_M), key=lambda n: -norms[n])
        worst, per = open_[0], factor("length", unit)
        size = median_size(bodies)
        # a gap as large as the links is no small miss: say so against the mechanism's size
        times = (f"; the gap is {norms[worst] / size:.3g} times the median size of its ground "
                 f"and bodies ({size / per:.4g} {unit})" if size > 0.0 else "")
        also = "".join(f"; loop {n} too: {norms[n] / per:.4g} {unit}" for n in open_[1:])
        message = (f"loop {worst} cannot be closed from the given pose: its points "
                   f"stay {norms[worst] / per:.4g} {unit} apart{also} with the actuated "
                   "joints at their given angles (the links cannot reach, or the "
                   f"pose is far from an assembled one){times}")
        return None, (worst, message)
    moved = {f"{b}.{p}": math.dist(placed[b].world(xy), reference[b].world(xy))
             for b in bodies if b != GROUND for p, xy in bodies[b].points_m.items()}
    names = [j.name for j in revolute]
    slides = {j.name for j in revolute if j.type == "prismatic"}

    def wrap(n: str, v: float) -> float:
        return v if n in slides else wrap_angle(v)
    return placed, Assembly(
        pose=pose,
        given_rad={n: wrap(n, start[n]) for n in names},
        angles_rad={n: wrap(n, angles[n]) for n in names},
        angle_change_rad={n: angles[n] - start[n] for n in names},
        point_moved_m=moved,
        gaps_before_m={j.name: float(np.hypot(*gap0[2 * k:2 * k + 2]))
                       for k, j in enumerate(loops)},
        gaps_after_m=norms,
        iterations=steps, slides=frozenset(slides), length_unit=unit)
