"""The continuation over an atlas's grid: the start pose, the cell it starts from, and which
cells its working mode reaches, with their poses.

*Reachable* means reachable from the start pose by continuous motion in its working mode: a
flood fill over the grid, cell to neighbouring cell, with batched Newton

.. code:: text

    F(q) = [Phi(q); x(q) - x*] = 0,    q <- q - K^-1 F(q),    K = [Phi_q; J]

that keeps the sign of det K (crossing it means crossing a Type I singularity into another
working mode). The sign of det Phi_p may change on the way: a cell whose sign differs from the
start pose's is in another assembly mode (``Atlas.same_assembly``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, WorkspaceError
from ..model.robot import Robot
from .atlas_grid import Grid
from .pose_measures import stacked

#: Newton iterations per (sub)step: it corrects until |F|_inf <= NEWTON_AIM (1 + |x*|_inf)
#: (m, rad; a few hundred times the rounding of x(q)), and accepts a cell whose residual is
#: below NEWTON_TOL (1 + |x*|_inf) after the last iteration
NEWTON_ITER = 12
NEWTON_AIM = 1e-14
NEWTON_TOL = 1e-12
#: a correction from the neighbour's pose larger than this (rad, or L_c for a slider) is not
#: trusted: the cell is retried in SUBSTEPS steps, then from another neighbour
DQ_LIMIT = 0.5
SUBSTEPS = 4
#: a drawn pose that is singular is bent by this much at every revolute joint after the first
#: (trees only): the seed's elbow convention (q2 = +acos) picks the positive bend
BEND_RAD = np.radians(30.0)
#: a closed chain's q_start may miss its loops by this much (m; it chooses the assembly mode)
START_GAP_M = 1e-3


class _Newton:
    """Batched Newton on F(q) = [Phi(q); x(q) - x*] from given poses, numpy over all cells."""

    def __init__(self, robot: Robot, length_scale: float, sign0: float):
        self.robot, self.sign0 = robot, sign0
        self.limit = np.array([DQ_LIMIT * (length_scale if u == "m" else 1.0)
                               for u in robot.coordinate_units])

    def solve(self, q0: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, ok): converged, in the start's working mode, not too far from q0."""
        q = q0.copy()
        scale = 1 + np.max(np.abs(target), axis=1)
        alive = np.ones(len(q), dtype=bool)
        for it in range(NEWTON_ITER + 1):
            K, x, phi, _ = stacked(self.robot, q)
            res = np.max(np.abs(F := np.concatenate([phi, x - target], axis=1)), axis=1)
            done = res <= NEWTON_TOL * scale
            step = alive & ~(res <= NEWTON_AIM * scale)
            if it == NEWTON_ITER or not step.any():
                break
            det = np.linalg.det(K[step])
            fine = np.abs(det) > 0
            idx = np.flatnonzero(step)
            alive[idx[~fine]] = False
            idx = idx[fine]
            dq = np.linalg.solve(K[idx], F[idx][..., None])[..., 0]
            new = q[idx] - dq
            # twice as far as accepted: given up (a target out of reach sends Newton far off)
            near = np.all(np.abs(new - q0[idx]) <= 2 * self.limit, axis=1)
            q[idx[near]] = new[near]
            alive[idx[~near]] = False
        sign = np.sign(np.linalg.det(K))
        ok = alive & done & (sign == self.sign0) & np.all(np.abs(q - q0) <= self.limit, axis=1)
        return q, ok

    def advance(self, q0, x0, x1, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """From q0 at targets x0 to targets x1 in ``steps`` equal steps."""
        q, ok = q0.copy(), np.ones(len(q0), dtype=bool)
        for s in range(1, steps + 1):
            idx = np.flatnonzero(ok)
            if not len(idx):
                break
            q_s, ok_s = self.solve(q[idx], x0[idx] + s / steps * (x1[idx] - x0[idx]))
            q[idx[ok_s]] = q_s[ok_s]
            ok[idx[~ok_s]] = False
        return q, ok


def _neighbours(shape: tuple[int, int, int]):
    """Directions (axis, sign) and a function giving the flat index of each cell's neighbour
    in every direction (cells, directions), -1 outside the grid."""
    strides = (shape[1] * shape[2], shape[2], 1)
    dirs = [(a, s) for a in (2, 1, 0) if shape[a] > 1 for s in (1, -1)]

    def of(idx: np.ndarray) -> np.ndarray:
        sub = np.unravel_index(idx, shape)
        out = np.empty((len(idx), len(dirs)), dtype=np.int64)
        for d, (a, s) in enumerate(dirs):
            inside = (sub[a] + s >= 0) & (sub[a] + s < shape[a])
            out[:, d] = np.where(inside, idx + s * strides[a], -1)
        return out
    return dirs, of


def flood(robot: Robot, targets: np.ndarray, shape, start: int, q_start: np.ndarray,
          length_scale: float, progress=None) -> np.ndarray:
    """Poses of every cell reachable from cell ``start`` (solved at ``q_start``), NaN elsewhere.

    Wave by wave, each unsolved neighbour of a solved cell gets one batched Newton from that
    neighbour's pose (then in SUBSTEPS steps if it failed); a cell that fails is tried again
    from each other solved neighbour in later waves. A cell is accepted when Newton converges,
    det K keeps the start's sign and no coordinate moves more than DQ_LIMIT per step.
    ``progress(done, total)``, if given, hears after each wave how many of the grid's cells
    are solved, and (total, total) when the fill ends (the rest are out of reach).
    """
    sign0 = float(np.sign(np.linalg.det(stacked(robot, q_start[None])[0][0])))
    newton = _Newton(robot, length_scale, sign0)
    dirs, of = _neighbours(shape)
    N = len(targets)
    q = np.full((N, robot.n), np.nan)
    solved = np.zeros(N, dtype=bool)
    tried = np.zeros((N, len(dirs)), dtype=bool)
    q[start], solved[start] = q_start, True
    new, pending = np.array([start]), np.zeros(0, dtype=np.int64)
    while True:
        nb = of(new).reshape(-1)
        cand = np.unique(np.concatenate([nb[nb >= 0], pending]))
        cand = cand[~solved[cand]]
        nbs = of(cand)
        usable = (nbs >= 0) & solved[np.maximum(nbs, 0)] & ~tried[cand]
        has = usable.any(axis=1)
        cand, nbs, usable = cand[has], nbs[has], usable[has]
        if not len(cand):
            if progress is not None:
                progress(N, N)
            return q
        d = np.argmax(usable, axis=1)
        src = nbs[np.arange(len(cand)), d]
        tried[cand, d] = True
        q_new, ok = newton.advance(q[src], targets[src], targets[cand], 1)
        retry = np.flatnonzero(~ok)
        if len(retry):
            q_r, ok_r = newton.advance(q[src[retry]], targets[src[retry]], targets[cand[retry]],
                                       SUBSTEPS)
            q_new[retry], ok[retry] = q_r, ok_r
        q[cand[ok]] = q_new[ok]
        solved[cand[ok]] = True
        new, pending = cand[ok], cand[~ok]
        if progress is not None:
            progress(int(solved.sum()), N)


def _resolve(robot) -> Robot:
    """A Robot as it is, or loaded from a built-in name, a description file or a folder."""
    if isinstance(robot, Robot):
        return robot
    from ..model.locate import load

    return load(robot)


def start(robot: Robot, q_start) -> tuple[np.ndarray, str]:
    """The start pose (rad, m) and a note: ``q_start``, else the drawn configuration; a tree
    whose drawn configuration is singular (a stretched arm) starts bent by BEND_RAD at every
    revolute joint after the first, the seed's elbow (q2 = +acos). A closed chain's
    ``q_start`` may miss its loops by up to START_GAP_M: its passive joints are then solved
    from its actuated ones (``motion.closure.solve_passive``); so are the drawn
    configuration's, where the parameters moved a loop's joints further than that."""
    from ..motion.newton import start_pose

    if q_start is not None and robot.is_closed_chain:
        from ..motion.closure import solve_passive

        gap = float(np.max(np.abs(robot.constraint(q_start))))
        if gap > START_GAP_M:
            raise InputError(f"{robot.name}: q_start does not close the loops (|Phi| = "
                             f"{gap * 1e3:.4g} mm, limit {START_GAP_M * 1e3:g} mm): give an "
                             "assembled pose")
        q_start = solve_passive(robot, q_start[list(robot.actuated)][None], q_start)[0]
    if q_start is None and robot.is_closed_chain:
        gap = float(np.max(np.abs(robot.constraint(robot.q_drawn))))
        if gap > START_GAP_M:  # lengths changed since the drawing (with_parameters, a sweep)
            from ..motion.closure import solve_passive

            q = solve_passive(robot, robot.q_drawn[list(robot.actuated)][None],
                              robot.q_drawn)[0]
            return start_pose(robot, q), (
                f"the drawn configuration misses the loops by {gap * 1e3:.3g} mm with these "
                "parameters: started from its actuated angles, the passive joints solved")
    if q_start is not None or robot.is_closed_chain:
        return start_pose(robot, q_start), ""
    try:
        return start_pose(robot, None), ""
    except WorkspaceError:
        q = robot.q_drawn.copy()
        rev = [i for i, u in enumerate(robot.coordinate_units) if u == "rad"][1:]
        q[rev] += BEND_RAD
        note = (f"the drawn configuration is singular: started from it with joints "
                f"{', '.join(robot.coordinates[i] for i in rev)} bent by "
                f"{np.degrees(BEND_RAD):g} deg (give q_start for another working mode)")
        return start_pose(robot, q), note


def _start_cell(robot: Robot, grid: Grid, targets: np.ndarray,
                q0: np.ndarray) -> tuple[int, np.ndarray]:
    """The cell nearest the start pose's task position, and its pose, continued from q0
    along a straight line (motion.newton.solve)."""
    from ..motion import newton

    x0 = np.reshape(robot.task(q0)[0], -1)
    k = [int(np.argmin(np.abs(grid.y_m - x0[1]))), int(np.argmin(np.abs(grid.x_m - x0[0])))]
    k = [int(np.argmin(np.abs(grid.phi_rad - x0[2]))) if len(grid.phi_rad) else 0] + k
    cell = int(np.ravel_multi_index(k, grid.shape))
    path = np.linspace(x0, targets[cell], 9)
    run = newton.solve(robot, np.linspace(0.0, 1.0, 9), path, q0)
    if run.failed is not None:
        where = ", ".join(f"{t} {v * (1e3 if t != 'phi' else 180 / np.pi):.4g} "
                          f"{'mm' if t != 'phi' else 'deg'}"
                          for t, v in zip(robot.task_names, targets[cell]))
        raise WorkspaceError(f"{robot.name}: the grid point nearest the start pose ({where}) "
                             "cannot be reached from it in its working mode: choose a region "
                             "around the start pose or another start pose (q_start)")
    return cell, run.q[-1]
