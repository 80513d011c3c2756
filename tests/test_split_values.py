"""The actuation matrix and the torque split (``planar_sym.dynamics.inverse``) as values, against
references built without them: the survivors of mutation testing (issue 30).

1. Trees: the inertial, velocity and gravity parts against Pinocchio, M(q) qdd from CRBA, the
   links' C(q, qd) qd as RNEA(q, qd, 0) less the generalised gravity, g(q) from
   ``computeGeneralizedGravity``; on the seed 2-DOF arm and on the geared one
   (``examples/serial_2dof_geared.toml``: the same links, rotors and shoulder friction, which
   must not leak into the velocity part). Measured 3e-14 of the largest entry (asserted 1e-12).
2. Closed chains (the five-bar, two actuated angles; the slider-driven slider-crank, one
   actuated slider force), on the loops: each part has one column per actuated joint; the parts
   add up to the generated ``closed_chain_inverse_dynamics``; the gravity part is its torque at
   rest (qd = qdd = 0); starting from rest with an acceleration the velocity part is zero and
   the inertial part is its torque with g = 0.
3. The slider-crank's actuation matrix [S^T Phi_q^T] by hand: S^T the unit column of the slide
   coordinate, Phi_q = d(B_rod - B_slider)/dq from the crank r = 153 mm and the rod l = 306 mm.
4. A singular pose is refused by Phi_p's 1-norm condition number, naming the time: near the
   dead centre (crank angle 4.6e-6 rad, O, A and B nearly in line) Phi_p = [[0, r s],
   [x, x - r c]] has a 1-norm condition number (x + (x - r c)) / (r s) = 1.09e6 > 1e6 while its
   2-norm one is 9.4e5 < 1e6: the figure in the message is the 1-norm one; a crank angle of
   0.01 rad (condition number 500) passes.
5. Exact numbers (fractions.Fraction) are read as floats: the same split bit for bit.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pinocchio as pin
import pytest
from conftest import ROOT
from pinocchio_model import pinocchio_model

import planar_sym as ps
from planar_sym.dynamics.inverse import SPLIT_PARTS, actuation_matrix, torque_split
from planar_sym.errors import WorkspaceError
from planar_sym.model import description
from planar_sym.motion.closure import complete_rates, solve_passive

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"
TOL = 1e-12


def _pinocchio_parts(q, qd, qdd):
    """(inertial, velocity, gravity) of the seed 2-DOF arm's links, by Pinocchio, (N, 2) each."""
    model, _ = pinocchio_model(description.load("serial_2dof"))
    data = model.createData()
    out = np.empty((3, len(q), model.nv))
    for k in range(len(q)):
        mass = pin.crba(model, data, q[k])
        mass = np.triu(mass) + np.triu(mass, 1).T  # CRBA fills the upper triangle
        gravity = pin.computeGeneralizedGravity(model, data, q[k]).copy()
        bias = pin.rnea(model, data, q[k], qd[k], np.zeros(model.nv)).copy()
        out[:, k] = mass @ qdd[k], bias - gravity, gravity
    return out


@pytest.mark.parametrize("robot", ["serial_2dof", GEARED])
def test_tree_parts_against_pinocchio(robot):
    robot = ps.load(robot)
    rng = np.random.default_rng(30)
    q, qd, qdd = (rng.uniform(-3, 3, (25, 2)) for _ in range(3))
    parts = torque_split(robot, q, qd, qdd)
    assert list(parts) == list(SPLIT_PARTS)
    for name, ref in zip(("inertial", "velocity", "gravity"), _pinocchio_parts(q, qd, qdd)):
        assert parts[name].shape == (25, 2)
        assert np.abs(parts[name] - ref).max() <= TOL * np.abs(ref).max(), name
    if robot.drive_train.has_friction:  # the geared arm's shoulder rubs (up to 8e-3 N*m), more
        # than the velocity torques (up to 3.7e-3 N*m): filed under velocity it would show
        assert np.abs(parts["friction"]).max() > 2 * np.abs(parts["velocity"]).max()


def _on_loops(robot, rng, n_s=10, at_rest=False):
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + rng.uniform(-0.1, 0.1, (n_s, len(act)))
    q = np.vstack([solve_passive(robot, qa[None], robot.q_drawn) for qa in q_act])
    qd_act = np.zeros((n_s, len(act))) if at_rest else rng.uniform(-2, 2, (n_s, len(act)))
    qd, qdd = complete_rates(robot, q, qd_act, rng.uniform(-2, 2, (n_s, len(act))))
    return q, qd, qdd


