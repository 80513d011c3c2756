"""Forward dynamics: integrate M(q) qdd + h(q, qd) = tau with error control.

Serial (tree) robots: SciPy's ``solve_ivp`` (DOP853 by default; Radau/BDF get the compiled
Jacobian of the right-hand side) on the compiled ``qdd = M^-1 (tau - h)``, dense output at the
requested times. Closed chains are in ``planar_sym.closed_chain``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from .dynamics import Robot, as_samples
from .errors import InputError, SimulationError
from .library import SingleCall

Torque = None | float | np.ndarray | Callable[[float], np.ndarray]


@dataclass(frozen=True)
class Simulation:
    """A forward-dynamics run: arrays of shape (N, n) at times ``t_s``; energies (J) per sample."""

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    kinetic_j: np.ndarray
    potential_j: np.ndarray
    method: str
    rtol: float
    atol: float
    n_rhs: int
    constraint_drift_m: float = 0.0  # max |Phi| over the run (closed chains)

    @property
    def energy_j(self) -> np.ndarray:
        return self.kinetic_j + self.potential_j

    @property
    def energy_drift(self) -> float:
        """max |E(t) - E(0)| / max(|E(0)|, E scale) over the run."""
        e = self.energy_j
        scale = max(abs(e[0]), np.max(np.abs(self.kinetic_j)), 1e-300)
        return float(np.max(np.abs(e - e[0])) / scale)


def torque_function(torque: Torque, n: int) -> Callable[[float], np.ndarray]:
    """Zero, a constant vector, or a function of time (s) returning (n,) torques in N*m."""
    if torque is None:
        zero = np.zeros(n)
        return lambda t: zero
    if callable(torque):
        def checked(t: float) -> np.ndarray:
            tau = np.asarray(torque(t), dtype=float)
            if tau.shape != (n,) or not np.all(np.isfinite(tau)):
                raise InputError(f"torque function returned {tau!r} at t = {t:.6g} s; "
                                 f"expected {n} finite values (N*m)")
            return tau
        return checked
    const = np.broadcast_to(np.asarray(torque, dtype=float), (n,)).copy()
    if not np.all(np.isfinite(const)):
        raise InputError(f"torque must be finite (got {const.tolist()})")
    return lambda t: const


def time_grid(t_span: tuple[float, float], t_eval) -> np.ndarray:
    t0, t1 = float(t_span[0]), float(t_span[1])
    if not (np.isfinite(t0) and np.isfinite(t1) and t1 > t0):
        raise InputError(f"time span must be finite with end > start (got {t_span})")
    if t_eval is None:
        return np.linspace(t0, t1, 1001)
    t = np.asarray(t_eval, dtype=float)
    if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0) or t[0] < t0 or t[-1] > t1:
        raise InputError(f"t_eval must be increasing times inside {t_span}")
    return t


def simulate(robot: Robot, q0, qd0, t_span: tuple[float, float], *, torque: Torque = None,
             t_eval=None, rtol: float = 1e-11, atol: float = 1e-12,
             method: str = "DOP853") -> Simulation:
    """Integrate a serial robot from (q0 rad, qd0 rad/s) over ``t_span`` (s) under ``torque``.

    Returns the state at ``t_eval`` (default: 1001 evenly spaced times), with energies.
    """
    if robot.is_closed_chain:
        from .closed_chain import simulate_closed
        return simulate_closed(robot, q0, qd0, t_span, torque=torque, t_eval=t_eval,
                               rtol=rtol, atol=atol, method=method)
    n = robot.n
    x0 = np.concatenate([as_samples("q0", q0, n)[0], as_samples("qd0", qd0, n)[0]])
    t = time_grid(t_span, t_eval)
    tau_of = torque_function(torque, n)
    fd = SingleCall(robot.library.functions["forward_dynamics"], robot.p)
    count = [0]

    def rhs(tt, x):
        count[0] += 1
        (qdd,) = fd(x[:n], x[n:], tau_of(tt))
        return np.concatenate([x[n:], qdd])

    jac = None
    if method in ("Radau", "BDF", "LSODA"):
        fj = SingleCall(robot.library.functions["forward_dynamics_jacobian"], robot.p)

        def jac(tt, x):
            dq, dqd = fj(x[:n], x[n:], tau_of(tt))
            top = np.hstack([np.zeros((n, n)), np.eye(n)])
            return np.vstack([top, np.hstack([dq.reshape(n, n).T, dqd.reshape(n, n).T])])

    extra = {"jac": jac} if jac is not None else {}
    sol = solve_ivp(rhs, (t[0], t[-1]), x0, method=method, t_eval=t, rtol=rtol, atol=atol,
                    **extra)
    if not sol.success:
        t_fail = sol.t[-1] if sol.t.size else t[0]
        raise SimulationError(f"{robot.name}: integration failed at t = {t_fail:.6g} s: "
                              f"{sol.message}")
    q, qd = sol.y[:n].T.copy(), sol.y[n:].T.copy()
    kin, pot = robot.energy(q, qd)
    taus = np.array([tau_of(tt) for tt in t])
    return Simulation(t, q, qd, taus, kin, pot, method, rtol, atol, count[0])
