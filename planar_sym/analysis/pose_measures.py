"""Measures of a robot at given poses (batched over poses, no grid): how close to either kind
of singularity, the dexterity, and the torques at rest with their envelope.

Notation: q (n coordinates), actuated a, passive p; Phi(q) the loop residuals (m equations),
x(q) the task (n_t = n - m coordinates) and

.. code:: text

    K = [Phi_q; J]            the n x n inverse-kinematics matrix
    Type I  (loses a motion):  K singular      (a leg stretched or folded: the workspace edge)
    Type II (gains a motion):  Phi_p = Phi_q[:, p] singular   (closed chains only)
    dexterity:                 1 / cond_2(J_x),  xd = J_x qd_a,  J_x^-1 = (K^-1)[a, m:]

Both matrices are made dimensionless before they are measured, with a characteristic length
L_c (default: the reach radius R): rows of length (Phi, x, y) x 1, angle rows (phi) x L_c;
revolute columns x 1 / L_c, prismatic ones x 1. The measures are 1 / cond_2 in [0, 1]; the
signed determinants of the scaled K and Phi_p are kept as well, since the loci are their zeros.

At rest (qd = 0) the torques are affine in the task acceleration:
``tau(xdd) = tau_g + A xdd`` with ``qdd = K^-1 [0; xdd]``; over the translational directions of
size ``a`` the largest ``|tau_k|`` is exactly ``|tau_g,k| + a ||A_k||_2`` (the envelope).
"""

from __future__ import annotations

import numpy as np

from ..model.kinematics import stacked_jacobian
from ..model.loops import COND_LIMIT
from ..model.robot import Robot


def scales(robot: Robot, length_scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Row and column factors of K (rows: loops then task; columns: coordinates)."""
    task = [length_scale if t == "phi" else 1.0 for t in robot.task_names]
    rows = np.concatenate([np.ones(robot.n_constraints), task])
    cols = np.array([1.0 / length_scale if u == "rad" else 1.0 for u in robot.coordinate_units])
    return rows, cols


def stacked(robot: Robot, q: np.ndarray, qd=None):
    """K = [Phi_q; J] (N, n, n), x (N, nt), Phi (N, m) and Jdot qd (N, nt) at poses q (N, n)
    (``model.kinematics.stacked_jacobian``, the generic inverse kinematics' K, with Phi)."""
    k, x, jdq = stacked_jacobian(robot, q, qd)
    m = robot.n_constraints
    phi = np.reshape(robot.constraint(q), (len(q), m)) if m else np.zeros((len(q), 0))
    return k, x, phi, jdq


def _ratio(mats: np.ndarray) -> np.ndarray:
    """1 / cond_2 of each matrix (0 where singular; 1 for 0 x 0)."""
    if mats.shape[-1] == 0:
        return np.ones(len(mats))
    s = np.linalg.svd(mats, compute_uv=False)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(s[:, 0] > 0, s[:, -1] / s[:, 0], 0.0)


def _safe_inverse(mats: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses, NaN where a matrix is exactly singular (and which those are)."""
    det = np.linalg.det(mats)
    bad = ~(np.abs(det) > 0)
    mats = mats.copy()
    mats[bad] = np.eye(mats.shape[-1])
    inv = np.linalg.inv(mats)
    inv[bad] = np.nan
    return inv, bad


def pose_measures(robot: Robot, q, length_scale: float) -> dict[str, np.ndarray]:
    """Singularity measures and dexterity at poses q (N, n) (on the loops), each (N,).

    Returns det_type1, det_type2 (signed determinants of the scaled K and Phi_p), type1,
    type2 and dexterity (1 / cond_2 of the scaled K, Phi_p and J_x; see the module docstring).
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    rows, cols = scales(robot, length_scale)
    K = stacked(robot, q)[0] * rows[:, None] * cols
    m, act, pas = robot.n_constraints, list(robot.actuated), list(robot.passive)
    Pp = K[:, :m][:, :, pas]
    inv, _ = _safe_inverse(K)
    sub = inv[:, act][:, :, m:]
    ok = np.all(np.isfinite(sub), axis=(1, 2))
    dex = np.zeros(len(q))
    dex[ok] = _ratio(sub[ok])
    return {"det_type1": np.linalg.det(K), "det_type2": np.linalg.det(Pp),
            "type1": _ratio(K), "type2": _ratio(Pp), "dexterity": dex}


def rest_torques(robot: Robot, q, accel_m_s2: float = 1.0) -> dict[str, np.ndarray]:
    """Torques at rest at poses q (N, n): gravity tau_g (N, na), the map A (N, na, 2) of the
    task's x and y accelerations (m/s^2) and the envelope over directions of size
    ``accel_m_s2``, with its worst direction (rad). NaN at a closed chain's Type II
    singular poses (Phi_p condition number above COND_LIMIT), where torques are not unique."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    N, n, m = len(q), robot.n, robot.n_constraints
    K = stacked(robot, q)[0]
    inv, bad = _safe_inverse(K)
    trans = [m + k for k, t in enumerate(robot.task_names) if t in ("x", "y")]
    qdd = [np.zeros((N, n))] + [np.nan_to_num(inv[:, :, j]) for j in trans]
    tau = inverse_dynamics_at_rest(robot, np.tile(q, (len(qdd), 1)), np.concatenate(qdd))
    tau = tau.reshape(len(qdd), N, -1)
    tau[:, bad] = np.nan
    g, A = tau[0], np.stack([t - tau[0] for t in tau[1:]], axis=-1)
    return {"gravity": g, "A": A, **envelope(g, A, accel_m_s2)}


def envelope(b: np.ndarray, A: np.ndarray, accel: float) -> dict[str, np.ndarray]:
    """max over unit u of |b_k + accel A_k u| = |b_k| + accel ||A_k||, and that u's angle."""
    norm = np.linalg.norm(A, axis=-1)
    s = np.where(b < 0, -1.0, 1.0)
    with np.errstate(invalid="ignore"):
        angle = np.arctan2(s * A[..., 1], s * A[..., 0])
    return {"envelope": np.abs(b) + accel * norm, "envelope_angle_rad": angle}


def inverse_dynamics_at_rest(robot: Robot, q: np.ndarray, qdd: np.ndarray,
                             qd: np.ndarray | None = None) -> np.ndarray:
    """Actuated torques (N, na) for q, qdd on the loops; NaN where Phi_p is singular."""
    qd = np.zeros_like(q) if qd is None else qd
    if not robot.is_closed_chain:
        return np.asarray(robot.tree_inverse_dynamics(q, qd, qdd)).reshape(len(q), -1)[
            :, list(robot.actuated)]
    out = robot._closed_inverse_dynamics(q, qd, qdd)
    tau, cond = (np.asarray(a).reshape(len(q), -1) for a in (out[0], out[2]))
    return np.where(~(cond <= COND_LIMIT), np.nan, tau)
