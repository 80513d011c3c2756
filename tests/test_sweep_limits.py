"""A sweep says which designs break an actuator limit, and its RMS is the run's (a user trial).

* 9 of 12 designs of a gear-ratio sweep broke their motor's torque or speed limit with no word
  (no column, no warning, nothing on the plot); each design run alone warned. Now every design
  names the limits it passes (``SweepResult.over_limits``, the CSV's ``limits`` column, one
  warning, red rings on the plot), by the rule ``dynamics.sizing`` applies to one run: checked
  design by design against ``Result.sizing`` of the design's own run (its ``exceeded``).
* The sweep's ``rms_tau`` was the plain mean over the samples while the run, the sizing and the
  sweep's own ``rms_motor_tau`` are time averages (trapezoidal rule): 8.5e-4 apart on a fast
  move, so ``rms_motor_tau * N != rms_tau`` in one row. Now one definition, checked against the
  trapezoidal rule by hand on the run's own columns.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis.sweep import sweep
from planar_sym.cli import main
from planar_sym.study.run import load_study

ROOT = Path(__file__).resolve().parent.parent
PEND = ROOT / "tests" / "robots" / "pend_lim.toml"

#: the geared pendulum (N = 20; joint torque limit 1.2 N*m, motor 0.5 N*m, 3000 rpm) swung
#: 60 degrees in 0.5 s: low gears pass the motor torque, high ones the joint torque (the rotor's
#: N^2 J_m) and the motor speed, the middle ones nothing
SWING = f"""title = "geared pendulum swung 60 degrees in 0.5 s"
robot = "{PEND}"
kind = "inverse"
[units]
angle = "deg"
[motion]
space = "joint"
profile = "quintic"
start = [-90.0]
by = [60.0]
duration = 0.5
samples = 71
"""

TRACK = f"""title = "the swing tracked by PD, torque clipped at the limits"
robot = "{PEND}"
kind = "control"
[units]
angle = "deg"
[motion]
space = "joint"
profile = "quintic"
start = [-90.0]
by = [60.0]
duration = 0.5
samples = 36
[control]
law = "pd"
natural_frequency_hz = 8.0
samples = 71
"""

GEARS = [1.2, 8.0, 20.0, 60.0, 150.0]


@pytest.fixture()
def swing(tmp_path) -> Path:
    path = tmp_path / "swing.toml"
    path.write_text(SWING)
    return path


def design_run(path, gear: float):
    st = load_study(path)
    return ps.run_study(replace(st, parameters={**st.parameters, "gear_j1": (gear, "1")}))


def kinds(sentences) -> set[str]:
    """Which limits the sentences name: joint torque, motor torque, motor speed."""
    text = " ".join(sentences)
    return {k for k in ("joint torque", "motor torque", "motor speed") if k in text}


def test_each_design_names_the_limits_its_own_run_passes(swing):
    with pytest.warns(RuntimeWarning, match=r"of 5 designs pass an actuator limit") as got:
        res = sweep(swing, {"gear_j1": GEARS}, workers=1)
    assert res.route == "shared motion" and not res.failed
    seen = set()
    for k, gear in enumerate(GEARS):
        (alone,) = design_run(swing, gear).sizing
        want = kinds(alone.exceeded)
        assert kinds([res.over_limits.get(k, "")]) == want, (gear, alone.exceeded)
        seen |= want
        if want:
            assert res.note.count("over an actuator limit") == 1
    # the sweep's values are the run's: the motor's peak speed and torque as the run gives them
    assert seen == {"joint torque", "motor torque", "motor speed"}  # each kind passed somewhere
    assert str(len(res.over_limits)) in str(got[0].message)
    assert 0 < len(res.over_limits) < len(GEARS)  # and some designs pass none
    # the figures of a design over a limit are kept
    for k in res.over_limits:
        assert np.isfinite(res.columns["peak_tau1_n_m"][k])


def test_limits_by_hand_at_the_slow_gear(swing):
    """N = 1.2: the motor torque is the joint's / 1.2, over 0.5 N*m; the text gives the peak."""
    with pytest.warns(RuntimeWarning, match="1 of 1 designs"):
        res = sweep(swing, {"gear_j1": [1.2]}, workers=1)
    (alone,) = design_run(swing, 1.2).sizing
    assert alone.peak_motor_torque_n_m == pytest.approx(alone.peak_torque / 1.2, rel=1e-15)
    assert res.over_limits[0] == (f"j1: motor torque peak {alone.peak_motor_torque_n_m:.4g} "
                                  f"N*m over its limit 0.5 N*m")


