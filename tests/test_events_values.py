"""Events of a controlled run (planar_sym.dynamics.events) by value: every spec field and every
sentence word for word, against references worked out by hand here.

- ``coordinate_index`` at its edges: 0-based integers 0 and n - 1 (n refused, -1 refused, a
  bool refused), ``q1``..``qN`` (``q0``, ``q{n+1}``, ``q``, ``qa`` refused), joint names, and
  the refusal sentence listing ``q1..qN`` and the joint names;
- ``joint_limit_events``: two specs per coordinate (kind 0 at the lower bound, kind 1 at the
  upper), both stopping for "stop" and neither for "continue"; angles in rad and degrees
  (-1 rad = -57.2958 deg, 2 rad = 114.592 deg, 3.05 rad = 174.752 deg), a slider's bounds in m
  without degrees; every refusal sentence (bad action, not a pair, lower >= upper, infinite,
  NaN);
- ``actuator_events`` on actuated_2dof (joint1: 0.8 N*m at the joint, 0.02 N*m motor x 50 =
  1 N*m, so 0.8 N*m binds; 3000 rpm / 50 = 2 pi rad/s = 6.283 rad/s), with its gear parameter
  changed to 10 (motor 0.2 N*m binds, 31.42 rad/s), on serial_2dof_geared (motor limit only:
  0.01 x 50 = 0.5 N*m), and on a stand-in robot with a 4 mm lead screw (gear 2 pi / 0.004 rad
  per m; 0.1 N*m motor -> 157.1 N; 3000 rpm -> 0.2 m/s) whose parameters name no gear;
- ``output_events``: linear g columns with known zero crossings on an uneven time grid (the
  interpolated time is exact for a line), a column already at or below zero at the first sample
  (no event), a column touching zero at a sample and going back up (an event there), a column
  that dips and recovers (only its first crossing), several columns at once;
- ``Event.__str__`` with and without "(run stopped)".
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.dynamics.events import (
    Event,
    EventSpec,
    actuator_events,
    coordinate_index,
    joint_limit_events,
    output_events,
)
from planar_sym.errors import InputError

TOL = 1e-14


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


@pytest.fixture(scope="module")
def rpr():
    return ps.load("serial_rpr")


@pytest.fixture(scope="module")
def actuated():
    return ps.load(TEST_ROBOTS / "actuated_2dof.toml")


def _refused(call, *args) -> str:
    with pytest.raises(InputError) as err:
        call(*args)
    return str(err.value)


# --- coordinate_index ----------------------------------------------------------------------

def test_coordinate_index_integers_at_their_edges(arm, rpr):
    assert coordinate_index(arm, 0) == 0
    assert coordinate_index(arm, 1) == 1
    assert coordinate_index(arm, np.int64(1)) == 1
    assert type(coordinate_index(arm, np.int64(1))) is int
    assert coordinate_index(rpr, 2) == 2
    for key in (2, -1, True, 2.0):
        assert _refused(coordinate_index, arm, key) == (
            f"joint limit for {key!r}: not a coordinate of serial_2dof (q1..q2, or joint1, "
            "joint2)")
    assert _refused(coordinate_index, rpr, 3) == (
        "joint limit for 3: not a coordinate of serial_rpr (q1..q3, or shoulder, extend, wrist)")


def test_coordinate_index_q_names_and_joint_names(arm, rpr):
    assert coordinate_index(arm, "q1") == 0
    assert coordinate_index(arm, "q2") == 1
    assert coordinate_index(rpr, "q1") == 0
    assert coordinate_index(rpr, "q3") == 2
    assert coordinate_index(arm, "joint1") == 0
    assert coordinate_index(arm, "joint2") == 1
    assert coordinate_index(rpr, "extend") == 1
    assert coordinate_index(rpr, "wrist") == 2
    for key in ("q0", "q3", "q", "qa", "x", "", "joint3", "Q1", "q-1"):
        assert _refused(coordinate_index, arm, key) == (
            f"joint limit for {key!r}: not a coordinate of serial_2dof (q1..q2, or joint1, "
            "joint2)")
    assert _refused(coordinate_index, rpr, "q4") == (
        "joint limit for 'q4': not a coordinate of serial_rpr (q1..q3, or shoulder, extend, "
        "wrist)")


# --- joint_limit_events --------------------------------------------------------------------

def test_joint_limits_of_two_revolute_joints_stop(arm):
    specs = joint_limit_events(arm, {"q1": (-1.0, 2.0), "joint2": [-3.05, 3.05]}, "stop")
    assert specs == [
        EventSpec(0, 0, -1.0, True, "joint joint1 reached its lower limit -1 rad (-57.2958 deg)"),
        EventSpec(1, 0, 2.0, True, "joint joint1 reached its upper limit 2 rad (114.592 deg)"),
        EventSpec(0, 1, -3.05, True,
                  "joint joint2 reached its lower limit -3.05 rad (-174.752 deg)"),
        EventSpec(1, 1, 3.05, True,
                  "joint joint2 reached its upper limit 3.05 rad (174.752 deg)"),
    ]
    assert all(type(s.value) is float for s in specs)


def test_joint_limits_continue_and_a_slider_in_metres(rpr):
    specs = joint_limit_events(rpr, {1: ("0.1", 0.45), "q3": (-0.5, 0.5)}, "continue")
    assert specs == [
        EventSpec(0, 1, 0.1, False, "joint extend reached its lower limit 0.1 m"),
        EventSpec(1, 1, 0.45, False, "joint extend reached its upper limit 0.45 m"),
        EventSpec(0, 2, -0.5, False, "joint wrist reached its lower limit -0.5 rad (-28.6479 deg)"),
        EventSpec(1, 2, 0.5, False, "joint wrist reached its upper limit 0.5 rad (28.6479 deg)"),
    ]
    assert joint_limit_events(rpr, {}, "stop") == []
    assert joint_limit_events(rpr, None, "continue") == []


def test_joint_limit_refusals_word_for_word(arm, rpr):
    for action in ("halt", "STOP", "Stop", None):
        assert _refused(joint_limit_events, arm, {"q1": (-1.0, 1.0)}, action) == (
            f'on_joint_limit must be "stop" or "continue" (got {action!r})')
    # the action is checked first, even with no limits at all
    assert _refused(joint_limit_events, arm, {}, "pause") == (
        "on_joint_limit must be \"stop\" or \"continue\" (got 'pause')")
    for bounds in ((1.0,), (1.0, 2.0, 3.0), "ab", None, ("a", 1.0)):
        assert _refused(joint_limit_events, arm, {"joint2": bounds}, "stop") == (
            f"joint limit of joint2: give [lower, upper] (got {bounds!r})")
    for bounds, shown in (((2.0, 1.0), "[2, 1]"), ((1.0, 1.0), "[1, 1]"),
                          ((-math.inf, 1.0), "[-inf, 1]"), ((0.0, math.inf), "[0, inf]"),
                          ((0.0, math.nan), "[0, nan]"), ((math.nan, 0.5), "[nan, 0.5]")):
        assert _refused(joint_limit_events, rpr, {"extend": bounds}, "stop") == (
            f"joint limit of extend: need finite lower < upper (got {shown})")


# --- actuator_events -----------------------------------------------------------------------

def test_actuator_limits_of_actuated_2dof(actuated):
    """joint1: min(0.8, 0.02 * 50) = 0.8 N*m; 3000 rpm = 100 pi rad/s, / 50 = 2 pi rad/s.
    joint2 gives no limit: no event, bound inf."""
    specs, bound = actuator_events(actuated, "stop")
    assert [(s.kind, s.index, s.stop) for s in specs] == [(2, 0, True), (3, 0, True)]
    assert specs[0].value == pytest.approx(0.8, rel=TOL)
    assert specs[1].value == pytest.approx(2.0 * math.pi, rel=TOL)
    assert specs[0].name == "actuator joint1 commanded beyond its torque limit 0.8 N*m"
    assert specs[1].name == ("joint joint1 faster than its motor's limit (6.283 rad/s at the "
                             "joint)")
    assert bound.shape == (2,)
    assert bound[0] == pytest.approx(0.8, rel=TOL) and bound[1] == math.inf

    specs, _ = actuator_events(actuated, "continue")
    assert [(s.kind, s.index, s.stop) for s in specs] == [(2, 0, False), (3, 0, False)]


def test_gear_parameter_over_the_description_ratio(actuated):
    """gear_joint1 = 10: motor 0.02 * 10 = 0.2 N*m < 0.8 binds; 100 pi / 10 = 31.42 rad/s."""
    specs, bound = actuator_events(actuated.with_parameters(gear_joint1=10.0), "stop")
    assert [(s.kind, s.index) for s in specs] == [(2, 0), (3, 0)]
    assert specs[0].value == pytest.approx(0.2, rel=TOL)
    assert bound[0] == pytest.approx(0.2, rel=TOL)
    assert specs[0].name == ("actuator joint1 commanded beyond its torque limit 0.2 N*m at the "
                             "joint (the motor's 0.02 N*m x N = 10)")
    assert specs[1].value == pytest.approx(10.0 * math.pi, rel=TOL)
    assert specs[1].name == ("joint joint1 faster than its motor's limit (31.42 rad/s at the "
                             "joint)")


def test_motor_torque_limit_alone():
    """serial_2dof_geared: motor limits 0.01 N*m x 50 = 0.5 N*m on both joints, no joint-side
    limit; joint1's motor 8000 rpm: 800 pi / 3 rad/s / 50 = 16.76 rad/s."""
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    specs, bound = actuator_events(robot, "continue")
    assert [(s.kind, s.index, s.stop) for s in specs] == [(2, 0, False), (3, 0, False),
                                                          (2, 1, False)]
    assert [s.value for s in specs] == pytest.approx([0.5, 800.0 * math.pi / 3.0 / 50.0, 0.5],
                                                     rel=TOL)
    assert bound == pytest.approx([0.5, 0.5], rel=TOL)
    assert [s.name for s in specs] == [
        ("actuator joint1 commanded beyond its torque limit 0.5 N*m at the joint (the motor's "
         "0.01 N*m x N = 50)"),
        "joint joint1 faster than its motor's limit (16.76 rad/s at the joint)",
        ("actuator joint2 commanded beyond its torque limit 0.5 N*m at the joint (the motor's "
         "0.01 N*m x N = 50)"),
    ]


