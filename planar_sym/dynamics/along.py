"""Everything inverse dynamics says along one joint motion, in one typed value: the actuated
torques, the cut-joint forces of a closed chain, every joint's load, the torque split, the
power and what each actuator must deliver. The API gets it from ``inverse_along`` in one call
(each quantity computed once, from the same samples); ``inverse_series`` gives its typed series,
the columns a study writes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.arrays import as_samples
from ..model.loops import warn_near_singular
from ..model.robot import Robot
from .inverse import torque_split
from .reactions import JointLoads, load_series, loads_of_motion
from .series import Series
from .sizing import ActuatorSizing, size


@dataclass(frozen=True)
class InverseAlong:
    """Inverse dynamics along samples ``t_s`` (N,) of a joint motion (SI).

    Attributes
    ----------
    tau : ndarray, shape (N, actuated)
        The actuated joints' torques (N*m; N at a slider), ``robot.actuated`` order.
    cut_forces : ndarray, shape (N, 2 * loops), or None
        A closed chain's lambda (N, world x and y, on each cut joint's parent body); None for a
        tree.
    loads : JointLoads
        Every joint's force and couple (parent body on child body).
    split : dict of str to ndarray
        ``torque_split``: the parts of ``tau``, each (N, actuated) in N*m.
    sizing : tuple of ActuatorSizing
        Peaks, RMS, power, energy and limits exceeded, one per actuator.
    power_w : ndarray, shape (N, actuated)
        tau * qd at each actuated joint (W).
    loop_residual_m : float or None
        A closed chain's largest |Phi(q)| over the samples (m); None for a tree.
    """

    tau: np.ndarray
    cut_forces: np.ndarray | None
    loads: JointLoads
    split: dict
    sizing: tuple[ActuatorSizing, ...]
    power_w: np.ndarray
    loop_residual_m: float | None


def inverse_along(robot: Robot, t_s, q, qd, qdd) -> InverseAlong:
    """Inverse dynamics of ``robot`` along the samples ``t_s`` (N,) in s of the motion ``q``,
    ``qd``, ``qdd`` (N, n: every coordinate, rad or m; on the loops for a closed chain); a
    sample off the loops or at a singular pose is refused by its time."""
    n_samples = len(np.atleast_2d(q))  # (q itself is checked by the inverse dynamics below)
    try:
        t = np.asarray(t_s, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"t_s must be an array of numbers, one time (s) per sample: {exc}"
                         ) from None
    if t.ndim != 1 or len(t) != n_samples:
        raise InputError(f"t_s has shape {t.shape}: one time (s) for each of the {n_samples} "
                         "samples of q")
    t = as_samples("t_s", t[:, None], 1)[:, 0]  # finite, or the sample is named
    # the torques first: they refuse a sample off the loops or at a singular pose by its time,
    # so the loads and the split below see checked samples (and reuse these torques)
    if robot.is_closed_chain:
        tau, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd, t=t)
        residual = float(np.max(np.abs(robot.constraint(q))))
        jac = robot.constraint_jacobian(q).reshape(len(t), robot.n_constraints, robot.n)
        warn_near_singular(robot.name, np.linalg.cond(jac[:, :, list(robot.passive)], 1), t)
    else:  # a tree with a passive joint is refused here: its torques are not unique
        tau, lam, residual = robot.inverse_dynamics(q, qd, qdd), None, None
    # the links' motion from the same checked samples, in the same pass through the model:
    # every joint's load follows from it and the torques
    q, qd, qdd = (as_samples(k, a, robot.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                  ("qdd", qdd)))
    motion = robot.body_motion(q, qd, qdd)
    loads = loads_of_motion(robot, qdd, tau, lam, motion)
    act = list(robot.actuated)
    return InverseAlong(tau=tau, cut_forces=lam, loads=loads,
                        split=torque_split(robot, q, qd, qdd, t=t),
                        sizing=size(robot, t, qd, tau),
                        power_w=tau * np.asarray(qd)[:, act],
                        loop_residual_m=residual)


def inverse_series(robot: Robot, inv: InverseAlong) -> list[Series]:
    """``inv`` as typed series, in the order a study's columns have them: the torque ``tau``
    (N*m; N at a slider) of each actuated coordinate; a closed chain's cut-joint forces ``fx``,
    ``fy`` (N, world axes, on the cut joint's parent body) of each loop; every joint's load
    (``reactions.load_series``: a joint with an actuator model shows its link-side couple);
    the power ``p`` (W) each actuator delivers. Each series has shape (N,)."""
    units = robot.coordinate_units
    data = [Series.of_coordinate("tau", i, units[i], inv.tau[:, k])
            for k, i in enumerate(robot.actuated)]
    for k, loop in enumerate(robot.loops):
        data += [Series("fx", "N", inv.cut_forces[:, 2 * k], joint=loop),
                 Series("fy", "N", inv.cut_forces[:, 2 * k + 1], joint=loop)]
    data += load_series(inv.loads, {d.joint for d in robot.drive_train.drives if d.modelled})
    return data + [Series("p", "W", inv.power_w[:, k], index=i)
                   for k, i in enumerate(robot.actuated)]