def test_rms_is_the_time_average_of_the_run(swing):
    res = sweep(swing, {"gear_j1": [8.0, 20.0]}, workers=1)
    for k, gear in enumerate([8.0, 20.0]):
        run = design_run(swing, gear)
        t, tau = run.columns["t_s"], run.columns["tau1_n_m"]
        by_hand = np.sqrt(np.sum(np.diff(t) * (tau[1:] ** 2 + tau[:-1] ** 2) / 2) / (t[-1] - t[0]))
        np.testing.assert_allclose(res.columns["rms_tau1_n_m"][k], by_hand, rtol=1e-13)
        np.testing.assert_allclose(res.columns["rms_motor_tau1_n_m"][k] * gear,
                                   res.columns["rms_tau1_n_m"][k], rtol=1e-14)
        np.testing.assert_allclose(run.sizing[0].rms_torque, by_hand, rtol=1e-13)
        # the plain mean (the old figure) is measurably off on this move's uneven torque
        assert abs(np.sqrt(np.mean(tau**2)) / by_hand - 1) > 1e-4


def test_a_control_sweep_names_the_clipped_designs(tmp_path):
    """Per design: the controlled run's actuator events (commands clipped at the torque limit,
    the motor too fast), as the design's own run logs them."""
    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    with pytest.warns(RuntimeWarning, match="pass an actuator limit"):
        res = sweep(path, {"gear_j1": [1.2, 20.0]}, workers=1)
    assert res.route == "per design"
    for k, gear in enumerate([1.2, 20.0]):
        run = design_run(path, gear)
        events = "; ".join(dict.fromkeys(str(e) for e in run.events))
        assert res.over_limits.get(k, "") == events
    assert "commanded beyond its torque limit" in res.over_limits[0] and 1 not in res.over_limits


