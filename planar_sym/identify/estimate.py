"""Estimate a robot's base parameters from measured torques: weighted least squares.

Every experiment's regressor rows are stacked, ``W beta = tau`` (the kept columns of Y, base
parameters ``beta``), and solved twice: ordinary least squares first, then each joint's rows
weighted by the inverse of its residual's standard deviation (Gautier's weighting: joints with
noisier torques count less). The covariance of the estimate is ``s^2 (W~^T W~)^-1`` for the
weighted system ``W~``, ``s^2`` its residual variance: the standard deviations reported.

A tree's passive joint is an equation too: its torque is zero.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from .base import BaseParameters, base_parameters
from .data import Experiment
from .regressor import regressor


@dataclass(frozen=True)
class Estimate:
    """Base parameters estimated from data, in ``base``'s order and units (SI).

    ``values`` shape (b,) and ``std`` shape (b,) their standard deviations; ``sigma`` (rows,) each joint's
    torque residual's standard deviation (N*m; N at a slider) after the fit, ``rows`` naming
    the joints; ``condition`` the condition number of the weighted, column-scaled stack;
    ``samples`` the number of states used; ``notes`` what was done to the data; ``scale``
    (b,) the size of each base parameter that alone would give torques of the data's size
    (|tau| / |its column|), in its unit; ``unexplained`` (rows,) each joint's residual RMS over
    its torque's RMS (above ``POOR_FIT`` the fit does not describe the data).
    """

    base: BaseParameters
    values: np.ndarray
    std: np.ndarray
    sigma: np.ndarray
    rows: tuple[str, ...]
    condition: float
    samples: int
    notes: tuple[str, ...]
    scale: np.ndarray
    unexplained: tuple[float, ...] = ()

    @property
    def poor_fit(self) -> str:
        """The joints whose torque the fit leaves unexplained beyond ``POOR_FIT``, as
        ``"joint1 93.4 %, joint2 98.3 %"``; "" for a fit that describes the data."""
        return ", ".join(f"{j} {100 * u:.3g} %" for j, u in zip(self.rows, self.unexplained)
                         if u > POOR_FIT)

    @property
    def relative_std(self) -> np.ndarray:
        """std / |value|, shape (b,), dimensionless; inf where the value is 0."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.values != 0, self.std / np.abs(self.values), np.inf)

    def table(self) -> list[tuple[str, float, float, float, str]]:
        """(name, value, std, relative std, unit) per base parameter."""
        return [(n, float(v), float(s), float(r), u) for n, v, s, r, u in
                zip(self.base.names, self.values, self.std, self.relative_std, self.base.units)]


def stacked(robot: Robot, experiments, base: BaseParameters) -> tuple[np.ndarray, np.ndarray,
                                                                       np.ndarray]:
    """(W, tau, joint), of shape (rows, b), (rows,), (rows,): every experiment's regressor rows
    in the kept columns (N*m per unit of each base parameter), their torques in N*m (N at a
    slider; 0 at a tree's passive joint) and each row's coordinate."""
    ws, taus, joints = [], [], []
    act = list(robot.actuated)
    for ex in experiments:
        reg = regressor(robot, ex.q, ex.qd, ex.qdd, ex.t_s)
        tau = np.zeros((len(ex), len(reg.rows)))
        cols = [reg.rows.index(i) for i in act]
        tau[:, cols] = ex.tau
        ws.append(reg.y[..., list(base.kept)].reshape(-1, len(base)))
        taus.append(tau.reshape(-1))
        joints.append(np.tile(np.array(reg.rows), len(ex)))
    return np.vstack(ws), np.concatenate(taus), np.concatenate(joints)


def identify(robot: Robot, experiments, base: BaseParameters | None = None,
             weighted: bool = True) -> Estimate:
    """Base parameters of ``robot`` from ``experiments`` (``data.Experiment``, one or more).

    ``base`` defaults to ``base_parameters(robot)``; ``weighted=False`` keeps the ordinary
    least squares. InputError when the data do not determine every base parameter (too few
    samples, or a motion that does not excite them): the badly determined ones are named.
    """
    experiments = [experiments] if isinstance(experiments, Experiment) else list(experiments)
    if not experiments:
        raise InputError("identify needs at least one experiment")
    base = base or base_parameters(robot)
    w, tau, joint = stacked(robot, experiments, base)
    if len(tau) <= len(base):
        raise InputError(f"{robot.name}: {len(tau)} torque rows cannot determine "
                         f"{len(base)} base parameters: give more samples")
    scale = np.linalg.norm(w, axis=0)
    dead = scale <= 1e-12 * max(scale.max(), 1e-300)
    if dead.any():
        names = [base.names[k] for k in np.flatnonzero(dead)]
        raise InputError(f"{robot.name}: the motion does not excite {', '.join(names)} (their "
                         "regressor columns are zero): move the joints they belong to")
    coords, joint_row = np.unique(joint, return_inverse=True)
    coords = coords.tolist()
    weights = np.ones(len(tau))
    beta, r_mat = _solve(w, tau, weights)
    sigma = _sigmas(tau - w @ beta, joint_row, len(coords), len(base))
    if weighted and np.all(sigma > 0):
        weights = 1.0 / sigma[joint_row]
        beta, r_mat = _solve(w, tau, weights)
        sigma = _sigmas(tau - w @ beta, joint_row, len(coords), len(base))
    s2 = float(np.sum(((tau - w @ beta) * weights) ** 2) / (len(tau) - len(base)))
    # the weighted stack's columns have the norms of R's: its scaled condition number is R's
    sv = np.linalg.svd(r_mat / np.linalg.norm(r_mat, axis=0), compute_uv=False)
    condition = float(sv[0] / sv[-1]) if sv[-1] > 0 else np.inf
    if not condition < 1e10:
        raise InputError(f"{robot.name}: the data determine the base parameters badly "
                         f"(condition number {condition:.3g} of the scaled regressor): use an "
                         "exciting motion (planar-sym excite) or more of it")
    r_inv = np.linalg.inv(r_mat)
    cov = s2 * (r_inv @ r_inv.T)  # s^2 (W~^T W~)^-1 = s^2 R^-1 R^-T
    notes = tuple(dict.fromkeys(n for ex in experiments for n in ex.notes))
    unexplained = _unexplained(tau, tau - w @ beta, joint_row, len(coords))
    est = Estimate(base, beta, np.sqrt(np.diag(cov)), sigma,
                   tuple(robot.coordinates[c] for c in coords), condition,
                   sum(len(ex) for ex in experiments), notes, np.linalg.norm(tau) / scale,
                   unexplained)
    if est.poor_fit:
        warnings.warn(f"{robot.name}: the fit leaves much of the torque unexplained (residual "
                      f"RMS against the torque's: {est.poor_fit}; a good fit leaves a few "
                      "per cent): are these data this robot's, the angles in radians and the "
                      "torques in N*m (N at a slider), the times in seconds?", RuntimeWarning,
                      stacklevel=2)
    return est


