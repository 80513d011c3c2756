"""Robots with prismatic joints against independent references: the built-in slider_crank,
slider_crank_slider_driven, serial_rpr and parallel_3rpr, and the test robot
tests/robots/cart_pole_incline.toml (a tilted rail given in world coordinates, point masses,
no task; tests/test_sliders.py checks tests/robots/cart_pole.toml against analytic equations).

References and tolerances (``rel_err`` of conftest: per-sample normwise relative):

* trees (serial_rpr, cart_pole_incline): M, h, g, tau, forward dynamics, energies, frames
  and the task against Pinocchio's crba, nonLinearEffects, computeGeneralizedGravity, rnea,
  aba and kinematics, at random states, to 1e-10 (measured about 3e-15);
* closed chains: their spanning trees the same way, and the actuator forces and the cut-joint
  forces against Pinocchio's tree dynamics projected through the loops:
  ``b = rnea(q, qd, qdd)``, ``Phi_q`` from Pinocchio's frame Jacobians of the two points of
  every cut joint (not our generated Phi_q), ``[S^T  Phi_q^T] [tau; lambda] = b`` solved with
  numpy, compared with ``closed_chain_inverse_dynamics`` to 1e-9 (measured about 1e-14), on
  the loops: along each built-in study and along random smooth actuated motions;
* power balance along each new built-in study: the work of the actuators,
  ``integral of tau . qd_actuated dt`` by 20-point Gauss-Legendre on pieces where the motion
  is smooth (the trapezoid's speed kinks are piece ends), against ``E(t) - E(0)`` with
  ``E = T + V`` from ``robot.energy``, at every piece end: 1e-10 of the largest ``|E - E(0)|``
  (measured below 1e-13);
* forward of inverse dynamics (as tests/test_roundtrip.py: ``simulate`` with the study's
  exact torque at every time it asks, in segments of at most 0.25 s started from the exact
  state, the trapezoid's kinks at segment ends): every coordinate within 1e-8 rad or m
  (measured below 1e-10);
* the slider-crank's slider position and speed along the crank study against the closed form
  ``x = l1 cos th + sqrt(l2^2 - (l1 sin th)^2)``: 1e-12 m and 1e-10 m/s; the rod angle and,
  along the slider-driven study, the crank angle from the same triangle: 1e-12 rad;
* the slider-driven slider-crank refuses a move that reaches or passes a dead centre;
* the drawing shows each slider (rail and block at the described points, 1e-9 mm) and the
  equation report names the prismatic coordinates d<k>.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import GENERATED, TEST_ROBOTS, random_states, record, rel_err, study_motion
from pinocchio_model import pinocchio_tree, xyz

import planar_sym as ps
from planar_sym.dynamics.forward import simulate
from planar_sym.errors import WorkspaceError
from planar_sym.model import description
from planar_sym.model.description import GROUND
from planar_sym.model.locate import load
from planar_sym.study.run import load_study, run

TREE_TOL = 1e-10
CLOSED_TOL = 1e-9
POWER_TOL = 1e-10
ROUND_TRIP_TOL = 1e-8
N_SAMPLES = 40

NEW_TREES = ("serial_rpr",)
NEW_CLOSED = ("slider_crank", "slider_crank_slider_driven", "parallel_3rpr")
NEW_ROBOTS = NEW_TREES + NEW_CLOSED
NEW_STUDIES = ("slider_crank_turn", "slider_crank_slider_driven_stroke", "serial_rpr_tool_move",
               "parallel_3rpr_move_x")
PRISMATIC = {"slider_crank": ["slide"], "slider_crank_slider_driven": ["slide"],
             "serial_rpr": ["extend"], "parallel_3rpr": ["leg1", "leg2", "leg3"]}

# Flores, Leine & Glocker (2010), Table 1 (SI)
L1, L2 = 0.153, 0.306


def _robot(name: str, derived):
    """(description, Robot) of a built-in robot or a test robot of tests/robots."""
    if (TEST_ROBOTS / f"{name}.toml").is_file():
        path = TEST_ROBOTS / f"{name}.toml"
        return description.load(path), derived(path)[1]
    return description.load(name), load(name)


# -- Pinocchio, our coordinate order ----------------------------------------------------------

class Pin:
    """Pinocchio's tree of a description, called with our coordinate order."""

    def __init__(self, desc):
        self.desc = desc
        self.tree = pinocchio_tree(desc)
        self.model = self.tree.model
        self.frames = {}
        for j in desc.loop_joints:  # the two points of each cut joint
            for body, point in ((j.parent, j.parent_point), (j.child, j.child_point)):
                self.frames[(body, point)] = self._frame(body, point)
        if desc.task_point is not None:
            self.frames[desc.task_point] = self._frame(*desc.task_point)
        self.data = self.model.createData()

    def _frame(self, body, point) -> int:
        jid, pl = self.tree.where[body]
        placement = pl * pin.SE3(np.eye(3), xyz(self.desc.bodies[body].points_m[point]))
        return self.model.addFrame(pin.Frame(f"{body}.{point}", jid, placement,
                                             pin.FrameType.OP_FRAME))

    def each(self, fn, *arrays):
        """``fn(*per-sample arrays in Pinocchio's order)`` for every sample, back in ours."""
        out = [self.tree.from_pin(fn(*[self.tree.to_pin(a[k]) for a in arrays]))
               for k in range(len(arrays[0]))]
        return np.array(out)

    def mass_matrix(self, q):
        def one(qk):
            m = pin.crba(self.model, self.data, qk)
            return np.triu(m) + np.triu(m, 1).T
        return np.array([self.tree.matrix_from_pin(one(self.tree.to_pin(qk))) for qk in q])

    def rnea(self, q, qd, qdd):
        return self.each(lambda a, b, c: pin.rnea(self.model, self.data, a, b, c).copy(),
                         q, qd, qdd)

    def point_jacobian(self, qk, key) -> tuple[np.ndarray, np.ndarray]:
        """World position (2,) and Jacobian (2, n), our columns, of a body point at one q."""
        qp = self.tree.to_pin(qk)
        jac = pin.computeFrameJacobian(self.model, self.data, qp, self.frames[key],
                                       pin.LOCAL_WORLD_ALIGNED)
        pin.updateFramePlacements(self.model, self.data)
        return (self.data.oMf[self.frames[key]].translation[:2].copy(),
                self.tree.from_pin(jac[:2]))

    def constraint(self, qk) -> tuple[np.ndarray, np.ndarray]:
        """Phi (parent point minus child point at each cut joint) and Phi_q, from Pinocchio."""
        phi, rows = [], []
        for j in self.desc.loop_joints:
            a, ja = self.point_jacobian(qk, (j.parent, j.parent_point))
            b, jb = self.point_jacobian(qk, (j.child, j.child_point))
            phi.append(a - b)
            rows.append(ja - jb)
        return np.concatenate(phi), np.vstack(rows)

    def closed_inverse_dynamics(self, q, qd, qdd, actuated):
        """Actuator forces and cut-joint forces: [S^T Phi_q^T] [tau; lambda] = rnea (tree)."""
        b = self.rnea(q, qd, qdd)
        n, na = q.shape[1], len(actuated)
        s_t = np.zeros((n, na))
        s_t[list(actuated), range(na)] = 1.0
        tau, lam, gap = [], [], 0.0
        for k in range(len(q)):
            phi, phi_q = self.constraint(q[k])
            gap = max(gap, float(np.max(np.abs(phi))))
            x = np.linalg.solve(np.hstack([s_t, phi_q.T]), b[k])
            tau.append(x[:na])
            lam.append(x[na:])
        return np.array(tau), np.array(lam), gap


