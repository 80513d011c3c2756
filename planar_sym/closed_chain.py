"""Closed chains: passive joints from the loop constraints, torques together with the loop
reaction forces, and forward dynamics that stays on the constraint manifold.

Sign convention, stated once and tested (tests/test_closed_chain.py):

.. code:: text

    M(q) qdd + h(q, qd) = S^T tau + Phi_q(q)^T lambda,
    Phi(q) = r(parent point) - r(child point)  at every cut joint,

so ``lambda`` (N, world x and y) is the force the cut joint's child body exerts on its parent
body; the child feels ``-lambda``. ``S`` selects the actuated coordinates; passive joints carry
no torque.
"""

from __future__ import annotations

import numpy as np

from .dynamics import Robot, as_samples
from .errors import InputError, SimulationError, WorkspaceError
from .kinematics import COND_LIMIT, JointTrajectory
from .library import SingleCall

#: Newton on Phi(q) = 0 stops below this residual (m); far under the 1e-9 m the tests demand.
NEWTON_TOL_M = 1e-13
NEWTON_MAX_ITER = 30


def partition(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the actuated and passive coordinates; checks the chain is fully actuated."""
    act = np.array(robot.actuated, dtype=int)
    pas = np.array([i for i in range(robot.n) if i not in robot.actuated], dtype=int)
    if len(act) + robot.n_constraints != robot.n:
        raise InputError(f"{robot.name}: {len(act)} actuated joints and {robot.n_constraints} "
                         f"loop equations for {robot.n} coordinates: the chain is not exactly "
                         "actuated, so torques are not unique")
    return act, pas


def _when(t, k: int) -> str:
    return f"t = {t[k]:.6g} s (sample {k})" if t is not None else f"sample {k}"


def _check_cond(robot: Robot, mats: np.ndarray, what: str, t) -> None:
    cond = np.linalg.cond(mats)
    bad = ~np.isfinite(cond) | (cond > COND_LIMIT)
    if bad.any():
        k = int(np.argmax(bad))
        raise WorkspaceError(f"{robot.name}: singular pose at {_when(t, k)}: the {what} has "
                             f"condition number {cond[k]:.3g} > {COND_LIMIT:g}")


def solve_passive(robot: Robot, q_act, q_guess=None, t=None) -> np.ndarray:
    """Full coordinates from actuated ones, Newton on Phi(q) = 0 for the passive joints.

    Sample by sample, each started from the previous solution: continuation keeps the
    assembly mode (the first sample starts from ``q_guess``, default the drawn configuration).
    """
    act, pas = partition(robot)
    q_act = as_samples("q_act", q_act, len(act), times=t)
    phi_f = SingleCall(robot.library.functions["constraint"], robot.p)
    jac_f = SingleCall(robot.library.functions["constraint_jacobian"], robot.p)
    q = np.array(robot.q_drawn if q_guess is None else q_guess, dtype=float)
    out = np.empty((len(q_act), robot.n))
    m = robot.n_constraints
    for k, qa in enumerate(q_act):
        q[act] = qa
        for _ in range(NEWTON_MAX_ITER):
            (phi,) = phi_f(q)
            if np.max(np.abs(phi)) < NEWTON_TOL_M:
                break
            (jac,) = jac_f(q)
            jp = jac.reshape(robot.n, m).T[:, pas]
            q[pas] -= np.linalg.solve(jp, phi)
        else:
            raise WorkspaceError(f"{robot.name}: the loops cannot be closed at {_when(t, k)} "
                                 f"for actuated angles {np.round(qa, 9).tolist()} rad "
                                 f"(|Phi| = {np.max(np.abs(phi)):.3g} m): outside the workspace")
        out[k] = q
    return out


def complete_rates(robot: Robot, q, qd_act, qdd_act, t=None) -> tuple[np.ndarray, np.ndarray]:
    """Passive rates from the constraints, batched.

    .. code:: text

        Phi_p qd_p = -Phi_a qd_a,    Phi_p qdd_p = gamma - Phi_a qdd_a
    """
    act, pas = partition(robot)
    q = as_samples("q", q, robot.n, times=t)
    jac = robot.constraint_jacobian(q)
    jac = jac if jac.ndim == 3 else jac[None]
    _check_cond(robot, jac[:, :, pas], "passive-joint constraint Jacobian Phi_p", t)
    qd = np.zeros_like(q)
    qd[:, act] = as_samples("qd_act", qd_act, len(act), times=t)
    qd[:, pas] = np.linalg.solve(jac[:, :, pas], -(jac[:, :, act] @ qd[:, act, None]))[..., 0]
    gamma = robot.constraint_bias(q, qd).reshape(len(q), -1)
    qdd = np.zeros_like(q)
    qdd[:, act] = as_samples("qdd_act", qdd_act, len(act), times=t)
    qdd[:, pas] = np.linalg.solve(jac[:, :, pas],
                                  (gamma - (jac[:, :, act] @ qdd[:, act, None])[..., 0])[..., None]
                                  )[..., 0]
    return qd, qdd


def inverse_dynamics(robot: Robot, q, qd, qdd, t=None) -> tuple[np.ndarray, np.ndarray]:
    """Actuated torques (N*m) and cut-joint reaction forces lambda (N), batched.

    Solves ``[S^T  Phi_q^T] [tau; lambda] = M qdd + h`` at every sample; q, qd, qdd must satisfy
    the constraints (use ``complete_rates`` or the inverse kinematics).
    Returns tau (N, actuated) and lambda (N, 2 * loops: x, y per cut joint).
    """
    act, _ = partition(robot)
    q, qd, qdd = (as_samples(k, a, robot.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                   ("qdd", qdd)))
    if not hasattr(robot, "_closed_inverse_dynamics"):  # exact path: the solve in numpy
        b = robot.tree_inverse_dynamics(q, qd, qdd).reshape(len(q), robot.n)
        sol = np.linalg.solve(actuation_matrix(robot, q, t), b[..., None])[..., 0]
        return sol[:, :len(act)], sol[:, len(act):]
    tau, lam, cond = robot._closed_inverse_dynamics(q, qd, qdd)
    _report_singular(robot, cond, t)
    return tau, lam


def actuation_matrix(robot: Robot, q: np.ndarray, t=None) -> np.ndarray:
    """``[S^T Phi_q^T]`` at each sample, shape (N, n, n); refuses a singular pose by time.

    The matrix is singular exactly when the passive-joint block ``Phi_p`` is (its actuated
    rows are identity rows), so that block's 1-norm condition number is the measure.
    """
    act, pas = partition(robot)
    n_s, n = len(q), robot.n
    jac = robot.constraint_jacobian(q).reshape(n_s, robot.n_constraints, n)
    _report_singular(robot, np.linalg.cond(jac[:, :, pas], 1), t)
    a = np.zeros((n_s, n, n))
    a[:, act, np.arange(len(act))] = 1.0
    a[:, :, len(act):] = jac.transpose(0, 2, 1)
    return a


def _report_singular(robot: Robot, cond: np.ndarray, t) -> None:
    bad = ~np.isfinite(cond) | (cond > COND_LIMIT)
    if bad.any():
        k = int(np.argmax(bad))
        raise WorkspaceError(f"{robot.name}: singular pose at {_when(t, k)}: the passive-joint "
                             f"constraint Jacobian Phi_p (which the actuation matrix "
                             f"[S^T Phi_q^T] needs) has 1-norm condition number {cond[k]:.3g} "
                             f"> {COND_LIMIT:g}")


def from_actuated(robot: Robot, t, q_act, qd_act, qdd_act, q_guess=None) -> JointTrajectory:
    """Full joint motion of a closed chain from its actuated joints' motion."""
    q = solve_passive(robot, q_act, q_guess, t)
    qd, qdd = complete_rates(robot, q, qd_act, qdd_act, t)
    return JointTrajectory(np.asarray(t), q, qd, qdd)


# -- forward dynamics ---------------------------------------------------------------------------

def project(robot: Robot, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """Closest point on the manifold: Gauss-Newton on Phi(q) = 0, then Phi_q qd = 0 (min. norm)."""
    q, qd = np.array(q, dtype=float), np.array(qd, dtype=float)
    m, n = robot.n_constraints, robot.n
    for _ in range(NEWTON_MAX_ITER):
        phi = robot.constraint(q)
        jac = robot.constraint_jacobian(q).reshape(m, n)
        if np.max(np.abs(phi)) < NEWTON_TOL_M:
            break
        q -= jac.T @ np.linalg.solve(jac @ jac.T, phi)
    else:
        raise SimulationError(f"{robot.name}: cannot project q = {q.tolist()} onto the loop "
                              f"constraints (|Phi| = {np.max(np.abs(phi)):.3g} m)")
    qd -= jac.T @ np.linalg.solve(jac @ jac.T, jac @ qd)
    return q, qd


def simulate_closed(robot: Robot, q0, qd0, t_span, *, torque=None, t_eval=None,
                    rtol: float = 1e-11, atol: float = 1e-12, method: str = "dopri5",
                    segment_s: float = 0.1, drift_limit_m: float = 1e-6):
    """Forward dynamics of a closed chain, on the constraint manifold.

    Method (index reduction with projection): the full state (q, qd) is integrated (the C
    Dormand-Prince 5(4) by default, or a SciPy method) with the accelerations of the index-1
    system

    .. code:: text

        [ M     -Phi_q^T ] [ qdd    ]   [ S^T tau - h ]
        [ Phi_q   0      ] [ lambda ] = [ gamma       ]

    and every ``segment_s`` the state is projected back onto Phi = 0, Phi_q qd = 0 (the
    integrator restarts there); a segment that drifts beyond ``drift_limit_m`` raises
    SimulationError naming the time. ``q0`` is the full coordinate vector (projected first);
    ``torque`` acts on the actuated joints. The result reports ``constraint_drift_m``, the
    largest |Phi| at any output time.
    """
    from scipy.integrate import solve_ivp

    from .simulation import SCIPY_METHODS, Simulation, dopri5, time_grid, torque_function

    act, _ = partition(robot)
    n, m = robot.n, robot.n_constraints
    q, qd = project(robot, as_samples("q0", q0, n)[0], as_samples("qd0", qd0, n)[0])
    t = time_grid(t_span, t_eval)
    tau_of = torque_function(torque, len(act))
    terms = SingleCall(robot.library.functions["constrained_terms"], robot.p)
    kkt = np.zeros((n + m, n + m))
    rhs_v = np.zeros(n + m)
    count, last_t = [0], [t[0]]

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

    if method not in ("dopri5", *SCIPY_METHODS):
        raise InputError(f"unknown method {method!r}; known: dopri5, {', '.join(SCIPY_METHODS)}")
    use_c = method == "dopri5" and not callable(torque)
    if method == "dopri5" and callable(torque):
        method = "DOP853"
    fn = robot.library.address("constrained_terms") if use_c else 0
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
    kin, pot = robot.energy(qa, qda)
    taus = np.array([tau_of(tt) for tt in t])
    return Simulation(t, qa, qda, taus, kin, pot, method, rtol, atol, count[0], drift)
