"""Motion profiles against their closed forms and their own definitions: quintic, trapezoid,
via points and tables (rates by the spline, with the convergence order stated), the CSV
reader's bad inputs, and a study driven by a table of another study's output."""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.motion.smooth import quintic, trapezoid, trapezoid_duration
from planar_sym.motion.splines import table, via
from planar_sym.motion.tables import read_table
from planar_sym.study.run import run


def central(f, t, h=1e-5):
    """Fourth-order central difference of f at t (an independent check of a derivative)."""
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def test_quintic_is_its_closed_form():
    t = np.linspace(0.0, 2.0, 41)
    tr = quintic([1.0, -1.0], [0.5, 2.0], 2.0, t)
    u = t / 2.0
    s = 10 * u**3 - 15 * u**4 + 6 * u**5
    np.testing.assert_allclose(tr.x, np.array([1.0, -1.0]) + s[:, None] * [0.5, 2.0], atol=1e-15)
    for k in (0, -1):  # at rest, zero acceleration, at both ends
        assert np.max(np.abs(tr.xd[k])) < 1e-15 and np.max(np.abs(tr.xdd[k])) < 1e-14
    inner = t[2:-2]
    pos = lambda tt: quintic([1.0, -1.0], [0.5, 2.0], 2.0, tt).x
    vel = lambda tt: quintic([1.0, -1.0], [0.5, 2.0], 2.0, tt).xd
    assert np.max(np.abs(central(pos, inner) - tr.xd[2:-2])) < 1e-9
    assert np.max(np.abs(central(vel, inner) - tr.xdd[2:-2])) < 1e-8


def test_trapezoid_peak_speed_acceleration_and_duration():
    """dx = (0.2, 0.1) m, v_max 0.1 m/s, a_max 0.5 m/s^2: channel 1 binds; the textbook
    T = d / v + v / a = 0.2 / 0.1 + 0.1 / 0.5 = 2.2 s."""
    T = trapezoid_duration([0.2, 0.1], 0.1, 0.5)
    assert T == pytest.approx(2.2, rel=1e-14)
    t = np.linspace(0.0, T, 2201)
    tr = trapezoid([0.0, 0.0], [0.2, 0.1], t, v_max=0.1, a_max=0.5)
    assert np.max(np.abs(tr.xd[:, 0])) == pytest.approx(0.1, rel=1e-12)
    assert np.max(np.abs(tr.xdd[:, 0])) == pytest.approx(0.5, rel=1e-12)
    assert tr.x[-1] == pytest.approx([0.2, 0.1], abs=1e-15)
    assert np.allclose(tr.x[:, 1], tr.x[:, 0] / 2, atol=1e-16)  # one path: they end together
    # the rate integrates to the position (trapezoid rule on the piecewise-linear speed)
    steps = np.cumsum(np.diff(t) * (tr.xd[1:, 0] + tr.xd[:-1, 0]) / 2)
    assert np.max(np.abs(steps - tr.x[1:, 0])) < 1e-7


def test_trapezoid_triangular_and_with_a_duration():
    # speed never reached: T = 2 sqrt(d / a) = 2 sqrt(0.01 / 1) = 0.2 s, peak sqrt(a d) = 0.1
    T = trapezoid_duration([0.01], 10.0, 1.0)
    assert T == pytest.approx(0.2, rel=1e-14)
    tr = trapezoid([0.0], [0.01], np.linspace(0, T, 201), v_max=10.0, a_max=1.0)
    assert np.max(tr.xd) == pytest.approx(0.1, rel=1e-12)
    slow = trapezoid([0.0], [0.2], np.linspace(0, 5.0, 501), v_max=0.1, a_max=0.5,
                     duration_s=5.0)
    assert slow.x[-1, 0] == pytest.approx(0.2, abs=1e-15)
    assert np.max(slow.xdd) == pytest.approx(0.5) and np.max(slow.xd) < 0.1
    with pytest.raises(InputError, match="shorter than the 2.2 s"):
        trapezoid([0.0], [0.2], [0.0], v_max=0.1, a_max=0.5, duration_s=1.0)


def test_via_points_are_passed_exactly_and_the_ends_are_at_rest():
    times = [0.0, 0.5, 1.5, 2.0]
    points = [[0.0, 1.0], [0.3, 1.2], [0.1, 0.8], [0.4, 1.0]]
    tr = via(times, points, np.linspace(0.0, 2.0, 401))
    at = via(times, points, times)
    np.testing.assert_allclose(at.x, points, atol=1e-15)
    assert np.max(np.abs(at.xd[[0, -1]])) < 1e-14
    # C2: the acceleration is continuous through the inner knots
    eps = 1e-9
    for tk in times[1:-1]:
        left, right = via(times, points, [tk - eps]).xdd, via(times, points, [tk + eps]).xdd
        assert np.max(np.abs(left - right)) < 1e-6
    assert tr.x.shape == (401, 2)


