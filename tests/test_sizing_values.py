"""Actuator sizing (planar_sym.study.sizing) by value: RMS and peak torques against closed
forms and against the result's own columns recomputed here.

- synthetic torques through ``size``: a constant torque's RMS is its magnitude (3.5 and 2.5
  N*m, one of them negative); a sine over whole periods has RMS amplitude / sqrt(2) (the
  trapezoidal rule is exact for it up to rounding); ``1 - 4 sin(pi t / T)`` swings from +1 to
  -3 N*m, so its peak is 3 (its largest signed value is 1); all to 1e-14 relative;
- a study run (the RPR arm swung out to the left, tests write it here): the shoulder torque is
  negative throughout, about -13 to -23 N*m; each actuator's peak equals ``max |tau|`` of its
  CSV column and its RMS ``sqrt(trapz(tau^2, t) / T)``, both recomputed from the columns with
  numpy (1e-14 relative); peak power, net energy likewise from the ``p<k>_w`` column.

A mean square in place of the RMS, or the largest signed value in place of the largest
magnitude, is off by a factor (12.25 against 3.5; -13 against 22.6 N*m) and fails these.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.study.run import run
from planar_sym.study.sizing import size

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
