"""Actuator sizing (planar_sym.dynamics.sizing) by value: RMS and peak torques against closed
forms and against the result's own columns recomputed here.

- synthetic torques through ``size``: a constant torque's RMS is its magnitude (3.5 and 2.5
  N*m, one of them negative); a sine over whole periods has RMS amplitude / sqrt(2) (the
  trapezoidal rule is exact for it up to rounding); ``1 - 4 sin(pi t / T)`` swings from +1 to
  -3 N*m, so its peak is 3 (its largest signed value is 1); all to 1e-14 relative;
- a study run (the RPR arm swung out to the left, tests write it here): the shoulder torque is
  negative throughout, about -13 to -23 N*m; each actuator's peak equals ``max |tau|`` of its
  CSV column and its RMS ``sqrt(trapz(tau^2, t) / T)``, both recomputed from the columns with
  numpy (1e-14 relative); peak power, net energy likewise from the ``p<k>_w`` column.

- every field through ``size`` on a stand-in robot (actuators and parameters only): a constant
  torque against a ramp speed (the trapezoidal rule is exact on a line: energy -10 J, mean
  power -5 W), a 4 mm lead screw (300 rpm), gear ratios 4 and 2 pi / 0.004, a ``gear_<joint>``
  parameter over the description's ratio (also on examples/serial_2dof_geared.toml through
  ``with_parameters``), one sample, samples at one instant, two samples, float32 times;
- the limit sentences word for word (first sample over, the peak and its time, rpm), a value
  exactly at its limit (within), and ``table`` (header, units, "within", m/s for a screw).

A mean square in place of the RMS, or the largest signed value in place of the largest
magnitude, is off by a factor (12.25 against 3.5; -13 against 22.6 N*m) and fails these.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.dynamics.sizing import ActuatorSizing, size, table
from planar_sym.study.run import load_study, run

TOL = 1e-14
_trapezoid = getattr(np, "trapezoid", None) or np.trapz

#: the RPR arm from 150 deg (reaching out to the upper left: gravity needs a negative shoulder
#: torque), its boom out by 0.15 m and its wrist by 60 deg in 1 s
RPR_LEFT = """title = "RPR arm swung out to the left"
robot = "serial_rpr"
kind = "inverse"
[units]
length = "m"
angle = "deg"
[motion]
space = "joint"
profile = "quintic"
start = [150.0, 0.0, 0.0]
by = [20.0, 0.15, 60.0]
duration = 1.0
samples = 201
"""


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")  # two ideal actuators (gear ratio 1)


def _near(reference):
    return pytest.approx(reference, rel=TOL, abs=0.0)


def test_constant_torques_have_their_own_magnitude_as_rms_and_peak(arm):
    """Reference: for tau(t) = c, sqrt(1/T int c^2 dt) = |c| and max |tau| = |c|."""
    t = np.linspace(0.0, 2.0, 101)
    tau = np.column_stack([np.full_like(t, 3.5), np.full_like(t, -2.5)])
    shoulder, elbow = size(arm, t, np.zeros((len(t), arm.n)), tau)
    assert shoulder.rms_torque == _near(3.5)
    assert elbow.rms_torque == _near(2.5)
    assert shoulder.peak_torque == _near(3.5)
    assert elbow.peak_torque == _near(2.5)
    assert shoulder.rms_motor_torque_n_m == _near(3.5)  # gear ratio 1


def test_a_sine_over_whole_periods_has_rms_amplitude_over_root_two(arm):
    """Reference: sqrt(1/T int (A sin(2 pi f t))^2 dt) = A / sqrt(2) over whole periods."""
    t = np.linspace(0.0, 1.5, 301)  # three periods of 2 Hz
    tau = np.column_stack([4.0 * np.sin(4 * np.pi * t), 0.6 * np.cos(4 * np.pi * t)])
    shoulder, elbow = size(arm, t, np.zeros((len(t), arm.n)), tau)
    assert shoulder.rms_torque == _near(4.0 / np.sqrt(2.0))
    assert elbow.rms_torque == _near(0.6 / np.sqrt(2.0))
    assert shoulder.peak_torque == _near(4.0)
    assert elbow.peak_torque == _near(0.6)


def test_the_peak_is_the_largest_magnitude_when_it_is_negative(arm):
    """Reference: 1 - 4 sin(pi t / T) runs from +1 down to -3 (at t = T/2, a sample) and back:
    its peak magnitude is 3, its largest signed value 1."""
    t = np.linspace(0.0, 1.0, 201)
    tau = np.column_stack([1.0 - 4.0 * np.sin(np.pi * t), -0.5 + 0.2 * np.sin(np.pi * t)])
    shoulder, elbow = size(arm, t, np.zeros((len(t), arm.n)), tau)
    assert shoulder.peak_torque == _near(3.0)
    assert elbow.peak_torque == _near(0.5)
    assert shoulder.peak_motor_torque_n_m == _near(3.0)


def test_a_study_sizing_against_its_own_columns(tmp_path):
    """Reference: the written CSV's columns, reduced here with numpy: max |tau|,
    sqrt(trapz(tau^2, t) / T), max |p|, trapz(p, t)."""
    study = tmp_path / "rpr_left.toml"
    study.write_text(RPR_LEFT)
    result = run(study)
    ps.write_result(result, tmp_path, plot=False)
    data = np.genfromtxt(tmp_path / "rpr_left.csv", delimiter=",", names=True)
    t = data["t_s"]
    assert np.array_equal(t, result.columns["t_s"])  # 17 digits: the CSV is the columns
    span = t[-1] - t[0]
    columns = {"shoulder": "tau1_n_m", "extend": "tau2_n", "wrist": "tau3_n_m"}
    powers = {"shoulder": "p1_w", "extend": "p2_w", "wrist": "p3_w"}
    shoulder = data["tau1_n_m"]
    assert shoulder.max() < -10.0  # negative throughout, beyond 10 N*m: the case that matters
    assert [s.joint for s in result.sizing] == list(columns)
    for s in result.sizing:
        tau, power = data[columns[s.joint]], data[powers[s.joint]]
        assert s.peak_torque == _near(np.max(np.abs(tau))), s.joint
        assert s.rms_torque == _near(np.sqrt(_trapezoid(tau**2, t) / span)), s.joint
        assert s.peak_power_w == _near(np.max(np.abs(power))), s.joint
        assert s.energy_j == _near(_trapezoid(power, t)), s.joint
    assert result.sizing[0].peak_torque > 20.0  # N*m: about 22.6


# --- every field, the edge cases, the limit sentences and the table -------------------------

LEAD = 0.004  # m per motor turn: a screw whose gear ratio is 2 pi / lead rad per m
SCREW = 2.0 * np.pi / LEAD  # rad/m
RPM = 60.0 / (2.0 * np.pi)
GEARED = ROOT / "examples" / "serial_2dof_geared.toml"


class _Robot:
    """What ``size`` reads of a robot: its actuators and its parameters, nothing else."""

    def __init__(self, *actuators, parameters=None):
        self.actuators = tuple(actuators)
        self.parameters = dict(parameters or {})


def _act(joint, coordinate, ratio=1.0, unit="N*m", torque=None, motor_torque=None,
         motor_speed=None):
    return {"joint": joint, "coordinate": coordinate, "unit": unit, "model": True,
            "gear_ratio": ratio, "torque_limit": torque, "motor_torque_limit": motor_torque,
            "motor_speed_limit_rad_s": motor_speed}


def _one(t, tau, qd, **act):
    """The sizing of one actuator on coordinate 0 of a one-coordinate robot."""
    (s,) = size(_Robot(_act("j", 0, **act)), np.asarray(t), np.column_stack([qd]),
                np.column_stack([tau]))
    return s


def test_every_field_of_a_geared_joint_and_a_screw_on_other_coordinates():
    """References, on t in [1, 3] s (T = 2 s, not starting at 0):

    - elbow (coordinate 2, tau column 0, N = 4): tau = -2.5 N*m, qd = 0.5 + 1.5 (t - 1)
      (0.5 to 3.5 rad/s): energy = -2.5 * int qd dt = -2.5 * (1 + 3) = -10 J (the trapezoidal
      rule is exact on a line), mean power -10 / 2 = -5 W, peak power 2.5 * 3.5 = 8.75 W, motor
      torque 2.5 / 4, motor speed 3.5 * 4 = 14 rad/s;
    - slide (prismatic, coordinate 0, tau column 1, a 4 mm lead screw: N = 2 pi / 0.004 rad/m):
      F = 40 sin(pi (t - 1) / 2) N over half a period (RMS 40 / sqrt(2)), qd = 0.02 m/s: motor
      speed 0.02 / 0.004 = 5 turns/s = 300 rpm; energy trapz(F qd, t) by numpy;
    - coordinate 1 runs at 100 rad/s and drives nothing: a wrong column shows at once."""
    t = np.linspace(1.0, 3.0, 201)
    robot = _Robot(_act("elbow", 2, ratio=4.0), _act("slide", 0, ratio=SCREW, unit="N"))
    ramp = 0.5 + 1.5 * (t - 1.0)
    force = 40.0 * np.sin(np.pi * (t - 1.0) / 2.0)
    qd = np.column_stack([np.full_like(t, 0.02), np.full_like(t, 100.0), ramp])
    tau = np.column_stack([np.full_like(t, -2.5), force])
    elbow, slide = size(robot, t, qd, tau)
    rel = pytest.approx

    assert (elbow.joint, elbow.coordinate, elbow.unit, elbow.gear_ratio) == ("elbow", 2, "N*m",
                                                                             4.0)
    assert elbow.peak_torque == rel(2.5, rel=TOL) and elbow.rms_torque == rel(2.5, rel=TOL)
    assert elbow.peak_motor_torque_n_m == rel(0.625, rel=TOL)
    assert elbow.rms_motor_torque_n_m == rel(0.625, rel=TOL)
    assert elbow.peak_speed == rel(3.5, rel=TOL)
    assert elbow.peak_motor_speed_rad_s == rel(14.0, rel=TOL)
    assert elbow.peak_motor_speed_rpm == rel(14.0 * 60.0 / (2.0 * np.pi), rel=TOL)
    assert elbow.peak_power_w == rel(8.75, rel=TOL)
    assert elbow.energy_j == rel(-10.0, rel=1e-12)
    assert elbow.mean_power_w == rel(-5.0, rel=1e-12)
    assert elbow.exceeded == ()

    assert (slide.joint, slide.coordinate, slide.unit) == ("slide", 0, "N")
    assert slide.gear_ratio == rel(2.0 * np.pi / 0.004, rel=TOL)
    assert slide.peak_torque == rel(40.0, rel=TOL)
    assert slide.rms_torque == rel(40.0 / np.sqrt(2.0), rel=1e-12)
    assert slide.peak_motor_torque_n_m == rel(40.0 * 0.004 / (2.0 * np.pi), rel=TOL)
    assert slide.rms_motor_torque_n_m == rel(40.0 / np.sqrt(2.0) * 0.004 / (2.0 * np.pi),
                                             rel=1e-12)
    assert slide.peak_speed == rel(0.02, rel=TOL)
    assert slide.peak_motor_speed_rpm == rel(300.0, rel=TOL)
    assert slide.peak_power_w == rel(0.8, rel=TOL)  # 40 N * 0.02 m/s at t = 2 s (a sample)
    energy = _trapezoid(force * 0.02, t)
    assert energy == rel(0.02 * 40.0 * 4.0 / np.pi, rel=1e-4)  # int_0^2 sin(pi s / 2) = 4 / pi
    assert slide.energy_j == rel(energy, rel=TOL)
    assert slide.mean_power_w == rel(energy / 2.0, rel=TOL)


def test_a_gear_parameter_overrides_the_description_ratio():
    """Reference: the ratio ``gear_<joint>`` in the robot's parameters, not the actuator's: 10
    over a described 4 gives motor torque 3 / 10 and motor speed 2 * 10; an unrelated joint's
    gear parameter changes nothing."""
    t = np.linspace(0.0, 1.0, 11)
    tau, qd = np.full((11, 1), 3.0), np.full((11, 1), 2.0)
    robot = _Robot(_act("elbow", 0, ratio=4.0), parameters={"gear_elbow": 10.0})
    (s,) = size(robot, t, qd, tau)
    assert s.gear_ratio == 10.0
    assert s.peak_motor_torque_n_m == pytest.approx(0.3, rel=TOL)
    assert s.rms_motor_torque_n_m == pytest.approx(0.3, rel=TOL)
    assert s.peak_motor_speed_rad_s == pytest.approx(20.0, rel=TOL)
    other = _Robot(_act("elbow", 0, ratio=4.0), parameters={"gear_wrist": 10.0})
    assert size(other, t, qd, tau)[0].gear_ratio == 4.0


def test_a_geared_robot_with_its_gear_parameter_changed():
    """examples/serial_2dof_geared.toml: both joints N = 50; ``with_parameters(gear_joint1=20)``
    sizes joint 1 through 20 and leaves joint 2 at 50 (motor torque tau / N, speed N qd)."""
    robot = ps.load(GEARED)
    t = np.linspace(0.0, 1.0, 5)
    tau = np.column_stack([np.full(5, 0.4), np.full(5, -0.1)])
    qd = np.column_stack([np.full(5, 1.0), np.full(5, 0.5)])
    s1, s2 = size(robot, t, qd, tau)
    assert (s1.gear_ratio, s2.gear_ratio) == (50.0, 50.0)
    assert s1.peak_motor_torque_n_m == pytest.approx(0.4 / 50.0, rel=TOL)
    s1, s2 = size(robot.with_parameters(gear_joint1=20.0), t, qd, tau)
    assert (s1.gear_ratio, s2.gear_ratio) == (20.0, 50.0)
    assert s1.peak_motor_torque_n_m == pytest.approx(0.4 / 20.0, rel=TOL)
    assert s1.peak_motor_speed_rad_s == pytest.approx(20.0, rel=TOL)
    assert s2.peak_motor_torque_n_m == pytest.approx(0.1 / 50.0, rel=TOL)
    # 0.4 / 20 = 0.02 N*m is over the example's 0.01 N*m motor torque limit from the start
    assert s1.exceeded == (("joint1: motor torque exceeds its limit 0.01 N*m from t = 0 s "
                            "(sample 0); peak 0.02 N*m at t = 0 s"),)


def test_a_single_sample():
    """Reference: one sample at t = 0.7 s, tau = -3 N*m, qd = 2 rad/s: RMS = peak = 3, peak
    power 6 W, no duration: energy and mean power 0."""
    s = _one([0.7], [-3.0], [2.0])
    assert s.rms_torque == 3.0 and s.peak_torque == 3.0
    assert s.peak_power_w == 6.0
    assert s.energy_j == 0.0 and s.mean_power_w == 0.0


def test_samples_at_one_instant():
    """Reference: three samples all at t = 1.5 s (zero span), tau = 3, -4, 0 N*m: the RMS is
    the plain one, sqrt((9 + 16 + 0) / 3); energy and mean power 0 (no duration)."""
    s = _one([1.5, 1.5, 1.5], [3.0, -4.0, 0.0], [1.0, 1.0, 1.0])
    assert s.rms_torque == pytest.approx(np.sqrt(25.0 / 3.0), rel=TOL)
    assert s.energy_j == 0.0 and s.mean_power_w == 0.0
    assert s.peak_torque == 4.0


def test_two_samples():
    """Reference: t = 0.2, 0.7 s (T = 0.5 s), tau = 2, 4 N*m, qd = 1, 3 rad/s: power 2, 12 W,
    energy (2 + 12) / 2 * 0.5 = 3.5 J, mean power 3.5 / 0.5 = 7 W, RMS sqrt((4 + 16) / 2)."""
    s = _one([0.2, 0.7], [2.0, 4.0], [1.0, 3.0])
    assert s.energy_j == pytest.approx(3.5, rel=TOL)
    assert s.mean_power_w == pytest.approx(7.0, rel=TOL)
    assert s.rms_torque == pytest.approx(np.sqrt(10.0), rel=TOL)
    assert s.peak_power_w == 12.0


def test_single_precision_times_are_sized_in_double():
    """Reference: the same times as float64 (numpy): float32 times (a logged column) give the
    energy, mean power and RMS of their exact values; reduced in float32, the span 7.2 s would
    be off by ~2e-8 relative (7.2000003 against 7.20000019)."""
    t32 = np.linspace(0.1, 7.3, 37, dtype=np.float32)
    t = t32.astype(float)
    tau = 2.0 + np.sin(t)
    qd = 1.0 + 0.1 * t
    s = _one(t32, tau, qd)
    energy = _trapezoid(tau * qd, t)
    assert s.energy_j == pytest.approx(energy, rel=TOL)
    assert s.mean_power_w == pytest.approx(energy / (t[-1] - t[0]), rel=TOL)
    assert s.rms_torque == pytest.approx(np.sqrt(_trapezoid(tau**2, t) / (t[-1] - t[0])),
                                         rel=TOL)


#: samples for the limit sentences: t = 2, 2.25, ..., 3 s
T5 = 2.0 + np.array([0.0, 0.25, 0.5, 0.75, 1.0])
TAU5 = np.array([1.0, 3.0, -5.0, 2.0, 0.0])  # N*m: over 2.5 from sample 1, peak 5 at sample 2
QD5 = np.array([0.0, 10.0, 30.0, -40.0, 5.0])  # rad/s: through N = 4, 0 40 120 -160 20 rad/s


def test_the_limit_sentences_give_the_first_time_over_and_the_peak():
    """References by hand (N = 4): joint torque over 2.5 N*m first at sample 1 (3 N*m, t =
    2.25 s), peak 5 N*m at t = 2.5 s; motor torque tau / 4 = 0.25 0.75 -1.25 0.5 0 over 0.6
    N*m from sample 1, peak 1.25; motor speed 4 qd = 0 40 120 -160 20 rad/s over 1000 rpm
    (104.7 rad/s) from sample 2, peak 160 rad/s = 160 * 60 / (2 pi) = 1528 rpm at t = 2.75 s."""
    s = _one(T5, TAU5, QD5, ratio=4.0, torque=2.5, motor_torque=0.6,
             motor_speed=1000.0 / RPM)
    assert s.exceeded == (
        ("j: joint torque exceeds its limit 2.5 N*m from t = 2.25 s (sample 1); "
         "peak 5 N*m at t = 2.5 s"),
        ("j: motor torque exceeds its limit 0.6 N*m from t = 2.25 s (sample 1); "
         "peak 1.25 N*m at t = 2.5 s"),
        ("j: motor speed exceeds its limit 1000 rpm from t = 2.5 s (sample 2); "
         "peak 1528 rpm at t = 2.75 s"))


def test_a_prismatic_joint_exceeds_a_force_limit():
    """Reference: a slide (unit N) with forces 10 35 -40 0 N and a 30 N limit: over from
    sample 1 (t = 0.1 s), peak 40 N at t = 0.2 s; its sentence says force, not torque."""
    s = _one([0.0, 0.1, 0.2, 0.3], [10.0, 35.0, -40.0, 0.0], [0.0] * 4, unit="N", torque=30.0)
    assert s.exceeded == (("j: joint force exceeds its limit 30 N from t = 0.1 s (sample 1); "
                           "peak 40 N at t = 0.2 s"),)


def test_a_value_exactly_at_its_limit_is_within():
    """Reference: |tau| reaches 5 N*m (the limit) and no more; tau / 4 reaches 1.25; 4 qd
    reaches 160 rad/s: the limits are |v| > limit, so nothing is exceeded."""
    s = _one(T5, TAU5, QD5, ratio=4.0, torque=5.0, motor_torque=1.25, motor_speed=160.0)
    assert s.exceeded == ()
    over = _one(T5, TAU5, QD5, ratio=4.0, torque=4.999)
    assert over.exceeded == (("j: joint torque exceeds its limit 4.999 N*m from t = 2.5 s "
                              "(sample 2); peak 5 N*m at t = 2.5 s"),)


HEADER = ("| joint | gear | peak / RMS joint torque | peak / RMS motor torque (N*m) | "
          "peak joint speed | peak motor speed (rpm) | peak / mean power (W) | energy (J) | "
          "limits |")


def test_the_table():
    """Reference: the header with its units, the separator, and one row per actuator from
    hand-picked fields: a revolute joint within its limits (rad/s) and a screw (m/s) with two
    limits exceeded, joined by "; ". Motor speed 14 rad/s = 14 * 60 / (2 pi) = 133.7 rpm;
    300 rpm = 10 pi rad/s."""
    elbow = ActuatorSizing(joint="elbow", coordinate=2, unit="N*m", gear_ratio=4.0,
                           peak_torque=2.5, rms_torque=2.25, peak_motor_torque_n_m=0.625,
                           rms_motor_torque_n_m=0.5625, peak_speed=3.5,
                           peak_motor_speed_rad_s=14.0, peak_power_w=8.75, mean_power_w=-5.0,
                           energy_j=-10.0)
    slide = ActuatorSizing(joint="slide", coordinate=0, unit="N", gear_ratio=1570.8,
                           peak_torque=40.0, rms_torque=28.28, peak_motor_torque_n_m=0.02546,
                           rms_motor_torque_n_m=0.018, peak_speed=0.02,
                           peak_motor_speed_rad_s=10.0 * np.pi, peak_power_w=0.8,
                           mean_power_w=0.2546, energy_j=0.5093,
                           exceeded=("slide: first sentence", "slide: second sentence"))
    assert table(()) == ""
    assert table((elbow, slide)).split("\n") == [
        HEADER,
        "|---|---|---|---|---|---|---|---|---|",
        ("| elbow | 4 | 2.5 / 2.25 N*m | 0.625 / 0.5625 | 3.5 rad/s | 133.7 | 8.75 / -5 | -10 "
         "| within |"),
        ("| slide | 1571 | 40 / 28.28 N | 0.02546 / 0.018 | 0.02 m/s | 300 | 0.8 / 0.2546 | "
         "0.5093 | slide: first sentence; slide: second sentence |")]


def test_a_value_on_its_limit_to_a_solvers_accuracy_is_within():
    """An optimal motion rides its limits to its solver's accuracy: |tau| = 5 N*m against a
    limit 1e-7 below (relative) is on it; 1e-5 below, it is over."""
    assert _one(T5, TAU5, QD5, ratio=4.0, torque=5.0 / (1 + 1e-7)).exceeded == ()
    over = _one(T5, TAU5, QD5, ratio=4.0, torque=5.0 / (1 + 1e-5))
    assert len(over.exceeded) == 1 and "joint torque exceeds" in over.exceeded[0]


def test_a_clipped_control_run_is_not_within_its_limits(tmp_path):
    """A trial: the report's sizing table said "within" for a controlled run whose command was
    clipped at the torque limit from 0.05 s (its applied torque stays within by clipping).
    The limits cell now carries the run's events for that actuator, as the run logged them;
    an actuator with no event and no limit passed still says "within"."""
    from test_sweep_limits import TRACK

    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    st = load_study(path)
    run = ps.run_study(replace(st, parameters={**st.parameters, "gear_j1": (1.2, "1")}))
    clipped = [str(e) for e in run.events if "commanded beyond" in e.name]
    assert clipped and all(not s.exceeded for s in run.sizing)  # applied: within, by clipping
    row = table(run.sizing, run.events).splitlines()[2]
    assert row.split("|")[-2].strip() == "; ".join(dict.fromkeys(str(e) for e in run.events))
    assert "within" not in row and "at the joint (the motor's 0.5 N*m x N = 1.2)" in row
    quiet = ps.run_study(replace(st, parameters={**st.parameters, "gear_j1": (20.0, "1")}))
    assert not quiet.events
    assert table(quiet.sizing, quiet.events).splitlines()[2].endswith("| within |")
