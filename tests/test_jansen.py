"""The three-loop Jansen leg (examples/jansen_linkage.toml, driven by examples/jansen_turn.toml)
end to end: one degree of freedom from 7 coordinates and 3 loops, the loops closed by the
compiled code, the crank torque against power balance (dE/dt from the energy alone, over the
turn), the holding torque against the slope of the potential, and the foot's flat stride."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import study_motion

import planar_sym as ps

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
LEG, TURN = EXAMPLES / "jansen_linkage.toml", EXAMPLES / "jansen_turn.toml"


@pytest.fixture(scope="module")
def leg():
    return ps.load(LEG)


def test_seven_coordinates_three_loops_one_degree_of_freedom(leg):
    assert (leg.n, len(leg.actuated), len(leg.loops)) == (7, 1, 3)
    assert np.max(np.abs(leg.constraint(leg.q_drawn[None, :]))) < 1e-12
    jac = leg.constraint_jacobian(leg.q_drawn[None, :])[0]
    assert np.linalg.matrix_rank(jac, tol=1e-9) == 6


def test_power_balance_over_the_turn():
    t, h = np.linspace(0.05, 1.15, 45), 2.5e-4
    t = t[(np.abs(t - 0.1) > 1e-3) & (np.abs(t - 1.1) > 1e-3)]  # the ramps' ends: qdd jumps
    robot, _, jt = study_motion(str(TURN), t)
    tau, _ = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=t)
    power = tau[:, 0] * jt.qd[:, robot.actuated[0]]

    def energy(shift):
        _, _, j = study_motion(str(TURN), t + shift)
        kin, pot = robot.energy(j.q, j.qd)
        return kin + pot

    de_dt = (energy(-2 * h) - 8 * energy(-h) + 8 * energy(h) - energy(2 * h)) / (12 * h)
    assert np.max(np.abs(power)) > 1.0
    assert np.max(np.abs(power - de_dt)) / np.max(np.abs(power)) < 1e-8


def test_holding_torque_is_the_slope_of_the_potential(leg):
    theta0, h = 0.7, 1e-3

    def pose(theta):
        return ps.from_actuated(leg, [0.0], [[theta]], [[0.0]], [[0.0]]).q

    def potential(theta):
        return leg.energy(pose(theta), np.zeros((1, leg.n)))[1][0]

    slope = (potential(theta0 - 2 * h) - 8 * potential(theta0 - h) + 8 * potential(theta0 + h)
             - potential(theta0 + 2 * h)) / (12 * h)
    q = pose(theta0)
    tau, _ = leg.closed_chain_inverse_dynamics(q, np.zeros_like(q), np.zeros_like(q))
    assert abs(slope) > 1e-2
    assert tau[0, 0] == pytest.approx(slope, rel=1e-8)


def test_the_foot_walks_flat():
    """Jansen's point: the foot stays within 1 mm of its lowest height over more than 30 cm of
    stride (the example's header says 38 cm)."""
    robot, _, jt = study_motion(str(TURN), np.linspace(0.1, 1.1, 2001))
    x, y = robot.task(jt.q)[0][:, 0], robot.task(jt.q)[0][:, 1]
    low = y < y.min() + 1e-3
    assert np.ptp(x[low]) > 0.30
    assert np.ptp(y) > 0.2  # and lifts on the way back
