"""Forward dynamics of the inverse-dynamics torques reproduces the motion (S3-S7), and the free
swing S1 keeps its energy.

The torque fed to ``simulate`` is exact at every time the integrator asks for: cubic +
inverse kinematics + inverse dynamics evaluated at that very time (no table interpolation).

Why the runs are split into 0.5 s segments (multiple shooting), each started from the exact
trajectory state: the open-loop motion is exponentially unstable. Linearised about the S3 start
pose (q = [0, 90 deg], link 2 pointing up) the 2-DOF arm has an eigenvalue of +11.3 /s, the
3-DOF arm +15.9 /s, so a 1e-13 rad integration error grows by e^56 (S3) over the 5 s and the
single-shot run diverges (measured: 165 rad at the end of S3); the 5-bars grow by ~1e8 over
their 2 s (measured single-shot: 1.5e-5 rad, five_bar_type1_move_x). Over 0.5 s the growth is
at most e^8, far below the error the test would catch: a torque wrong by 1e-6 of its size
already moves the arm by more than the tolerance within one segment.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from conftest import seed_studies, study_motion

from planar_sym.dynamics.forward import simulate
from planar_sym.model.locate import load
from planar_sym.study.run import run

SCENARIOS = seed_studies()

SEGMENT_S = 0.5
ROUND_TRIP_TOL_RAD = 1e-8  # measured <= 3e-10 rad (S4), ~1e-11 elsewhere
ENERGY_TOL = 1e-8  # relative to the peak kinetic energy of the swing (measured ~1e-13)

TASK_SCENARIOS = ("serial_2dof_cartesian_move", "serial_3dof_cartesian_move",
                  *[n for n, s in SCENARIOS.items()
                    if s.robot in ("five_bar_type1", "five_bar_type2", "parallel_3rrr")])


def _setup(name):
    T = SCENARIOS[name].motion.duration_s
    robot = study_motion(name, [0.0])[0]

    def motion(t):
        return study_motion(name, np.clip(np.atleast_1d(t), 0.0, T))[2]

    def torque(t: float) -> np.ndarray:
        jt = motion(t)
        if robot.is_closed_chain:
            return robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)[0][0]
        return robot.inverse_dynamics(jt.q, jt.qd, jt.qdd)[0]

    return robot, T, motion, torque


@pytest.mark.parametrize("name", TASK_SCENARIOS)
def test_forward_of_inverse_dynamics(name):
    robot, T, motion, torque = _setup(name)
    act = list(robot.actuated)
    worst, worst_all, moved = 0.0, 0.0, 0.0
    edges = np.linspace(0.0, T, round(T / SEGMENT_S) + 1)
    for a, b in itertools.pairwise(edges):
        t = np.linspace(a, b, 26)
        ref = motion(t)
        sim = simulate(robot, ref.q[0], ref.qd[0], (a, b), torque=torque, t_eval=t,
                       rtol=1e-11, atol=1e-12)
        worst = max(worst, float(np.max(np.abs(sim.q[:, act] - ref.q[:, act]))))
        worst_all = max(worst_all, float(np.max(np.abs(sim.q - ref.q))))
        moved = max(moved, float(np.max(np.abs(ref.q[:, act] - ref.q[0, act]))))
        # and the torque the integrator saw is the inverse dynamics at the sample times
        assert np.allclose(sim.tau, np.array([torque(tt) for tt in t]), rtol=0, atol=1e-15)
    print(f"{name}: forward of inverse dynamics, max actuated-joint error {worst:.2e} rad "
          f"(all joints {worst_all:.2e} rad)")
    assert moved > 0.05, "the trajectory barely moves the joints"
    assert worst < ROUND_TRIP_TOL_RAD
    assert worst_all < ROUND_TRIP_TOL_RAD


def test_round_trip_catches_a_wrong_torque():
    """The same check with the torque off by 1e-6 of itself fails by far: the test can fail."""
    robot, _, motion, torque = _setup("five_bar_type1_move_y")
    t = np.linspace(0.0, SEGMENT_S, 26)
    ref = motion(t)
    sim = simulate(robot, ref.q[0], ref.qd[0], (0.0, SEGMENT_S),
                   torque=lambda tt: torque(tt) * (1 + 1e-6), t_eval=t)
    act = list(robot.actuated)
    assert np.max(np.abs(sim.q[:, act] - ref.q[:, act])) > 10 * ROUND_TRIP_TOL_RAD


# -- S1: the free swing keeps its energy ----------------------------------------------------------

# seed Table 1 (SI): link 1, motor mass at the elbow, link 2
M1, I1, LC1, A1 = 0.071, 89.395e-6, 0.0373, 0.1
MM = 0.292
M2, I2, LC2 = 0.075, 109.864e-6, 0.04168
G = 9.81


def energy_by_hand(q, qd) -> np.ndarray:
    """Total energy of the 2-DOF arm from the Table 1 numbers (q1 absolute, q2 relative)."""
    q1, q12 = q[:, 0], q[:, 0] + q[:, 1]
    w1, w12 = qd[:, 0], qd[:, 0] + qd[:, 1]
    vx = -A1 * np.sin(q1) * w1 - LC2 * np.sin(q12) * w12
    vy = A1 * np.cos(q1) * w1 + LC2 * np.cos(q12) * w12
    kin = 0.5 * (I1 + M1 * LC1**2 + MM * A1**2) * w1**2 + 0.5 * I2 * w12**2 \
        + 0.5 * M2 * (vx**2 + vy**2)
    pot = G * ((M1 * LC1 + (MM + M2) * A1) * np.sin(q1) + M2 * LC2 * np.sin(q12))
    return kin + pot, kin


def test_free_swing_energy():
    res = run("serial_2dof_free_swing", 1001)
    c = res.columns
    q = np.column_stack([c["q1_rad"], c["q2_rad"]])
    qd = np.column_stack([c["qd1_rad_s"], c["qd2_rad_s"]])
    e, kin = energy_by_hand(q, qd)
    assert c["t_s"][-1] == pytest.approx(1.0)
    assert np.max(kin) > 0.01, "the arm did not swing"
    assert np.max(np.abs(c["energy_j"] - e)) < 1e-12 * np.max(np.abs(e))
    drift = float(np.max(np.abs(e - e[0])) / np.max(kin))
    print(f"S1: energy drift over 1 s {drift:.2e} of the peak kinetic energy "
          f"{np.max(kin):.4g} J")
    assert drift < ENERGY_TOL
    # and directly through simulate: start from rest at q1 = -60 deg, the energy it starts with
    robot = load("serial_2dof")
    sim = simulate(robot, np.radians([-60.0, 0.0]), np.zeros(2), (0.0, 1.0))
    e2, _ = energy_by_hand(sim.q, sim.qd)
    assert e2[0] == pytest.approx(G * (M1 * LC1 + (MM + M2) * A1 + M2 * LC2)
                                  * np.sin(np.radians(-60.0)), rel=1e-14)
    assert np.max(np.abs(e2 - e2[0])) / np.max(kin) < ENERGY_TOL
