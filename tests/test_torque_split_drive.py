"""The torque split with a drive train: friction and the rotors are parts of their own, each
against its closed form on the geared 2-DOF arm (``examples/serial_2dof_geared.toml``: a
50:1 gearmotor at each joint, rotor J_m = 0.5 kg*mm^2 each, the shoulder's on the ground, the
elbow's carried by link1; viscous and Coulomb friction at the shoulder):

.. code:: text

    friction   D_1 = b qd1 + c tanh(qd1 / v_s),   D_2 = 0
    rotors     tau_1 = N1^2 J1 qdd1 + J2 qdd1 + N2 J2 qdd2      (T_rotor2 = J2/2 (qd1 + N2 qd2)^2:
               tau_2 = N2 J2 qdd1 + N2^2 J2 qdd2                 no velocity terms)

and the velocity part is the links' C qd alone: zero at rest whatever the friction (before,
Coulomb friction was filed under it). The parts add up to the inverse dynamics (1e-12), on the
tree and through a closed chain's multiplier solve.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.dynamics.inverse import SPLIT_PARTS, torque_split

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"


@pytest.fixture(scope="module")
def geared():
    return ps.load(GEARED)


def _states(n_s: int = 30, n: int = 2, seed: int = 3):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (n_s, n)), rng.uniform(-2, 2, (n_s, n)),
            rng.uniform(-5, 5, (n_s, n)))


def test_parts_against_their_closed_forms(geared):
    q, qd, qdd = _states()
    p = geared.parameters
    parts = torque_split(geared, q, qd, qdd)
    assert list(parts) == list(SPLIT_PARTS)
    tau = geared.inverse_dynamics(q, qd, qdd)
    total = sum(parts.values())
    assert np.max(np.abs(total - tau)) <= 1e-12 * np.max(np.abs(tau))
    friction = np.column_stack([
        p["fv_joint1"] * qd[:, 0] + p["fc_joint1"] * np.tanh(qd[:, 0] / p["vs_joint1"]),
        np.zeros(len(q))])
    assert np.max(np.abs(parts["friction"] - friction)) <= 1e-15
    n1, n2, j1, j2 = p["gear_joint1"], p["gear_joint2"], p["jm_joint1"], p["jm_joint2"]
    rotor = np.column_stack([n1**2 * j1 * qdd[:, 0] + j2 * qdd[:, 0] + n2 * j2 * qdd[:, 1],
                             n2 * j2 * qdd[:, 0] + n2**2 * j2 * qdd[:, 1]])
    assert np.max(np.abs(parts["rotor"] - rotor)) <= 1e-12 * np.max(np.abs(rotor))
    # links only: the seed arm's own M, C and g (the geared example adds no link mass)
    seed = ps.load("serial_2dof")
    plain = torque_split(seed, q, qd, qdd)
    for k in ("inertial", "velocity", "gravity"):
        assert np.max(np.abs(parts[k] - plain[k])) <= 1e-12 * np.max(np.abs(plain[k])), k


def test_at_rest_the_velocity_part_is_zero(geared):
    """Starting from rest with an acceleration: C qd = 0 exactly; Coulomb friction at a tiny
    rate (1e-3 rad/s: 10 % of v_s) shows as friction, not as a velocity torque."""
    q = np.array([[0.3, 0.8], [0.3, 0.8]])
    qd = np.array([[0.0, 0.0], [1e-3, 0.0]])
    qdd = np.array([[2.0, -1.0], [2.0, -1.0]])
    parts = torque_split(geared, q, qd, qdd)
    assert np.max(np.abs(parts["velocity"])) <= 1e-9  # C qd ~ qd^2: 1e-6 * M
    assert parts["friction"][1, 0] == pytest.approx(
        1e-3 * geared.parameters["fv_joint1"]
        + geared.parameters["fc_joint1"] * np.tanh(0.1), rel=1e-12)


def test_a_robot_without_drives_has_zero_drive_parts():
    q, qd, qdd = _states(n=2)
    parts = torque_split(ps.load("serial_2dof"), q, qd, qdd)
    assert not np.any(parts["friction"]) and not np.any(parts["rotor"])
