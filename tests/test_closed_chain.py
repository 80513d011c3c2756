"""Closed chains (five_bar_type1, five_bar_type2, parallel_3rrr) against independent references.

Sign convention under test (planar_sym/dynamics/inverse.py):

.. code:: text

    M qdd + h = S^T tau + Phi_q^T lambda,    Phi = r(parent point) - r(child point),

lambda = force the cut joint's child body exerts on its parent body (the child feels -lambda).

References, none of them the multiplier solve under test:

* power balance: ``tau . qd_act = dE/dt``, dE/dt by a 4th-order central difference of the total
  energy on the inverse-kinematics trajectory re-run at t +- h, t +- 2h (h = 1 ms; truncation
  error ~ h^4, rounding ~ eps E / h, both measured ~1e-11 of the peak power);
* virtual work with Pinocchio: RNEA on the spanning tree (Pinocchio model built here from the
  description) and the loop Jacobian from Pinocchio's point Jacobians give the null-space matrix
  G (qd = G qd_act), ``tau = G^T (M qdd + h)``, ``lambda = Phi_p^-T (M qdd + h)_p``;
* the sign of lambda from free bodies in static poses (moments about a passive joint);
* forward kinematics, loop residuals, energy conservation and the actuated-joint route.

Error measure ``rel``: per sample, the largest absolute difference divided by the largest
absolute reference entry, worst over the samples (for joint rates, which vanish at the ends of
a trajectory: over the whole trajectory at once).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import seed_studies, study_motion
from pinocchio_model import pinocchio_model
from pinocchio_model import xyz as _xyz

from planar_sym.dynamics.forward import simulate
from planar_sym.model import description
from planar_sym.model.description import GROUND
from planar_sym.model.locate import load
from planar_sym.motion import closure

SCENARIOS = seed_studies()

CLOSED_ROBOTS = ("five_bar_type1", "five_bar_type2", "parallel_3rrr")
CLOSED_SCENARIOS = tuple(n for n, s in SCENARIOS.items() if s.robot in CLOSED_ROBOTS)

POWER_TOL = 1e-9  # |tau.qd_act - dE/dt| / peak |power| (measured ~1e-11)
ROUTE_TOL = 1e-9  # virtual work (Pinocchio) vs multiplier solve, relative (measured ~1e-14)
PHI_TOL_M = 1e-12
FK_TOL_M = 1e-12
FREE_DRIFT_M = 1e-9
FREE_ENERGY_TOL = 1e-8  # max |E(t) - E(0)| / max kinetic energy
ACT_ROUTE_TOL = 1e-10


def rel(actual, reference, whole: bool = False) -> float:
    """Per sample (or, ``whole``, over the whole array: for rates that vanish at the ends)."""
    a = np.asarray(actual, dtype=float)
    b = np.asarray(reference, dtype=float)
    assert a.shape == b.shape, (a.shape, b.shape)
    if whole:
        return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))
    a, b = a.reshape(len(a), -1), b.reshape(len(b), -1)
    return float(np.max(np.max(np.abs(a - b), axis=1) / np.max(np.abs(b), axis=1)))


def _rot2(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


class PinTree:
    """Pinocchio model of the spanning tree of a description, with frames at the points of the
    cut joints and at the task point. One RZ joint per revolute tree joint (angle = child frame
    angle minus parent frame angle), welded bodies appended to their parent's joint."""

    def __init__(self, desc: description.Description):
        model, where = pinocchio_model(desc)

        def point_frame(label, body, point):
            jid, pl = where[body]
            xy = desc.bodies[body].points_m[point]
            return model.addFrame(pin.Frame(label, jid, pl * pin.SE3(np.eye(3), _xyz(xy)),
                                            pin.FrameType.OP_FRAME))

        self.cuts = [(point_frame(f"{j.name}_parent", j.parent, j.parent_point),
                      point_frame(f"{j.name}_child", j.child, j.child_point))
                     for j in desc.loop_joints]
        self.task = point_frame("task", *desc.task_point)
        self.model, self.data = model, model.createData()

    def rnea(self, q, qd, qdd) -> np.ndarray:
        return np.array([pin.rnea(self.model, self.data, a, b, c).copy()
                         for a, b, c in zip(q, qd, qdd)])

    def loops(self, q) -> tuple[np.ndarray, np.ndarray]:
        """Phi (N, 2 loops) and Phi_q (N, 2 loops, n) from Pinocchio's point Jacobians."""
        phis, jacs = [], []
        for qk in q:
            pin.computeJointJacobians(self.model, self.data, qk)
            pin.updateFramePlacements(self.model, self.data)
            phi, jac = [], []
            for fp, fc in self.cuts:
                phi += list(self.data.oMf[fp].translation[:2] - self.data.oMf[fc].translation[:2])
                jp = pin.getFrameJacobian(self.model, self.data, fp, pin.LOCAL_WORLD_ALIGNED)
                jc = pin.getFrameJacobian(self.model, self.data, fc, pin.LOCAL_WORLD_ALIGNED)
                jac += list((jp - jc)[:2])
            phis.append(phi)
            jacs.append(jac)
        return np.array(phis), np.array(jacs)

    def task_point(self, q) -> np.ndarray:
        out = []
        for qk in q:
            pin.framesForwardKinematics(self.model, self.data, qk)
            out.append(self.data.oMf[self.task].translation[:2].copy())
        return np.array(out)


