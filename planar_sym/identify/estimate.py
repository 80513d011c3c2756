"""Estimate a robot's base parameters from measured torques: weighted least squares.

Every experiment's regressor rows are stacked, ``W beta = tau`` (the kept columns of Y, base
parameters ``beta``), and solved twice: ordinary least squares first, then each joint's rows
weighted by the inverse of its residual's standard deviation (Gautier's weighting: joints with
noisier torques count less). The covariance of the estimate is ``s^2 (W~^T W~)^-1`` for the
weighted system ``W~``, ``s^2`` its residual variance: the standard deviations reported.

A tree's passive joint is an equation too: its torque is zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from .base import BaseParameters, base_parameters
from .data import Experiment
from .regressor import regressor


@dataclass(frozen=True)
class Estimate:
    """Base parameters estimated from data, in ``base``'s order and units.

    ``values`` (b,) and ``std`` (b,) their standard deviations; ``sigma`` (rows,) each joint's
    torque residual's standard deviation (N*m; N at a slider) after the fit, ``rows`` naming
    the joints; ``condition`` the condition number of the weighted, column-scaled stack;
    ``samples`` the number of states used; ``notes`` what was done to the data; ``scale``
    (b,) the size of each base parameter that alone would give torques of the data's size
    (|tau| / |its column|), in its unit.
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

    @property
    def relative_std(self) -> np.ndarray:
        """std / |value| (dimensionless); inf where the value is 0."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.values != 0, self.std / np.abs(self.values), np.inf)

    def table(self) -> list[tuple[str, float, float, float, str]]:
        """(name, value, std, relative std, unit) per base parameter."""
        return [(n, float(v), float(s), float(r), u) for n, v, s, r, u in
                zip(self.base.names, self.values, self.std, self.relative_std, self.base.units)]


def stacked(robot: Robot, experiments, base: BaseParameters) -> tuple[np.ndarray, np.ndarray,
                                                                       np.ndarray]:
    """(W (rows, b), tau (rows,), joint (rows,)): every experiment's regressor rows in the
    kept columns, their torques (0 at a tree's passive joint) and each row's coordinate."""
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
    beta = np.linalg.lstsq(w, tau, rcond=None)[0]
    coords = sorted(set(joint.tolist()))
    weights = np.ones(len(tau))
    sigma = np.zeros(len(coords))
    for k, c in enumerate(coords):
        rows = joint == c
        r = tau[rows] - w[rows] @ beta
        sigma[k] = np.sqrt(r @ r / max(rows.sum() - len(base) / len(coords), 1.0))
    if weighted and np.all(sigma > 0):
        for k, c in enumerate(coords):
            weights[joint == c] = 1.0 / sigma[k]
        ww, tw = w * weights[:, None], tau * weights
        beta = np.linalg.lstsq(ww, tw, rcond=None)[0]
        for k, c in enumerate(coords):
            rows = joint == c
            r = tau[rows] - w[rows] @ beta
            sigma[k] = np.sqrt(r @ r / max(rows.sum() - len(base) / len(coords), 1.0))
    ww, tw = w * weights[:, None], tau * weights
    s2 = float(np.sum((tw - ww @ beta) ** 2) / (len(tau) - len(base)))
    scaled = ww / np.linalg.norm(ww, axis=0)
    sv = np.linalg.svd(scaled, compute_uv=False)
    condition = float(sv[0] / sv[-1]) if sv[-1] > 0 else np.inf
    if not condition < 1e10:
        raise InputError(f"{robot.name}: the data determine the base parameters badly "
                         f"(condition number {condition:.3g} of the scaled regressor): use an "
                         "exciting motion (planar-sym excite) or more of it")
    cov = s2 * np.linalg.inv(ww.T @ ww)
    notes = tuple(dict.fromkeys(n for ex in experiments for n in ex.notes))
    return Estimate(base, beta, np.sqrt(np.diag(cov)), sigma,
                    tuple(robot.coordinates[c] for c in coords), condition,
                    sum(len(ex) for ex in experiments), notes, np.linalg.norm(tau) / scale)


def predicted_torques(robot: Robot, estimate: Estimate, ex: Experiment) -> np.ndarray:
    """The actuated torques (N, actuated) the estimate gives along ``ex``'s motion (N*m)."""
    reg = regressor(robot, ex.q, ex.qd, ex.qdd, ex.t_s)
    tau = reg.y[..., list(estimate.base.kept)] @ estimate.values
    return tau[:, [reg.rows.index(i) for i in robot.actuated]]
