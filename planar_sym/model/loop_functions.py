"""A closed chain's functions of a Robot: its torques with the loops' multipliers, the loop
residuals and their derivatives, and the refusals of states off the loops or at singular poses.

A base class of ``Robot`` (one concept, kept apart from the tree functions of ``robot.py``):
every method reads the robot's manifest names, its generated functions (``_fns``, ``_call``)
and its parameter vector ``p``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .arrays import as_samples
from .loops import check_on_loops, refuse_singular


class LoopFunctions:
    """The closed-chain methods of ``Robot`` (see there for the arrays' shapes and units)."""

    def closed_chain_inverse_dynamics(self, q, qd, qdd, t=None) -> tuple[np.ndarray, np.ndarray]:
        """Actuated torques (N, actuated) in N*m and cut-joint forces lambda (N, 2 * loops) in N.

        q, qd, qdd: every coordinate, on the loops (from inverse_kinematics or
        motion.closure.from_actuated). Convention: M qdd + h = S^T tau + Phi_q^T lambda, solved
        in one generated function, which also returns the loop residuals; a sample off the
        loops (``LOOP_TOL_M``, see ``check_on_loops``) raises InputError, and a pose where the
        passive-joint constraint Jacobian Phi_p is singular (1-norm condition number above
        COND_LIMIT) raises WorkspaceError, each naming the sample (and the time ``t``, s).

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (N, n) or (n,)
            Every coordinate (rad; m at a slider), its rate (rad/s) and acceleration
            (rad/s^2), passive joints included.
        t : ndarray, shape (N,), optional
            Times (s), only to name the time of a refused sample.

        Returns
        -------
        tau : ndarray, shape (N, actuated)
            Torques at the actuated coordinates (N*m; N at a slider), in ``actuated`` order.
        lam : ndarray, shape (N, 2 * loops)
            Force (N, world x and y per cut joint, in ``loops`` order) the cut joint's child
            body exerts on its parent body.
        """
        if not self.is_closed_chain:
            raise InputError(f"{self.name} is not a closed chain: use inverse_dynamics")
        q, qd, qdd = (as_samples(k, a, self.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                       ("qdd", qdd)))
        out = self._closed_inverse_dynamics(q, qd, qdd)
        tau, lam, cond, phi, phi_v, phi_a = (np.asarray(a).reshape(len(q), -1) for a in out)
        self.check_on_loops(phi, phi_v, phi_a, qd, qdd, t)
        self.refuse_singular(cond[:, 0], t)
        return tau, lam

    def refuse_singular(self, cond: np.ndarray, t=None) -> None:
        """``model.loops.refuse_singular`` for this robot: WorkspaceError at the first sample
        whose Phi_p has a 1-norm condition number ``cond`` (N,) (dimensionless) above
        COND_LIMIT; ``t`` (N,) in s names its time."""
        refuse_singular(self.name, cond, t)

    def check_on_loops(self, phi, phi_v, phi_a, qd, qdd, t=None) -> None:
        """``model.loops.check_on_loops`` for this robot: InputError at the first sample off
        the loops (residuals Phi in m, Phi_q qd in m/s, Phi_q qdd - gamma in m/s^2, each
        (N, 2 * loops); rates ``qd`` (N, n) in rad/s, ``qdd`` in rad/s^2; ``t`` (N,) in s)."""
        check_on_loops(self.name, self.loops, phi, phi_v, phi_a, qd, qdd, t)

    def _closed_inverse_dynamics(self, q, qd, qdd):
        """The fused generated function's outputs (exact path): tau, lambda, cond and the loop
        residuals Phi, Phi_q qd, Phi_q qdd - gamma."""
        r = self._fns["closed_inverse_dynamics"](len(q), {"q": q, "qd": qd, "qdd": qdd,
                                                          "p": self.p})
        return tuple(r[k] for k in ("tau", "lambda", "cond", "phi", "phi_v", "phi_a"))

    def constraint(self, q) -> np.ndarray:
        """Loop-closure residual Phi(q) (m), shape (N, 2 * loops)."""
        r, s = self._call("constraint", q=q)
        return self._out(r["phi"], s)

    def constraint_jacobian(self, q) -> np.ndarray:
        """Loop-closure Jacobian Phi_q = dPhi/dq (m/rad; m/m at a slider), shape
        (N, 2 * loops, n)."""
        r, s = self._call("constraint_jacobian", q=q)
        return self._out(r["phi_q"], s)

    def constraint_bias(self, q, qd) -> np.ndarray:
        """gamma = -(Phi_q qd)_q qd, so that Phi_q qdd = gamma: shape (N, 2 * loops), m/s^2
        (``q`` in rad, ``qd`` in rad/s, each (N, n))."""
        r, s = self._call("constraint_bias", q=q, qd=qd)
        return self._out(r["gamma"], s)
