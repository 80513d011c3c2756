"""The compiled dynamics against Pinocchio, a model built generically from the description.

The Pinocchio model of a description is built in tests/pinocchio_model.py.

Tolerance: ``rel_err`` of conftest (per-sample normwise relative) below 1e-10.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import ALL_ROBOTS, CLOSED, TEST_ROBOTS, TREES, random_states, record, rel_err
from pinocchio_model import pinocchio_model
from pinocchio_model import xyz as _xyz

from planar_sym.model import description
from planar_sym.model.description import GROUND
from planar_sym.model.locate import load

TOL = 1e-10
N_SAMPLES = 50


def _task_frames(model, where, desc):
    """Add OP frames at the task point and at the orientation body's frame."""
    body, point = desc.task_point
    jid, pl = where[body]
    tool = pl * pin.SE3(np.eye(3), _xyz(desc.bodies[body].points_m[point]))
    f_point = model.addFrame(pin.Frame("task_point", jid, tool, pin.FrameType.OP_FRAME))
    f_orient = None
    if desc.task_orientation:
        jid_o, pl_o = where[desc.task_orientation]
        f_orient = model.addFrame(pin.Frame("task_orientation", jid_o, pl_o,
                                            pin.FrameType.OP_FRAME))
    return f_point, f_orient


class Reference:
    """Everything Pinocchio says about one robot at a batch of states."""

    def __init__(self, desc, q, qd, qdd):
        model, where = pinocchio_model(desc)
        f_point, f_orient = _task_frames(model, where, desc)
        data = model.createData()
        assert model.nq == model.nv == len(desc.coordinates)
        self.names = [b for b in desc.bodies if b != GROUND]
        M, h, tau, T, V, frames, x, J, jdq = ([] for _ in range(9))
        for qk, vk, ak in zip(q, qd, qdd):
            Mk = pin.crba(model, data, qk)
            M.append(np.triu(Mk) + np.triu(Mk, 1).T)
            h.append(pin.nonLinearEffects(model, data, qk, vk).copy())
            tau.append(pin.rnea(model, data, qk, vk, ak).copy())
            T.append(pin.computeKineticEnergy(model, data, qk, vk))
            V.append(pin.computePotentialEnergy(model, data, qk))
            pin.forwardKinematics(model, data, qk, vk, np.zeros_like(vk))
            pin.updateFramePlacements(model, data)
            rows = []
            for b in self.names:
                jid, pl = where[b]
                o = data.oMi[jid] * pl
                rows.append([o.translation[0], o.translation[1],
                             math.atan2(o.rotation[1, 0], o.rotation[0, 0])])
            frames.append(rows)
            frame_ids = [f_point] + ([f_orient] if f_orient is not None else [])
            Jk = pin.computeFrameJacobian(model, data, qk, f_point, pin.LOCAL_WORLD_ALIGNED)
            xk = list(data.oMf[f_point].translation[:2])
            Jrows = [Jk[0], Jk[1]]
            a = pin.getFrameClassicalAcceleration(model, data, f_point, pin.LOCAL_WORLD_ALIGNED)
            jk = list(a.linear[:2])
            if len(frame_ids) == 2:
                R = data.oMf[f_orient].rotation
                xk.append(math.atan2(R[1, 0], R[0, 0]))
                Jo = pin.computeFrameJacobian(model, data, qk, f_orient, pin.LOCAL_WORLD_ALIGNED)
                Jrows.append(Jo[5])
                ao = pin.getFrameClassicalAcceleration(model, data, f_orient,
                                                       pin.LOCAL_WORLD_ALIGNED)
                jk.append(ao.angular[2])
            x.append(xk)
            J.append(np.array(Jrows))
            jdq.append(jk)
        self.M, self.h, self.tau = np.array(M), np.array(h), np.array(tau)
        self.T, self.V = np.array(T), np.array(V)
        self.frames, self.x = np.array(frames), np.array(x)
        self.J, self.jdot_qd = np.array(J), np.array(jdq)


CASES = ALL_ROBOTS + ("bent_arm",)  # bent_arm: tests/robots, rotated weld and tilted gravity


@pytest.fixture(scope="module", params=CASES)
def case(request, derived):
    name = request.param
    if name in ALL_ROBOTS:
        desc, robot = description.load(name), load(name)
    else:
        path = TEST_ROBOTS / f"{name}.toml"
        desc, robot = description.load(path), derived(path)[1]
    rng = np.random.default_rng(CASES.index(name) + 11)
    q, qd, qdd = random_states(rng, N_SAMPLES, robot.n)
    return name, desc, robot, (q, qd, qdd), Reference(desc, q, qd, qdd)


def _check(worst, key, actual, reference, tol=TOL):
    err = record(worst, key, rel_err(actual, reference))
    assert err < tol, f"{key}: worst relative error {err:.3e} >= {tol:g}"


def test_mass_matrix(case, worst_errors):
    name, _, robot, (q, _, _), ref = case
    _check(worst_errors, f"pin M {name}", robot.mass_matrix(q), ref.M)


def test_bias(case, worst_errors):
    name, _, robot, (q, qd, _), ref = case
    _check(worst_errors, f"pin h {name}", robot.bias(q, qd), ref.h)


def test_gravity(case, worst_errors):
    name, desc, robot, (q, _, _), _ = case
    model, _ = pinocchio_model(desc)
    data = model.createData()
    g_ref = np.array([pin.computeGeneralizedGravity(model, data, qk).copy() for qk in q])
    _check(worst_errors, f"pin g {name}", robot.gravity(q), g_ref)


