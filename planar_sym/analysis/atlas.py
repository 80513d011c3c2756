"""An atlas of a robot over a grid of task positions (analysis stage, no plotting): where its
start pose's working mode reaches, both kinds of singularity, dexterity, gravity torque and the
torque envelope.

.. code:: text

    atlas(robot):  grid = make_grid(...)                       the region   (atlas_grid)
                   q    = flood(grid, start pose)              reached poses (atlas_flood)
                   maps = pose_measures(q), rest_torques(q)    per cell     (pose_measures)

This module holds the ``Atlas`` (its maps, summary and files) and ``atlas``, which builds one;
``envelope_along`` (the envelope along a study's path) is re-exported from ``envelope_along``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_files
from ..model.arrays import as_vector
from ..model.robot import Robot
from .atlas_flood import _resolve, _start_cell, flood, start
from .atlas_grid import _task_body, make_grid
from .envelope_along import EnvelopeAlong, envelope_along
from .pose_measures import pose_measures, rest_torques

__all__ = ["NEAR_TYPE2", "REGULAR", "REGULAR_TYPE1", "Atlas", "EnvelopeAlong", "atlas",
           "envelope_along", "pose_measures", "rest_torques", "stick", "type2_crossed",
           "write_csv", "write_npz"]

#: type2 below this counts as near a Type II singularity (the summary's fraction of such cells)
NEAR_TYPE2 = 1e-2
#: the summary's regular peaks take only cells with type2 >= REGULAR: torques grow like
#: cond(Phi_p) near a Type II singularity, so these stay within ~10x of a well-conditioned
#: pose's (NEAR_TYPE2, cond 100, let in 5-bar peaks ~10x the links' weight x length)
REGULAR = 0.1
#: the envelope's regular peak also needs type1 >= REGULAR_TYPE1: 1 / cond of the scaled K
#: (loop and task rows together) stays small on some robots (at most 0.07 on parallel_3rrr,
#: 0.12 on serial_3dof), so REGULAR would leave them few cells or none
REGULAR_TYPE1 = 1e-2
#: rows analysed per batch (bounds the temporaries of the n x n matrices)
CHUNK = 20000


@dataclass(frozen=True, eq=False)
class Atlas:
    """Maps over a grid: array axes (orientation, y, x[, ...]), NaN where unreachable.

    Attributes
    ----------
    x_m, y_m : ndarray, shape (nx,), (ny,)
        Grid (m); ``phi_rad`` (nphi,) the orientations (rad), empty for a robot without one
        (one layer then: nphi = 1 in the maps' shapes).
    q : ndarray, shape (nphi, ny, nx, n)
        Pose of every reachable cell (rad; m for a slider).
    reachable, same_assembly : ndarray of bool, shape (nphi, ny, nx)
        Reached from the start pose in its working mode; and in its assembly mode too (the
        sign of det Phi_p; always for a tree).
    det_type1, det_type2 : ndarray, shape (nphi, ny, nx)
        Signed determinants of the scaled K = [Phi_q; J] and Phi_p (1 for a tree).
    type1, type2, dexterity : ndarray, shape (nphi, ny, nx)
        1 / cond_2 of the scaled K, Phi_p and J_x, in [0, 1].
    gravity, envelope, envelope_angle_rad : ndarray, shape (nphi, ny, nx, n_actuated)
        At rest: the gravity torque and the largest |torque| over task accelerations of size
        ``accel_m_s2`` (m/s^2) in the x-y plane (angular acceleration 0), per actuated joint in
        ``actuator_units`` (N*m, or N for a slider), and the worst direction (rad from +x).
        NaN also where Phi_p is singular (condition number above COND_LIMIT).
    start_pose : ndarray, shape (n,)
        The pose the working mode is taken from; ``start_note`` says if it was chosen.
    length_scale_m, reach_box_m, time_s
        L_c (m); the reach bound's box (x_min, x_max, y_min, y_max) (m, None with sliders on
        every leg); the time the atlas took (s).
    robot : str
        The robot's name.
    coordinates, coordinate_units : tuple of str
        The robot's coordinates and their units ("rad" or "m"): the last axis of ``q``.
    actuated : tuple of int
        The actuated coordinates (0-based): the last axis of the torque maps.
    task_names : tuple of str
        The task coordinates mapped (x, y, and phi where the task has one).
    n_constraints : int
        Loop equations of the robot (0 for a tree).
    start_drawing : dict
        The start pose as lines (m), as ``stick`` returns it, to draw over the maps.
    length_unit : str
        The unit the robot's description is typed in ("m", "cm", "mm"): the maps' axes.
    """

    robot: str
    x_m: np.ndarray
    y_m: np.ndarray
    phi_rad: np.ndarray
    q: np.ndarray
    reachable: np.ndarray
    same_assembly: np.ndarray
    det_type1: np.ndarray
    det_type2: np.ndarray
    type1: np.ndarray
    type2: np.ndarray
    dexterity: np.ndarray
    gravity: np.ndarray
    envelope: np.ndarray
    envelope_angle_rad: np.ndarray
    accel_m_s2: float
    start_pose: np.ndarray
    length_scale_m: float
    reach_box_m: tuple[float, float, float, float] | None
    time_s: float
    coordinates: tuple[str, ...] = ()
    coordinate_units: tuple[str, ...] = ()
    actuated: tuple[int, ...] = ()
    actuator_units: tuple[str, ...] = ()
    task_names: tuple[str, ...] = ()
    n_constraints: int = 0
    start_note: str = ""
    #: the start pose as lines (m): "bodies" (list of (k, 2)), "joints", "ground" (k, 2), "task"
    start_drawing: dict = field(default_factory=dict)
    length_unit: str = "m"

    @property
    def cell_area_m2(self) -> float:
        """Area of one grid cell (m^2)."""
        return float(np.ptp(self.x_m) / (len(self.x_m) - 1)
                     * np.ptp(self.y_m) / (len(self.y_m) - 1))

    def summary(self) -> dict:
        """Figures of the atlas: areas (m^2, cells reached at some listed orientation), worst
        and median dexterity, Type II nearness, peak torques per actuator (actuator units) over
        the reachable cells, and over those away from singular poses (``_regular``: gravity
        where type2 >= REGULAR, the envelope where type1 >= REGULAR_TYPE1 too; near a Type II
        singularity torques grow without bound, near a Type I one the joint accelerations
        do)."""
        reach = self.reachable
        regular = reach & (self.type2 >= REGULAR)
        both = regular & (self.type1 >= REGULAR_TYPE1)
        dex = self.dexterity[reach]

        def peak(values: np.ndarray, where: np.ndarray) -> list[float]:
            v = np.abs(values[where])
            return [float(np.nanmax(v[:, k])) if np.isfinite(v[:, k]).any() else float("nan")
                    for k in range(v.shape[1])]

        return {
            "robot": self.robot, "cells": int(reach.size), "reachable_cells": int(reach.sum()),
            "area_m2": float(reach.any(axis=0).sum()) * self.cell_area_m2,
            "area_same_assembly_m2": float((reach & self.same_assembly).any(axis=0).sum())
            * self.cell_area_m2,
            "worst_dexterity": float(dex.min()) if dex.size else float("nan"),
            "median_dexterity": float(np.median(dex)) if dex.size else float("nan"),
            "type2_near_fraction": float(np.mean(self.type2[reach] < NEAR_TYPE2))
            if dex.size else float("nan"),
            "type2_inside": type2_crossed(self),
            "peak_gravity": peak(self.gravity, reach),
            "peak_envelope": peak(self.envelope, reach),
            "peak_gravity_regular": peak(self.gravity, regular),
            "peak_envelope_regular": peak(self.envelope, both),
            "actuator_units": list(self.actuator_units), "accel_m_s2": self.accel_m_s2,
            "time_s": self.time_s,
        }

    def arrays(self) -> dict[str, np.ndarray]:
        """Every array, named with its unit, as ``to_npz`` writes them.

        Shapes as the attributes' (maps (nphi, ny, nx[, ...]), ``x_m`` (nx,), ...), SI units
        in the names (``x_m``, ``phi_rad``, ``accel_m_s2``); ``q`` in rad (m at a slider),
        the torque maps in ``actuator_units``.
        """
        return {"x_m": self.x_m, "y_m": self.y_m, "phi_rad": self.phi_rad, "q": self.q,
                "reachable": self.reachable, "same_assembly": self.same_assembly,
                "det_type1": self.det_type1, "det_type2": self.det_type2, "type1": self.type1,
                "type2": self.type2, "dexterity": self.dexterity, "gravity": self.gravity,
                "envelope": self.envelope, "envelope_angle_rad": self.envelope_angle_rad,
                "start_pose": self.start_pose, "accel_m_s2": np.array(self.accel_m_s2),
                "length_scale_m": np.array(self.length_scale_m),
                "robot": np.array(self.robot), "coordinates": np.array(self.coordinates),
                "coordinate_units": np.array(self.coordinate_units),
                "actuated": np.array(self.actuated, dtype=int),
                "actuator_units": np.array(self.actuator_units)}

    def table(self) -> tuple[list[str], np.ndarray]:
        """Long format, one row per cell: column names with units, and the (cells, columns)
        values (x_mm, y_mm[, phi_deg], reachable, same_assembly, q..., measures, torques).

        Units as the names say: positions in mm and angles in deg (for reading), coordinates
        ``q<k>_rad`` (``_m`` at a slider), torques ``_n_m`` (N*m) or ``_n`` (N); the measures
        (type1, type2, dexterity) are dimensionless.
        """
        nphi, ny, nx = self.reachable.shape
        P, Y, X = np.meshgrid(self.phi_rad if len(self.phi_rad) else [0.0], self.y_m, self.x_m,
                              indexing="ij")
        names, cols = ["x_mm", "y_mm"], [X * 1e3, Y * 1e3]
        if len(self.phi_rad):
            names.append("phi_deg")
            cols.append(np.degrees(P))
        names += ["reachable", "same_assembly"]
        cols += [self.reachable.astype(float), self.same_assembly.astype(float)]
        for i, u in enumerate(self.coordinate_units):
            names.append(f"q{i + 1}_{u}")
            cols.append(self.q[..., i])
        names += ["type1", "type2", "dexterity", "det_type1", "det_type2"]
        cols += [self.type1, self.type2, self.dexterity, self.det_type1, self.det_type2]
        for k, (i, u) in enumerate(zip(self.actuated, self.actuator_units)):
            suffix = "n_m" if u == "N*m" else "n"
            names += [f"tau_g{i + 1}_{suffix}", f"tau_env{i + 1}_{suffix}",
                      f"env_angle{i + 1}_deg"]
            cols += [self.gravity[..., k], self.envelope[..., k],
                     np.degrees(self.envelope_angle_rad[..., k])]
        return names, np.column_stack([np.reshape(c, nphi * ny * nx) for c in cols])

    def to_npz(self, path) -> None:
        """Write ``arrays()`` to ``path`` (.npz), whole or not at all."""
        with atomic_files([Path(path)]) as (tmp,):
            write_npz(self, tmp)

    def to_csv(self, path) -> None:
        """Write ``table()`` to ``path`` (.csv, one header row), whole or not at all."""
        with atomic_files([Path(path)]) as (tmp,):
            write_csv(self, tmp)


def write_npz(atlas: Atlas, path) -> None:
    """``atlas.arrays()`` into ``path`` as it is (compressed NPZ)."""
    with open(path, "wb") as fh:
        np.savez_compressed(fh, **atlas.arrays())


def write_csv(atlas: Atlas, path) -> None:
    """``atlas.table()`` into ``path`` as it is (CSV, one header row with units)."""
    names, values = atlas.table()
    np.savetxt(path, values, delimiter=",", header=",".join(names), comments="", fmt="%.10g")


def type2_crossed(atlas: Atlas) -> bool:
    """Whether det_type2 changes sign between two neighbouring reachable cells."""
    d, r = np.sign(atlas.det_type2), atlas.reachable
    return any(bool(np.any((np.diff(d, axis=a) != 0) & r.take(range(1, r.shape[a]), axis=a)
                           & r.take(range(r.shape[a] - 1), axis=a))) for a in (0, 1, 2)
               if r.shape[a] > 1)


def atlas(robot, x_range=None, y_range=None, step=None, points=None, orientations=None,
          q_start=None, accel_m_s2: float = 1.0, length_scale=None, progress=None) -> Atlas:
    """The atlas of a robot over a grid of task positions (and orientations).

    Parameters
    ----------
    robot : Robot, or a built-in name, a description file or a generated folder
    x_range, y_range : (float, float), optional
        Region (m); default: around the ground pivots, the reach bound (``reach``).
    step : float, optional
        Grid step (m), the same along x and y; or
    points : int or (int, int), optional
        Points per axis (>= 2). Default: DEFAULT_POINTS along the longer side.
    orientations : sequence of float, optional
        Platform angles phi (rad) of a robot whose task has one; default the start pose's.
    q_start : array_like, shape (n,), optional
        Start pose (rad, m for sliders), default the drawn configuration: its working mode is
        mapped, and ``same_assembly`` compares with its assembly mode.
    accel_m_s2 : float
        Size of the task acceleration of the envelope (m/s^2, in the x-y plane).
    length_scale : float, optional
        L_c (m) that makes the Jacobians dimensionless; default the reach radius.
    progress : callable, optional
        Called as ``progress(stage, done, total)`` as the work goes: stage "poses" (grid
        cells tried by the flood fill) then "measures" (reachable cells measured); the
        command line shows it (``progress.Meter``).

    Returns
    -------
    Atlas

    Raises
    ------
    InputError
        Bad ranges, step, points, orientations, or a grid larger than MEMORY_LIMIT_GB.
    WorkspaceError
        A robot whose task does not fix its coordinates, or a singular start pose.
    """
    from ..motion.newton import check_square

    t0 = time.perf_counter()
    robot = _resolve(robot)
    if not robot.task_names:
        raise InputError(f"{robot.name} has no task point (its description has no [task]): an "
                         "atlas maps the task point's positions")
    check_square(robot)
    if not (np.ndim(accel_m_s2) == 0 and np.isfinite(accel_m_s2) and accel_m_s2 >= 0):
        raise InputError(f"accel_m_s2 must be a finite acceleration >= 0 in m/s^2 "
                         f"(got {accel_m_s2!r})")
    if q_start is not None:
        q_start = as_vector("q_start", q_start, robot.n)
    q0, note = start(robot, q_start)
    x0 = np.reshape(robot.task(q0)[0], -1)
    phi0 = float(x0[robot.task_names.index("phi")]) if "phi" in robot.task_names else 0.0
    grid = make_grid(robot, x_range, y_range, step, points, orientations, length_scale, phi0)
    targets = grid.targets()
    cell, q_cell = _start_cell(robot, grid, targets, q0)
    q = flood(robot, targets, grid.shape, cell, q_cell, grid.length_scale_m,
              None if progress is None else lambda done, total: progress("poses", done, total))
    maps = _maps(robot, q, grid.length_scale_m, float(accel_m_s2), q_cell,
                 None if progress is None else lambda done, total: progress("measures", done,
                                                                          total))
    shape = grid.shape
    return Atlas(
        robot.name, grid.x_m, grid.y_m, grid.phi_rad, q.reshape(*shape, robot.n),
        **{k: v.reshape(*shape, *v.shape[1:]) for k, v in maps.items()},
        accel_m_s2=float(accel_m_s2), start_pose=q0, length_scale_m=grid.length_scale_m,
        reach_box_m=grid.reach_box_m, time_s=time.perf_counter() - t0,
        coordinates=robot.coordinates, coordinate_units=robot.coordinate_units,
        actuated=robot.actuated, actuator_units=tuple(a["unit"] for a in robot.actuators),
        task_names=robot.task_names, n_constraints=robot.n_constraints, start_note=note,
        start_drawing=stick(robot, q0), length_unit=robot.length_unit)


#: a joint's gravity torque at most this fraction of its envelope everywhere is rounding
ROUNDING = 1e-12


def _maps(robot: Robot, q: np.ndarray, L: float, accel: float, q_ref: np.ndarray,
          progress=None) -> dict:
    """Every map at the solved cells (rows of q that are finite), in chunks; NaN elsewhere."""
    N, na = len(q), len(robot.actuated)
    reach = np.all(np.isfinite(q), axis=1)
    out = {k: np.full(N, np.nan) for k in ("det_type1", "det_type2", "type1", "type2",
                                           "dexterity")}
    out.update({k: np.full((N, na), np.nan) for k in ("gravity", "envelope",
                                                      "envelope_angle_rad")})
    idx = np.flatnonzero(reach)
    for lo in range(0, len(idx), CHUNK):
        rows = idx[lo:lo + CHUNK]
        found = {**pose_measures(robot, q[rows], L), **rest_torques(robot, q[rows], accel)}
        for k, values in out.items():
            values[rows] = found[k]
        if progress is not None:
            progress(min(lo + CHUNK, len(idx)), len(idx))
    # a joint whose gravity torque is rounding next to its own envelope at every cell (a wrist
    # with its centre of gravity on its axis: +-6e-16 N*m against 0.06) holds none: 0, not
    # noise drawn as a full colour map and printed as a peak. Cell by cell, not the largest
    # gravity against the largest envelope: near a Type I singular pose the envelope grows
    # without bound (1e14 N*m at the 2-link arm's folded pose, a cell of its default grid),
    # which made every joint's gravity look like rounding and mapped it as 0 everywhere
    with np.errstate(invalid="ignore"):
        for k in range(na):
            g, env = np.abs(out["gravity"][:, k]), np.abs(out["envelope"][:, k])
            if not np.any(g > ROUNDING * env):  # NaN cells (unreached, singular) compare False
                out["gravity"][:, k] = np.where(np.isfinite(g), 0.0, np.nan)
    ref = np.sign(pose_measures(robot, q_ref[None], L)["det_type2"][0])
    same = reach & (np.sign(out["det_type2"]) == ref)
    return {"reachable": reach, "same_assembly": same, **out}


def stick(robot: Robot, q: np.ndarray) -> dict:
    """The pose as lines (m): per body its joints (and the task point), in drawing order.

    ``q`` (n,) is the pose (rad; m at a slider). Returns ``"bodies"`` (a list of (k, 2)
    point arrays), ``"ground"`` (k, 2), ``"joints"`` (joints, 2) and ``"task"`` (2,), in m.
    """
    joints = robot.library.manifest["joints"]
    zeros = np.zeros((1, robot.n))
    pts = np.asarray(robot.body_motion(q[None], zeros, zeros)[2]).reshape(2, -1).T
    tip = np.reshape(robot.task(q)[0], -1)[:2]
    on: dict[str, list[np.ndarray]] = {}
    for k, j in enumerate(joints):
        for b in (j["parent"], j["child"]):
            on.setdefault(b, []).append(pts[k])
    body = _task_body(joints, np.reshape(robot.task(q)[1], (len(robot.task_names), robot.n)))
    if body is not None:
        on.setdefault(body, []).append(tip)
    ground = np.array(on.pop("ground", np.zeros((0, 2))))
    bodies = [_order(np.unique(np.array(p), axis=0)) for p in on.values() if len(p) > 1]
    return {"bodies": [b for b in bodies if len(b) > 1], "ground": ground,
            "joints": pts[:len(joints)], "task": tip}


def _order(p: np.ndarray) -> np.ndarray:
    """Points of a body in drawing order: along its axis if thin, else around it (closed)."""
    if len(p) < 3:
        return p
    c = p - p.mean(axis=0)
    _, s, vt = np.linalg.svd(c, full_matrices=False)
    if s[1] < 0.1 * s[0]:
        return p[np.argsort(c @ vt[0])]
    ring = p[np.argsort(np.arctan2(c[:, 1], c[:, 0]))]
    return np.vstack([ring, ring[:1]])