_CACHE: dict = {}


def scenario_motion(name: str, t=None):
    """(robot, target trajectory (SI), joint trajectory) of a closed-chain seed study."""
    return study_motion(name, t)


def pin_tree(robot_name: str) -> tuple[description.Description, PinTree]:
    if robot_name not in _CACHE:
        desc = description.load(robot_name)
        _CACHE[robot_name] = (desc, PinTree(desc))
    return _CACHE[robot_name]


# -- power balance --------------------------------------------------------------------------------

@pytest.mark.parametrize("name", CLOSED_SCENARIOS)
def test_power_balance(name):
    """sum tau_i qd_act_i = dE/dt of all bodies, dE/dt from the energy alone."""
    sc = SCENARIOS[name]
    T, h = sc.motion.duration_s, 1e-3
    t = np.linspace(0.05, T - 0.05, 41)  # interior: t +- 2h stays inside [0, T]
    robot, _, jt = scenario_motion(name, t)
    tau, _ = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=t)
    power = np.sum(tau * jt.qd[:, list(robot.actuated)], axis=1)

    def energy(shift):
        _, _, j = scenario_motion(name, t + shift)
        kin, pot = robot.energy(j.q, j.qd)
        return kin + pot

    de_dt = (energy(-2 * h) - 8 * energy(-h) + 8 * energy(h) - energy(2 * h)) / (12 * h)
    peak = np.max(np.abs(power))
    assert peak > 1e-3, f"{name}: peak power {peak:.3g} W: the test would be trivial"
    err = float(np.max(np.abs(power - de_dt)) / peak)
    print(f"{name}: power balance error {err:.2e} of peak {peak:.4g} W")
    assert err < POWER_TOL, f"{name}: |tau.qd - dE/dt| = {err:.3e} of peak power"


# -- second route: virtual work with Pinocchio ---------------------------------------------------

@pytest.mark.parametrize("name", CLOSED_SCENARIOS)
def test_torques_by_virtual_work_pinocchio(name):
    sc = SCENARIOS[name]
    robot, _, jt = scenario_motion(name, np.linspace(0.0, sc.motion.duration_s, 41))
    _, tree = pin_tree(sc.robot)
    tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd, t=jt.t_s)

    b = tree.rnea(jt.q, jt.qd, jt.qdd)  # M qdd + h of the spanning tree
    phi, jac = tree.loops(jt.q)
    assert np.max(np.abs(phi)) < PHI_TOL_M
    act = list(robot.actuated)
    pas = [i for i in range(robot.n) if i not in act]
    n_act = len(act)
    tau_ref, lam_ref = [], []
    for bk, jk in zip(b, jac):
        G = np.zeros((robot.n, n_act))
        G[act] = np.eye(n_act)
        G[pas] = -np.linalg.solve(jk[:, pas], jk[:, act])
        assert np.max(np.abs(jk @ G)) < 1e-12
        tau_ref.append(G.T @ bk)
        lam_ref.append(np.linalg.solve(jk[:, pas].T, bk[pas]))  # passive rows: no torque
    tau_ref, lam_ref = np.array(tau_ref), np.array(lam_ref)
    e_tau, e_lam = rel(tau, tau_ref), rel(lam, lam_ref)
    print(f"{name}: virtual work vs multipliers: tau {e_tau:.2e}, lambda {e_lam:.2e}")
    assert e_tau < ROUTE_TOL
    assert e_lam < ROUTE_TOL


