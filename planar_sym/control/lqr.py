"""LQR about an equilibrium: the gain K that minimises the integral of
``dx^T Q dx + du^T R du`` for the linearised robot (``dynamics.linearize``), from SciPy's
continuous-time algebraic Riccati solver:

.. code:: text

    A^T P + P A - P B R^-1 B^T P + Q = 0,   K = R^-1 B^T P,   u = u_ref + K (x_ref - x)

``x = (q, qd)`` holds every coordinate of a tree, passive ones included, so an underactuated
robot (a cart-pole's free pole) is stabilised through its motors; a closed chain's holds its
actuated coordinates (the loops set the others). The law runs in the compiled loop
(``simulate_controlled``, controller kind "lqr").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..dynamics.laws import Controller
from ..dynamics.linearize import Linearization, linearize
from ..errors import InputError, warn_caller
from ..model.robot import Robot


@dataclass(frozen=True)
class LQR:
    """``gain`` K (actuated, 2n): N*m per rad and per rad/s (N per m, per m/s at a slider);
    ``riccati`` P (2n, 2n); ``poles`` (2n,) of A - B K in 1/s, each with a negative real part;
    ``linearization`` the model it was designed on; ``q_weight`` Q (2n, 2n) and ``r_weight``
    R (actuated, actuated), the weights it was designed with, as matrices (checked, SI)."""

    gain: np.ndarray
    riccati: np.ndarray
    poles: np.ndarray
    linearization: Linearization
    q_weight: np.ndarray | None = None
    r_weight: np.ndarray | None = None

    def controller(self, saturate: bool = True) -> Controller:
        """The law for ``simulate_controlled``: tau = u_ref + K (x_ref - x), clipped at the
        description's actuator limits when ``saturate``."""
        lin = self.linearization
        n, cols = len(lin.q), list(lin.coordinates)
        gain = np.zeros((self.gain.shape[0], 2 * n))  # over every coordinate: a closed
        gain[:, cols] = self.gain[:, :len(cols)]      # chain's passive ones get no feedback
        gain[:, [n + c for c in cols]] = self.gain[:, len(cols):]
        return Controller("lqr", saturate=bool(saturate), gain=tuple(gain.ravel().tolist()),
                          x_ref=tuple(np.concatenate([lin.q, lin.qd]).tolist()),
                          u_ref=tuple(lin.tau.tolist()))


#: Coulomb friction's slope at the state, over the joint's viscous friction, past which the
#: design is said to lean on it
COULOMB_DAMPING_RATIO = 10.0


def lqr(robot: Robot, q, qd=None, tau=None, *, q_weight, r_weight) -> LQR:
    """The LQR gain of ``robot`` about ``q`` (n,) rad (m at a slider), ``qd`` (default zero)
    and ``tau`` (default: the torques that hold it; see ``linearize``).

    ``q_weight``: (2n,) diagonal or (2n, 2n) symmetric positive semi-definite weight on the
    state error (per rad^2, per (rad/s)^2...); ``r_weight``: (actuated,) or square, positive
    definite, on the torques (per (N*m)^2). Raises InputError for weights of the wrong shape
    or sign, a state that is not an equilibrium, or a linearisation no gain can stabilise.
    """
    from scipy.linalg import solve_continuous_are

    # the weights checked first, against the state linearize gives: every coordinate of a
    # tree, a closed chain's actuated ones (the loops set the others)
    na = len(robot.actuated)
    held = na if robot.is_closed_chain else robot.n
    qm = _weight("q_weight", q_weight, 2 * held, definite=False)
    rm = _weight("r_weight", r_weight, na, definite=True)
    lin = linearize(robot, q, qd, tau)
    # at rest the smoothed Coulomb friction c tanh(qd / v_s) linearises to a damping c / v_s
    # that holds only below v_s (0.01 rad/s by default): a trial's geared arm got 20 N*m*s/rad
    # against 0.05 of viscous friction, rate gains 10 times lower, and no word
    drives = robot.drive_train
    slope = drives.coulomb_slope(lin.qd)  # lin.qd: every coordinate, a drive's at its own
    leaning = [f"{d.joint} {slope[d.coordinate]:.3g} {d.unit}*s/{'m' if d.unit == 'N' else 'rad'} "
               f"(viscous {d.viscous:.3g})" for d in drives.drives
               if slope[d.coordinate] > COULOMB_DAMPING_RATIO * d.viscous]
    if leaning:
        warn_caller(f"{robot.name}: the linearisation counts smoothed Coulomb friction as "
                    f"damping: {'; '.join(leaning)}, a slope that holds only within the "
                    "smoothing speed of rest: the gains lean on it. To design without it, "
                    "linearise robot.with_parameters(fc_<joint>=0)")
    scale = max(float(np.abs(lin.a).max()), 1.0)
    if np.abs(lin.qdd).max() > 1e-9 * scale:
        raise InputError(f"{robot.name}: not an equilibrium (qdd = {lin.qdd.tolist()} there): "
                         "LQR holds a state that stays put; give the torques that hold it "
                         "(tau) or another q")
    try:
        p = solve_continuous_are(lin.a, lin.b, qm, rm)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise InputError(f"{robot.name}: no stabilising LQR gain at this state ({exc}): the "
                         "motors cannot reach an unstable motion, or q_weight leaves an "
                         "unstable motion unweighted") from None
    k = np.linalg.solve(rm, lin.b.T @ p)
    poles = np.linalg.eigvals(lin.a - lin.b @ k)
    if not np.all(poles.real < 0):
        raise InputError(f"{robot.name}: the LQR loop is not stable (poles {poles}): weight "
                         "every state that can drift (q_weight)")
    return LQR(k, p, poles, lin, qm, rm)


def _weight(name: str, w, size: int, definite: bool) -> np.ndarray:
    try:
        arr = np.asarray(w, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers: {size} (a diagonal) or {size}x{size}, "
                         f"got {w!r}") from None
    if arr.ndim == 0 or arr.shape == (size,):
        arr = np.diag(np.broadcast_to(arr, (size,)))
    if arr.shape != (size, size):
        raise InputError(f"{name} must have {size} values (a diagonal) or shape "
                         f"({size}, {size}), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)) or np.abs(arr - arr.T).max() > 1e-12 * max(
            np.abs(arr).max(), 1e-300):
        raise InputError(f"{name} must be finite and symmetric")
    low = float(np.linalg.eigvalsh(arr).min())
    if low < 0 or (definite and low <= 0):
        raise InputError(f"{name} must be positive {'definite' if definite else 'semi-definite'}"
                         f" (smallest eigenvalue {low:.3g})")
    return arr