def _check(worst, key, actual, reference, tol):
    err = record(worst, key, rel_err(actual, reference))
    assert err < tol, f"{key}: worst relative error {err:.3e} >= {tol:g}"
    return err


# -- trees: every dynamic and kinematic quantity -----------------------------------------------

@pytest.fixture(scope="module", params=["serial_rpr", "cart_pole_incline"])
def tree_case(request, derived):
    desc, robot = _robot(request.param, derived)
    assert not robot.is_closed_chain
    assert "m" in robot.coordinate_units  # a prismatic joint, else this proves nothing new
    q, qd, qdd = random_states(np.random.default_rng(31), N_SAMPLES, robot.n)
    return request.param, desc, robot, (q, qd, qdd), Pin(desc)


def test_tree_dynamics_vs_pinocchio(tree_case, worst_errors):
    name, _, robot, (q, qd, qdd), ref = tree_case
    m, d = ref.model, ref.data
    _check(worst_errors, f"prismatic M {name}", robot.mass_matrix(q), ref.mass_matrix(q),
           TREE_TOL)
    h = ref.each(lambda a, b: pin.nonLinearEffects(m, d, a, b).copy(), q, qd)
    _check(worst_errors, f"prismatic h {name}", robot.bias(q, qd), h, TREE_TOL)
    g = ref.each(lambda a: pin.computeGeneralizedGravity(m, d, a).copy(), q)
    _check(worst_errors, f"prismatic g {name}", robot.gravity(q), g, TREE_TOL)
    _check(worst_errors, f"prismatic rnea {name}", robot.inverse_dynamics(q, qd, qdd),
           ref.rnea(q, qd, qdd), TREE_TOL)
    tau = qdd  # random forces and torques
    aba = ref.each(lambda a, b, c: pin.aba(m, d, a, b, c).copy(), q, qd, tau)
    _check(worst_errors, f"prismatic aba {name}", robot.forward_dynamics(q, qd, tau), aba,
           TREE_TOL)


