"""What both integrators of a controlled run share: the friction of the plant (for the work
integral), and the driver that runs a closed chain in segments re-projected onto its loops."""

from __future__ import annotations

import numpy as np

from ..model.robot import Robot

#: closed chains: the run is re-projected onto the loops this often (s), and a segment whose
#: loops open by more than DRIFT_LIMIT_M stops the run as an event
SEGMENT_S = 0.1
DRIFT_LIMIT_M = 1e-6


def friction(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per coordinate: viscous b, Coulomb c and smoothing v_s of D = b qd + c tanh(qd / v_s)."""
    drives = robot.drive_train
    return drives.viscous, drives.coulomb, drives.smoothing


def run_segments(plant, setup, y0, t, segment, count):
    """Drive ``segment(times, y) -> (states, rows filled, failure time or None)`` over the run:
    once for a tree; for a closed chain every SEGMENT_S, re-projected onto the loops, with
    the loops' failure (a singular constraint matrix, drift beyond DRIFT_LIMIT_M) an event.
    Returns states, their times, RHS evaluations, the largest |Phi| and the loop event."""
    from .forward_closed import project

    n, m = plant.n, plant.n_constraints
    rows, times, drift = [y0], [t[0]], 0.0
    k, y = 0, y0.copy()
    while k < len(t) - 1:
        end = len(t) - 1 if not m else min(max(int(np.searchsorted(
            t, t[k] + SEGMENT_S, side="right")) - 1, k + 1), len(t) - 1)
        tt = np.ascontiguousarray(t[k:end + 1], dtype=float)
        out, got, failed_at = segment(tt, y)
        rows += list(out[1:got])
        times += list(tt[1:got])
        if failed_at is not None:  # a failure at t = 0 is one too
            return (np.array(rows), np.array(times), count[0], drift,
                    (failed_at, "singular constraint matrix"))
        if setup.c.stopped:
            rows.append(setup.y_stop.copy())
            times.append(setup.c.t_stop)
            break
        if m:
            seg = float(np.max(np.abs(plant.constraint(out[1:got, :n])))) if got > 1 else 0.0
            drift = max(drift, seg)
            if not seg <= DRIFT_LIMIT_M:
                return (np.array(rows), np.array(times), count[0], drift,
                        (float(tt[0]), (f"|Phi| reached {seg:.3g} m by t = {tt[-1]:.6g} s, "
                                        f"above {DRIFT_LIMIT_M:g} m")))
            qp, qdp = project(plant, out[-1, :n], out[-1, n:2 * n])
            y = np.concatenate([qp, qdp, out[-1, 2 * n:]])
        k = end
    return np.array(rows), np.array(times), count[0], drift, None
