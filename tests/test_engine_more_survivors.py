"""More of the controlled engine's survivors of mutation testing (issue 30): ``engine``
(``simulate_controlled``) on SUNDIALS, where events are found on the output grid.

* A stop event that falls exactly on an output time: the run ends at the last sample *before*
  the first stop event (engine.simulate_controlled: ``keep = t_out < min(stops)``), checked
  against an input torque ramp whose crossing of the actuator limit is known in closed form.
* A closed chain's constraint drift: the run's ``constraint_drift_m`` is the largest |Phi| of
  its samples, evaluated here by the robot's own constraint function.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.control import controller, from_table, simulate_controlled


@pytest.fixture(scope="module")
def arm():
    from conftest import TEST_ROBOTS

    return ps.load(TEST_ROBOTS / "actuated_2dof.toml")


@pytest.mark.parametrize("method", ["cvodes", "idas"])
def test_a_stop_exactly_on_an_output_time_ends_the_run_before_it(arm, method):
    """Catches ``t_out < min(stops)`` turned into ``<=`` (a stop event on an output time kept
    as the run's last sample). Open loop (controller "none") on tests/robots/actuated_2dof.toml,
    joint 1 limited to 0.8 N*m, driven by the input torque ramp tau_1 = 8 t N*m (a table
    through (0, 0), (0.1, 0.8), (0.2, 1.6)): the limit is reached at t = 0.8 / 8 = 0.1 s
    exactly, an output time of the grid 0, 0.05, ..., 0.2 s, where the event value
    0.8 - |tau_1| is exactly 0. The event is at 0.1 s and stops the run; the samples kept are
    those before it, 0 and 0.05 s, with the commanded torque 8 t there. (The C route, which
    locates the event itself, appends the state at the event time: its last sample is 0.1 s.)"""
    ramp = from_table([0.0, 0.1, 0.2], [[0.0, 0.0], [0.8, 0.0], [1.6, 0.0]])
    t = np.linspace(0.0, 0.2, 5)
    assert t[2] == 0.1 and ramp(t)[2, 0] == 0.8  # the crossing is on the grid, bit for bit
    run = simulate_controlled(arm, controller("none"), (0.0, 0.2), q0=[0.0, 0.0], torque=ramp,
                              t_eval=t, on_actuator_limit="stop", method=method)
    assert [(e.name, e.time_s, bool(e.stopped)) for e in run.events] == [
        ("actuator joint1 commanded beyond its torque limit 0.8 N*m", 0.1, True)]
    assert run.t_s.tolist() == [0.0, 0.05]
    np.testing.assert_allclose(run.tau_cmd[:, 0], 8.0 * run.t_s, rtol=0, atol=1e-15)
    c_route = simulate_controlled(arm, controller("none"), (0.0, 0.2), q0=[0.0, 0.0],
                                  torque=ramp, t_eval=t, on_actuator_limit="stop")
    assert c_route.t_s[-1] == pytest.approx(0.1, abs=1e-9)
    assert c_route.events[0].time_s == pytest.approx(0.1, abs=1e-9)


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_a_closed_chains_run_reports_its_largest_loop_error(method):
    """Catches the drift left out of the Simulation simulate_controlled returns (then 0.0,
    the field's default): five_bar_type1 falling freely from its drawn pose (controller
    "none") for 0.35 s, four segments re-projected onto the loops; constraint_drift_m is
    max |Phi(q)| over every sample after the start (the start is on the loops, |Phi| ~ 1e-17,
    the run's own is 1e-12 to 1e-10), with Phi the robot's constraint function."""
    robot = ps.load("five_bar_type1")
    run = simulate_controlled(robot, controller("none"), (0.0, 0.35), q0=robot.q_drawn,
                              t_eval=np.linspace(0.0, 0.35, 36), method=method)
    drift = float(np.max(np.abs(robot.constraint(run.q[1:]))))
    assert drift > 1e-13
    assert run.constraint_drift_m == pytest.approx(drift, rel=1e-12)