def test_tree_energy_and_kinematics_vs_pinocchio(tree_case, worst_errors):
    name, desc, robot, (q, qd, _), ref = tree_case
    m, d = ref.model, ref.data
    kin, pot = robot.energy(q, qd)
    t_ref = np.array([pin.computeKineticEnergy(m, d, ref.tree.to_pin(a), ref.tree.to_pin(b))
                      for a, b in zip(q, qd)])
    v_ref = np.array([pin.computePotentialEnergy(m, d, ref.tree.to_pin(a)) for a in q])
    _check(worst_errors, f"prismatic kinetic {name}", kin, t_ref, TREE_TOL)
    assert np.max(np.abs(pot - v_ref)) < TREE_TOL * np.max(np.abs(v_ref))
    # every body's frame: origin and angle
    frames = robot.frames(q)
    names = [b for b in desc.bodies if b != GROUND]
    want = []
    for qk in q:
        pin.forwardKinematics(m, d, ref.tree.to_pin(qk))
        row = []
        for b in names:
            jid, pl = ref.tree.where[b]
            o = d.oMi[jid] * pl
            row.append([o.translation[0], o.translation[1],
                        math.atan2(o.rotation[1, 0], o.rotation[0, 0])])
        want.append(row)
    want = np.array(want)
    _check(worst_errors, f"prismatic frames {name}", frames[:, :, :2], want[:, :, :2], TREE_TOL)
    assert np.max(np.abs(np.angle(np.exp(1j * (frames[:, :, 2] - want[:, :, 2]))))) < TREE_TOL
    if desc.task_point is None:  # cart_pole_incline: no task
        with pytest.raises(ps.InputError, match="no task point"):
            robot.task(q)
        return
    x, jac, _ = robot.task(q, qd)
    xs, js = zip(*(ref.point_jacobian(qk, desc.task_point) for qk in q))
    _check(worst_errors, f"prismatic task x {name}", x[:, :2], np.array(xs), TREE_TOL)
    _check(worst_errors, f"prismatic task J {name}", jac[:, :2], np.array(js), TREE_TOL)


