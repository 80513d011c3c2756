"""The "uncompiled" baseline: the same SymPy equations, evaluated by ``sympy.lambdify`` (numpy).

What planar_sym does with the model in C (CasADi-generated, compiled), this does in numpy,
from the very same ``derive.model.build`` expressions, with ``cse=True`` (common subexpressions
shared, the fairest lambdify):

* ``inverse_dynamics``: ``M(q) qdd + h(q, qd)`` vectorised over N samples (one numpy call per
  expression, whole columns at once): the tree part for closed chains;
* ``simulate_serial``: SciPy DOP853 on a pure-numpy right-hand side ``qdd = solve(M, tau - h)``
  evaluated per state, i.e. planar_sym's ``simulate`` with the compiled function swapped out;
* ``simulate_closed``: the same for a closed chain, with planar_sym's method (index-1 KKT
  system, projection onto Phi = 0 and Phi_q qd = 0 every 0.1 s), Phi, Phi_q, gamma lambdified.
"""

from __future__ import annotations

import numpy as np


class SymbolicRobot:
    """A robot's SymPy model with lambdified numpy functions and planar_sym's parameter values."""

    def __init__(self, robot):
        import sympy as sp

        from derive import model as derive_model
        from planar_sym.model import description

        self.robot = robot
        self.model = derive_model.build(description.load(robot.name))
        s, lag, con = self.model.sym, self.model.lagrangian, self.model.constraints
        self.n = len(s.q)
        values = robot.parameters
        self.p = [values[sym.name] for sym in s.p]
        qdd = sp.Matrix(s.qdd)
        tau = list(lag.mass_matrix * qdd + lag.bias)
        opts = {"modules": "numpy", "cse": True}
        self._tau = sp.lambdify([*s.q, *s.qd, *s.qdd, *s.p], tau, **opts)
        self._mh = sp.lambdify([*s.q, *s.qd, *s.p], [lag.mass_matrix, lag.bias], **opts)
        self.m = con.count
        if self.m:
            self._con = sp.lambdify([*s.q, *s.qd, *s.p],
                                    [con.jacobian, con.accel_bias], **opts)
            self._phi = sp.lambdify([*s.q, *s.p], [con.phi, con.jacobian], **opts)

    # -- inverse dynamics ------------------------------------------------------------------
    def inverse_dynamics(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        """M qdd + h over N samples, (N, n) in and out (constant rows broadcast)."""
        cols = self._tau(*q.T, *qd.T, *qdd.T, *self.p)
        out = np.empty(q.shape)
        for i, c in enumerate(cols):
            out[:, i] = c
        return out

    # -- forward dynamics, serial --------------------------------------------------------------
    def qdd(self, q, qd, tau) -> np.ndarray:
        M, h = self._mh(*q, *qd, *self.p)
        return np.linalg.solve(M, tau - h[:, 0])

    def simulate_serial(self, q0, qd0, t_end: float, *, rtol: float, atol: float, t_eval):
        """(q, qd, n_rhs) at ``t_eval`` from SciPy DOP853 on the numpy right-hand side."""
        from scipy.integrate import solve_ivp

        n = self.n
        zero = np.zeros(n)

        def rhs(t, x):
            return np.concatenate([x[n:], self.qdd(x[:n], x[n:], zero)])

        sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([q0, qd0]), method="DOP853",
                        t_eval=t_eval, rtol=rtol, atol=atol)
        assert sol.success, sol.message
        return sol.y[:n].T, sol.y[n:].T, sol.nfev

    # -- forward dynamics, closed chain ------------------------------------------------------
    def project(self, q, qd, tol: float = 1e-13):
        for _ in range(30):
            phi, jac = self._phi(*q, *self.p)
            phi = phi[:, 0]
            if np.max(np.abs(phi)) < tol:
                break
            q = q - jac.T @ np.linalg.solve(jac @ jac.T, phi)
        else:
            raise RuntimeError("projection onto the loop constraints failed")
        return q, qd - jac.T @ np.linalg.solve(jac @ jac.T, jac @ qd)

    def simulate_closed(self, q0, qd0, t_end: float, *, rtol: float, atol: float, t_eval,
                        segment_s: float = 0.1):
        """planar_sym.forward_closed.simulate_closed's method, every term lambdified (zero torque)."""
        from scipy.integrate import solve_ivp

        n, m = self.n, self.m
        kkt = np.zeros((n + m, n + m))
        rhs_v = np.zeros(n + m)
        count = 0

        def rhs(t, x):
            nonlocal count
            count += 1
            q, qd = x[:n], x[n:]
            M, h = self._mh(*q, *qd, *self.p)
            jac, gamma = self._con(*q, *qd, *self.p)
            kkt[:n, :n] = M
            kkt[:n, n:] = -jac.T
            kkt[n:, :n] = jac
            rhs_v[:n] = -h[:, 0]
            rhs_v[n:] = gamma[:, 0]
            return np.concatenate([qd, np.linalg.solve(kkt, rhs_v)[:n]])

        t = np.asarray(t_eval)
        q, qd = self.project(np.array(q0, float), np.array(qd0, float))
        qs, qds = [q], [qd]
        k = 0
        while k < len(t) - 1:
            end = int(np.searchsorted(t, t[k] + segment_s, side="right")) - 1
            end = min(max(end, k + 1), len(t) - 1)
            sol = solve_ivp(rhs, (t[k], t[end]), np.concatenate([q, qd]), method="DOP853",
                            t_eval=t[k:end + 1], rtol=rtol, atol=atol)
            assert sol.success, sol.message
            qs += list(sol.y[:n, 1:].T)
            qds += list(sol.y[n:, 1:].T)
            q, qd = self.project(sol.y[:n, -1], sol.y[n:, -1])
            k = end
        return np.array(qs), np.array(qds), count