def test_no_actuator_limits(arm):
    specs, bound = actuator_events(arm, "stop")
    assert specs == []
    assert bound.shape == (2,) and np.all(np.isinf(bound))


class _Robot:
    """What ``actuator_events`` reads of a robot: actuated, actuators and parameters."""

    def __init__(self, *actuators, parameters=None):
        self.actuators = tuple(actuators)
        self.actuated = tuple(a["coordinate"] for a in actuators)
        self.parameters = dict(parameters or {})


def _act(joint, coordinate, ratio=1.0, unit="N*m", torque=None, motor_torque=None,
         motor_speed=None):
    return {"joint": joint, "coordinate": coordinate, "unit": unit, "model": True,
            "gear_ratio": ratio, "torque_limit": torque, "motor_torque_limit": motor_torque,
            "motor_speed_limit_rad_s": motor_speed}


def test_a_screw_reports_force_in_newtons_and_speed_in_metres_per_second():
    """A 4 mm lead screw (gear 2 pi / 0.004 rad/m) on coordinate 2, first actuator: motor
    0.1 N*m -> 0.1 * 2 pi / 0.004 = 157.08 N < 300 N binds; motor 3000 rpm = 100 pi rad/s ->
    100 pi * 0.004 / (2 pi) = 0.2 m/s. The parameters name no gear: the description's ratio.
    A revolute joint (ratio 4) on coordinate 0, second actuator: 2 N*m at the joint,
    40 rad/s motor -> 10 rad/s."""
    screw = 2.0 * math.pi / 0.004
    robot = _Robot(_act("slide", 2, ratio=screw, unit="N", torque=300.0, motor_torque=0.1,
                        motor_speed=100.0 * math.pi),
                   _act("elbow", 0, ratio=4.0, torque=2.0, motor_speed=40.0),
                   parameters={"m_link": 1.0})
    specs, bound = actuator_events(robot, "stop")
    assert [(s.kind, s.index, s.stop) for s in specs] == [(2, 0, True), (3, 2, True),
                                                          (2, 1, True), (3, 0, True)]
    assert [s.value for s in specs] == pytest.approx([0.1 * screw, 0.2, 2.0, 10.0], rel=TOL)
    assert bound == pytest.approx([0.1 * screw, 2.0], rel=TOL)
    assert [s.name for s in specs] == [
        ("actuator slide commanded beyond its force limit 157.1 N at the joint (the motor's "
         "0.1 N*m x N = 1571)"),
        "joint slide faster than its motor's limit (0.2 m/s at the joint)",
        "actuator elbow commanded beyond its torque limit 2 N*m",
        "joint elbow faster than its motor's limit (10 rad/s at the joint)",
    ]

    # a gear parameter for the joint wins over the description's ratio: 0.1 * 2 = 0.2 N,
    # 100 pi / 2 = 157.1 m/s
    geared = _Robot(*robot.actuators, parameters={"gear_slide": 2.0})
    specs, bound = actuator_events(geared, "continue")
    assert [s.value for s in specs[:2]] == pytest.approx([0.2, 50.0 * math.pi], rel=TOL)
    assert [s.stop for s in specs] == [False] * 4
    assert specs[0].name == ("actuator slide commanded beyond its force limit 0.2 N at the joint "
                             "(the motor's 0.1 N*m x N = 2)")
    assert specs[1].name == "joint slide faster than its motor's limit (157.1 m/s at the joint)"