def test_cart_pole_incline_is_what_it_claims():
    """The test robot exercises a tilted axis in world coordinates and point masses."""
    desc = description.load(TEST_ROBOTS / "cart_pole_incline.toml")
    rail = desc.tree_joints[0]
    assert rail.type == "prismatic" and 0.1 < abs(rail.axis[1]) < 0.9
    assert all(b.point_mass for n, b in desc.bodies.items() if n != GROUND)
    assert desc.task_point is None
    assert "izz_cart" not in {p.name for p in desc.parameters()}


# -- closed chains: spanning tree, then torques and loop forces --------------------------------

@pytest.mark.parametrize("name", NEW_CLOSED)
def test_closed_chain_spanning_tree_vs_pinocchio(name, worst_errors):
    desc, robot = description.load(name), load(name)
    ref = Pin(desc)
    q, qd, qdd = random_states(np.random.default_rng(5), N_SAMPLES, robot.n)
    _check(worst_errors, f"prismatic tree M {name}", robot.mass_matrix(q), ref.mass_matrix(q),
           TREE_TOL)
    _check(worst_errors, f"prismatic tree rnea {name}", robot.tree_inverse_dynamics(q, qd, qdd),
           ref.rnea(q, qd, qdd), TREE_TOL)
    # our generated loop residual and Jacobian agree with Pinocchio's points (any q)
    phi, phi_q = zip(*(ref.constraint(qk) for qk in q))
    _check(worst_errors, f"prismatic Phi {name}", robot.constraint(q), np.array(phi), TREE_TOL)
    _check(worst_errors, f"prismatic Phi_q {name}", robot.constraint_jacobian(q),
           np.array(phi_q), TREE_TOL)


def _wavy_motion(name: str, robot):
    """A smooth motion of the actuated joints about the drawn pose (exact rates), passive joints
    from the loops: states on the loops with sizable velocities and accelerations."""
    rng = np.random.default_rng(17)
    t = np.linspace(0.0, 1.0, N_SAMPLES)
    act = list(robot.actuated)
    amp = np.array([0.03 if robot.coordinate_units[i] == "m" else 0.6 for i in act])
    amp = amp * rng.uniform(0.5, 1.0, len(act))
    w = rng.uniform(3.0, 8.0, len(act))
    ph = rng.uniform(0.0, 2 * np.pi, len(act))
    arg = w * t[:, None] + ph
    q0 = np.asarray(robot.q_drawn)[act]
    q_a = q0 + amp * (np.sin(arg) - np.sin(ph))
    return ps.from_actuated(robot, t, q_a, amp * w * np.cos(arg), -amp * w**2 * np.sin(arg))


@pytest.mark.parametrize("source", ["study", "wavy"])
@pytest.mark.parametrize("name", NEW_CLOSED)
def test_closed_chain_forces_vs_pinocchio_projected(name, source, worst_errors):
    desc, robot = description.load(name), load(name)
    if source == "study":
        study = next(s for s in NEW_STUDIES if load_study(s).robot == name)
        jt = study_motion(study, np.linspace(0.0, load_study(study).motion.duration_s or 0.75,
                                             N_SAMPLES))[2]
    else:
        jt = _wavy_motion(name, robot)
    tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    tau_ref, lam_ref, gap = Pin(desc).closed_inverse_dynamics(jt.q, jt.qd, jt.qdd,
                                                              robot.actuated)
    assert gap < 1e-12  # the states close Pinocchio's loops too (m)
    assert np.max(np.abs(jt.qd)) > 0.01 and np.max(np.abs(jt.qdd)) > 0.01  # a real motion
    both = np.hstack([tau, lam])
    err = _check(worst_errors, f"prismatic closed tau+lambda {name} {source}", both,
                 np.hstack([tau_ref, lam_ref]), CLOSED_TOL)
    print(f"{name} ({source}): tau and lambda vs Pinocchio projected, {err:.1e}")