@pytest.mark.parametrize("robot_name", CLOSED_ROBOTS)
def test_constraint_functions_vs_pinocchio(robot_name):
    """Phi and Phi_q of the compiled code at random (off-manifold) poses, against Pinocchio:
    the residual checks below are meaningless if Phi were identically small."""
    robot = load(robot_name)
    _, tree = pin_tree(robot_name)
    q = np.random.default_rng(5).uniform(-np.pi, np.pi, (30, robot.n))
    phi, jac = tree.loops(q)
    assert np.min(np.max(np.abs(phi), axis=1)) > 1e-3
    assert rel(robot.constraint(q), phi) < 1e-12
    assert rel(robot.constraint_jacobian(q), jac) < 1e-12


# -- sign of lambda: free bodies in static poses ---------------------------------------------------

def _world_points(robot, desc, q):
    """world position of (body, point) and of each body's CG at pose q, from robot.frames."""
    fr = robot.frames(q)
    frames = {b: fr[i] for i, b in enumerate(robot.body_names)}

    def at(body, xy):
        o = frames[body]
        return o[:2] + _rot2(o[2]) @ np.asarray(xy)

    def point(body, name):
        if body == GROUND:
            return np.asarray(desc.bodies[GROUND].points_m[name])
        return at(body, desc.bodies[body].points_m[name])

    def cg(body):
        return at(body, desc.bodies[body].cg_m)

    return point, cg


def _cross(r, f) -> float:
    return float(r[0] * f[1] - r[1] * f[0])


def _static_poses(robot_name):
    out = [load(robot_name).q_drawn]
    for name in CLOSED_SCENARIOS:
        if SCENARIOS[name].robot == robot_name:
            _, _, jt = scenario_motion(name, np.array([0.7, SCENARIOS[name].motion.duration_s]))
            out += list(jt.q)
    return out


@pytest.mark.parametrize("robot_name", CLOSED_ROBOTS)
def test_lambda_sign_static_free_bodies(robot_name):
    """qd = qdd = 0: the moment about a passive pin joint of a body hanging on a cut joint is
    zero when the cut joint's child feels -lambda and its parent +lambda (and not otherwise).

    5-bars: R_Link2 (child of cut C) about D; L_Link2 (parent of C) about B.
    3-RRR: the platform (child of cuts B2, B3) about B1; Link2_2 (parent of B2) about elbow2;
    Link3_2 (parent of B3) about elbow3.
    """
    robot = load(robot_name)
    desc = description.load(robot_name)
    grav = np.asarray(desc.gravity_m_s2)
    cuts = {j.name: j for j in desc.loop_joints}
    joints = {j.name: j for j in desc.tree_joints}
    if robot_name.startswith("five_bar"):
        checks = [("R_Link2", "D"), ("L_Link2", "B")]
    else:
        checks = [("platform", "B1"), ("Link2_2", "elbow2"), ("Link3_2", "elbow3")]
    worst = flipped = 0.0
    for q in _static_poses(robot_name):
        z = np.zeros(robot.n)
        assert np.max(np.abs(robot.constraint(q))) < PHI_TOL_M
        _, lam = robot.closed_chain_inverse_dynamics(q[None], z[None], z[None])
        lam = lam[0]
        point, cg = _world_points(robot, desc, q)
        for body, pivot_joint in checks:
            pj = joints[pivot_joint]
            pivot = point(pj.child, pj.child_point)
            weight = desc.bodies[body].mass_kg * grav
            m_weight = _cross(cg(body) - pivot, weight)
            m_lam = 0.0
            for k, loop in enumerate(robot.loops):
                cut = cuts[loop]
                force = lam[2 * k:2 * k + 2]
                if cut.child == body:  # child feels -lambda
                    m_lam += _cross(point(cut.child, cut.child_point) - pivot, -force)
                elif cut.parent == body:  # parent feels +lambda
                    m_lam += _cross(point(cut.parent, cut.parent_point) - pivot, force)
            scale = np.linalg.norm(weight) * 0.1  # the weight on a 0.1 m lever
            resid = abs(m_weight + m_lam) / scale
            flipped = max(flipped, abs(m_weight - m_lam) / scale)
            worst = max(worst, resid)
            assert resid < 1e-10, (f"{robot_name}: moment of {body} about {pivot_joint} = "
                                   f"{resid:.3e} of its weight times 0.1 m")
    print(f"{robot_name}: static free-body moment residual {worst:.1e}, with lambda's sign "
          f"flipped {flipped:.2f}")
    assert flipped > 0.05, "the opposite sign of lambda would pass too"