@pytest.mark.parametrize("name", ["five_bar_type1", "slider_crank_slider_driven"])
def test_closed_chain_parts_against_the_generated_inverse_dynamics(name):
    robot = ps.load(name)
    rng = np.random.default_rng(31)
    n_act = len(robot.actuated)
    q, qd, qdd = _on_loops(robot, rng)
    parts = torque_split(robot, q, qd, qdd)
    tau, _ = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    scale = np.abs(tau).max()
    assert all(v.shape == (len(q), n_act) for v in parts.values())
    assert np.abs(sum(parts.values()) - tau).max() <= TOL * scale
    zero = np.zeros_like(q)
    statics, _ = robot.closed_chain_inverse_dynamics(q, zero, zero)
    assert np.abs(parts["gravity"] - statics).max() <= TOL * np.abs(statics).max()
    assert np.abs(parts["velocity"]).max() > 1e-3 * scale  # moving: a velocity part to get right
    # from rest: no velocity part; the inertial part is the torque without gravity
    q, qd, qdd = _on_loops(robot, rng, at_rest=True)
    assert not np.any(qd)
    parts = torque_split(robot, q, qd, qdd)
    weightless, _ = robot.with_parameters(g=0.0).closed_chain_inverse_dynamics(q, qd, qdd)
    assert np.abs(parts["velocity"]).max() <= TOL * np.abs(parts["gravity"]).max()
    assert np.abs(parts["inertial"] - weightless).max() <= TOL * np.abs(weightless).max()
    assert not np.any(parts["friction"]) and not np.any(parts["rotor"])


# -- the slider-crank, driven at its slider: the actuation matrix by hand ------------------------

def _slider_crank():
    robot = ps.load("slider_crank_slider_driven")
    assert robot.coordinates == ("O", "A", "slide") and robot.actuated == (2,)
    return robot


def _crank_pose(robot, theta):
    """q (N, 3) on the loop at crank angles theta (rad): x_B = r c + sqrt(l^2 - r^2 s^2), the
    rod's absolute angle phi from A to B; also x_B, phi."""
    p = robot.parameters
    r, l, s0 = p["px_crank_A"], p["px_rod_B"], p["s0_slide"]
    theta = np.asarray(theta, dtype=float)
    x = r * np.cos(theta) + np.sqrt(l * l - (r * np.sin(theta)) ** 2)
    phi = np.arctan2(-r * np.sin(theta), x - r * np.cos(theta))
    return np.column_stack([theta, phi - theta, x - s0]), x, phi


def _phi_q(robot, theta):
    """d(B_rod - B_slider)/d(theta, q_A, s), (N, 2, 3), by hand."""
    p = robot.parameters
    r, l = p["px_crank_A"], p["px_rod_B"]
    _, _, phi = _crank_pose(robot, theta)
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(phi), np.cos(phi)
    zero, one = np.zeros_like(st), np.ones_like(st)
    return np.stack([np.stack([-r * st - l * sp, -l * sp, -one], axis=-1),
                     np.stack([r * ct + l * cp, l * cp, zero], axis=-1)], axis=1)


def test_slider_crank_actuation_matrix_by_hand():
    robot = _slider_crank()
    theta = np.array([0.3, 1.1, 2.0, -0.7])
    q, _, _ = _crank_pose(robot, theta)
    assert np.abs(robot.constraint(q)).max() < 1e-15
    a = actuation_matrix(robot, q)
    assert a.shape == (4, 3, 3)
    assert np.array_equal(a[:, :, 0], np.tile([0.0, 0.0, 1.0], (4, 1)))  # S^T: the slide
    assert np.abs(a[:, :, 1:] - _phi_q(robot, theta).transpose(0, 2, 1)).max() < 1e-15


def _condition_numbers(robot, theta):
    """Phi_p's (passive columns O and A) 1-norm condition number from its explicit inverse, and
    its 2-norm one, by hand."""
    (p,) = _phi_q(robot, np.array([theta]))[:, :, :2]
    inv = np.array([[p[1, 1], -p[0, 1]], [-p[1, 0], p[0, 0]]]) / (p[0, 0] * p[1, 1]
                                                                    - p[0, 1] * p[1, 0])
    norm1 = lambda m: np.abs(m).sum(axis=0).max()
    sv = np.linalg.svd(p, compute_uv=False)
    return norm1(p) * norm1(inv), sv[0] / sv[1]


def test_singular_pose_refused_by_the_one_norm_condition_number_with_its_time():
    robot = _slider_crank()
    near_dead_centre = 4.6e-6  # rad
    cond_1, cond_2 = _condition_numbers(robot, near_dead_centre)
    assert cond_2 < 1e6 < cond_1  # only the 1-norm refuses this pose
    assert f"{cond_1:.3g}" == "1.09e+06"
    q, _, _ = _crank_pose(robot, [0.3, near_dead_centre, 0.01])
    t = np.array([0.0, 0.25, 0.5])
    tail = ("the passive-joint constraint Jacobian Phi_p (which the actuation matrix "
            "[S^T Phi_q^T] needs) has 1-norm condition number 1.09e+06 > 1e+06")
    timed = f"slider_crank_slider_driven: singular pose at t = 0.25 s (sample 1): {tail}"
    with pytest.raises(WorkspaceError) as exc:
        actuation_matrix(robot, q, t)
    assert str(exc.value) == timed
    with pytest.raises(WorkspaceError) as exc:
        actuation_matrix(robot, q)
    assert str(exc.value) == f"slider_crank_slider_driven: singular pose at sample 1: {tail}"
    zero = np.zeros_like(q)
    with pytest.raises(WorkspaceError) as exc:
        torque_split(robot, q, zero, zero, t=t)
    assert str(exc.value) == timed
    # a simulated motion's split (forward and control studies) names the time too
    from planar_sym.dynamics.inverse import split_along

    with pytest.raises(WorkspaceError) as exc:
        split_along(robot, q, zero, np.zeros((len(q), len(robot.actuated))), t=t)
    assert str(exc.value) == timed
    # inverse dynamics along the motion (an inverse study) refuses it first, by its time too
    from planar_sym.dynamics.along import inverse_along

    with pytest.raises(WorkspaceError) as exc:
        inverse_along(robot, t, q, zero, zero)
    assert str(exc.value) == timed
    # the neighbours pass: 0.01 rad from the dead centre is a condition number of 500
    assert _condition_numbers(robot, 0.01)[0] == pytest.approx(500.0, rel=1e-3)
    parts = torque_split(robot, q[[0, 2]], zero[:2], zero[:2], t=t[[0, 2]])
    assert parts["gravity"].shape == (2, 1)