def test_projected_comparison_detects_a_small_mass_change():
    """Negative control: the slider 1e-6 (relative) heavier is seen far above the tolerance."""
    robot = load("slider_crank")
    jt = _wavy_motion("slider_crank", robot)
    ref = Pin(description.load("slider_crank"))
    tau_ref, lam_ref, _ = ref.closed_inverse_dynamics(jt.q, jt.qd, jt.qdd, robot.actuated)
    heavy = robot.with_parameters(m_slider=0.076 * (1 + 1e-6))
    tau, lam = heavy.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    assert rel_err(np.hstack([tau, lam]), np.hstack([tau_ref, lam_ref])) > 100 * CLOSED_TOL


# -- along the built-in studies --------------------------------------------------------------

def _pieces(name: str) -> list[float]:
    """Times (s) splitting a study into pieces where its motion is smooth, at most 0.25 s."""
    st = load_study(name)
    m = st.motion
    if m.profile == "trapezoid":
        ramp = m.v_max[0] / m.a_max[0]  # one channel: the time to reach the cruise speed
        span = abs(m.by[0]) / m.v_max[0] + ramp
        kinks = [0.0, ramp, span - ramp, span]
    else:
        kinks = [0.0, m.duration_s]
    edges = []
    for a, b in itertools.pairwise(kinks):
        k = max(1, math.ceil((b - a) / 0.25 - 1e-9))
        edges += list(np.linspace(a, b, k + 1)[:-1])
    return [*edges, kinks[-1]]


def _torque(robot, jt):
    if robot.is_closed_chain:
        return robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)[0]
    return robot.inverse_dynamics(jt.q, jt.qd, jt.qdd)


@pytest.mark.parametrize("name", NEW_STUDIES)
def test_power_balance_along_the_study(name, worst_errors):
    """Work of the actuators = change of kinetic plus potential energy, at every piece end."""
    edges = _pieces(name)
    nodes, weights = np.polynomial.legendre.leggauss(20)
    t, w = [], []
    for a, b in itertools.pairwise(edges):
        t += [a, *(a + (b - a) * (nodes + 1) / 2)]
        w += [0.0, *((b - a) / 2 * weights)]
    t, w = np.array([*t, edges[-1]]), np.array([*w, 0.0])
    robot, _, jt = study_motion(name, t)
    act = list(robot.actuated)
    power = np.sum(_torque(robot, jt) * jt.qd[:, act], axis=1)
    kin, pot = robot.energy(jt.q, jt.qd)
    energy = kin + pot
    at_edge = np.isin(t, edges)
    work = np.cumsum(w * power)[at_edge]
    change = (energy - energy[0])[at_edge]
    scale = np.max(np.abs(energy - energy[0]))
    err = record(worst_errors, f"power balance {name}", float(np.max(np.abs(work - change))) / scale)
    print(f"{name}: work vs energy change over {len(edges) - 1} pieces, {err:.1e} of "
          f"{scale:.4g} J (peak power {np.max(np.abs(power)):.4g} W)")
    assert scale > 1e-3 and np.max(np.abs(power)) > 1e-2  # energy really flows
    assert err < POWER_TOL


class StudyMotion:
    """A study's joint motion at any single time, exactly as the study computes it (profile,
    then inverse kinematics or the loops), with the Newton solve started from the nearest
    sample of a dense run of the study: the continuation the study itself does (a solve
    started from the drawn pose may land in another assembly mode far from it)."""

    def __init__(self, name: str, times=()):
        from planar_sym.study.motion import profile_at

        self.profile_at = profile_at
        self.st = load_study(name)
        self.span = _pieces(name)[-1]
        self.dense_t = np.unique(np.concatenate([np.linspace(0.0, self.span, 2001), times]))
        self.robot, _, dense = study_motion(name, self.dense_t)
        self.dense_q = dense.q

    def __call__(self, t):
        from planar_sym.motion.closure import from_actuated
        from planar_sym.motion.ik import inverse_kinematics
        from planar_sym.motion.profiles import JointTrajectory

        t = np.clip(np.atleast_1d(np.asarray(t, dtype=float)), 0.0, self.span)
        guess = self.dense_q[int(np.argmin(np.abs(self.dense_t - t[0])))]
        tr = self.profile_at(self.st, self.robot, t)
        if self.st.motion.space == "task":
            return inverse_kinematics(self.robot, tr, solver=self.st.motion.ik, q_start=guess)
        if self.robot.is_closed_chain:
            return from_actuated(self.robot, tr.t_s, tr.x, tr.xd, tr.xdd, q_guess=guess)
        return JointTrajectory(tr.t_s, tr.x, tr.xd, tr.xdd)