def test_actuator_action_refused_word_for_word(actuated):
    for action in ("halt", "STOP", "", None):
        assert _refused(actuator_events, actuated, action) == (
            f'on_actuator_limit must be "stop" or "continue" (got {action!r})')


# --- output_events -------------------------------------------------------------------------

def test_one_linear_crossing_on_an_uneven_grid():
    """g = 4, 3, 1, -2, -5 at t = 0, 0.5, 1.5, 3, 5: first non-positive at index 3, the line
    from (1.5, 1) to (3, -2) is zero at 1.5 + 1.5 / 3 = 2.0 s."""
    t = np.array([0.0, 0.5, 1.5, 3.0, 5.0])
    g = np.array([[4.0], [3.0], [1.0], [-2.0], [-5.0]])
    ((k, time),) = output_events(g, t)
    assert k == 0
    assert time == pytest.approx(2.0, rel=TOL)


def test_several_columns_both_directions_and_edges():
    """t = 0, 1, 3, 4, 7, 8 (uneven). Columns:

    0. starts at 0 (already at its limit at the first sample): no event;
    1. 6, -6, ...: zero half-way through the first interval, t = 0.5;
    2. starts negative and rises: no event (not positive at the first sample);
    3. 2, 1, 0, 1, 2, 3: touches 0 exactly at t = 3 and recovers: an event at 3;
    4. 5, 5, 5, 5, 1, -3: crosses in the last interval: 7 + 1/4 = 7.25;
    5. 1, -1, 1, -1, 1, -1: several crossings, only the first: t = 0.5;
    6. always positive: no event;
    7. 3, 2, -4, -4, 8, 8: crosses in the second interval, 1 + 2 * 2/6 = 1 + 2/3."""
    t = np.array([0.0, 1.0, 3.0, 4.0, 7.0, 8.0])
    g = np.array([
        [0.0, 6.0, -1.0, 2.0, 5.0, 1.0, 1.0, 3.0],
        [1.0, -6.0, 0.0, 1.0, 5.0, -1.0, 2.0, 2.0],
        [2.0, -9.0, 1.0, 0.0, 5.0, 1.0, 3.0, -4.0],
        [3.0, -9.0, 2.0, 1.0, 5.0, -1.0, 4.0, -4.0],
        [4.0, -9.0, 3.0, 2.0, 1.0, 1.0, 5.0, 8.0],
        [5.0, -9.0, 4.0, 3.0, -3.0, -1.0, 6.0, 8.0],
    ])
    out = output_events(g, t)
    assert [k for k, _ in out] == [1, 3, 4, 5, 7]
    assert [time for _, time in out] == pytest.approx([0.5, 3.0, 7.25, 0.5, 1.0 + 2.0 / 3.0],
                                                      rel=TOL)


