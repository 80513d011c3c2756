"""Time-varying LQR along a motion (a swing-up, an optimal move), then LQR about its end:
the law that makes an open-loop plan work on a plant that starts off it or differs from it.

Along the motion ``x_r(t) = (q_r, qd_r)`` with its torques ``u_r(t)`` the robot is linearised
at every sample (``dynamics.linearize``: ``A_k``, ``B_k``; linear in between), and the
Riccati differential equation is integrated backwards from the end, where ``P(T)`` is the
LQR solution about the end state (which must be an equilibrium at rest):

.. code:: text

    -dP/dt = A^T P + P A - P B R^-1 B^T P + Q,   P(T) = P_lqr(x_r(T))
    K(t) = R^-1 B(t)^T P(t),   u = u_r(t) + K(t) (x_r(t) - x)

After the motion's end the law is the LQR about the end (K(T) is its gain: the same P, the
same A and B up to the end torques). The compiled loop runs it as controller "lqr" with a
schedule (``dynamics.laws``), K linear between samples, x_r and u_r by ``reference``:

* ``"spline"`` (default): q_r and u_r C2 cubic splines through the samples (q_r clamped to the
  motion's end rates), qd_r the derivative of q_r. An optimal plan's accelerations are constant
  per interval and alternate about the true ones (its passive joints are free only on average
  over each interval), so its rates have a kink at every node; fed back through K they made a
  saw-tooth of the interval's period in the force (the cart-pole swing-up: 0.085 N in the second
  difference at 10 ms, its 0.2 N limit passed by 0.0022 N on the nominal plant; 0.009 N and
  within the limit with splines, tracking errors unchanged).
* ``"hermite"``: the motion itself between samples, a cubic Hermite through (q, qd) (exact
  for a piecewise-quadratic plan), u_r linear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..dynamics.laws import Controller
from ..dynamics.linearize import linearize
from ..errors import InputError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from ..motion.signals import Signal
from .lqr import LQR, lqr

#: the Riccati equation's tolerances (relative, absolute on P's entries)
RTOL, ATOL = 1e-8, 1e-10


@dataclass(frozen=True)
class TVLQR:
    """``t_s`` (N,) the motion's sample times (s); ``gain`` (N, actuated, 2k) K(t) there and
    ``riccati`` (N, 2k, 2k) P(t), k the coordinates of the state (``hold.linearization``);
    ``motion`` and ``tau`` (N, actuated) N*m (N) the plan it tracks; ``hold`` the LQR about
    the end, the law after it; ``reference`` how x_r and u_r run between the samples
    (``"spline"`` or ``"hermite"``, see the module's note)."""

    t_s: np.ndarray
    gain: np.ndarray
    riccati: np.ndarray
    motion: JointTrajectory
    tau: np.ndarray
    hold: LQR
    reference: str = "spline"

    def controller(self, saturate: bool = True) -> Controller:
        """The law for ``simulate_controlled`` (no reference: the schedule carries it)."""
        return Controller("lqr", saturate=bool(saturate), schedule=self.schedule())

    def schedule(self) -> Signal:
        """x_r (2n), u_r (actuated) and K (actuated x 2n, row-major, zero on a closed chain's
        passive coordinates) as one Signal; after the end, constant: the hold's."""
        jt, n = self.motion, len(self.motion.q[0])
        na = self.tau.shape[1]
        cols = list(self.hold.linearization.coordinates)
        t, h = jt.t_s, np.diff(jt.t_s)[:, None]
        nseg = len(t) - 1
        coef = np.zeros((nseg + 1, 2 * n + na + 2 * n * na, 4))
        if self.reference == "spline":  # (two samples: the same cubic as Hermite's)
            from scipy.interpolate import CubicSpline

            c = CubicSpline(t, jt.q, bc_type=((1, jt.qd[0]), (1, jt.qd[-1]))).c[::-1]
            coef[:nseg, :n] = np.moveaxis(c, 0, -1)  # (4, nseg, n), rising powers
            coef[:nseg, n:2 * n, :3] = np.moveaxis(c[1:] * [[[1]], [[2]], [[3]]], 0, -1)
            cu = CubicSpline(t, self.tau).c[::-1]
            coef[:nseg, 2 * n:2 * n + na] = np.moveaxis(cu, 0, -1)
        else:
            q0, q1, v0, v1 = jt.q[:-1], jt.q[1:], jt.qd[:-1], jt.qd[1:]
            # cubic Hermite through (q, qd) at both ends (exact for a piecewise-quadratic plan)
            c2 = (3 * (q1 - q0) / h - 2 * v0 - v1) / h
            c3 = (2 * (q0 - q1) / h + v0 + v1) / h**2
            coef[:nseg, :n] = np.stack([q0, v0, c2, c3], axis=-1)
            coef[:nseg, n:2 * n] = np.stack([v0, 2 * c2, 3 * c3, 0 * c3], axis=-1)
            du = np.diff(self.tau, axis=0) / h
            coef[:nseg, 2 * n:2 * n + na, 0] = self.tau[:-1]
            coef[:nseg, 2 * n:2 * n + na, 1] = du
        full = spread(self.gain, n, cols)  # (N, na, 2n)
        flat = full.reshape(len(t), -1)
        coef[:nseg, 2 * n + na:, 0] = flat[:-1]
        coef[:nseg, 2 * n + na:, 1] = np.diff(flat, axis=0) / h
        hold = self.hold.controller()
        coef[nseg, :, 0] = np.concatenate([hold.x_ref, hold.u_ref, hold.gain])
        return Signal(np.append(t, t[-1] + 1.0), coef)


def spread(gain: np.ndarray, n: int, cols: list[int]) -> np.ndarray:
    """Gains, shape (..., actuated, 2k) over the state's k coordinates ``cols``, as gains over
    every coordinate, shape (..., actuated, 2n), zero on the others (SI: N*m per rad and per
    rad/s; N per m and per m/s at a slider)."""
    k = len(cols)
    out = np.zeros(gain.shape[:-1] + (2 * n,))
    out[..., cols] = gain[..., :k]
    out[..., [n + c for c in cols]] = gain[..., k:]
    return out


REFERENCES = ("spline", "hermite")


def tvlqr(robot: Robot, motion: JointTrajectory, tau=None, *, q_weight, r_weight,
          reference: str = "spline") -> TVLQR:
    """The time-varying LQR of ``robot`` along ``motion`` (every coordinate's samples; it must
    end at rest in an equilibrium) with the torques ``tau`` (N, actuated) N*m (N) that make
    it (default: the inverse dynamics along it, for a robot whose every joint is actuated or
    set by the loops), then the LQR about its end. Weights as ``lqr`` (SI, per unit of the state: rad^2,
    (rad/s)^2, m^2...; per (N*m)^2 on the torques). ``reference``: how x_r and u_r run between
    the samples, ``"spline"`` or ``"hermite"`` (see the module's note).

    Raises InputError for samples that do not match, weights of the wrong shape, or an end
    that is not a held equilibrium.
    """
    from scipy.integrate import solve_ivp

    if reference not in REFERENCES:
        raise InputError(f"reference must be one of {', '.join(map(repr, REFERENCES))} "
                         f"(got {reference!r})")
    if not isinstance(motion, JointTrajectory):
        raise InputError(f"motion must be a JointTrajectory (got {type(motion).__name__})")
    t = np.asarray(motion.t_s, dtype=float)
    na = len(robot.actuated)
    if tau is not None:
        tau = np.asarray(tau, dtype=float)
        if tau.shape != (len(t), na) or not np.all(np.isfinite(tau)):
            raise InputError(f"tau must be finite, shape ({len(t)}, {na}): one row per sample "
                             f"of the motion, one column per actuated joint (got {tau.shape})")
    if len(t) < 2 or np.any(np.diff(t) <= 0):
        raise InputError("the motion's times must increase (at least 2 samples)")
    try:
        hold = lqr(robot, motion.q[-1], np.zeros(robot.n), q_weight=q_weight,
                   r_weight=r_weight)
    except InputError as exc:
        raise InputError(f"the motion's end: {exc}") from None
    moving = float(np.abs(motion.qd[-1]).max())
    if moving > 1e-6:
        raise InputError(f"the motion ends moving (|qd| {moving:.3g} per s): the law holds its "
                         "end, which must be at rest")
    if tau is None:  # the torques that make the motion: its inverse dynamics
        from ..dynamics.along import inverse_along

        tau = inverse_along(robot, motion.t_s, motion.q, motion.qd, motion.qdd).tau
    lins = [linearize(robot, q, qd, u) for q, qd, u in zip(motion.q, motion.qd, tau)]
    a, b = np.stack([x.a for x in lins]), np.stack([x.b for x in lins])
    k2 = a.shape[1]
    qm, rm = hold.q_weight, hold.r_weight  # checked by lqr, for this state and these motors
    r_inv = np.linalg.inv(rm)

    def ab(s: float):
        i = int(np.clip(np.searchsorted(t, s, side="right") - 1, 0, len(t) - 2))
        w = (s - t[i]) / (t[i + 1] - t[i])
        return (1 - w) * a[i] + w * a[i + 1], (1 - w) * b[i] + w * b[i + 1]

    def rhs(s, p_flat):
        p = p_flat.reshape(k2, k2)
        aa, bb = ab(s)
        pb = p @ bb
        dp = -(aa.T @ p + p @ aa - pb @ r_inv @ pb.T + qm)
        return ((dp + dp.T) / 2).ravel()  # P stays symmetric

    sol = solve_ivp(rhs, (t[-1], t[0]), hold.riccati.ravel(), t_eval=t[::-1], rtol=RTOL,
                    atol=ATOL, method="RK45")
    if not sol.success:
        raise InputError(f"{robot.name}: the Riccati equation along the motion could not be "
                         f"integrated ({sol.message})")
    p = sol.y.T[::-1].reshape(len(t), k2, k2)
    gain = np.einsum("ij,njk,nkl->nil", r_inv, b.transpose(0, 2, 1), p)
    return TVLQR(t, gain, p, motion, tau, hold, reference)