def test_exact_numbers_are_read_as_floats():
    robot = ps.load("serial_2dof")
    q = [[Fraction(1, 2), Fraction(-3, 4)], [Fraction(2), Fraction(1, 8)]]
    qd = [[Fraction(1, 3), Fraction(2)], [Fraction(-1), Fraction(0)]]
    qdd = [[Fraction(-5, 2), Fraction(1, 8)], [Fraction(3), Fraction(-7, 4)]]
    exact = torque_split(robot, q, qd, qdd)
    floats = torque_split(robot, *(np.array(a, dtype=float) for a in (q, qd, qdd)))
    for k, v in floats.items():
        assert exact[k].dtype == np.float64 and exact[k].tobytes() == v.tobytes(), k


def test_split_along_a_simulated_motion_sums_to_the_applied_torques():
    """split_along (the forward and control studies' split): along a simulated motion under
    constant torques, the parts sum to the applied torques (to rounding) on a tree with a
    passive joint (cart-pole: the slider's force only, the hinge left out), a closed chain and
    a fully actuated arm; on the arm each part equals torque_split at the accelerations the
    forward dynamics gives, computed here directly."""
    from conftest import TEST_ROBOTS

    from planar_sym.dynamics.inverse import split_along

    cases = [(ps.load(TEST_ROBOTS / "cart_pole.toml"), [0.0, 0.4], [1.5]),
             (ps.load("five_bar_type1"), None, [0.02, -0.01]),
             (ps.load("serial_2dof"), [-1.0, 0.3], [0.05, -0.02])]
    for robot, q0, tau in cases:
        q0 = robot.q_drawn if q0 is None else np.array(q0)
        sim = ps.simulate(robot, q0, np.zeros(robot.n), (0.0, 0.3), torque=tau)
        applied = sim.tau[:, list(robot.actuated)] if sim.tau.shape[1] == robot.n else sim.tau
        parts = split_along(robot, sim.q, sim.qd, applied)
        assert all(v.shape == applied.shape for v in parts.values()), robot.name
        assert np.max(np.abs(sum(parts.values()) - applied)) < 1e-12, robot.name
    arm = cases[2][0]
    qdd = arm.forward_dynamics(sim.q, sim.qd, applied)
    direct = torque_split(arm, sim.q, sim.qd, qdd)
    for k, v in parts.items():
        assert np.array_equal(v, direct[k]), k


def test_near_a_singular_pose_the_forces_are_warned_about_with_the_time():
    """Issue 25, class 2: between COND_WARN (1e3) and the refusal (1e6) the results come back
    with a warning naming the first sample past 1e3 and the worst one, by the same 1-norm
    condition number, here checked against the explicit 2 x 2 inverse by hand; at 0.01 rad
    from the dead centre (500) there is none."""
    import warnings

    from planar_sym.dynamics.along import inverse_along

    robot = _slider_crank()
    theta = np.array([0.3, 0.01, 2e-4, 1e-4])  # rad from the dead centre
    q, _, _ = _crank_pose(robot, theta)
    zero = np.zeros_like(q)
    t = np.array([0.0, 0.5, 1.0, 1.5])
    by_hand = [_condition_numbers(robot, th)[0] for th in theta]
    assert by_hand[1] < 1e3 < by_hand[2] < by_hand[3] < 1e6
    with pytest.warns(RuntimeWarning) as caught:
        inv = inverse_along(robot, t, q, zero, zero)
    (w,) = caught
    assert str(w.message).startswith(
        f"slider_crank_slider_driven: near a singular pose from t = 1 s (sample 2): the "
        f"passive-joint constraint Jacobian Phi_p has 1-norm condition number "
        f"{by_hand[2]:.3g} (largest {by_hand[3]:.3g}, at t = 1.5 s (sample 3); refused above "
        "1e+06)")
    assert np.all(np.isfinite(inv.tau))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inverse_along(robot, t[:2], q[:2], zero[:2], zero[:2])
