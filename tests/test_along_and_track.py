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