def test_inverse_dynamics(case, worst_errors):
    name, _, robot, (q, qd, qdd), ref = case
    _check(worst_errors, f"pin rnea {name}", robot.tree_inverse_dynamics(q, qd, qdd), ref.tau)
    if not robot.is_closed_chain:
        _check(worst_errors, f"pin rnea {name}", robot.inverse_dynamics(q, qd, qdd), ref.tau)


@pytest.mark.parametrize("which", ["serial_2dof", "serial_3dof", "bent_arm"])
def test_forward_dynamics_vs_aba(which, worst_errors, derived):
    if which in TREES:
        desc, robot = description.load(which), load(which)
    else:
        path = TEST_ROBOTS / f"{which}.toml"
        desc, robot = description.load(path), derived(path)[1]
    model, _ = pinocchio_model(desc)
    data = model.createData()
    rng = np.random.default_rng(7)
    q, qd, tau = random_states(rng, N_SAMPLES, robot.n)
    ref = np.array([pin.aba(model, data, a, b, c).copy() for a, b, c in zip(q, qd, tau)])
    _check(worst_errors, f"pin aba {which}", robot.forward_dynamics(q, qd, tau), ref)


def test_energy(case, worst_errors):
    """Pinocchio's potential energy is -sum m g.c (zero at the world origin), like ours."""
    name, _, robot, (q, qd, _), ref = case
    T, V = robot.energy(q, qd)
    _check(worst_errors, f"pin kinetic {name}", T, ref.T)
    # V changes sign over the workspace: relative to the largest |V| of the batch
    err = record(worst_errors, f"pin potential {name}",
                 float(np.max(np.abs(V - ref.V)) / np.max(np.abs(ref.V))))
    assert err < TOL


def test_pinocchio_potential_sign_convention():
    """A point mass 1 kg at height 2 m under g = 9.81 down: Pinocchio says +19.62 J."""
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    jid = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "j")
    model.appendBodyToJoint(jid, pin.Inertia(1.0, np.array([2.0, 0.0, 0.0]), np.zeros((3, 3))),
                            pin.SE3.Identity())
    data = model.createData()
    assert pin.computePotentialEnergy(model, data, np.array([math.pi / 2])) == pytest.approx(19.62)


def test_frames(case, worst_errors):
    name, _, robot, (q, _, _), ref = case
    fr = robot.frames(q)
    assert fr.shape == ref.frames.shape
    _check(worst_errors, f"pin frame origins {name}", fr[:, :, :2], ref.frames[:, :, :2])
    dang = np.angle(np.exp(1j * (fr[:, :, 2] - ref.frames[:, :, 2])))
    err = record(worst_errors, f"pin frame angles {name}", float(np.max(np.abs(dang))))
    assert err < TOL


def test_task(case, worst_errors):
    name, desc, robot, (q, qd, _), ref = case
    x, J, jdq = robot.task(q, qd)
    _check(worst_errors, f"pin task x {name}", x[:, :2], ref.x[:, :2])
    if desc.task_orientation:
        dphi = np.angle(np.exp(1j * (x[:, 2] - ref.x[:, 2])))
        assert np.max(np.abs(dphi)) < TOL
    _check(worst_errors, f"pin task J {name}", J, ref.J)
    _check(worst_errors, f"pin task Jdot qd {name}", jdq, ref.jdot_qd)


def test_pinocchio_model_matches_description_structure():
    """The reference model itself: one joint per coordinate, total mass of every body."""
    for name in ALL_ROBOTS:
        desc = description.load(name)
        model, _ = pinocchio_model(desc)
        assert model.njoints - 1 == len(desc.coordinates)
        total = sum(b.mass_kg for b in desc.bodies.values())
        assert sum(I.mass for I in model.inertias) == pytest.approx(total, rel=1e-14)
    assert set(CLOSED).isdisjoint(TREES)


def test_bent_arm_exercises_rotated_weld_and_tilted_gravity():
    """The extra test robot really has what it is there for (else the comparison proves less)."""
    desc = description.load(TEST_ROBOTS / "bent_arm.toml")
    weld = next(j for j in desc.tree_joints if j.type == "weld")
    rel = desc.bodies[weld.child].drawn_angle_rad - desc.bodies[weld.parent].drawn_angle_rad
    assert abs(rel) > 0.1
    assert desc.tree_joints[-1].parent == "bracket"
    assert desc.gravity_m_s2[0] != 0.0
    assert all(b.cg_m[1] != 0.0 for n, b in desc.bodies.items() if n != GROUND)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_comparison_detects_a_small_parameter_change(name):
    """Negative control: a mass 1e-6 (relative) off is seen far above the tolerance."""
    desc = description.load(name)
    robot = load(name)
    heaviest = max((b for b in desc.bodies.values() if b.name != GROUND), key=lambda b: b.mass_kg)
    wrong = robot.with_parameters(**{f"m_{heaviest.name}": heaviest.mass_kg * (1 + 1e-6)})
    q, qd, qdd = random_states(np.random.default_rng(3), 5, robot.n)
    ref = Reference(desc, q, qd, qdd)
    assert rel_err(robot.tree_inverse_dynamics(q, qd, qdd), ref.tau) < TOL
    assert rel_err(wrong.tree_inverse_dynamics(q, qd, qdd), ref.tau) > 100 * TOL
