"""Linearisation of the equations of motion about a state, for control design (LQR):

.. code:: text

    x = (q, qd),  u = the actuated torques (N*m; N at a slider)
    d(x - x0)/dt = A (x - x0) + B (u - u0) + (0, qdd0)      qdd0 = 0 at an equilibrium
    A = [[0, I], [dqdd/dq, dqdd/dqd]],   B = [[0], [M(q0)^-1 S]]

For a tree, ``dqdd/dq`` and ``dqdd/dqd`` come from the generated Jacobian of the forward
dynamics (exact derivatives of the same expressions, rotors and smoothed friction included),
``M`` from the mass matrix; ``S`` picks the actuated coordinates.

A closed chain is linearised in its independent coordinates, the actuated ones (x = (q_a,
qd_a)): CasADi differentiates, exactly, the chain of the generated functions

.. code:: text

    q_p(q_a) from Phi(q) = 0 (a rootfinder: derivatives by the implicit function theorem),
    qd_p = -Phi_p^-1 Phi_a qd_a,
    [M  -Phi_q^T; Phi_q  0] [qdd; lambda] = [S tau - h; gamma],   qdd_a its actuated rows
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.arrays import as_vector
from ..model.robot import Robot


@dataclass(frozen=True)
class Linearization:
    """``a`` (2n, 2n) in 1/s and 1/s^2 (per unit of each state: rad, rad/s; m, m/s at a
    slider), ``b`` (2n, actuated) in rad/s^2 per N*m (m/s^2 per N); the point: ``q`` (n,),
    ``qd`` (n,), ``tau`` (actuated,) and the acceleration there ``qdd`` (n,), zero at an
    equilibrium; ``states`` and ``inputs`` name the columns with their units; ``coordinates``
    the coordinates (0-based) the state holds. A closed chain's state is its actuated
    coordinates and their rates: 2n is then twice their number."""

    a: np.ndarray
    b: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    qdd: np.ndarray
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    #: the coordinates the state holds (0-based): every one of a tree, a closed chain's
    #: actuated ones (its passive ones follow from the loops)
    coordinates: tuple[int, ...] = ()

    def state_space(self):
        """The system as a python-control ``StateSpace`` (every state measured); needs the
        ``control`` package."""
        try:
            import control
        except ImportError:
            raise InputError("state_space() needs python-control: pip install control "
                             "(Linearization.a and .b are the matrices)") from None
        n = len(self.a)
        return control.ss(self.a, self.b, np.eye(n), np.zeros((n, self.b.shape[1])),
                          states=list(self.states), inputs=list(self.inputs),
                          outputs=list(self.states))


def linearize(robot: Robot, q, qd=None, tau=None) -> Linearization:
    """A and B of ``robot`` about ``q`` (n,) rad (m at a slider), ``qd`` (n,) rad/s (default
    zero) and the actuated torques ``tau`` (actuated,) N*m (N at a slider); by default the
    torques that hold the actuated joints still there (the gravity torques at rest), so an
    upright pendulum or a balanced cart-pole is an equilibrium (``qdd`` all zero).

    A closed chain's ``q`` and ``qd`` are every coordinate, on its loops (or its actuated ones
    only: the loops give the others, from the drawn assembly mode).

    Raises InputError for a bad shape, a non-finite value or a closed chain's state off its
    loops.
    """
    n, act = robot.n, list(robot.actuated)
    if robot.is_closed_chain:
        return _closed(robot, q, qd, tau)
    q0 = as_vector("q", q, n)
    qd0 = np.zeros(n) if qd is None else as_vector("qd", qd, n)
    full = np.zeros(n)
    if tau is None:
        full[act] = robot.tree_inverse_dynamics(q0, qd0, np.zeros(n))[act]
    else:
        full[act] = as_vector("tau", tau, len(act))
    args = {"q": q0[None], "qd": qd0[None], "tau": full[None], "p": robot.p}
    jac = robot.library.functions["forward_dynamics_jacobian"](1, args)
    qdd = robot.tree_forward_dynamics(q0, qd0, full)
    m_inv = np.linalg.inv(robot.mass_matrix(q0))
    a = np.block([[np.zeros((n, n)), np.eye(n)], [jac["dqdd_dq"][0], jac["dqdd_dqd"][0]]])
    b = np.vstack([np.zeros((n, len(act))), m_inv[:, act]])
    units = robot.coordinate_units
    states = tuple(f"{c} ({u})" for c, u in zip(robot.coordinates, units)) + tuple(
        f"{c}_rate ({u}/s)" for c, u in zip(robot.coordinates, units))
    inputs = tuple(f"{robot.coordinates[i]} ({'N' if units[i] == 'm' else 'N*m'})" for i in act)
    return Linearization(a, b, q0, qd0, full[act], qdd, states, inputs, tuple(range(n)))


def _closed(robot: Robot, q, qd, tau) -> Linearization:
    """A closed chain in its actuated coordinates (module docstring)."""
    import casadi as ca

    from ..motion.closure import from_actuated

    n, act, pas = robot.n, list(robot.actuated), list(robot.passive)
    na, m = len(act), len(pas)
    if robot.n_constraints != m:
        raise InputError(f"{robot.name}: linearize needs as many passive coordinates as loop "
                         f"equations ({m} against {robot.n_constraints})")
    q_in = np.asarray(q, dtype=float).ravel()
    qd_in = None if qd is None else np.asarray(qd, dtype=float).ravel()
    q_act = as_vector("q", q_in[act] if len(q_in) == n else q_in, na)
    qd_act = (np.zeros(na) if qd_in is None else
              as_vector("qd", qd_in[act] if len(qd_in) == n else qd_in, na))
    guess = q_in if len(q_in) == n else None
    if guess is not None and np.abs(robot.constraint(guess)).max() > 1e-9:
        raise InputError(f"q is off {robot.name}'s loops (|Phi| = "
                         f"{np.abs(robot.constraint(guess)).max():.3g} m): give a pose on the "
                         "loops, or its actuated coordinates only")
    # the state on the loops, and the accelerations that hold the actuated joints still
    still = from_actuated(robot, np.zeros(1), q_act[None], qd_act[None], np.zeros((1, na)),
                          guess)
    q0, qd0 = still.q[0], still.qd[0]
    p = ca.DM(robot.p)
    f = {k: robot.casadi_function(k) for k in ("mass_matrix", "bias", "constraint",
                                               "constraint_jacobian", "constraint_bias")}

    def whole(a_part, p_part):
        rows = dict(zip(act, ca.vertsplit(a_part))) | dict(zip(pas, ca.vertsplit(p_part)))
        return ca.vertcat(*[rows[i] for i in range(n)])

    qa, qda, ta = ca.MX.sym("qa", na), ca.MX.sym("qda", na), ca.MX.sym("ta", na)
    qp_sym = ca.MX.sym("qp", m)
    loops = ca.Function("loops", [qp_sym, qa], [f["constraint"](whole(qa, qp_sym), p)])
    qp = ca.rootfinder("passive", "newton", loops, {"abstol": 1e-14})(ca.DM(q0[pas]), qa)
    qq = whole(qa, qp)
    jac = f["constraint_jacobian"](qq, p)
    qdp = -ca.solve(jac[:, pas], ca.mtimes(jac[:, act], qda))
    qqd = whole(qda, qdp)
    tau_full = whole(ta, ca.MX.zeros(m))
    kkt = ca.blockcat([[f["mass_matrix"](qq, p), -jac.T], [jac, ca.MX.zeros(m, m)]])
    rhs = ca.vertcat(tau_full - f["bias"](qq, qqd, p), f["constraint_bias"](qq, qqd, p))
    qdd = ca.solve(kkt, rhs)[:n]  # every coordinate's, the passive ones too
    qdd_a = qdd[act]
    x = ca.vertcat(qa, qda)
    lin = ca.Function("lin", [qa, qda, ta], [ca.jacobian(qdd_a, x), ca.jacobian(qdd_a, ta),
                                             qdd])
    if tau is None:  # the torques that hold the actuated joints still here (qdd_a = 0)
        tau0 = robot.closed_chain_inverse_dynamics(q0[None], qd0[None], still.qdd)[0][0]
    else:
        tau0 = as_vector("tau", tau, na)
    dx, du, qdd0 = (np.asarray(v) for v in lin(q_act, qd_act, tau0))
    a = np.block([[np.zeros((na, na)), np.eye(na)], [dx]])
    b = np.vstack([np.zeros((na, na)), du])
    units = robot.coordinate_units
    names = [robot.coordinates[i] for i in act]
    states = tuple(f"{names[k]} ({units[i]})" for k, i in enumerate(act)) + tuple(
        f"{names[k]}_rate ({units[i]}/s)" for k, i in enumerate(act))
    inputs = tuple(f"{names[k]} ({'N' if units[i] == 'm' else 'N*m'})" for k, i in enumerate(act))
    return Linearization(a, b, q0, qd0, tau0, qdd0.ravel(), states, inputs, tuple(act))