@pytest.mark.parametrize("name", NEW_STUDIES)
def test_forward_of_inverse_dynamics(name, worst_errors):
    """``simulate`` driven by the study's own torques follows the study's motion."""
    pieces = [np.linspace(a, b, 11) for a, b in itertools.pairwise(_pieces(name))]
    motion = StudyMotion(name, np.concatenate(pieces))
    robot = motion.robot

    def torque(t: float) -> np.ndarray:
        return _torque(robot, motion(t))[0]

    worst, moved = 0.0, 0.0
    for t in pieces:
        a, b = t[0], t[-1]
        ref = motion(t)
        on_run = motion.dense_q[np.searchsorted(motion.dense_t, t)]
        assert np.max(np.abs(ref.q - on_run)) < 1e-11  # the study's own motion, continued
        sim = simulate(robot, ref.q[0], ref.qd[0], (a, b), torque=torque, t_eval=t,
                       rtol=1e-11, atol=1e-12)
        worst = max(worst, float(np.max(np.abs(sim.q - ref.q))))
        moved = max(moved, float(np.max(np.abs(ref.q - ref.q[0]))))
    record(worst_errors, f"round trip {name}", worst)
    print(f"{name}: forward of inverse dynamics, max error {worst:.2e} (rad or m)")
    assert moved > 0.01
    assert worst < ROUND_TRIP_TOL


def test_slider_position_along_the_crank_study_is_the_closed_form():
    res = run("slider_crank_turn")
    c = res.columns
    th, thd = c["q1_rad"], c["qd1_rad_s"]
    assert np.degrees(th[-1] - th[0]) == pytest.approx(450.0, abs=1e-9)  # dead centres passed
    root = np.sqrt(L2**2 - (L1 * np.sin(th)) ** 2)
    x = L1 * np.cos(th) + root
    xd = -L1 * np.sin(th) * thd - L1**2 * np.sin(th) * np.cos(th) * thd / root
    robot = load("slider_crank")
    s0 = robot.parameters["s0_slide"]
    assert np.max(np.abs(s0 + c["q3_m"] - x)) < 1e-12
    assert np.max(np.abs(c["qd3_m_s"] - xd)) < 1e-10
    # the slider body itself is there (frames: independent of the coordinate bookkeeping)
    q = np.column_stack([c[f"q{k}_{u}"] for k, u in ((1, "rad"), (2, "rad"), (3, "m"))])
    slider = robot.frames(q)[:, robot.body_names.index("slider")]
    assert np.max(np.abs(slider[:, 0] - x)) < 1e-12 and np.max(np.abs(slider[:, 1:])) < 1e-12
    # the rod: phi2 = -asin(l1 sin th / l2), its coordinate relative to the crank
    rod = -np.arcsin(L1 * np.sin(th) / L2) - th
    assert np.max(np.abs(np.angle(np.exp(1j * (c["q2_rad"] - rod))))) < 1e-12


@pytest.mark.parametrize(("by_mm", "what"), [
    (0.459e3 - 352.3246725729952 + 5.0, "outside the workspace"),   # past x = l1 + l2
    (0.459e3 - 352.3246725729952, "singular pose"),                  # to x = l1 + l2
    (0.153e3 - 352.3246725729952, "singular pose"),                  # to x = l2 - l1
    (0.153e3 - 352.3246725729952 - 5.0, "outside the workspace")])  # past x = l2 - l1
