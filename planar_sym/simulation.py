"""Forward dynamics: integrate M(q) qdd + h(q, qd) = tau with error control.

Methods:

* ``"dopri5"`` (default): adaptive Dormand-Prince 5(4) written in C (planar_sym/_integrate.c),
  calling the compiled forward dynamics with no Python per step; steps land exactly on the
  requested output times. For zero or constant torques.
* any SciPy ``solve_ivp`` method (``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``)
  on the compiled ``qdd = M^-1 (tau - h)``; Radau/BDF/LSODA get the compiled Jacobian. A torque
  that is a function of time always goes this way (DOP853 unless told otherwise).

Closed chains are in ``planar_sym.closed_chain``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .dynamics import Robot, as_samples
from .errors import InputError, SimulationError
from .library import SingleCall, integrator

Torque = None | float | np.ndarray | Callable[[float], np.ndarray]
SCIPY_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")


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
    try:
        const = np.broadcast_to(np.asarray(torque, dtype=float), (n,)).copy()
    except (TypeError, ValueError) as exc:
        raise InputError(f"torque must be None, {n} numbers (N*m) or a function of time "
                         f"(got {torque!r}: {exc})") from None
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
             method: str = "dopri5", max_steps: int = 10_000_000) -> Simulation:
    """Integrate a robot from (q0 rad, qd0 rad/s) over ``t_span`` (s) under ``torque`` (N*m).

    ``torque``: None (zero), a constant (n,) vector, or a function of time returning (n,);
    for a closed chain, torques of the actuated joints and ``q0`` the full coordinates.
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
    if method == "dopri5" and not callable(torque):
        fd = robot.library.address("forward_dynamics")
        y, n_rhs = dopri5(robot, 0, fd, x0, t, tau_of(t[0]), rtol, atol, max_steps)
        q, qd = y[:, :n].copy(), y[:, n:].copy()
        kin, pot = robot.energy(q, qd)
        return Simulation(t, q, qd, np.tile(tau_of(t[0]), (len(t), 1)), kin, pot, method,
                          rtol, atol, n_rhs)
    method = "DOP853" if method == "dopri5" else method
    if method not in SCIPY_METHODS:
        raise InputError(f"unknown method {method!r}; known: dopri5, {', '.join(SCIPY_METHODS)}")
    fd = SingleCall(robot.library.functions["forward_dynamics"], robot.p)
    count, last_t = [0], [t[0]]

    def rhs(tt, x):
        count[0] += 1
        last_t[0] = tt
        (qdd,) = fd(x[:n], x[n:], tau_of(tt))
        if not np.all(np.isfinite(qdd)):  # else SciPy shrinks its step for ever
            raise SimulationError(f"{robot.name}: accelerations became {qdd.tolist()} at "
                                  f"t = {tt:.6g} s (state {x.tolist()})")
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
        raise SimulationError(f"{robot.name}: integration failed at t = {last_t[0]:.6g} s: "
                              f"{sol.message}")
    q, qd = sol.y[:n].T.copy(), sol.y[n:].T.copy()
    kin, pot = robot.energy(q, qd)
    taus = np.array([tau_of(tt) for tt in t])
    return Simulation(t, q, qd, taus, kin, pot, method, rtol, atol, count[0])


_DOPRI5_ERRORS = {1: "the right-hand side failed (singular mass or KKT matrix?)",
                  2: "the step size fell below 1e-14 s: the problem is stiff or singular here",
                  3: "too many steps (raise max_steps or loosen the tolerances)",
                  4: "the robot is too large for the built-in integrator (32 coordinates)"}


def dopri5(robot: Robot, kind: int, fn: int, y0: np.ndarray, t: np.ndarray, tau: np.ndarray,
           rtol: float, atol: float, max_steps: int, act: np.ndarray | None = None):
    """The C integrator: states (len(t), 2n) at ``t`` and the number of RHS evaluations.

    kind 0: tree (``fn`` = forward_dynamics batch); kind 1: closed chain (``fn`` =
    constrained_terms batch, ``tau`` on the actuated coordinates ``act``).
    """
    import ctypes

    if not (rtol > 0 and atol > 0):
        raise InputError(f"tolerances must be positive (rtol {rtol}, atol {atol})")
    n, m = robot.n, robot.n_constraints if kind == 1 else 0
    y0 = np.ascontiguousarray(y0, dtype=float)
    t = np.ascontiguousarray(t, dtype=float)
    tau = np.ascontiguousarray(tau, dtype=float)
    act_arr = np.ascontiguousarray(act if act is not None else [], dtype=np.intc)
    out = np.empty((len(t), 2 * n))
    stats = np.zeros(3, dtype=np.int64)
    t_fail = ctypes.c_double()
    rc = integrator()(kind, n, m, len(act_arr), act_arr.ctypes.data, tau.ctypes.data,
                      robot.p.ctypes.data, fn, float(t[0]), y0.ctypes.data, len(t),
                      t.ctypes.data, rtol, atol, max_steps, out.ctypes.data, stats.ctypes.data,
                      ctypes.byref(t_fail))
    if rc:
        raise SimulationError(f"{robot.name}: integration failed at t = {t_fail.value:.6g} s: "
                              f"{_DOPRI5_ERRORS.get(rc, rc)}")
    return out, int(stats[0])