def test_no_columns_and_nothing_crossing():
    t = np.linspace(0.0, 1.0, 4)
    assert output_events(np.ones((4, 3)), t) == []
    assert output_events(np.zeros((4, 0)), t) == []
    assert output_events(np.zeros((4, 2)), t) == []  # at zero from the first sample


# --- Event ---------------------------------------------------------------------------------

def test_event_sentence():
    name = "joint joint1 reached its upper limit 2 rad (114.592 deg)"
    assert str(Event(name, 1.23456789, True)) == (
        "joint joint1 reached its upper limit 2 rad (114.592 deg) at t = 1.23457 s (run stopped)")
    assert str(Event(name, 0.25, False)) == (
        "joint joint1 reached its upper limit 2 rad (114.592 deg) at t = 0.25 s")


def test_an_event_past_at_the_start_fires_again_after_it_recovers():
    """The SUNDIALS route found events on its output grid from the first non-positive sample,
    so an event already past at the start (logged at t = 0) never fired again, while the
    compiled route's did (found by a helper's mutation work, issue 30). Now both report the
    crossing after the recovery."""
    assert output_events(np.array([[-1.0], [1.0], [-1.0]]), np.array([0.0, 1.0, 2.0])) == \
        [(0, 1.5)]
    assert output_events(np.array([[0.0], [0.0], [-1.0]]), np.array([0.0, 1.0, 2.0])) == []
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study

    robot = ps.load("serial_2dof")
    jt, _ = joint_motion(load_study("serial_2dof_joint_move"), robot)
    w = 8.0 * math.pi
    ctl = ps.controller("computed_torque", w * w, 2.0 * w, width=2)
    q0 = jt.q[0] + np.array([math.pi / 4 + 0.2, 0.0])
    times = {}
    for method in ("dopri5", "cvodes"):
        run = ps.simulate_controlled(robot, ctl, (0.0, float(jt.t_s[-1])), reference=jt,
                                     q0=q0, joint_limits={"joint1": (-10.0, math.pi / 4)},
                                     on_joint_limit="continue", method=method,
                                     t_eval=np.linspace(0.0, float(jt.t_s[-1]), 501))
        times[method] = [e.time_s for e in run.events if "upper limit" in e.name]
    assert times["dopri5"][0] == times["cvodes"][0] == 0.0
    assert len(times["dopri5"]) == len(times["cvodes"]) == 2
    # the output grid's linear interpolation against the compiled loop's located event
    assert abs(times["cvodes"][1] - times["dopri5"][1]) < 0.01


def test_a_stop_is_a_python_bool_on_every_route():
    """``Event.stopped`` was a NumPy bool on the SUNDIALS route (``tt == min(stops)`` of
    NumPy times) and a Python bool on the compiled one: ``e.stopped is True`` told them apart.
    The same stop on both routes, at the same time to the output grid's spacing."""
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study

    robot = ps.load("serial_2dof")
    jt, _ = joint_motion(load_study("serial_2dof_joint_move"), robot)
    ctl = ps.controller("pd", 400.0, 40.0, width=2)
    stops = {}
    for method in ("dopri5", "cvodes"):
        run = ps.simulate_controlled(robot, ctl, (0.0, float(jt.t_s[-1])), reference=jt,
                                     joint_limits={"joint1": (-10.0, float(jt.q[0, 0]) + 0.1)},
                                     method=method,
                                     t_eval=np.linspace(0.0, float(jt.t_s[-1]), 401))
        assert all(type(e.stopped) is bool for e in run.events), method
        stops[method] = run.stopped
    assert stops["dopri5"] is not None and stops["cvodes"] is not None
    assert stops["dopri5"].stopped is True and stops["cvodes"].stopped is True
    assert abs(stops["dopri5"].time_s - stops["cvodes"].time_s) < 0.01
