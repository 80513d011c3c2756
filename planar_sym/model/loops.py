"""A closed chain's states checked against its loops: off the constraints, or at a pose where
the passive joints are not determined (a singular Phi_p), a sample is refused and named.

.. code:: text

    |Phi|                  <= LOOP_TOL_M                              (m)
    |Phi_q qd|             <= LOOP_TOL_M (1 + max|qd|)                (m/s)
    |Phi_q qdd - gamma|    <= LOOP_TOL_M (1 + max|qd|^2 + max|qdd|)   (m/s^2)
    cond_1(Phi_p)          <= COND_LIMIT

(rates in rad/s, accelerations in rad/s^2: the allowance grows with the terms' size)
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, WorkspaceError
from .arrays import when

#: a Jacobian whose condition number exceeds this is called singular. Near a singularity the
#: condition number grows like 1 / distance, and joint rates and torques with it: at 1e6 they
#: are already about a million times their size at a well-conditioned pose.
COND_LIMIT = 1e6

#: below the refusal, a condition number above this is warned about (``warn_near_singular``):
#: the results are still the model's, but forces there are about this many times their size
#: at a well-conditioned pose, so any error in the geometry or the motion is amplified as much
COND_WARN = 1e3

#: a closed chain's state is on its loops when its residuals stay within this (m; see
#: check_on_loops): Newton closes them to 1e-13 m, the seed's closed forms to 1e-16 m
LOOP_TOL_M = 1e-9


def refuse_singular(robot_name: str, cond: np.ndarray, t=None) -> None:
    """Refuse the first sample whose passive-joint constraint Jacobian Phi_p has a 1-norm
    condition number ``cond`` (N,) above COND_LIMIT (or not finite), naming it (and its time,
    from ``t`` (N,) in s): WorkspaceError."""
    bad = ~np.isfinite(cond) | (cond > COND_LIMIT)
    if bad.any():
        k = int(np.argmax(bad))
        raise WorkspaceError(f"{robot_name}: singular pose at {when(t, k)}: the passive-joint "
                             f"constraint Jacobian Phi_p (which the actuation matrix "
                             f"[S^T Phi_q^T] needs) has 1-norm condition number "
                             f"{cond[k]:.3g} > {COND_LIMIT:g}")


def warn_near_singular(robot_name: str, cond: np.ndarray, t=None) -> None:
    """A RuntimeWarning naming the first sample whose Phi_p 1-norm condition number ``cond``
    (N,) is above COND_WARN (and the largest), once per call; nothing below it."""
    near = cond > COND_WARN
    if not near.any():
        return
    k, worst = int(np.argmax(near)), int(np.argmax(cond))
    warnings.warn(f"{robot_name}: near a singular pose from {when(t, k)}: the passive-joint "
                  f"constraint Jacobian Phi_p has 1-norm condition number {cond[k]:.3g} "
                  f"(largest {cond[worst]:.3g}, at {when(t, worst)}; refused above "
                  f"{COND_LIMIT:g}). Forces there grow like 1 / the distance to the singular "
                  "pose, and so does any error in the geometry or the motion: keep the motion "
                  "farther from it, or check the forces against the mechanism's strength",
                  RuntimeWarning, stacklevel=3)


def refuse_singular_matrices(robot_name: str, mats: np.ndarray, what: str, t=None) -> None:
    """Refuse the first of ``mats`` (N, m, m) whose 2-norm condition number is above
    COND_LIMIT (or not finite), naming ``what`` it is and the sample (its time from ``t`` (N,)
    in s): WorkspaceError."""
    cond = np.linalg.cond(mats)
    bad = ~np.isfinite(cond) | (cond > COND_LIMIT)
    if bad.any():
        k = int(np.argmax(bad))
        raise WorkspaceError(f"{robot_name}: singular pose at {when(t, k)}: the {what} has "
                             f"condition number {cond[k]:.3g} > {COND_LIMIT:g}")


def check_on_loops(robot_name: str, loops: tuple[str, ...], phi, phi_v, phi_a, qd, qdd,
                   t=None) -> None:
    """Refuse samples off the loop constraints (the module's limits), naming the first, its
    residual and the cut joint (``loops``, one name per loop): InputError.

    ``phi``, ``phi_v``, ``phi_a`` (N, 2 * loops) are Phi (m), Phi_q qd (m/s) and
    Phi_q qdd - gamma (m/s^2); ``qd``, ``qdd`` (N, n) scale the allowances; ``t`` (N,) in s
    names the time.
    """
    if all(r.size == 0 or max(r.max(), -r.min()) <= LOOP_TOL_M for r in (phi, phi_v, phi_a)):
        return  # every sample within the smallest allowance: one pass per array, no rows
    speed = np.max(np.abs(qd), axis=1)
    limits = {"Phi (m)": (phi, LOOP_TOL_M * np.ones(len(phi))),
              "Phi_q qd (m/s)": (phi_v, LOOP_TOL_M * (1 + speed)),
              "Phi_q qdd - gamma (m/s^2)": (
                  phi_a, LOOP_TOL_M * (1 + speed**2 + np.max(np.abs(qdd), axis=1)))}
    for what, (residual, limit) in limits.items():
        worst = np.max(np.abs(residual), axis=1)
        bad = ~(worst <= limit)
        if bad.any():
            k = int(np.argmax(bad))
            cut = loops[int(np.argmax(np.abs(residual[k]))) // 2]
            raise InputError(
                f"{robot_name}: sample {k}{f' (t = {t[k]:.6g} s)' if t is not None else ''} "
                f"is off the loop constraints: |{what.split(' (')[0]}| = {worst[k]:.3g} "
                f"{what.split('(')[1][:-1]} at cut joint {cut} (limit {limit[k]:.3g}); "
                "give q, qd, qdd that close the loops (inverse_kinematics, from_actuated)")
