"""A user's two-loop linkage end to end: the Watt six-bar of examples/six_bar_watt.toml,
written link by link with rough angles, assembled, derived on first use and driven a full crank
turn by examples/six_bar_turn.toml. Checked against independent references: the loops closed by
Pinocchio's kinematics, power balance (dE/dt from the energy alone), torques by virtual work on
Pinocchio's spanning-tree RNEA, and the static torque as the slope of the potential energy."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import study_motion
from test_closed_chain import PinTree, rel

import planar_sym as ps
from planar_sym.model import description

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SIX_BAR = EXAMPLES / "six_bar_watt.toml"
STUDY = EXAMPLES / "six_bar_turn.toml"


@pytest.fixture(scope="module")
def six():
    robot = ps.load(SIX_BAR)  # derived and compiled on first use (a few seconds)
    desc = description.load(SIX_BAR)
    return robot, desc, PinTree(desc)


def test_both_loops_close_and_one_degree_of_freedom_remains(six):
    robot, desc, tree = six
    q0 = robot.q_drawn[None, :]
    phi, jac = tree.loops(q0)  # Pinocchio's kinematics, not ours
    assert np.max(np.abs(phi)) < 1e-12
    assert np.max(np.abs(robot.constraint(q0))) < 1e-12
    assert (robot.n, len(robot.actuated)) == (5, 1)
    assert np.linalg.matrix_rank(jac[0], tol=1e-9) == 4  # 4 loop equations, all independent
    assert desc.q_drawn()[0] == np.radians(60.0)  # the crank kept the angle given


def test_power_balance_over_a_full_crank_turn():
    t, h = np.linspace(0.05, 1.95, 39), 2.5e-4  # a fast move: truncation ~h^4 dominates
    robot, _, jt = study_motion(str(STUDY), t)
    tau, _ = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=t)
    power = np.sum(tau * jt.qd[:, list(robot.actuated)], axis=1)

    def energy(shift):
        _, _, j = study_motion(str(STUDY), t + shift)
        kin, pot = robot.energy(j.q, j.qd)
        return kin + pot

    de_dt = (energy(-2 * h) - 8 * energy(-h) + 8 * energy(h) - energy(2 * h)) / (12 * h)
    peak = np.max(np.abs(power))
    assert peak > 1e-2
    assert np.max(np.abs(power - de_dt)) / peak < 1e-9


def test_torques_by_virtual_work_on_pinocchio(six):
    robot, _, tree = six
    _, _, jt = study_motion(str(STUDY), np.linspace(0.0, 2.0, 41))
    tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=jt.t_s)
    b = tree.rnea(jt.q, jt.qd, jt.qdd)
    _, jac = tree.loops(jt.q)
    act = list(robot.actuated)
    pas = [i for i in range(robot.n) if i not in act]
    tau_ref, lam_ref = [], []
    for bk, jk in zip(b, jac):
        g = np.zeros((robot.n, len(act)))
        g[act] = np.eye(len(act))
        g[pas] = -np.linalg.solve(jk[:, pas], jk[:, act])  # qd = G qd_act on both loops
        tau_ref.append(g.T @ bk)
        lam_ref.append(np.linalg.solve(jk[:, pas].T, bk[pas]))
    assert rel(tau, np.array(tau_ref)) < 1e-9
    assert rel(lam, np.array(lam_ref)) < 1e-9


def test_holding_torque_is_the_slope_of_the_potential(six):
    """At rest, tau = dV/dtheta along the mechanism (virtual work with gravity alone); V by the
    compiled energy at poses the loops give for crank angles theta +- h, +- 2h."""
    robot, _, _ = six
    theta0, h = robot.q_drawn[0] + 0.4, 1e-3

    def pose(theta):
        m = ps.from_actuated(robot, [0.0], [[theta]], [[0.0]], [[0.0]])
        return m.q

    def potential(theta):
        return robot.energy(pose(theta), np.zeros((1, robot.n)))[1][0]

    slope = (potential(theta0 - 2 * h) - 8 * potential(theta0 - h) + 8 * potential(theta0 + h)
             - potential(theta0 + 2 * h)) / (12 * h)
    q = pose(theta0)
    tau, _ = robot.closed_chain_inverse_dynamics(q, np.zeros_like(q), np.zeros_like(q))
    assert abs(slope) > 1e-3
    assert tau[0, 0] == pytest.approx(slope, rel=1e-9)