#: a fit that leaves more than this share of a joint's torque RMS unexplained does not describe
#: the data: a trial's angles in degrees under rad headers explained 28 % and 7 % of the
#: torques, and identify wrote a robot from them without a word
POOR_FIT = 0.2


def _unexplained(tau: np.ndarray, residual: np.ndarray, joint_row: np.ndarray,
                 joints: int) -> tuple[float, ...]:
    """Each joint's residual RMS over its torque's RMS (0 where the torque is 0)."""
    out = []
    for k in range(joints):
        rows = joint_row == k
        rms = float(np.sqrt(np.mean(tau[rows] ** 2)))
        out.append(float(np.sqrt(np.mean(residual[rows] ** 2))) / rms if rms > 0 else 0.0)
    return tuple(out)


#: up to this condition number (column-scaled) the normal equations with one step of
#: refinement are as accurate as QR (the error grows like cond^2 eps before refinement); above
#: it the QR route
NORMAL_COND = 1e6
#: refinement steps: each divides the normal equations' error by about cond^2 eps
REFINE = 2


def _solve(w: np.ndarray, tau: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray,
                                                                         np.ndarray]:
    """Weighted least squares: beta and R, the triangular factor of the weighted stack
    (W~^T W~ = R^T R).

    The normal equations W~^T W~ beta = W~^T tau~ by Cholesky, refined twice (a pair of
    products each): a few times faster than a QR of 10^5 rows and as accurate while the scaled
    condition number stays below NORMAL_COND; past it one QR of ``[W~ | tau~]`` (R and
    Q^T tau~ without forming Q)."""
    ww, tw = w * weights[:, None], tau * weights
    gram = ww.T @ ww
    d = np.sqrt(np.diag(gram))
    scaled = gram / np.outer(d, d)
    try:
        chol = np.linalg.cholesky(scaled)
        well = np.linalg.cond(chol) ** 2 < NORMAL_COND ** 2
    except np.linalg.LinAlgError:
        well = False
    if well:
        def solve(rhs):  # (D^-1 G D^-1) (D x) = D^-1 rhs
            y = np.linalg.solve(chol, rhs / d)
            return np.linalg.solve(chol.T, y) / d
        beta = solve(ww.T @ tw)
        for _ in range(REFINE):  # refinement: the residual's normal equations
            beta += solve(ww.T @ (tw - ww @ beta))
        return beta, chol.T * d  # R = L^T D: W~^T W~ = D L L^T D
    r_aug = np.linalg.qr(np.column_stack([ww, tw]), mode="r")
    b = w.shape[1]
    return np.linalg.solve(r_aug[:b, :b], r_aug[:b, b]), r_aug[:b, :b]


def _sigmas(residual: np.ndarray, joint_row: np.ndarray, n_joints: int, b: int) -> np.ndarray:
    """Each joint's residual standard deviation (its share of the b parameters counted);
    ``joint_row`` (rows,) numbers each row's joint 0 .. n_joints - 1."""
    sums = np.bincount(joint_row, residual * residual, minlength=n_joints)
    counts = np.bincount(joint_row, minlength=n_joints)
    return np.sqrt(sums / np.maximum(counts - b / n_joints, 1.0))


def predicted_torques(robot: Robot, estimate: Estimate, ex: Experiment) -> np.ndarray:
    """The actuated torques (N, actuated) the estimate gives along ``ex``'s motion (N*m)."""
    reg = regressor(robot, ex.q, ex.qd, ex.qdd, ex.t_s)
    tau = reg.y[..., list(estimate.base.kept)] @ estimate.values
    return tau[:, [reg.rows.index(i) for i in robot.actuated]]
