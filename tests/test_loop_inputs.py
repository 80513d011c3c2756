"""Closed-chain inverse dynamics refuses states off the loop constraints and accepts states on
them (a Hypothesis property over random actuated poses, rates, accelerations and
perturbations), and a simulation never moves a user's initial state silently."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.model.loops import LOOP_TOL_M

CLOSED = ("five_bar_type1", "five_bar_type2", "parallel_3rrr")
SETTINGS = settings(max_examples=60, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])


def on_loops(robot, offsets, rates, accels):
    """A state on the loops: actuated angles near the drawn pose, the passive ones by Newton."""
    act = list(robot.actuated)
    qa = (robot.q_drawn[act] + np.array(offsets))[None]
    return ps.from_actuated(robot, [0.0], qa, np.array(rates)[None], np.array(accels)[None])


def vec(size, bound):
    return st.lists(st.floats(-bound, bound), min_size=size, max_size=size)


@SETTINGS
@given(data=st.data())
@pytest.mark.parametrize("name", CLOSED)
def test_on_the_loops_accepted_off_refused(name, data):
    robot = ps.load(name)
    k = len(robot.actuated)
    try:
        j = on_loops(robot, data.draw(vec(k, 0.05)), data.draw(vec(k, 3.0)),
                     data.draw(vec(k, 10.0)))
    except ps.WorkspaceError:
        return  # that pose does not assemble: nothing to check
    tau, lam = robot.closed_chain_inverse_dynamics(j.q, j.qd, j.qdd)  # accepted
    assert np.all(np.isfinite(tau)) and np.all(np.isfinite(lam))
    which = data.draw(st.sampled_from(("q", "qd", "qdd")))
    direction = np.array(data.draw(vec(robot.n, 1.0)))
    size = data.draw(st.floats(1e-6, 1e-2))
    if np.linalg.norm(direction) < 1e-3:
        return
    state = {"q": j.q.copy(), "qd": j.qd.copy(), "qdd": j.qdd.copy()}
    state[which] += size * direction / np.linalg.norm(direction)
    jac = robot.constraint_jacobian(state["q"])
    residual = {"q": robot.constraint(state["q"]),
                "qd": jac @ state["qd"][0],
                "qdd": jac @ state["qdd"][0] - robot.constraint_bias(state["q"], state["qd"])}
    if np.max(np.abs(residual[which])) < 100 * LOOP_TOL_M * (1 + 100):
        return  # moved along the loops (or too little to tell): a state on them again
    with pytest.raises(InputError, match="is off the loop constraints"):
        robot.closed_chain_inverse_dynamics(state["q"], state["qd"], state["qdd"])


def test_the_seed_studies_are_on_the_loops():
    """Every closed-chain seed study passes the check (it runs), with its residual far inside."""
    for name in ("five_bar_type1_move_x", "five_bar_type2_move_y", "parallel_3rrr_move_x"):
        result = ps.run_study(name)
        assert "loop residual max |Phi|" in result.note


def test_simulate_does_not_move_a_state_off_the_loops():
    five = ps.load("five_bar_type2")
    q0 = five.q_drawn.copy()
    q0[1] += 1e-3  # a passive joint 1 mrad off
    with pytest.raises(InputError, match=r"q0 is off the loop constraints: \|Phi\| = "):
        ps.simulate(five, q0, np.zeros(4), (0.0, 0.1))
    qd0 = np.array([1.0, 0.0, 0.0, 0.0])  # only A moving: breaks the loop's velocity
    with pytest.raises(InputError, match=r"qd0 is off the loop constraints: \|Phi_q qd\| = "):
        ps.simulate(five, five.q_drawn, qd0, (0.0, 0.1))


def test_simulate_projects_when_asked_and_reports_it():
    """project=True moves the passive joints only (never the actuated ones), and says how far."""
    five = ps.load("five_bar_type2")
    q0 = five.q_drawn.copy()
    q0[1] += 1e-3
    sim = ps.simulate(five, q0, np.zeros(4), (0.0, 0.1), project=True)
    act = list(five.actuated)
    assert np.array_equal(sim.q[0, act], q0[act])
    assert np.max(np.abs(five.constraint(sim.q[0]))) < 1e-12
    assert sim.initial_correction_rad == pytest.approx(np.max(np.abs(sim.q[0] - q0)), rel=1e-12)
    assert 1e-4 < sim.initial_correction_rad < 1e-2


def test_large_finite_inputs_are_not_mistaken_for_infinities():
    """as_samples checks finiteness by the sum first; a sum that overflows must fall back to
    the entries, not refuse finite values (and a real inf is still named)."""
    from planar_sym.errors import InputError
    from planar_sym.model.robot import as_samples

    big = np.full((3, 2), 1e308)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nor does the overflow of the sum reach the user
        assert np.array_equal(as_samples("q", big, 2), big)
    big[2, 1] = np.inf
    with pytest.raises(InputError, match=r"q\[2, 1\] is inf at sample 2"):
        as_samples("q", big, 2)


def test_passive_rates_refuse_arrays_of_different_lengths():
    """complete_rates checks q, qd_act and qdd_act together: a rate array one sample short is
    named with every array's sample count (before: a numpy broadcasting error, or none at all
    for one sample against many), and on consistent arrays the rates close the loops."""
    from planar_sym.motion.closure import complete_rates

    robot = ps.load("five_bar_type1")
    q = np.tile(robot.q_drawn, (3, 1))
    with pytest.raises(InputError, match=r"q, qd_act, qdd_act must have the same number of "
                                         r"samples, got q: 3, qd_act: 2, qdd_act: 3"):
        complete_rates(robot, q, np.ones((2, 2)), np.ones((3, 2)))
    qd, _ = complete_rates(robot, q, np.ones((3, 2)), np.zeros((3, 2)))
    jac = robot.constraint_jacobian(q)
    assert np.max(np.abs(np.einsum("kij,kj->ki", jac, qd))) < 1e-12  # Phi_q qd = 0
