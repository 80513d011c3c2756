"""The region and grid an atlas maps: the reach bound around the ground pivots and the checked
grid of task targets (x, y[, phi]) over it.

Each leg to the task point without a slider bounds it to a disc around its ground pivot c:

.. code:: text

    |x - c| <= REACH_MARGIN * (length of the polyline c -> leg's joints -> task point)

The default region is the intersection of the discs' boxes; the smallest radius is the
default characteristic length L_c of the measures (``pose_measures``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot

#: arrays of a grid above this many bytes are refused (with the size they would take)
MEMORY_LIMIT_GB = 2.0
#: points per axis when neither a step nor a count is given (the longer side)
DEFAULT_POINTS = 101
#: the reach bound (sum of link lengths along a leg) is widened by this factor for the grid
REACH_MARGIN = 1.05


def reach(robot: Robot) -> tuple[tuple[float, float, float, float], float] | None:
    """Box (x_min, x_max, y_min, y_max) (m) holding every reachable task point, and the
    smallest reach radius R (m); None when every leg to the task point has a slider.

    Each leg (a path of joints from the ground to the task point's body) bounds the task point
    to a disc around its ground pivot, radius the length of the polyline through the leg's
    joints and the task point in the drawn pose (times REACH_MARGIN): the box is the
    intersection of the discs' boxes. The task point's body is the one whose joints from the
    ground are exactly the coordinates that move the task point (non-zero columns of J).
    """
    joints = robot.library.manifest["joints"]
    q0 = robot.q_drawn[None]
    zeros = np.zeros_like(q0)
    points = np.asarray(robot.body_motion(q0, zeros, zeros)[2]).reshape(2, -1).T
    x, J, _ = robot.task(q0)
    tip = np.reshape(x, -1)[:2]
    body = _task_body(joints, np.reshape(J, (len(robot.task_names), robot.n)))
    if body is None:
        return None
    boxes, radii = [], []
    for path in _paths(joints, body):
        if any(joints[j]["type"] == "prismatic" for j in path):
            continue
        line = np.array([points[j] for j in path] + [tip])
        r = REACH_MARGIN * float(np.sum(np.hypot(*np.diff(line, axis=0).T)))
        c = line[0]
        boxes.append((c[0] - r, c[0] + r, c[1] - r, c[1] + r))
        radii.append(r)
    if not boxes:
        return None
    b = np.array(boxes)
    return (b[:, 0].max(), b[:, 1].min(), b[:, 2].max(), b[:, 3].min()), min(radii)


def _task_body(joints: list[dict], J: np.ndarray) -> str | None:
    moving = {i for i in range(J.shape[1]) if np.any(np.abs(J[:, i]) > 1e-12)}
    parent = {j["child"]: (k, j["parent"]) for k, j in enumerate(joints) if not j["closes_loop"]}
    best = None
    for b in parent:
        chain, at = [], b
        while at in parent:
            k, at = parent[at]
            chain.append(k)
        coords = {joints[k]["coordinate"] for k in chain} - {None}
        if coords == moving and (best is None or len(chain) < best[1]):
            best = (b, len(chain))
    return None if best is None else best[0]


def _paths(joints: list[dict], target: str, limit: int = 64) -> list[list[int]]:
    """Simple paths of joints from the ground to ``target`` (a joint links parent and child)."""
    out: list[list[int]] = []

    def walk(body: str, seen: set[str], path: list[int]) -> None:
        if body == target:
            out.append(path)
            return
        for k, j in enumerate(joints):
            for a, b in ((j["parent"], j["child"]), (j["child"], j["parent"])):
                if a == body and b not in seen and len(out) < limit:
                    walk(b, seen | {b}, path + [k])

    walk("ground", {"ground"}, [])
    return out


@dataclass(frozen=True)
class Grid:
    """A checked grid: its axes (m, rad), the reach bound's box (m) and L_c (m)."""

    x_m: np.ndarray
    y_m: np.ndarray
    phi_rad: np.ndarray  # empty: no orientation
    reach_box_m: tuple[float, float, float, float] | None
    length_scale_m: float

    @property
    def shape(self) -> tuple[int, int, int]:
        return max(len(self.phi_rad), 1), len(self.y_m), len(self.x_m)

    def targets(self) -> np.ndarray:
        """Task targets of every cell, (cells, nt): x, y[, phi]."""
        P, Y, X = np.meshgrid(self.phi_rad if len(self.phi_rad) else [0.0], self.y_m, self.x_m,
                              indexing="ij")
        cols = [X, Y] + ([P] if len(self.phi_rad) else [])
        return np.stack([c.reshape(-1) for c in cols], axis=1)


def _range(name: str, value) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be two numbers (min, max) in m (got {value!r})") from None
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise InputError(f"{name} = ({lo:g}, {hi:g}) m: both ends must be finite")
    if not lo < hi:
        raise InputError(f"{name} = ({lo:g}, {hi:g}) m: the minimum must be below the maximum")
    return lo, hi


def _count(name: str, lo: float, hi: float, step: float | None, points: int | None) -> int:
    if points is not None:
        return points
    count = int(min(np.floor((hi - lo) / step * (1 + 1e-12)), 1e15)) + 1
    if count < 2:
        raise InputError(f"step = {step:g} m leaves fewer than 2 points along {name} "
                         f"({lo:g} to {hi:g} m): use a smaller step")
    return count


def _points(points) -> tuple[int, int] | None:
    if points is None:
        return None
    pair = (points, points) if np.ndim(points) == 0 else tuple(points)
    if len(pair) != 2 or not all(isinstance(p, (int, np.integer)) and p >= 2 for p in pair):
        raise InputError(f"points must be an integer >= 2 per axis, or a pair (nx, ny) "
                         f"(got {points!r})")
    return int(pair[0]), int(pair[1])


def make_grid(robot: Robot, x_range=None, y_range=None, step=None, points=None,
              orientations=None, length_scale=None, phi0: float = 0.0) -> Grid:
    """The grid of task targets, checked (see ``atlas``); ``phi0`` is the start pose's phi,
    the default orientation."""
    has_phi = "phi" in robot.task_names
    if orientations is not None and not has_phi:
        raise InputError(f"orientations: {robot.name} has no orientation in its task "
                         f"({', '.join(robot.task_names)}): leave them out")
    phi = np.array([phi0] if has_phi else [], dtype=float)
    if orientations is not None:
        phi = np.unique(np.asarray(orientations, dtype=float).reshape(-1))
        if not len(phi) or not np.all(np.isfinite(phi)):
            raise InputError(f"orientations must be finite angles in rad (got {orientations!r})")
    if step is not None and points is not None:
        raise InputError("give a step or a number of points, not both")
    if step is not None and not (np.ndim(step) == 0 and np.isfinite(step) and step > 0):
        raise InputError(f"step must be a positive length in m (got {step!r})")
    counts = _points(points)
    found = reach(robot)
    box = found[0] if found else None
    if box is None and (x_range is None or y_range is None):
        raise InputError(f"{robot.name}: a slider on every leg to the task point leaves its reach "
                         "unbounded: give the region (x_range and y_range, m; --x and --y, mm)")
    xr = _range("x_range", x_range) if x_range is not None else box[:2]
    yr = _range("y_range", y_range) if y_range is not None else box[2:]
    if box is not None and (xr[0] > box[1] or xr[1] < box[0] or yr[0] > box[3] or yr[1] < box[2]):
        raise InputError(
            f"{robot.name}: the region x_range = ({xr[0]:g}, {xr[1]:g}) m, y_range = "
            f"({yr[0]:g}, {yr[1]:g}) m lies outside the robot's reach (x in ({box[0]:.4g}, "
            f"{box[1]:.4g}) m, y in ({box[2]:.4g}, {box[3]:.4g}) m): ranges are in m")
    if step is None and counts is None:
        step = max(xr[1] - xr[0], yr[1] - yr[0]) / (DEFAULT_POINTS - 1)
    nx = _count("x", *xr, step, None if counts is None else counts[0])
    ny = _count("y", *yr, step, None if counts is None else counts[1])
    _check_memory(robot, (max(len(phi), 1), ny, nx))
    x = np.linspace(xr[0], xr[0] + step * (nx - 1), nx) if counts is None else np.linspace(*xr, nx)
    y = np.linspace(yr[0], yr[0] + step * (ny - 1), ny) if counts is None else np.linspace(*yr, ny)
    L = found[1] if found else max(xr[1] - xr[0], yr[1] - yr[0]) / 2
    if length_scale is not None:
        if not (np.ndim(length_scale) == 0 and np.isfinite(length_scale) and length_scale > 0):
            raise InputError(f"length_scale must be a positive length in m (got {length_scale!r})")
        L = float(length_scale)
    return Grid(x, y, phi, box, float(L))


def _check_memory(robot: Robot, shape: tuple[int, int, int]) -> None:
    n, nt, na = robot.n, len(robot.task_names), len(robot.actuated)
    cells = shape[0] * shape[1] * shape[2]  # Python ints: no overflow
    # float64 per cell: the maps (q, targets, 5 measures, 3 per actuator), the fill's state
    # (q, targets) and the long table the files are written from (twice: stacking it)
    need = cells * 8 * (4 * n + nt + 20 + 9 * na) / 1e9
    if need > MEMORY_LIMIT_GB:
        nphi, ny, nx = shape
        layers = f" x {nphi} orientations" if nphi > 1 else ""
        raise InputError(f"{robot.name}: a grid of {cells:,} points ({nx} x {ny}{layers}) would "
                         f"take {need:.3g} GB of memory (limit {MEMORY_LIMIT_GB:g} GB): use a "
                         "larger step or fewer points")