# -- loop residual, inverse kinematics, actuated route -------------------------------------------

@pytest.mark.parametrize("name", CLOSED_SCENARIOS)
def test_loop_residual_and_ik_round_trip(name):
    robot, tr, jt = scenario_motion(name)
    _, tree = pin_tree(SCENARIOS[name].robot)
    phi = np.max(np.abs(robot.constraint(jt.q)))
    phi_pin = np.max(np.abs(tree.loops(jt.q[::10])[0]))
    fk = np.max(np.abs(robot.task(jt.q)[0] - tr.x))
    fk_pin = np.max(np.abs(tree.task_point(jt.q) - tr.x[:, :2]))
    print(f"{name}: max |Phi| {phi:.1e} m (Pinocchio {phi_pin:.1e}), FK error {fk:.1e} "
          f"(Pinocchio {fk_pin:.1e})")
    assert phi < PHI_TOL_M and phi_pin < PHI_TOL_M
    assert fk < FK_TOL_M and fk_pin < FK_TOL_M
    # rates consistent with the loops: Phi_q qd = 0
    jac = robot.constraint_jacobian(jt.q)
    assert np.max(np.abs(np.einsum("kij,kj->ki", jac, jt.qd))) < 1e-12


@pytest.mark.parametrize("name", CLOSED_SCENARIOS)
def test_from_actuated_matches_ik(name):
    robot, _, jt = scenario_motion(name)
    act = list(robot.actuated)
    via = closure.from_actuated(robot, jt.t_s, jt.q[:, act], jt.qd[:, act],
                                     jt.qdd[:, act], q_guess=robot.q_drawn)
    errs = {k: rel(getattr(via, k), getattr(jt, k), whole=True) for k in ("q", "qd", "qdd")}
    print(f"{name}: actuated route vs IK: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items()))
    assert all(v < ACT_ROUTE_TOL for v in errs.values()), errs


# -- forward dynamics: free motion keeps the loops closed and the energy --------------------------

@pytest.mark.parametrize("robot_name", CLOSED_ROBOTS)
def test_free_motion_from_drawn_pose(robot_name):
    robot = load(robot_name)
    sim = simulate(robot, robot.q_drawn, np.zeros(robot.n), (0.0, 10.0),
                   t_eval=np.linspace(0.0, 10.0, 1001))
    e = sim.energy_j
    drift_e = float(np.max(np.abs(e - e[0])) / np.max(sim.kinetic_j))
    phi = float(np.max(np.abs(robot.constraint(sim.q))))
    print(f"{robot_name}: 10 s free motion: constraint drift {sim.constraint_drift_m:.1e} m, "
          f"energy drift {drift_e:.1e} of peak kinetic {np.max(sim.kinetic_j):.3g} J")
    assert np.max(np.ptp(sim.q, axis=0)) > 1.0, "the chain did not move"
    assert phi == pytest.approx(sim.constraint_drift_m, abs=1e-15)
    assert sim.constraint_drift_m < FREE_DRIFT_M
    assert drift_e < FREE_ENERGY_TOL
    assert sim.energy_drift < FREE_ENERGY_TOL  # the package's own figure says the same
