"""Linearisation of the equations of motion about a state, for control design (LQR):

.. code:: text

    x = (q, qd),  u = the actuated torques (N*m; N at a slider)
    d(x - x0)/dt = A (x - x0) + B (u - u0) + (0, qdd0)      qdd0 = 0 at an equilibrium
    A = [[0, I], [dqdd/dq, dqdd/dqd]],   B = [[0], [M(q0)^-1 S]]

For a tree, ``dqdd/dq`` and ``dqdd/dqd`` come from the generated Jacobian of the forward
dynamics (exact derivatives of the same expressions, rotors and smoothed friction included),
``M`` from the mass matrix; ``S`` picks the actuated coordinates. A closed chain would need its
independent coordinates; it is refused with that reason.
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
    equilibrium; ``states`` and ``inputs`` name the columns with their units."""

    a: np.ndarray
    b: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    qdd: np.ndarray
    states: tuple[str, ...]
    inputs: tuple[str, ...]

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

    Raises InputError for a closed chain, a bad shape or a non-finite value.
    """
    if robot.is_closed_chain:
        raise InputError(f"{robot.name} is a closed chain: its linearisation needs its "
                         "independent coordinates, which linearize does not do yet")
    n, act = robot.n, list(robot.actuated)
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
    return Linearization(a, b, q0, qd0, full[act], qdd, states, inputs)