def test_table_rates_converge_at_the_stated_order():
    """A table sampled from a quintic (0 to 1 in 1 s: peak rate 1.875, peak acceleration
    5.77): the spline's positions converge as h^4, rates as h^3, accelerations as h^2.
    Measured with 101 rows: 1e-7, 6.3e-5 and 0.025; twice the rows divide them by 16, 7.9, 4."""
    t_fine = np.linspace(0.0, 1.0, 997)
    ref = quintic([0.0], [1.0], 1.0, t_fine)
    errs = []
    for rows in (51, 101):
        times = np.linspace(0.0, 1.0, rows)
        tr = table(times, quintic([0.0], [1.0], 1.0, times).x, t_fine)
        errs.append((np.max(np.abs(tr.x - ref.x)), np.max(np.abs(tr.xd - ref.xd)),
                     np.max(np.abs(tr.xdd - ref.xdd))))
    (x1, v1, a1), (x2, v2, a2) = errs
    assert x2 < 2e-7 and v2 < 1e-4 and a2 < 0.03
    assert x1 / x2 > 12 and v1 / v2 > 6.5 and a1 / a2 > 3.5


def write(tmp_path, text, name="t.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_csv_reader_converts_units_and_names_every_problem(tmp_path):
    _, v = read_table(write(tmp_path, "t_s,x_mm,phi_deg\n0,100,90\n1,200,180\n"),
                      [["x_mm", "x_m"], ["phi_rad", "phi_deg"]])
    np.testing.assert_allclose(v, [[0.1, np.pi / 2], [0.2, np.pi]], rtol=1e-15)
    bad = write(tmp_path, "t_s,x_mm\n0,1\n1,abc\n1,3\n0.5,2\n")
    with pytest.raises(InputError) as exc:
        read_table(bad, ["x_mm", "y_mm"])
    text = str(exc.value)
    assert "missing column y_mm (the header has t_s, x_mm)" in text
    assert "line 3, column x_mm: not a number ('abc')" in text
    with pytest.raises(InputError, match=r"line 4: time 1 s repeated \(line 3 has 1 s\)"):
        read_table(write(tmp_path, "t_s,x_mm\n0,1\n1,2\n1,3\n"), ["x_mm"])
    with pytest.raises(InputError, match=r"line 4: time 0.5 s not increasing"):
        read_table(write(tmp_path, "t_s,x_mm\n0,1\n1,2\n0.5,3\n"), ["x_mm"])
    with pytest.raises(InputError, match="needs at least 2 rows"):
        read_table(write(tmp_path, "t_s,x_mm\n0,1\n"), ["x_mm"])


def test_a_study_driven_by_another_studys_output(tmp_path):
    """S3's result as a joint-space table: the spline passes through S3's joint angles, its
    rates match S3's exact ones to the spline's accuracy, and so do the torques."""
    s3 = run("serial_2dof_cartesian_move")
    csv = tmp_path / "s3.csv"
    csv.write_text(s3.csv_text())
    study = tmp_path / "replay.toml"
    study.write_text('robot = "serial_2dof"\nkind = "inverse"\n[motion]\nspace = "joint"\n'
                     'profile = "table"\nfile = "s3.csv"\nsamples = 201\n')
    replay = run(study)
    for k in (1, 2):
        q, q3 = replay.columns[f"q{k}_rad"], s3.columns[f"q{k}_rad"]
        assert np.max(np.abs(q - q3)) < 1e-14
        qd, qd3 = replay.columns[f"qd{k}_rad_s"], s3.columns[f"qd{k}_rad_s"]
        assert np.max(np.abs(qd - qd3)) < 1e-5 * np.max(np.abs(qd3))
    tau, tau3 = replay.columns["tau1_n_m"], s3.columns["tau1_n_m"]
    assert np.max(np.abs(tau - tau3)) < 1e-4 * np.max(np.abs(tau3))


def test_a_via_study_in_task_space(tmp_path):
    """The 5-bar's P through three points (mm) in 2 s: the result passes them."""
    study = tmp_path / "via.toml"
    study.write_text('robot = "five_bar_type1"\nkind = "inverse"\n[units]\nlength = "mm"\n'
                     '[motion]\nspace = "task"\nprofile = "via"\ntimes = [0.0, 1.0, 2.0]\n'
                     'points = [[60.852, 154.665], [80.0, 170.0], [100.0, 160.0]]\n'
                     'samples = 201\n')
    result = run(study)
    x, y = result.columns["x_mm"], result.columns["y_mm"]
    for k, (px, py) in zip((0, 100, 200), [(60.852, 154.665), (80.0, 170.0), (100.0, 160.0)]):
        assert abs(x[k] - px) < 1e-9 and abs(y[k] - py) < 1e-9
    assert ps.load("five_bar_type1").constraint(np.column_stack(
        [result.columns[f"q{k}_rad"] for k in range(1, 5)])).max() < 1e-12


def test_a_trapezoid_study_takes_its_minimum_time(tmp_path):
    study = tmp_path / "trap.toml"
    study.write_text('robot = "serial_2dof"\nkind = "inverse"\n[units]\nangle = "deg"\n'
                     '[motion]\nspace = "joint"\nprofile = "trapezoid"\nstart = [0.0, 30.0]\n'
                     'by = [90.0, 0.0]\nv_max = [45.0, 45.0]\na_max = [90.0, 90.0]\n'
                     'samples = 101\n')
    result = run(study)
    assert result.columns["t_s"][-1] == pytest.approx(90 / 45 + 45 / 90, rel=1e-12)
    assert np.max(result.columns["qd1_rad_s"]) == pytest.approx(np.radians(45.0), rel=1e-12)
