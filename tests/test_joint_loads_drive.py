"""Joint loads with a drive train are link side, on a geared 2-DOF arm
(``examples/serial_2dof_geared.toml``: a rotor on the ground and one carried by link1, friction
at the shoulder) and a geared, rubbing RPR arm (``tests/robots/rpr_geared.toml``: a rotor at
every joint, two of them on moving bodies, viscous and Coulomb friction everywhere, a screw-
driven boom):

1. every body's free-body balance closes with the reported loads (1e-12; the balance built in
   ``tests/test_reactions.py`` from the loads, gravity, the accelerations and the rotors' spin
   J (alpha_stator + N qdd) on the body carrying each stator);
2. the drive balance, from the parameters read by name here: the actuator's generalised force
   (the inverse dynamics' tau) is the link-side couple (revolute) or axial force (prismatic)
   plus the friction b qd + c tanh(qd / v_s) plus the rotor's N J (alpha_stator + N qdd) (1e-12);
3. the motor torque is tau / N.

Before, a revolute joint's couple was the motor-side tau (0.284 of 0.313 N*m on the geared arm
balanced) and the boom's axial force was called the actuator force (3.1 N apart).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS
from test_reactions import free_body_residuals

import planar_sym as ps
from planar_sym.dynamics.reactions import joint_loads

ROBOTS = {"geared_2dof": ROOT / "examples" / "serial_2dof_geared.toml",
          "rpr_geared": TEST_ROBOTS / "rpr_geared.toml"}
TOL = 1e-12


@pytest.fixture(scope="module", params=list(ROBOTS))
def case(request):
    robot = ps.load(ROBOTS[request.param])
    rng = np.random.default_rng(11)
    n_s = 40
    q = robot.q_drawn + rng.uniform(-0.5, 0.5, (n_s, robot.n))
    qd, qdd = rng.uniform(-2, 2, (n_s, robot.n)), rng.uniform(-4, 4, (n_s, robot.n))
    qd[:3] = rng.uniform(-0.02, 0.02, (3, robot.n))  # near rest: Coulomb friction turning over
    return robot, q, qd, qdd, joint_loads(robot, q, qd, qdd)


def test_every_body_balances_with_drives(case):
    robot, q, qd, qdd, loads = case
    res_f, res_m = free_body_residuals(robot, q, qd, qdd, loads)
    assert res_f < TOL and res_m < TOL, (res_f, res_m)


def test_the_drive_balance(case):
    robot, q, qd, qdd, loads = case
    p, manifest = robot.parameters, robot.library.manifest
    tau = robot.inverse_dynamics(q, qd, qdd)
    alpha = robot.body_motion(q, qd, qdd)[0][:, 2, :]  # (N, bodies) rad/s^2
    bodies = list(robot.body_names)
    joints = {j["name"]: j for j in manifest["joints"]}
    scale = np.abs(tau).max()
    checked = 0
    for name, j in joints.items():
        if not j.get("actuated"):
            continue
        c = j["coordinate"]
        friction = p[f"fv_{name}"] * qd[:, c] + p[f"fc_{name}"] * np.tanh(qd[:, c] /
                                                                       p[f"vs_{name}"]) \
            if f"fv_{name}" in p else 0.0
        stator = alpha[:, bodies.index(j["parent"])] if j["parent"] != "ground" else 0.0
        ratio, inertia = p[f"gear_{name}"], p.get(f"jm_{name}", 0.0)
        rotor = ratio * inertia * (stator + ratio * qdd[:, c])
        i = loads.index(name)
        link = loads.axial[name] if j["type"] == "prismatic" else loads.couple[:, i]
        assert np.array_equal(loads.drive[name], tau[:, c])
        err = np.abs(tau[:, c] - (link + friction + rotor)).max()
        assert err < TOL * scale, (name, err / scale)
        assert np.abs(loads.motor_torque[name] - tau[:, c] / ratio).max() <= \
            1e-15 * np.abs(tau[:, c]).max()
        # the drive's share is not negligible here: the test would see a motor-side couple
        assert np.abs(friction + rotor).max() > 1e-3 * scale
        checked += 1
    assert checked == robot.n
