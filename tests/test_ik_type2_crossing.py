"""A task-space move of a closed chain that crosses a singular pose of its passive joints (a
Type II singularity: det Phi_p = 0) is refused, naming the sample where det Phi_p changes sign.

The five-bar of type 2 moved straight down from (100, 128) mm through 130 mm crosses its
singular curve near y = 16 mm: the stacked Jacobian [Phi_q; J] of the inverse kinematics stays
regular there, so the task was followed, but the mechanism driven at its two cranks switched
assembly mode between two samples. Its torques then depended on the sampling (peak 3.5 N*m at
101 samples, 4.9 at 201, 113 at 2001; about 0.1 N*m on the seed's own moves) with no word below
2001 samples. The reference for where it crosses is independent of the check: det Phi_p from
the robot's constraint Jacobian along the same move stopped just short of the curve, and the
closed form of the five-bar's passive angles is the seed's. A move that stays on one side runs.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError

ROBOT = "five_bar_type2"
START = np.array([0.100, 0.128])  # m
DOWN = np.array([0.0, -0.130])  # m: crosses the singular curve near y = 16 mm
T = 2.0


def _move(n: int, by=DOWN):
    t = np.linspace(0.0, T, n)
    return ps.cubic(START, by, T, t)


@pytest.fixture(scope="module")
def robot():
    return ps.load(ROBOT)


def _det_phi_p(robot, q):
    pas = [i for i in range(robot.n) if i not in robot.actuated]
    jac = robot.constraint_jacobian(q).reshape(len(q), robot.n_constraints, robot.n)
    return np.linalg.det(jac[:, :, pas])


@pytest.mark.parametrize("solver", ["seed", "newton"])
@pytest.mark.parametrize("n", [101, 201, 2001])
def test_a_task_move_across_a_type2_singularity_is_refused(robot, solver, n):
    traj = _move(n)
    with pytest.raises(WorkspaceError) as info:
        ps.inverse_kinematics(robot, traj, solver=solver)
    text = str(info.value)
    assert "det Phi_p changes sign" in text and "Type II" in text, text
    k = int(re.search(r"\(sample (\d+)\)", text).group(1))
    # independent: the same move solved up to the sample before, det Phi_p keeps its sign
    # there, and the refused sample's target lies past the place where it would change
    before = ps.inverse_kinematics(robot, ps.cubic(START, DOWN, T, traj.t_s[:k]), solver=solver)
    det = _det_phi_p(robot, before.q)
    assert np.all(np.sign(det) == np.sign(det[0])), "crossed before the sample named"
    y_cross = 0.0155  # m: between the samples named at 101, 201 and 2001 samples (below)
    assert traj.x[k - 1, 1] > y_cross - 1e-3 and traj.x[k, 1] < y_cross + 1e-3, traj.x[k - 1:k + 1]


def test_the_sample_named_is_where_the_sign_changes(robot):
    """At 201 samples the sign of det Phi_p over the move stopped one sample later (solved in
    pieces on each side, where each is regular) changes exactly between the samples named."""
    n = 201
    traj = _move(n)
    with pytest.raises(WorkspaceError) as info:
        ps.inverse_kinematics(robot, traj, solver="seed")
    k = int(re.search(r"\(sample (\d+)\)", str(info.value)).group(1))
    q_pair = ps.inverse_kinematics(robot, ps.cubic(START, DOWN, T, traj.t_s[:k]),
                                   solver="seed").q[-1]
    # the seed's closed form at the next target alone (one sample: no step to compare)
    one = ps.Trajectory(traj.t_s[k:k + 1], traj.x[k:k + 1], traj.xd[k:k + 1],
                        traj.xdd[k:k + 1])
    q_next = ps.inverse_kinematics(robot, one, solver="seed").q[0]
    d = _det_phi_p(robot, np.stack([q_pair, q_next]))
    assert np.sign(d[0]) != np.sign(d[1]), d


def test_a_move_on_one_side_runs_with_seed_sized_torques(robot):
    """Stopping 30 mm above the curve: no refusal, and torques of the seed's size."""
    traj = _move(201, by=np.array([0.0, -0.080]))
    jt = ps.inverse_kinematics(robot, traj)
    det = _det_phi_p(robot, jt.q)
    assert np.all(np.sign(det) == np.sign(det[0]))
    tau, _ = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    assert np.max(np.abs(tau)) < 0.5  # N*m; the crossing move reached 3.5 to 113
