"""Forward dynamics of a closed chain, on the constraint manifold (index reduction with
projection; see ``simulate_closed``)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError, SimulationError
from ..model.arrays import as_state
from ..model.library import SingleCall
from ..model.robot import Robot
from ..motion.closure import complete_state
from ..motion.continuation import NEWTON_MAX_ITER, NEWTON_TOL_M
from .integrate import (
    SCIPY_METHODS,
    Simulation,
    dopri5,
    time_grid,
    torque_function,
)


def closure_tol(q: np.ndarray, jac: np.ndarray) -> float:
    """The residual (m) a projection stops below: ``NEWTON_TOL_M``, or where larger what the
    angles themselves hold: an angle is stored to its float spacing (9e-13 rad at 6000 rad, a
    crank after 1000 turns), which moves a link's end by that times its length (the
    Jacobian's entries, m/rad). A trial's long run failed there, |Phi| = 1.3e-13 m."""
    scale = float(np.max(np.abs(jac))) if jac.size else 0.0
    return max(NEWTON_TOL_M, 8.0 * float(np.spacing(np.max(np.abs(q)))) * scale)


def project(robot: Robot, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """Closest point on the manifold: Gauss-Newton on Phi(q) = 0, then Phi_q qd = 0 (min. norm)."""
    q, qd = np.array(q, dtype=float), np.array(qd, dtype=float)
    m, n = robot.n_constraints, robot.n
    for _ in range(NEWTON_MAX_ITER):
        phi = robot.constraint(q)
        jac = robot.constraint_jacobian(q).reshape(m, n)
        if np.max(np.abs(phi)) < closure_tol(q, jac):
            break
        q -= jac.T @ np.linalg.solve(jac @ jac.T, phi)
    else:
        raise SimulationError(f"{robot.name}: cannot project q = {q.tolist()} onto the loop "
                              f"constraints (|Phi| = {np.max(np.abs(phi)):.3g} m)")
    qd -= jac.T @ np.linalg.solve(jac @ jac.T, jac @ qd)
    return q, qd


#: what a state off the loops is told to do, by route
PROJECT_HINT = ("give a state on the loops (planar_sym.from_actuated), or pass project=True "
                "(planar_sym.simulate) to solve the passive joints from the actuated ones")
CONTROLLED_HINT = ("give a state on the loops (planar_sym.from_actuated), pass project=True "
                   "to solve the passive joints from the actuated ones, or leave q0 out to "
                   "start on the reference (off it: track's start_error, on the actuated "
                   "joints, keeps the loops closed)")


def start_state(robot: Robot, q0, qd0, project_state: bool = False,
                hint: str = PROJECT_HINT) -> tuple[np.ndarray, np.ndarray, float]:
    """A run's start, checked by one rule on every route (``forward.simulate``, its engine
    and its closed-chain segments, ``engine.simulate_controlled``): ``q0``, ``qd0`` (n,) in
    rad, rad/s, finite and of the robot's width; a closed chain's on its loops (``hint`` says
    what to do instead), or, with ``project_state``, its passive joints solved from the
    actuated ones. Returns the state and how far the passive joints were moved (rad; m at a
    slider; 0 for a tree)."""
    q0, qd0 = as_state(q0, qd0, robot.n)
    if not robot.is_closed_chain:
        return q0, qd0, 0.0
    if project_state:
        act = list(robot.actuated)
        q, qd = complete_state(robot, q0[act], qd0[act], q_guess=q0)
        return q, qd, float(np.max(np.abs(q - q0)))
    jac = robot.constraint_jacobian(q0).reshape(robot.n_constraints, robot.n)
    phi = robot.constraint(q0).reshape(1, -1)
    zero = np.zeros((1, robot.n_constraints))
    for label, rows in (("q0", (phi, zero, zero)), ("qd0", (zero, (jac @ qd0)[None], zero))):
        try:
            robot.check_on_loops(*rows, qd0[None], np.zeros((1, robot.n)))
        except InputError as exc:
            raise InputError(str(exc).replace("sample 0", label, 1).replace(
                "give q, qd, qdd that close the loops (inverse_kinematics, from_actuated)",
                hint)) from None
    return q0, qd0, 0.0


#: a closed chain is integrated in segments of this length (s), projected onto the loops
#: between them; a segment whose loops drift apart by more than DRIFT_LIMIT_M (m) is refused
SEGMENT_S = 0.1
DRIFT_LIMIT_M = 1e-6


def simulate_closed(robot: Robot, q0, qd0, t_span, *, torque=None, t_eval=None,
                    rtol: float = 1e-11, atol: float = 1e-12, method: str = "dopri5",
                    segment_s: float = SEGMENT_S, drift_limit_m: float = DRIFT_LIMIT_M,
                    project_state: bool = False):
    """Forward dynamics of a closed chain, on the constraint manifold.

    Method (index reduction with projection): the full state (q, qd) is integrated (the C
    Dormand-Prince 5(4) by default, or a SciPy method) with the accelerations of the index-1
    system

    .. code:: text

        [ M     -Phi_q^T ] [ qdd    ]   [ S^T tau - h ]
        [ Phi_q   0      ] [ lambda ] = [ gamma       ]

    and every ``segment_s`` the state is projected back onto Phi = 0, Phi_q qd = 0 (the
    integrator restarts there); a segment that drifts beyond ``drift_limit_m`` raises
    SimulationError naming the time. ``q0`` is the full coordinate vector and must be on the
    loops, and ``qd0`` consistent with them (``Robot.check_on_loops``), else InputError; with
    ``project_state=True`` the passive joints' angles and rates are solved from the actuated
    ones instead (never the actuated joints moved), and ``initial_correction_rad`` reports how
    far. ``torque`` acts on the actuated joints. The result reports ``constraint_drift_m``, the
    largest |Phi| at any output time.
    """
    q0, qd0, correction = start_state(robot, q0, qd0, project_state)
    return run_closed(robot, q0, qd0, time_grid(t_span, t_eval), torque=torque, rtol=rtol,
                      atol=atol, method=method, segment_s=segment_s,
                      drift_limit_m=drift_limit_m, correction=correction)


def run_closed(robot: Robot, q0: np.ndarray, qd0: np.ndarray, t: np.ndarray, *, torque,
               rtol: float, atol: float, method: str, segment_s: float, drift_limit_m: float,
               correction: float):
    """``simulate_closed`` on inputs checked already: ``q0``, ``qd0`` (n,) in rad, rad/s and
    the output times ``t`` (N,) in s (what ``forward.simulate``, the entry point, passes);
    every setting given by the caller (no defaults of its own to drift from theirs)."""
    from scipy.integrate import solve_ivp

    act = list(robot.actuated)
    n = robot.n
    q, qd = q0.copy(), qd0.copy()
    tau_of = torque_function(torque, len(act))
    if method not in ("dopri5", *SCIPY_METHODS):
        raise InputError(f"unknown method {method!r}; known: dopri5, {', '.join(SCIPY_METHODS)}")
    use_c = method == "dopri5" and not callable(torque)
    if method == "dopri5" and callable(torque):
        method = "DOP853"
    count, last_t = [0], [t[0]]
    # the C loop calls the compiled batch itself; SciPy calls a Python right-hand side
    fn = robot.library.address("constrained_terms") if use_c else 0
    rhs = None if use_c else _kkt_rhs(robot, tau_of, count, last_t)
    qs, qds = [q.copy()], [qd.copy()]
    k = 0
    while k < len(t) - 1:
        end = int(np.searchsorted(t, t[k] + segment_s, side="right")) - 1
        end = min(max(end, k + 1), len(t) - 1)
        if use_c:
            y, n_rhs = dopri5(robot, 1, fn, np.concatenate([q, qd]), t[k:end + 1],
                              tau_of(t[k]), rtol, atol, 10_000_000, act)
            count[0] += n_rhs
            ys = y.T
        else:
            sol = solve_ivp(rhs, (t[k], t[end]), np.concatenate([q, qd]), method=method,
                            t_eval=t[k:end + 1], rtol=rtol, atol=atol)
            if not sol.success:
                raise SimulationError(f"{robot.name}: integration failed at t = "
                                      f"{last_t[0]:.6g} s: {sol.message}")
            ys = sol.y
        qs += list(ys[:n, 1:].T)
        qds += list(ys[n:, 1:].T)
        seg_drift = np.max(np.abs(robot.constraint(ys[:n, 1:].T)))
        if not seg_drift <= drift_limit_m:  # NaN too
            raise SimulationError(
                f"{robot.name}: the loops drifted apart by {seg_drift:.3g} m between t = "
                f"{t[k]:.6g} s and {t[end]:.6g} s (limit {drift_limit_m:g} m): tighten rtol/atol "
                "or shorten segment_s; near a singular pose the constraints cannot hold")
        q, qd = project(robot, ys[:n, -1], ys[n:, -1])
        k = end
    qa, qda = np.array(qs), np.array(qds)
    drift = float(np.max(np.abs(robot.constraint(qa))))
    taus = np.array([tau_of(tt) for tt in t])
    return Simulation.of_robot(robot, t, qa, qda, taus, method, rtol, atol, count[0],
                               constraint_drift_m=drift, initial_correction_rad=correction)


def _kkt_rhs(robot: Robot, tau_of, count: list, last_t: list):
    """SciPy's right-hand side of the index-1 system (``simulate_closed``) at (t, [q, qd]):
    [qd, qdd], counting its calls in ``count`` and the last time in ``last_t``."""
    act = list(robot.actuated)
    n, m = robot.n, robot.n_constraints
    terms = SingleCall(robot.library.functions["constrained_terms"], robot.p)
    kkt = np.zeros((n + m, n + m))
    rhs_v = np.zeros(n + m)

    def rhs(tt, x):
        count[0] += 1
        last_t[0] = tt
        M, h, jac, gamma = terms(x[:n], x[n:])
        jac = jac.reshape(n, m).T
        kkt[:n, :n] = M.reshape(n, n)
        kkt[:n, n:] = -jac.T
        kkt[n:, :n] = jac
        rhs_v[:n] = -h
        rhs_v[act] += tau_of(tt)
        rhs_v[n:] = gamma
        qdd = np.linalg.solve(kkt, rhs_v)[:n]
        if not np.all(np.isfinite(qdd)):  # else SciPy shrinks its step for ever
            raise SimulationError(f"{robot.name}: accelerations became {qdd.tolist()} at "
                                  f"t = {tt:.6g} s")
        return np.concatenate([x[n:], qdd])
    return rhs


def kkt_accelerations(robot: Robot, q, qd, tau_act) -> np.ndarray:
    """Every coordinate's acceleration (N, n) of a closed chain at N states under the actuated
    torques ``tau_act`` (N, actuated): the index-1 KKT system of ``simulate_closed``, batched."""
    q, qd, tau_act = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (q, qd, tau_act))
    n_s, n, m = len(q), robot.n, robot.n_constraints
    kkt = np.zeros((n_s, n + m, n + m))
    jac = robot.constraint_jacobian(q).reshape(n_s, m, n)
    kkt[:, :n, :n] = robot.mass_matrix(q).reshape(n_s, n, n)
    kkt[:, :n, n:] = -jac.transpose(0, 2, 1)
    kkt[:, n:, :n] = jac
    rhs = np.zeros((n_s, n + m))
    rhs[:, :n] = -robot.bias(q, qd).reshape(n_s, n)
    rhs[:, list(robot.actuated)] += tau_act
    rhs[:, n:] = robot.constraint_bias(q, qd).reshape(n_s, m)
    return np.linalg.solve(kkt, rhs[..., None])[..., :n, 0]