def test_the_csv_and_the_command_line_say_it(swing, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["sweep", str(swing), "--vary", "gear_j1=1.2,20,150", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert err.count("pass an actuator limit") == 1  # the warning names the count and the first
    header, *rows = (out / "swing_sweep.csv").read_text().splitlines()
    assert header.split(",")[-1] == "limits"
    assert rows[0].endswith('"j1: motor torque peak ' + rows[0].split('"j1: motor torque peak ')[1])
    with pytest.warns(RuntimeWarning, match="2 of 3 designs"):
        res = sweep(swing, {"gear_j1": [1.2, 20.0, 150.0]}, workers=1)
    for k, row in enumerate(rows):
        assert row.split(",", 3)[-1].endswith(f'"{res.over_limits.get(k, "")}"')


def test_the_c_loops_weighted_mean_square():
    """``Caller.designs(..., reduce=True, weights=w)``: sum w v^2 per design, against numpy on the
    unreduced outputs; weights of the wrong length, or without reduce, are refused."""
    from planar_sym.dynamics.sizing import rms_weights
    from planar_sym.errors import PlanarSymError

    robot = ps.load("serial_2dof")
    rng = np.random.default_rng(3)
    q, qd, qdd = (rng.uniform(-2, 2, (9, 2)) for _ in range(3))
    t = np.cumsum(rng.uniform(0.01, 0.1, 9))
    P = np.stack([robot.p, robot.p * 1.1])
    fn = robot.tree_inverse_dynamics
    full = fn.designs(P, q, qd, qdd)
    stats = fn.designs(P, q, qd, qdd, reduce=True, weights=rms_weights(t))
    np.testing.assert_allclose(stats[:, :, 2], np.einsum("s,dsc->dc", rms_weights(t), full**2),
                               rtol=1e-14)
    plain = fn.designs(P, q, qd, qdd, reduce=True)
    np.testing.assert_allclose(plain[:, :, 2], np.mean(full**2, axis=1), rtol=1e-14)
    for bad in ({"reduce": True, "weights": np.ones(8)}, {"weights": rms_weights(t)}):
        with pytest.raises(PlanarSymError, match="weights must be a float array of shape"):
            fn.designs(P, q, qd, qdd, **bad)


def _drive(joint, coordinate, **kw):
    from planar_sym.model.drive import Drive

    base = {"joint": joint, "coordinate": coordinate, "unit": "N*m", "gear_ratio": 1.0,
            "rotor_inertia": 0.0, "viscous": 0.0, "coulomb": 0.0, "smoothing": 0.01,
            "torque_limit": None, "motor_torque_limit": None, "motor_speed_limit_rad_s": None,
            "modelled": True}
    return Drive(**{**base, **kw})


class _Robot:
    """What over_limits reads of a robot: its drives, coordinate units and actuated joints."""

    def __init__(self, drives, units):
        from types import SimpleNamespace

        self.drive_train = SimpleNamespace(drives=tuple(drives))
        self.coordinate_units = tuple(units)
        self.actuated = tuple(d.coordinate for d in drives)


def test_each_limit_is_named_in_its_unit_by_hand():
    """A slider's joint force in N, a revolute joint's torque in N*m, a motor's torque and speed
    (rpm, at each design's own ratio), several limits of one design joined; a limit with none
    given is skipped without skipping the next; at the limit and within the margin is no
    breach (sizing's ON_LIMIT, 1e-6), beyond it is."""
    import math

    from planar_sym.analysis.sweep_limits import over_limits

    robot = _Robot([_drive("slide", 0, unit="N", torque_limit=100.0),
                    _drive("j1", 1, torque_limit=5.0, motor_torque_limit=0.5,
                           motor_speed_limit_rad_s=3000 * math.pi / 30)],
                   ["m", "rad"])
    ratios = np.array([[1.0, 10.0], [1.0, 20.0], [1.0, 10.0]])
    peak = np.array([[150.0, 6.0], [100.0 * (1 + 5e-7), 4.0], [100.0 * (1 + 2e-6), 5.0]])
    speed = np.array([0.1, 20.0])  # shared: m/s, rad/s
    got = over_limits(robot, ratios, peak, speed)
    assert got == {
        0: ("slide: joint force peak 150 N over its limit 100 N; j1: joint torque peak 6 N*m "
            "over its limit 5 N*m; j1: motor torque peak 0.6 N*m over its limit 0.5 N*m"),
        1: "j1: motor speed peak 3820 rpm over its limit 3000 rpm",  # 20 rad/s x 20 = 400
        2: "slide: joint force peak 100 N over its limit 100 N"}
    assert over_limits(_Robot([_drive("j1", 0, motor_torque_limit=0.5)], ["rad"]),
                       np.array([[2.0]]), np.array([[1.2]]), np.array([1.0])) == {
        0: "j1: motor torque peak 0.6 N*m over its limit 0.5 N*m"}
    # exactly on the margin is within, as sizing's _first_over has it (> not >=)
    from planar_sym.dynamics.sizing import ON_LIMIT

    edge = _Robot([_drive("j1", 0, torque_limit=100.0)], ["rad"])
    assert over_limits(edge, np.ones((1, 1)), np.array([[100.0 * (1 + ON_LIMIT)]]),
                       np.zeros(1)) == {}


def test_a_runs_limits_are_its_sizing_or_under_control_its_events():
    from types import SimpleNamespace

    from planar_sym.analysis.sweep_limits import run_over_limits

    sizing = (SimpleNamespace(exceeded=("j1: motor torque exceeds its limit",)),
              SimpleNamespace(exceeded=()))
    events = ("joint j2 reached its upper limit at t = 0.5 s",) * 2
    free = SimpleNamespace(reference=None, sizing=sizing, events=events)
    assert run_over_limits(free) == ("j1: motor torque exceeds its limit; joint j2 reached its "
                                     "upper limit at t = 0.5 s")
    tracked = SimpleNamespace(reference=np.zeros((2, 1)), sizing=sizing, events=events)
    assert run_over_limits(tracked) == "joint j2 reached its upper limit at t = 0.5 s"
    assert run_over_limits(SimpleNamespace(reference=None, sizing=(), events=())) == ""
