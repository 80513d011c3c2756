"""The two typed requests a study hands down, by value: ``inverse_along`` (inverse dynamics
along a joint motion: torques, loads, split, power, sizing) against the pendulum's closed form
and a closed chain's power balance; ``track`` (``control.Tracking`` in, ``Tracked`` out)
against the computed-torque error's closed form e(t) = e0 (1 + w t) exp(-w t), the loops, and
the split and sizing invariants."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.control import Tracking, track
from planar_sym.errors import InputError
from planar_sym.motion.closure import from_actuated
from planar_sym.motion.profiles import JointTrajectory

ROBOTS = Path(__file__).parent / "robots"
M, LC, IZZ, G = 1.5, 0.25, 0.02, 9.81  # tests/robots/pendulum.toml


def quintic(t, start, by, duration):
    """Rest to rest: q, qd, qdd of start + by (10 s^3 - 15 s^4 + 6 s^5), s = t / duration."""
    s = np.clip(t / duration, 0.0, 1.0)[:, None]
    by = np.atleast_1d(by)[None, :]
    q = start + by * (10 * s**3 - 15 * s**4 + 6 * s**5)
    qd = by * (30 * s**2 - 60 * s**3 + 30 * s**4) / duration
    qdd = by * (60 * s - 180 * s**2 + 120 * s**3) / duration**2
    return q, qd, qdd


@pytest.fixture(scope="module")
def pendulum():
    return ps.load(ROBOTS / "pendulum.toml")


@pytest.fixture(scope="module")
def five():
    return ps.load("five_bar_type1")


def test_inverse_along_a_pendulum_is_its_closed_form(pendulum):
    t = np.linspace(0.0, 1.0, 2001)
    q = (0.3 * np.sin(2 * t) - 0.4)[:, None]
    qd, qdd = (0.6 * np.cos(2 * t))[:, None], (-1.2 * np.sin(2 * t))[:, None]
    inv = ps.inverse_along(pendulum, t, q, qd, qdd)
    i_o = IZZ + M * LC**2
    tau = i_o * qdd[:, 0] + M * G * LC * np.cos(q[:, 0])
    assert np.max(np.abs(inv.tau[:, 0] - tau)) < 1e-12
    assert inv.cut_forces is None and inv.loop_residual_m is None
    assert np.max(np.abs(inv.power_w[:, 0] - tau * qd[:, 0])) < 1e-12
    # the split's parts add up to the torque; the gravity part is m g l cos q
    assert np.max(np.abs(sum(inv.split.values())[:, 0] - tau)) < 1e-12
    assert np.max(np.abs(inv.split["gravity"][:, 0] - M * G * LC * np.cos(q[:, 0]))) < 1e-12
    # the bearing: the rod's cg accelerates under the pivot's force and its weight
    a = LC * (qdd * np.hstack([-np.sin(q), np.cos(q)]) - qd**2 * np.hstack([np.cos(q), np.sin(q)]))
    force = M * a - M * np.array([0.0, -G])
    assert np.max(np.abs(inv.loads.force[:, 0] - force)) < 1e-12
    # sizing: the peak, and the net work = the change of kinetic plus potential energy
    (s,) = inv.sizing
    assert s.peak_torque == pytest.approx(np.max(np.abs(tau)), rel=1e-14)
    energy = 0.5 * i_o * qd[:, 0]**2 + M * G * LC * np.sin(q[:, 0])
    assert s.energy_j == pytest.approx(energy[-1] - energy[0], rel=1e-6, abs=1e-7)


def test_inverse_along_checks_its_times(pendulum):
    q = np.zeros((3, 1))
    with pytest.raises(InputError) as info:
        ps.inverse_along(pendulum, [0.0, 0.1], q, q, q)
    assert str(info.value) == "t_s has shape (2,): one time (s) for each of the 3 samples of q"
    with pytest.raises(InputError) as info:
        ps.inverse_along(pendulum, [[0.0, 0.1, 0.2]], q, q, q)
    assert str(info.value) == "t_s has shape (1, 3): one time (s) for each of the 3 samples of q"
    with pytest.raises(InputError) as info:
        ps.inverse_along(pendulum, [0.0, np.nan, 0.2], q, q, q)
    assert str(info.value).startswith("t_s[1, 0] is nan at sample 1")
    with pytest.raises(InputError) as info:
        ps.inverse_along(pendulum, [0.0, "a", 0.2], q, q, q)
    assert str(info.value).startswith("t_s must be an array of numbers")
    # times given as integers are times in s all the same
    whole = ps.inverse_along(pendulum, [0, 1, 2], q, q, q)
    assert whole.sizing[0].energy_j == 0.0 and whole.tau.dtype == np.float64


def test_inverse_along_a_closed_chain_balances_power(five):
    t = np.linspace(0.0, 0.5, 101)
    start = np.array(five.q_drawn)[list(five.actuated)]
    jt = from_actuated(five, t, *quintic(t, start, [0.2, -0.15], 0.5))
    inv = ps.inverse_along(five, jt.t_s, jt.q, jt.qd, jt.qdd)
    assert inv.loop_residual_m < 1e-9
    assert inv.cut_forces.shape == (len(t), 2 * len(five.loops))
    # the cut forces do no work (Phi_q qd = 0): the motors' power is that of M qdd + h
    tree = five.tree_inverse_dynamics(jt.q, jt.qd, jt.qdd).reshape(len(t), five.n)
    demand = np.sum(tree * jt.qd, axis=1)
    assert np.max(np.abs(inv.power_w.sum(axis=1) - demand)) < 1e-9 * (1 + np.max(np.abs(demand)))
    assert np.max(np.abs(sum(inv.split.values()) - inv.tau)) < 1e-10
    for k, s in enumerate(inv.sizing):
        assert s.peak_torque == pytest.approx(np.max(np.abs(inv.tau[:, k])), rel=1e-14)


def test_computed_torque_from_a_bandwidth_follows_its_closed_form(pendulum):
    """Perfect model, no saturation: e'' + 2 w e' + w^2 e = 0 from e0 = -0.05 rad, e0' = 0."""
    t = np.linspace(0.0, 1.0, 201)
    jt = JointTrajectory(t, *quintic(t, np.array([-0.5]), 0.6, 1.0))
    f_hz = 4.0
    done = track(pendulum, Tracking(jt, law="computed_torque", natural_frequency_hz=f_hz,
                                    damping=1.0, start_error=np.array([0.05]), saturate=False,
                                    samples=201, rtol=1e-12, atol=1e-13))
    w = 2 * np.pi * f_hz
    ctl = done.run.controller
    assert ctl.kp[0] == pytest.approx(w * w, rel=1e-15) and ctl.kd[0] == pytest.approx(2 * w)
    assert done.run.q[0, 0] - jt.q[0, 0] == pytest.approx(0.05, abs=1e-15)
    t = done.run.t_s
    e = -0.05 * (1 + w * t) * np.exp(-w * t)
    assert np.max(np.abs(done.run.error[:, 0] - e)) < 1e-7
    # the task point and its reference, and the split of the applied torques
    tip = np.c_[0.4 * np.cos(done.run.q[:, 0]), 0.4 * np.sin(done.run.q[:, 0])]
    assert np.max(np.abs(done.x - tip)) < 1e-12
    ref = done.reference(t)
    assert np.max(np.abs(done.x_ref - np.c_[0.4 * np.cos(ref[:, 0]), 0.4 * np.sin(ref[:, 0])])
                  ) < 1e-12
    assert np.max(np.abs(sum(done.split.values()) - done.run.tau)) < 1e-9


def test_a_closed_chain_started_off_its_reference_starts_on_its_loops(five):
    t = np.linspace(0.0, 0.5, 101)
    start = np.array(five.q_drawn)[list(five.actuated)]
    jt = from_actuated(five, t, *quintic(t, start, [0.2, -0.15], 0.5))
    err = np.array([0.01, -0.02])
    done = track(five, Tracking(jt, law="pd", kp=[200.0, 200.0], kd=[8.0, 8.0],
                                start_error=err, duration_s=0.6, samples=61))
    run, act = done.run, list(five.actuated)
    assert np.max(np.abs(run.q[0, act] - (jt.q[0, act] + err))) < 1e-12
    assert np.max(np.abs(five.constraint(run.q[0]))) < 1e-12
    jac = five.constraint_jacobian(run.q[0]).reshape(five.n_constraints, five.n)
    assert np.max(np.abs(jac @ run.qd[0])) < 1e-12
    assert abs(run.balance_residual) < 1e-6
    assert run.t_s[-1] == pytest.approx(0.6)  # held at rest after the motion's end
    assert np.max(np.abs(sum(done.split.values()) - run.tau)) < 1e-9
    for k, s in enumerate(done.sizing):
        assert s.peak_torque == pytest.approx(np.max(np.abs(run.tau[:, k])), rel=1e-14)


def test_a_closed_chain_plant_of_other_lengths_starts_on_its_own_loops(five):
    """A model error in a length: the plant's left crank 2 % longer than the model's. The
    reference is on the model's loops, not the plant's (|Phi_plant| 1.7 mm there), so the run
    starts at the reference's actuated coordinates (plus start_error) with the passive joints
    closed on the plant's loops, and says how far they moved. The run was refused, off the
    loop constraints, with the hint to give the start_error it had."""
    t = np.linspace(0.0, 0.5, 51)
    start = np.array(five.q_drawn)[list(five.actuated)]
    jt = from_actuated(five, t, *quintic(t, start, [0.1, -0.1], 0.5))
    plant = five.with_parameters(px_L_Link1_CS2=1.02 * five.parameters.get("px_L_Link1_CS2"))
    act, pas = list(five.actuated), list(five.passive)
    assert np.max(np.abs(plant.constraint(jt.q[0]))) > 1e-3
    for err in (None, np.array([0.01, 0.0])):
        done = track(five, Tracking(jt, law="computed_torque", natural_frequency_hz=5.0,
                                    start_error=err, plant=plant, samples=11))
        run = done.run
        q0 = run.q[0]
        assert np.array_equal(q0[act], jt.q[0, act] + (0.0 if err is None else err))
        assert np.max(np.abs(plant.constraint(q0))) < 1e-12
        jac = plant.constraint_jacobian(q0).reshape(plant.n_constraints, plant.n)
        assert np.max(np.abs(jac @ run.qd[0])) < 1e-12
        assert run.initial_correction_rad == np.max(np.abs(q0[pas] - jt.q[0, pas]))
        assert run.initial_correction_rad > 1e-3
    # the plant as the model: the reference's own pose, nothing moved
    run = track(five, Tracking(jt, law="computed_torque", natural_frequency_hz=5.0,
                               samples=11)).run
    assert np.max(np.abs(run.q[0] - jt.q[0])) < 1e-12 and run.initial_correction_rad < 1e-12


def test_a_request_that_cannot_run_is_refused_by_name(pendulum):
    t = np.linspace(0.0, 1.0, 11)
    moving = JointTrajectory(t, t[:, None], np.ones((11, 1)), np.zeros((11, 1)))
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(moving, law="pd", kp=[10.0], kd=[1.0], duration_s=2.0))
    assert str(info.value) == (
        "duration_s 2 s outlasts the motion (1 s), which ends moving (1 per s): the reference "
        "cannot be held; end the motion at rest or shorten duration_s")
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(moving, law="pd"))
    assert str(info.value) == ("Tracking: law 'pd' needs gains kp and kd, or "
                               "natural_frequency_hz (and damping) to set them")
    # tried as a user: these reached NumPy's ValueError and an AttributeError
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(moving, law="pd", kp=[10.0], kd=[1.0],
                                 start_error=np.array([0.05, 0.1])))
    assert str(info.value) == "start_error must have shape (N, 1) or (1,), got (2,)"
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(moving.q, law="pd", kp=[10.0], kd=[1.0]))
    assert str(info.value) == ("Tracking: motion must be a JointTrajectory (every coordinate: "
                               "inverse_kinematics, from_actuated), got ndarray")
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(moving, law="pd", kp=[10.0, 2.0], kd=[1.0]))
    assert str(info.value) == "kp must be one number (one actuated joint) (got [10.0, 2.0])"


def test_every_field_of_the_request_reaches_the_engine():
    """A request whose every field changes the run (plant, input torques, joint limits that
    fire and go on, an actuator limit that stops, SUNDIALS, tolerances, no saturation, a start
    already moving): track's run is the engine's run on the same arguments, bit for bit."""
    from planar_sym.control import controller, from_table, simulate_controlled

    robot = ps.load(ROBOTS / "actuated_2dof.toml")
    t = np.linspace(0.0, 1.0, 51)
    q0 = np.array(robot.q_drawn, dtype=float)
    v = np.array([0.4, -0.6])  # rad/s: the motion starts moving
    jt = JointTrajectory(t, q0 + t[:, None] * v, np.tile(v, (51, 1)), np.zeros((51, 2)))
    plant = robot.with_parameters(m_link2=1.3 * robot.parameters["m_link2"])
    limits = {"q2": (q0[1] - 0.2, q0[1] + 1.0)}
    ramp = from_table([0.0, 0.5, 1.0], [[0.0, 0.0], [0.0, 0.0], [30.0, -0.04]], "linear")
    req = Tracking(jt, law="pd", kp=[2.0, 30.0], kd=[0.2, 1.5], saturate=False, samples=51,
                   torque=ramp, joint_limits=limits,
                   on_joint_limit="continue", on_actuator_limit="stop", plant=plant,
                   method="cvodes", rtol=1e-9, atol=1e-11)
    done = track(robot, req)
    direct = simulate_controlled(
        robot, controller("pd", [2.0, 30.0], [0.2, 1.5], width=2, saturate=False), (0.0, 1.0),
        reference=jt, plant=plant, q0=jt.q[0], qd0=jt.qd[0], torque=ramp,
        t_eval=t, joint_limits={1: limits["q2"]}, on_joint_limit="continue",
        on_actuator_limit="stop", method="cvodes", rtol=1e-9, atol=1e-11)
    run = done.run
    assert run.q.shape == direct.q.shape and np.max(np.abs(run.q - direct.q)) < 1e-12
    assert np.max(np.abs(run.tau - direct.tau)) < 1e-12
    assert [str(e) for e in run.events] == [str(e) for e in direct.events]
    assert any(not e.stopped for e in run.events) and run.events[-1].stopped
    assert run.t_s[-1] < 1.0  # the actuator limit stopped it
    assert (run.method, run.rtol, run.atol, run.controller.saturate) == ("cvodes", 1e-9, 1e-11,
                                                                          False)
    assert np.array_equal(run.qd[0], v)
    # the motion's end is the run's end when no duration is given
    free = track(robot, Tracking(jt, law="pd", kp=[40.0, 30.0], kd=[2.0, 1.5], samples=11))
    assert free.run.t_s[-1] == 1.0 and len(free.run.t_s) == 11


def test_pd_gains_from_a_bandwidth_use_the_start_pose_and_open_loop_needs_none():
    arm = ps.load("serial_2dof")
    t = np.linspace(0.0, 1.0, 11)
    q0 = np.array([-1.0, 0.5])
    v = np.array([0.0, 2.0])  # the elbow moves: the shoulder's inertia changes at once
    jt = JointTrajectory(t, q0 + t[:, None] * v, np.tile(v, (11, 1)), np.zeros((11, 2)))
    done = track(arm, Tracking(jt, law="pd", natural_frequency_hz=2.0, damping=0.7, samples=11))
    mass = arm.mass_matrix(q0).reshape(2, 2)
    w = 2 * np.pi * 2.0
    assert np.max(np.abs(done.run.controller.kp - np.diag(mass) * w * w)) < 1e-12
    assert np.max(np.abs(done.run.controller.kd - np.diag(mass) * 2 * 0.7 * w)) < 1e-12
    # the law "none" takes no gains, only input torques; a robot with no task has no x
    cart = ps.load(ROBOTS / "cart_pole.toml")
    still = JointTrajectory(t, np.zeros((11, 2)), np.zeros((11, 2)), np.zeros((11, 2)))
    done = track(cart, Tracking(still, law="none", torque=np.array([1.0]), samples=11))
    assert done.x is None and done.x_ref is None
    # open loop: the input force is applied as given, and its work is the energy gained
    assert np.all(done.run.tau == 1.0)
    assert abs(done.run.balance_residual) < 1e-8


def test_a_start_off_the_reference_keeps_the_reference_assembly_mode(five):
    """The other assembly mode of the five-bar (passive joints near -2.62, 2.62 rad, the drawn
    pose's near -1.52, 1.52): started off the reference, the loops are solved from the
    reference's own pose, never from the drawn one."""
    t = np.linspace(0.0, 0.5, 51)
    act, pas = list(five.actuated), list(five.passive)
    guess = np.array(five.q_drawn, dtype=float)
    guess[pas] = [-2.62, 2.62]
    jt = from_actuated(five, t, *quintic(t, guess[act], [0.1, -0.1], 0.5), q_guess=guess)
    assert np.max(np.abs(jt.q[0, pas] - [-2.624842, 2.624842])) < 1e-5
    done = track(five, Tracking(jt, law="pd", kp=[50.0, 50.0], kd=[2.0, 2.0],
                                start_error=np.array([0.01, 0.01]), samples=11))
    assert np.max(np.abs(done.run.q[0, pas] - jt.q[0, pas])) < 0.05


def test_holding_the_end_is_refused_only_past_the_rest_tolerance(pendulum):
    t = np.linspace(0.0, 1.0, 11)
    q = np.zeros((11, 1))
    end_rate = np.zeros((11, 1))
    end_rate[-1] = 1e-9  # REST_TOL exactly: at rest
    jt = JointTrajectory(t, q, end_rate, q)
    done = track(pendulum, Tracking(jt, law="pd", kp=[10.0], kd=[1.0], duration_s=1.5,
                                    samples=4))
    assert done.run.t_s[-1] == 1.5
    with pytest.raises(InputError) as info:
        track(pendulum, Tracking(JointTrajectory(t, q, 2 * end_rate, q), law="pd", kp=[10.0],
                                 kd=[1.0], duration_s=1.5, where="s.toml"))
    assert str(info.value).startswith("s.toml: control.duration 1.5 s outlasts the motion "
                                      "(1 s), which ends moving (2e-09 per s)")
    assert str(info.value).endswith("shorten control.duration")
    # a duration past the motion's end by rounding only (1e-12 s) is the motion's end: a motion
    # that ends moving is not held, so not refused
    moving = JointTrajectory(t, 0.1 * t[:, None], np.full((11, 1), 0.1), q)
    done = track(pendulum, Tracking(moving, law="pd", kp=[10.0], kd=[1.0],
                                    duration_s=1.0 + 1e-12, samples=3))
    assert done.run.t_s[-1] == 1.0 + 1e-12


def test_gain_units_follow_the_law_and_the_coordinate():
    """What a control study's note prints next to the gains: PD gains in N*m/rad and N*m*s/rad
    at a revolute joint, N/m and N*s/m at a slider; computed-torque gains in 1/s^2 and 1/s."""
    from planar_sym.control import controller

    pd = controller("pd", 1.0, 0.1, width=1)
    assert pd.gain_units("rad") == ("N*m/rad", "N*m*s/rad")
    assert pd.gain_units("m") == ("N/m", "N*s/m")
    ct = controller("computed_torque", 1.0, 0.1, width=1)
    assert ct.gain_units("rad") == ct.gain_units("m") == ("1/s^2", "1/s")