def test_slider_driven_crank_refuses_a_dead_centre(tmp_path, by_mm, what):
    from planar_sym.study.builtin import find

    text = find("slider_crank_slider_driven_stroke").read_text().replace(
        "by = [-150.0]", f"by = [{by_mm!r}]")
    assert f"by = [{by_mm!r}]" in text
    study = tmp_path / "dead_centre.toml"
    study.write_text(text)
    with pytest.raises(WorkspaceError, match=what):
        run(study)


def test_slider_driven_crank_angle_is_the_closed_form():
    """Along the slider-driven study the crank angle is the triangle's: l2^2 = x^2 + l1^2 -
    2 x l1 cos th (crank above the axis), the slider at x = s0 + d3."""
    c = run("slider_crank_slider_driven_stroke").columns
    robot = load("slider_crank_slider_driven")
    x = robot.parameters["s0_slide"] + c["q3_m"]
    th = np.arccos((x**2 + L1**2 - L2**2) / (2 * x * L1))
    assert np.max(np.abs(c["q1_rad"] - th)) < 1e-12
    assert np.degrees(th[0]) == pytest.approx(60.0, abs=1e-9)
    assert np.degrees(th[-1]) == pytest.approx(118.2373, abs=1e-4)  # x = 202.32 mm
    assert np.max(np.abs(c["tau3_n"])) < 10.0  # N: far from a dead centre's blow-up


# -- pictures and the printed equations --------------------------------------------------------

@pytest.mark.parametrize("name", NEW_ROBOTS)
def test_drawing_shows_each_slider(name, tmp_path):
    from planar_sym.cli import main
    from planar_sym.outputs.drawing import drawing_figure

    out = tmp_path / f"{name}.png"
    assert main(["--quiet", "draw", name, "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    desc, robot = description.load(name), load(name)
    fig = drawing_figure(name)
    arts = {a.get_gid(): a for a in fig.axes[0].get_children() if a.get_gid()}
    frames = robot.frames(np.atleast_2d(robot.q_drawn))[0]

    def world(body, point):
        if body == GROUND:
            return np.array(desc.bodies[GROUND].points_m[point])
        x, y, a = frames[robot.body_names.index(body)]
        px, py = desc.bodies[body].points_m[point]
        return np.array([x + math.cos(a) * px - math.sin(a) * py,
                         y + math.sin(a) * px + math.cos(a) * py])

    for joint in PRISMATIC[name]:
        j = next(j for j in desc.tree_joints if j.name == joint)
        rail = np.column_stack(arts[f"rail:{joint}"].get_data())  # m: the robot is typed in m
        a, b = world(j.parent, j.parent_point), world(j.child, j.child_point)
        u = (rail[1] - rail[0]) / np.linalg.norm(rail[1] - rail[0])
        for p in (a, b):  # the rail passes through both points
            assert abs((p - rail[0])[0] * u[1] - (p - rail[0])[1] * u[0]) < 1e-12
        block = arts[f"joint:{joint}"].get_xy()[:4]
        assert np.max(np.abs(block.mean(axis=0) - b)) < 1e-12  # the block sits on the slider
        assert (arts[f"joint:{joint}"].get_facecolor()[0] == 0.0) == j.actuated  # black: driven
    import matplotlib.pyplot as plt

    plt.close(fig)


@pytest.mark.parametrize("name", NEW_ROBOTS)
def test_equation_report_names_the_prismatic_coordinates(name):
    text = (GENERATED / name / "equations.txt").read_text()
    coords = description.load(name).coordinates
    line = next(ln for ln in text.splitlines() if ln.startswith("Coordinates"))
    for k, c in enumerate(coords, start=1):
        letter = "d" if c in PRISMATIC[name] else "q"
        assert f"{letter}{k} = {c}" in line, (name, c, line)
    assert "(N)" in text  # a prismatic joint's force is in N
