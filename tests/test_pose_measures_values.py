"""planar_sym.analysis.pose_measures called directly (not through the atlas), value by value,
against independent routes:

* ``_ratio`` and ``_safe_inverse`` against numpy.linalg.cond / numpy.linalg.inv on hand-made
  stacks (a zero matrix, an exactly singular one, empty ones), with warnings as errors;
* ``envelope`` and ``rest_torques`` against a brute-force sweep of 3600 unit directions of the
  task acceleration (the max of |tau_k| per joint and the direction where it is reached), with
  A rebuilt from the robot's own Jacobians by numpy (serial_2dof: J in closed form from
  a1 = px_link1_CS2, a2 = px_link2_CS2; five_bar_type1: K = [Phi_q; J] solved by numpy) and the
  public inverse dynamics;
* ``inverse_dynamics_at_rest`` with rates against the 2-link arm's velocity terms in closed
  form and the five-bar's public ``closed_chain_inverse_dynamics``, and its NaN exactly above
  COND_LIMIT;
* ``stacked``'s Jdot qd against closed form (serial_2dof) and central differences of J along
  qd (five_bar_type1, serial_rpr).

2-link arm (planar_sym/robots/serial_2dof.toml), s1 = sin q1, s12 = sin(q1 + q2), ...:

.. code:: text

    J = [[-a1 s1 - a2 s12, -a2 s12], [a1 c1 + a2 c12, a2 c12]]
    Jdot qd = -a1 (c1, s1) qd1^2 - a2 (c12, s12) (qd1 + qd2)^2
    C(q, qd) qd = H s2 (-(2 qd1 qd2 + qd2^2), qd1^2),  H = m_link2 a1 cgx_link2
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis import pose_measures as pm
from planar_sym.model.loops import COND_LIMIT
from planar_sym.motion.seed_ik import SEED_SOLVERS

DIRECTIONS = 3600
ANGLES = np.linspace(0.0, 2 * np.pi, DIRECTIONS, endpoint=False)
#: serial_2dof poses: gravity torques of both signs at joint 1 (q1 = 2.5: arm to the left)
ARM_Q = np.array([[0.3, 1.2], [2.5, -1.0], [1.9, 2.2], [-0.4, -1.7]])
#: five_bar_type1 task points (m), inside its working mode
BAR_X = np.array([[0.0, 0.15], [0.03, 0.17], [-0.02, 0.12], [0.06, 0.14]])


def unit(angle):
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


@pytest.fixture(scope="module")
def bar():
    robot = ps.load("five_bar_type1")
    q = SEED_SOLVERS["five_bar_type1"](robot, np.arange(len(BAR_X), dtype=float), BAR_X)
    assert np.max(np.abs(robot.constraint(q))) < 1e-15
    return robot, q


def arm_jacobian(robot, q):
    a1, a2 = robot.parameters["px_link1_CS2"], robot.parameters["px_link2_CS2"]
    q1, q12 = q[:, 0], q[:, 0] + q[:, 1]
    return np.stack([np.stack([-a1 * np.sin(q1) - a2 * np.sin(q12), -a2 * np.sin(q12)], -1),
                     np.stack([a1 * np.cos(q1) + a2 * np.cos(q12), a2 * np.cos(q12)], -1)], 1)


def brute_force(torque, accel):
    """max over the 3600 directions u of |tau_k(accel u)| and the angle of the maximiser,
    ``torque(xdd)`` (D, 2) -> (D, na)."""
    tau = torque(accel * unit(ANGLES))
    worst = np.argmax(np.abs(tau), axis=0)
    return np.max(np.abs(tau), axis=0), ANGLES[worst]


def check_envelope(found, k, torque, accel):
    """found (rest_torques' output) at pose k against the brute force; returns the relative
    difference of the envelope."""
    brute, angle = brute_force(torque, accel)
    env = found["envelope"][k]
    assert np.all(brute <= env * (1 + 1e-12)), (brute, env)
    rel = float(np.max(np.abs(brute - env) / env))
    assert rel < 1e-6, rel
    assert np.all(np.abs(wrap(angle - found["envelope_angle_rad"][k])) <= np.pi / DIRECTIONS)
    return rel


# -- _ratio and _safe_inverse ----------------------------------------------------------------


def test_ratio_against_numpy_cond_and_zero_for_a_zero_matrix():
    """s_min / s_max = 1 / cond_2 for regular matrices; exactly 0.0 for an exactly singular
    one and for the all-zero matrix (s_max = 0: no 0 / 0, no RuntimeWarning)."""
    rng = np.random.default_rng(3)
    regular = rng.normal(size=(3, 2, 2))
    mats = np.concatenate([regular, [np.zeros((2, 2)), [[2.0, 0.0], [0.0, 0.0]]]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = pm._ratio(mats)
        zero = pm._ratio(np.zeros((2, 3, 3)))
    assert r.dtype == float and r.shape == (5,)
    assert np.allclose(r[:3], 1 / np.linalg.cond(regular), rtol=1e-13, atol=0)
    assert r[3] == 0.0 and r[4] == 0.0
    assert np.array_equal(zero, [0.0, 0.0])


def test_ratio_of_matrices_without_columns_is_one():
    """0 x 0 (a tree's Phi_p) and k x 0 (loops but no passive coordinate): no Type II, 1."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.array_equal(pm._ratio(np.zeros((3, 0, 0))), np.ones(3))
        assert np.array_equal(pm._ratio(np.zeros((3, 2, 0))), np.ones(3))


def test_safe_inverse_nan_only_at_the_singular_matrices():
    rng = np.random.default_rng(5)
    mats = rng.normal(size=(4, 3, 3))
    mats[1] = [[1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [4.0, 5.0, 6.0]]  # det exactly 0
    mats[2] = 0.0
    given = mats.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inv, bad = pm._safe_inverse(mats)
    assert np.array_equal(mats, given)  # the input is not overwritten
    assert np.array_equal(bad, [False, True, True, False])
    assert inv.dtype == float and np.isnan(inv[[1, 2]]).all()
    for k in (0, 3):
        assert np.allclose(inv[k], np.linalg.inv(mats[k]), rtol=1e-13, atol=1e-13)
        assert np.allclose(inv[k] @ mats[k], np.eye(3), atol=1e-12)


# -- envelope --------------------------------------------------------------------------------


def test_envelope_by_hand_against_a_sweep():
    """b of both signs and 0: the envelope |b_k| + a ||A_k|| and the direction of its maximum
    from a sweep of b_k + a A_k u; at b_k = 0 both u = +-A_k / ||A_k|| are worst and the
    function reports +A_k's angle (a smooth map where gravity vanishes)."""
    b = np.array([[0.7, -0.3, 0.0], [-2.0, 0.05, 0.0]])
    A = np.array([[[0.2, -0.5], [0.4, 0.1], [-0.3, 0.6]],
                  [[-1.0, -0.2], [0.02, -0.03], [0.0, 0.0]]])
    for accel in (1.0, 2.5):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            out = pm.envelope(b, A, accel)
        tau = b[..., None] + accel * np.einsum("nki,di->nkd", A, unit(ANGLES))
        assert np.allclose(out["envelope"], np.max(np.abs(tau), axis=-1), rtol=1e-6, atol=0)
        assert np.allclose(out["envelope"], np.abs(b) + accel * np.hypot(*np.moveaxis(A, -1, 0)),
                           rtol=1e-15, atol=0)
        nonzero = b != 0
        swept = ANGLES[np.argmax(np.abs(tau), axis=-1)]
        assert np.all(np.abs(wrap(swept - out["envelope_angle_rad"]))[nonzero]
                      <= np.pi / DIRECTIONS)
        assert out["envelope_angle_rad"][0, 2] == pytest.approx(np.arctan2(0.6, -0.3), abs=1e-15)
    # NaN rows (singular poses) stay NaN, quietly
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pm.envelope(np.full((1, 2), np.nan), np.full((1, 2, 2), np.nan), 1.0)
    assert np.isnan(out["envelope"]).all() and np.isnan(out["envelope_angle_rad"]).all()


# -- rest_torques ----------------------------------------------------------------------------


def test_arm_rest_torques_against_a_sweep(arm):
    """serial_2dof: qdd = J^-1 xdd with J in closed form, tau = inverse_dynamics; gravity of
    both signs at joint 1; accel 1 (the default) and 2."""
    J = arm_jacobian(arm, ARM_Q)
    assert np.allclose(J, arm.task(ARM_Q)[1], rtol=0, atol=1e-15)
    tau_g = arm.inverse_dynamics(ARM_Q, 0 * ARM_Q, 0 * ARM_Q)
    assert (tau_g[:, 0] < 0).any() and (tau_g[:, 0] > 0).any()
    worst = 0.0
    for accel in (1.0, 2.0):
        found = pm.rest_torques(arm, ARM_Q, accel)
        assert np.allclose(found["gravity"], tau_g, rtol=1e-13, atol=0)
        for k, q in enumerate(ARM_Q):
            def torque(xdd, q=q, k=k):
                qdd = np.linalg.solve(J[k], xdd.T).T
                return arm.inverse_dynamics(np.tile(q, (len(xdd), 1)), 0 * qdd, qdd)
            worst = max(worst, check_envelope(found, k, torque, accel))
            A = np.stack([torque(np.eye(2)[[i]])[0] - tau_g[k] for i in (0, 1)], -1)
            assert np.allclose(found["A"][k], A, rtol=1e-10, atol=1e-15)
    print(f"\nserial_2dof: envelope vs {DIRECTIONS}-direction sweep {worst:.1e} relative")


def test_five_bar_rest_torques_against_a_sweep(bar):
    """five_bar_type1: qdd = [Phi_q; J]^-1 [0; xdd] by numpy from the robot's Jacobians, tau
    by closed_chain_inverse_dynamics; joint 1's gravity torque is negative, joint 3's
    positive."""
    robot, q = bar
    K = np.concatenate([robot.constraint_jacobian(q), robot.task(q)[1]], axis=1)
    tau_g, _ = robot.closed_chain_inverse_dynamics(q, 0 * q, 0 * q)
    assert (tau_g[:, 0] < 0).all() and (tau_g[:, 1] > 0).all()
    worst = 0.0
    for accel in (1.0, 2.0):
        found = pm.rest_torques(robot, q, accel)
        assert np.allclose(found["gravity"], tau_g, rtol=1e-13, atol=0)
        for k in range(len(q)):
            def torque(xdd, k=k):
                rhs = np.column_stack([np.zeros((len(xdd), 2)), xdd])
                qdd = np.linalg.solve(K[k], rhs.T).T
                qs = np.tile(q[k], (len(xdd), 1))
                return robot.closed_chain_inverse_dynamics(qs, 0 * qs, qdd)[0]
            worst = max(worst, check_envelope(found, k, torque, accel))
    print(f"\nfive_bar_type1: envelope vs {DIRECTIONS}-direction sweep {worst:.1e} relative")


def test_rest_torques_default_accel_is_one_and_the_envelope_scales(bar):
    robot, q = bar
    default = pm.rest_torques(robot, q)
    one = pm.rest_torques(robot, q, accel_m_s2=1.0)
    two = pm.rest_torques(robot, q, accel_m_s2=2.0)
    for key in default:
        assert np.array_equal(default[key], one[key]), key
    assert np.array_equal(two["A"], one["A"]) and np.array_equal(two["gravity"], one["gravity"])
    part = one["envelope"] - np.abs(one["gravity"])
    assert np.all(part > 0)
    assert np.allclose(two["envelope"] - np.abs(two["gravity"]), 2 * part, rtol=1e-12, atol=0)
    assert np.array_equal(two["envelope_angle_rad"], one["envelope_angle_rad"])


def test_rest_torques_nan_where_K_is_exactly_singular(arm):
    """serial_2dof stretched (q2 = 0): det J is exactly 0, no torque map: every output NaN
    at that pose, gravity included; the regular pose in the same call is unchanged."""
    q = np.array([[0.7, 0.0], [0.3, 1.2]])
    assert np.linalg.det(arm.task(q)[1])[0] == 0.0
    found = pm.rest_torques(arm, q)
    alone = pm.rest_torques(arm, q[1:])
    for key, v in found.items():
        assert np.isnan(v[0]).all(), key
        assert np.allclose(v[1], alone[key][0], rtol=1e-14, atol=0), key


def five_bar_type2_pose(robot):
    """B, C, D collinear (tests/test_atlas.py, left leg at 90 deg): a Type II pose."""
    p = robot.parameters
    E, l2, l4, l5 = np.array([p["px_ground_E"], 0.0]), p["px_L_Link1_CS2"], \
        p["px_R_Link2_CS2"], p["px_R_Link1_CS2"]
    l3v = np.array([p["px_L_Link2_CS2"], p.get("py_L_Link2_CS2", 0.0)])
    l3 = np.hypot(*l3v)
    qa = np.pi / 2
    B = l2 * unit(qa)
    d = E - B
    r = np.hypot(*d)
    along = ((l3 + l4) ** 2 - l5**2 + r**2) / (2 * r)
    D = B + along * d / r + np.sqrt((l3 + l4) ** 2 - along**2) * np.array([-d[1], d[0]]) / r
    w = (D - B) / (l3 + l4)
    C = B + l3 * w
    theta = np.arctan2(w[1], w[0]) - np.arctan2(l3v[1], l3v[0])
    de = np.arctan2(*(D - E)[::-1])
    return np.array([qa, theta - qa, de, np.arctan2(*(C - D)[::-1]) - de])


def test_rest_torques_nan_at_a_type2_pose_of_the_five_bar(bar):
    robot, q = bar
    q2 = five_bar_type2_pose(robot)
    assert np.max(np.abs(robot.constraint(q2))) < 1e-15
    Pp = np.reshape(robot.constraint_jacobian(q2), (2, 4))[:, list(robot.passive)]
    assert np.linalg.cond(Pp, 1) > COND_LIMIT
    found = pm.rest_torques(robot, np.vstack([q[:1], q2]))
    alone = pm.rest_torques(robot, q[:1])
    for key, v in found.items():
        assert np.isnan(v[1]).all(), key
        assert np.allclose(v[0], alone[key][0], rtol=1e-14, atol=0), key


def test_integer_poses_equal_float_ones(arm):
    """q as a list of ints ([[0, 1]]) gives what the float pose gives."""
    qf = np.array([[0.0, 1.0], [2.0, -1.0]])
    qi = [[0, 1], [2, -1]]
    for got, ref in ((pm.pose_measures(arm, qi, 0.2), pm.pose_measures(arm, qf, 0.2)),
                     (pm.rest_torques(arm, qi), pm.rest_torques(arm, qf))):
        for key in ref:
            assert got[key].dtype == float and np.array_equal(got[key], ref[key]), key
    # and the values are the arm's: type1 = 1 / cond(J), gravity = inverse dynamics at rest
    m = pm.pose_measures(arm, qi, 0.2)
    assert np.allclose(m["type1"], 1 / np.linalg.cond(arm_jacobian(arm, qf)), rtol=1e-12)
    assert np.allclose(pm.rest_torques(arm, qi)["gravity"],
                       arm.inverse_dynamics(qf, 0 * qf, 0 * qf), rtol=1e-13, atol=0)


# -- inverse_dynamics_at_rest ----------------------------------------------------------------


def test_inverse_dynamics_with_rates_of_the_arm_in_closed_form(arm):
    rng = np.random.default_rng(11)
    q, qd, qdd = ARM_Q, rng.uniform(-3, 3, ARM_Q.shape), rng.uniform(-3, 3, ARM_Q.shape)
    p = arm.parameters
    H = p["m_link2"] * p["px_link1_CS2"] * p["cgx_link2"]
    s2 = np.sin(q[:, 1])
    cqd = H * s2[:, None] * np.column_stack([-(2 * qd[:, 0] * qd[:, 1] + qd[:, 1] ** 2),
                                            qd[:, 0] ** 2])
    moving = pm.inverse_dynamics_at_rest(arm, q, qdd, qd)
    still = pm.inverse_dynamics_at_rest(arm, q, qdd)
    assert np.max(np.abs(cqd)) > 1e-3
    assert np.allclose(moving - still, cqd, rtol=1e-10, atol=1e-15)
    assert np.allclose(moving, arm.inverse_dynamics(q, qd, qdd), rtol=1e-13, atol=0)
    assert np.allclose(still, arm.inverse_dynamics(q, 0 * qd, qdd), rtol=1e-13, atol=0)


def test_inverse_dynamics_with_rates_of_the_five_bar(bar):
    """qd = K^-1 [0; xd], qdd = K^-1 [gamma; xdd] (on the loops) by numpy; against the public
    closed_chain_inverse_dynamics (which checks the loops)."""
    robot, q = bar
    rng = np.random.default_rng(12)
    K = np.concatenate([robot.constraint_jacobian(q), robot.task(q)[1]], axis=1)
    xd, xdd = rng.uniform(-0.5, 0.5, (2, len(q), 2))
    qd = np.linalg.solve(K, np.column_stack([np.zeros((len(q), 2)), xd])[..., None])[..., 0]
    gamma = robot.constraint_bias(q, qd)
    qdd = np.linalg.solve(K, np.column_stack([gamma, xdd])[..., None])[..., 0]
    ref, _ = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    got = pm.inverse_dynamics_at_rest(robot, q, qdd, qd)
    assert np.allclose(got, ref, rtol=1e-13, atol=0)
    assert np.max(np.abs(got - pm.inverse_dynamics_at_rest(robot, q, qdd))) > 1e-3 * np.max(
        np.abs(ref))


def test_inverse_dynamics_nan_exactly_above_the_cond_limit(bar, monkeypatch):
    """NaN where the 1-norm condition number of Phi_p exceeds COND_LIMIT, not at it: with
    the limit moved onto a pose's own condition number the pose keeps its torque, one ulp
    below it is NaN. The condition number is numpy's cond(Phi_p, 1)."""
    robot, q = bar
    zero = np.zeros_like(q)
    cond = np.asarray(robot._closed_inverse_dynamics(q, zero, zero)[2]).reshape(-1)
    Pp = robot.constraint_jacobian(q)[:, :, list(robot.passive)]
    assert np.allclose(cond, np.linalg.cond(Pp, 1), rtol=1e-10)
    ref = pm.inverse_dynamics_at_rest(robot, q, zero)
    assert np.isfinite(ref).all()
    k = int(np.argmax(cond))
    monkeypatch.setattr(pm, "COND_LIMIT", float(cond[k]))
    assert np.array_equal(pm.inverse_dynamics_at_rest(robot, q, zero), ref)
    monkeypatch.setattr(pm, "COND_LIMIT", float(np.nextafter(cond[k], 0)))
    got = pm.inverse_dynamics_at_rest(robot, q, zero)
    assert np.isnan(got[k]).all()
    others = np.arange(len(q)) != k
    assert np.array_equal(got[others], ref[others])


# -- stacked ---------------------------------------------------------------------------------


def jdot_by_differences(robot, q, qd, h=1e-6):
    """(J(q + h qd) - J(q - h qd)) / (2 h) qd per pose: d/dt J along the motion, times qd."""
    up = np.reshape(robot.task(q + h * qd)[1], (len(q), -1, robot.n))
    down = np.reshape(robot.task(q - h * qd)[1], (len(q), -1, robot.n))
    return np.einsum("nij,nj->ni", (up - down) / (2 * h), qd)


@pytest.mark.parametrize("name", ["serial_2dof", "five_bar_type1", "serial_rpr"])
def test_stacked_with_rates(name, bar):
    robot = bar[0] if name == "five_bar_type1" else ps.load(name)
    q = bar[1] if name == "five_bar_type1" else ARM_Q if name == "serial_2dof" else \
        np.array([[0.5, 0.1, 1.0], [2.0, -0.2, -0.7]])
    rng = np.random.default_rng(13)
    qd = rng.uniform(-2, 2, q.shape)
    K, x, phi, jdq = pm.stacked(robot, q, qd)
    K0, _, _, jdq0 = pm.stacked(robot, q)
    m, nt = robot.n_constraints, len(robot.task_names)
    assert K.shape == (len(q), robot.n, robot.n) and jdq.shape == (len(q), nt)
    assert np.array_equal(K, K0) and np.array_equal(jdq0, np.zeros_like(jdq0))
    assert np.array_equal(x, np.reshape(robot.task(q)[0], (len(q), nt)))
    assert phi.shape == (len(q), m)
    if m:
        assert np.array_equal(phi, robot.constraint(q))
        assert np.array_equal(K[:, :m], robot.constraint_jacobian(q))
    ref = jdot_by_differences(robot, q, qd)
    if name == "serial_2dof":
        a1, a2 = robot.parameters["px_link1_CS2"], robot.parameters["px_link2_CS2"]
        q1, q12 = q[:, 0], q.sum(1)
        ref = (-a1 * unit(q1) * qd[:, :1] ** 2 - a2 * unit(q12) * qd.sum(1, keepdims=True) ** 2)
    assert np.max(np.abs(jdq)) > 1e-2
    assert np.allclose(jdq, ref, rtol=1e-6, atol=1e-9 * np.max(np.abs(ref)))
