"""Motion profiles, each against something independent of its implementation: the closed form
written out, the textbook duration of a trapezoid, high-order finite differences of the
positions (the rates are analytic, never differences), polynomials a spline must reproduce,
convergence orders of a table sampled from a known quintic, and the CSV reader's messages."""

from __future__ import annotations

import numpy as np
import pytest

from planar_sym.errors import InputError
from planar_sym.motion.profiles import coeff_3rd, cubic
from planar_sym.motion.profiles_by_name import KINDS, make_profile, profile_span
from planar_sym.motion.smooth import quintic, trapezoid, trapezoid_duration
from planar_sym.motion.splines import table, via
from planar_sym.motion.tables import read_table, to_si


def d1(f, t, h):
    """Rate by the 4th-order central difference of f (error h^4 f^(5) / 30)."""
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def d2(f, t, h):
    """Acceleration by the 4th-order central difference of f (error h^4 f^(6) / 90)."""
    return (-f(t - 2 * h) + 16 * f(t - h) - 30 * f(t) + 16 * f(t + h) - f(t + 2 * h)) / (12 * h * h)


def worst(a, b):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


# -- cubic: the seed's coeff_3rd, unchanged ---------------------------------------------------

def test_cubic_is_coeff_3rd_bit_for_bit():
    """The README's path: every value equal to the coeff_3rd formula evaluated in the same
    order (numpy's vectorised power is CPU-dependent in the last bit, so no hash is pinned:
    the formula, evaluated the same way, is the reference)."""
    x0, dx, T = np.array([0.1, 0.1]), np.array([-0.2, 0.0]), 5.0
    t = np.linspace(0.0, T, 201)
    tr = cubic(x0, dx, T, t)
    c2 = (3.0 * dx - (2.0 * 0.0 + 0.0) * T) / (T * T)
    c3 = (-2.0 * dx + (0.0 + 0.0) * T) / (T * T * T)
    tt = t[:, None]
    assert np.array_equal(tr.x, x0 + 0.0 * tt + c2 * tt**2 + c3 * tt**3)
    assert np.array_equal(tr.xd, 0.0 + 2 * c2 * tt + 3 * c3 * tt**2)
    assert np.array_equal(tr.xdd, 2 * c2 + 6 * c3 * tt)
    np.testing.assert_array_equal(coeff_3rd(x0, [0, 0], x0 + dx, [0, 0], T)[:, 2:],
                                  np.column_stack([c2, c3]))
    # ends: x0 and x0 + dx at rest; the textbook's peak rate 1.5 dx / T at T / 2
    assert worst(tr.x[[0, -1]], [x0, x0 + dx]) < 1e-16
    assert worst(tr.xd[[0, -1]], 0.0) < 1e-16
    assert tr.xd[100, 0] == pytest.approx(1.5 * -0.2 / 5.0, rel=1e-14)


# -- quintic -----------------------------------------------------------------------------------

X0, DX, T5 = np.array([0.1, -0.3]), np.array([0.25, 0.6]), 1.5


def test_quintic_is_its_closed_form_with_rest_at_both_ends():
    t = np.linspace(0.0, T5, 61)
    tr = quintic(X0, DX, T5, t)
    # x = x0 + dx (10 tau^3 - 15 tau^4 + 6 tau^5), and its derivatives written out
    tau = (t / T5)[:, None]
    # (measured 1.4e-15, 3.4e-15, 7.8e-15: rounding of a different evaluation order)
    assert worst(tr.x, X0 + DX * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)) < 1e-14
    assert worst(tr.xd, DX * (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / T5) < 1e-14
    assert worst(tr.xdd, DX * (60 * tau - 180 * tau**2 + 120 * tau**3) / T5**2) < 1e-13
    # boundary conditions: positions exact, rates and accelerations zero at 0 and T
    assert np.array_equal(tr.x[0], X0) and worst(tr.x[-1], X0 + DX) < 1e-16
    assert np.all(tr.xd[[0, -1]] == 0.0) and np.all(tr.xdd[[0, -1]] == 0.0)
    # textbook peaks: rate 15/8 dx/T at T/2, acceleration 10/sqrt(3) dx/T^2 at (3-sqrt 3)/6 T
    assert tr.xd[30] == pytest.approx(1.875 * DX / T5, rel=1e-14)
    at = quintic(X0, DX, T5, [(3 - np.sqrt(3)) / 6 * T5])
    assert at.xdd[0] == pytest.approx(10 / np.sqrt(3) * DX / T5**2, rel=1e-13)


def test_quintic_rates_match_finite_differences_of_its_positions():
    """Rates against a 4th-order difference of the positions (h = 1e-3 s: measured 2.1e-12,
    tolerance 1e-10), accelerations against a 4th-order second difference of the positions
    (measured 1.4e-9, rounding / h^2; tolerance 1e-7)."""
    t = np.linspace(0.01, T5 - 0.01, 57)
    tr = quintic(X0, DX, T5, t)
    pos = lambda tt: quintic(X0, DX, T5, tt).x
    assert worst(d1(pos, t, 1e-3), tr.xd) < 1e-10
    assert worst(d2(pos, t, 1e-3), tr.xdd) < 1e-7


# -- trapezoid ---------------------------------------------------------------------------------

def test_trapezoid_minimum_time_matches_the_textbook():
    """dx = (0.2, 0.1) m, v_max 0.1 m/s, a_max 0.5 m/s^2 for both: channel 1 binds.
    Textbook T = d / v + v / a = 0.2 / 0.1 + 0.1 / 0.5 = 2.2 s, ramps of v / a = 0.2 s."""
    T = trapezoid_duration([0.2, 0.1], 0.1, 0.5)
    assert T == pytest.approx(2.2, rel=1e-15)
    t = np.linspace(0.0, T, 2201)
    tr = trapezoid([0.3, -0.1], [0.2, 0.1], t, v_max=0.1, a_max=0.5)
    assert np.max(np.abs(tr.xd[:, 0])) == pytest.approx(0.1, rel=1e-14)
    assert np.max(np.abs(tr.xdd[:, 0])) == pytest.approx(0.5, rel=1e-14)
    assert np.max(np.abs(tr.xd[:, 1])) <= 0.1 and np.max(np.abs(tr.xdd[:, 1])) <= 0.5
    # exact ends: start, start + dx, at rest
    assert np.array_equal(tr.x[0], [0.3, -0.1]) and np.array_equal(tr.x[-1], [0.5, 0.0])
    assert np.all(tr.xd[[0, -1]] == 0.0)
    # synchronised: channel 2 is channel 1 scaled by 0.1/0.2, so both start and end together
    assert worst(tr.x[:, 1] + 0.1, (tr.x[:, 0] - 0.3) / 2) < 1e-16
    # cruise exactly between the ramps: t in [0.2, 2.0] s at 0.1 m/s, zero acceleration
    cruise = (t > 0.2 + 1e-9) & (t < 2.0 - 1e-9)
    assert np.all(tr.xd[cruise, 0] == 0.1) and np.all(tr.xdd[cruise, 0] == 0.0)
    assert np.all(tr.xdd[t < 0.2 - 1e-9, 0] == 0.5) and np.all(tr.xdd[t > 2.0 + 1e-9, 0] == -0.5)


def test_trapezoid_rates_match_finite_differences_inside_each_piece():
    """Each piece is a polynomial of degree <= 2, so a 4th-order difference whose stencil stays
    inside one piece is exact to rounding: measured 4.9e-13 for the rate (h = 1e-4 s,
    tolerance 1e-9), 6.1e-11 for the acceleration (h = 1e-3 s, tolerance 1e-7)."""
    tr_at = lambda tt: trapezoid([0.0], [0.2], tt, v_max=0.1, a_max=0.5).x
    t = np.concatenate([np.linspace(0.01, 0.19, 10), np.linspace(0.21, 1.99, 30),
                        np.linspace(2.01, 2.19, 10)])
    tr = trapezoid([0.0], [0.2], t, v_max=0.1, a_max=0.5)
    assert worst(d1(tr_at, t, 1e-4), tr.xd) < 1e-9
    assert worst(d2(tr_at, t, 1e-3), tr.xdd) < 1e-7


def test_trapezoid_triangular_when_the_cruise_speed_is_not_reached():
    """dx = 0.01 m, a_max 1 m/s^2, v_max 10 m/s: the triangle T = 2 sqrt(d / a) = 0.2 s,
    peak sqrt(a d) = 0.1 m/s at T / 2."""
    T = trapezoid_duration([0.01], 10.0, 1.0)
    assert T == pytest.approx(0.2, rel=1e-15)
    t = np.linspace(0.0, T, 201)
    tr = trapezoid([0.0], [0.01], t, v_max=10.0, a_max=1.0)
    assert np.max(tr.xd) == pytest.approx(0.1, rel=1e-14) and tr.xd[100, 0] == np.max(tr.xd)
    assert np.max(np.abs(tr.xdd)) == 1.0 and tr.x[-1, 0] == 0.01 and tr.xd[-1, 0] == 0.0


def test_trapezoid_per_channel_limits_choose_the_binding_channel():
    """dx = (0.2, -0.9) rad, v_max (1, 1.5) rad/s, a_max (4, 3) rad/s^2: per channel the path
    speed limits are 5 and 1.667 /s, the acceleration limits 20 and 3.333 /s^2: channel 2
    binds both; T = 0.9 / 1.5 + 1.5 / 3 = 1.1 s. With a_max 2 on channel 2 the cruise speed
    is out of reach (1.5^2 / 2 > 0.9): the triangle T = 2 sqrt(0.9 / 2) = 1.3416 s."""
    T = trapezoid_duration([0.2, -0.9], [1.0, 1.5], [4.0, 3.0])
    assert T == pytest.approx(0.9 / 1.5 + 1.5 / 3.0, rel=1e-15)
    tr = trapezoid([0.0, 0.0], [0.2, -0.9], np.linspace(0.0, T, 1101), v_max=[1.0, 1.5],
                   a_max=[4.0, 3.0])
    assert np.min(tr.xd[:, 1]) == pytest.approx(-1.5, rel=1e-14)
    assert np.max(np.abs(tr.xdd[:, 1])) == pytest.approx(3.0, rel=1e-14)
    assert trapezoid_duration([0.2, -0.9], [1.0, 1.5], [4.0, 2.0]) == \
        pytest.approx(2 * np.sqrt(0.45), rel=1e-15)
    assert np.max(np.abs(tr.xd[:, 0])) < 1.0 and worst(tr.x[-1], [0.2, -0.9]) < 1e-16


def test_trapezoid_with_a_duration_takes_exactly_that_long():
    """dx = 0.2 m in 5 s under a_max 0.5 m/s^2 (minimum 2.2 s): cruise vc solves
    vc (T - vc / a) = d, vc = (a T - sqrt(a^2 T^2 - 4 a d)) / 2 = 0.04066 m/s."""
    t = np.linspace(0.0, 5.0, 5001)
    tr = trapezoid([0.0], [0.2], t, v_max=0.1, a_max=0.5, duration_s=5.0)
    vc = (0.5 * 5.0 - np.sqrt(0.25 * 25.0 - 4 * 0.5 * 0.2)) / 2
    assert np.max(tr.xd) == pytest.approx(vc, rel=1e-13) and vc == pytest.approx(0.040661, 1e-4)
    assert np.max(tr.xdd) == 0.5 and tr.x[-1, 0] == 0.2 and tr.xd[-1, 0] == 0.0
    # a duration equal to the minimum gives the minimum-time profile
    fast = trapezoid([0.0], [0.2], t[t <= 2.2], v_max=0.1, a_max=0.5, duration_s=2.2)
    assert np.max(fast.xd) == pytest.approx(0.1, rel=1e-12)


def test_trapezoid_refusals_name_the_figures():
    with pytest.raises(InputError) as exc:
        trapezoid([0.0, 0.0], [0.2, 0.1], [0.0], v_max=0.1, a_max=0.5, duration_s=1.0)
    assert str(exc.value) == (
        "trapezoid: a duration of 1 s is shorter than the 2.2 s the speed and acceleration "
        "limits allow (speed set by channel 1 of 2: |dx| = 0.2, v_max = 0.1 per s; "
        "acceleration by channel 1 of 2: |dx| = 0.2, a_max = 0.5 per s^2)")
    with pytest.raises(InputError, match=r"0\.1 s is shorter than the 0\.2 s .*\(triangular"):
        trapezoid([0.0], [0.01], [0.0], v_max=10.0, a_max=1.0, duration_s=0.1)
    with pytest.raises(InputError, match="dx is zero in every channel"):
        trapezoid_duration([0.0, 0.0], 1.0, 1.0)
    with pytest.raises(InputError, match=r"v_max needs 1 or 2 values, one per channel \(got 3"):
        trapezoid([0, 0], [1, 1], [0.0], v_max=[1, 1, 1], a_max=1.0)
    with pytest.raises(InputError, match=r"a_max must be positive and finite \(got \[0\.0\]"):
        trapezoid([0], [1], [0.0], v_max=1.0, a_max=0.0)
    with pytest.raises(InputError, match=r"time t = 2\.3 s \(sample 1\) is outside the "
                                         r"trajectory \[0, 2\.2\] s"):
        trapezoid([0.0], [0.2], [0.0, 2.3], v_max=0.1, a_max=0.5)


# -- shared checks of the point-to-point profiles ----------------------------------------------

@pytest.mark.parametrize("make", [
    lambda x0, dx, T, t: quintic(x0, dx, T, t),
    lambda x0, dx, T, t: trapezoid(x0, dx, t, v_max=10.0, a_max=10.0, duration_s=T)])
def test_point_to_point_inputs_are_checked(make):
    for T in (0.0, -1.0, np.inf, np.nan, True, "2"):
        with pytest.raises(InputError, match="duration must be a positive number of seconds"):
            make([0.0], [1.0], T, [0.0])
    with pytest.raises(InputError, match=r"x0 and dx must have the same length \(got 2 and 1\)"):
        make([0.0, 0.0], [1.0], 2.0, [0.0])
    with pytest.raises(InputError, match="start must be finite"):
        make([np.nan], [1.0], 2.0, [0.0])
    with pytest.raises(InputError, match=r"time t = -0\.1 s \(sample 2\) is outside the "
                                         r"trajectory \[0, 2\] s"):
        make([0.0], [1.0], 2.0, [0.0, 1.0, -0.1])
    with pytest.raises(InputError, match=r"time t = nan s \(sample 0\) is not finite"):
        make([0.0], [1.0], 2.0, [np.nan])
    with pytest.raises(InputError, match="must be a 1-D array"):
        make([0.0], [1.0], 2.0, [[0.0]])


# -- via points ---------------------------------------------------------------------------------

VIA_T = [0.0, 0.5, 1.5, 2.0]
VIA_X = [[0.0, 1.0], [0.3, 1.2], [0.1, 0.8], [0.4, 1.0]]


def test_via_passes_every_point_at_rest_at_the_ends_and_is_c2():
    at = via(VIA_T, VIA_X, VIA_T)
    assert worst(at.x, VIA_X) < 1e-15
    assert worst(at.xd[[0, -1]], 0.0) < 1e-15
    for tk in VIA_T[1:-1]:  # C2: xd, xdd continuous through the inner points (jumps would be
        side = via(VIA_T, VIA_X, [tk - 1e-10, tk + 1e-10])  # O(1); measured 1.1e-9, 7.5e-10)
        assert worst(side.xdd[0], side.xdd[1]) < 1e-7 and worst(side.xd[0], side.xd[1]) < 1e-7
    t = np.linspace(0.0, 2.0, 401)
    tr = via(VIA_T, VIA_X, t)
    assert tr.x.shape == tr.xd.shape == tr.xdd.shape == (401, 2)
    pos = lambda tt: via(VIA_T, VIA_X, tt).x
    inner = t[(t > 0.01) & (t < 1.99) & np.all(np.abs(t[:, None] - VIA_T) > 0.01, axis=1)]
    assert worst(d1(pos, inner, 1e-3), via(VIA_T, VIA_X, inner).xd) < 1e-10  # measured 3.2e-13


def test_via_reproduces_a_cubic_at_rest_at_both_ends():
    """A clamped spline reproduces any cubic with the same end rates: points of 3 t^2 - 2 t^3
    (at rest at 0 and 1) at uneven times give back that cubic everywhere (to 1e-15)."""
    f = lambda t: 3 * t**2 - 2 * t**3
    times = np.array([0.0, 0.17, 0.6, 0.71, 1.0])
    t = np.linspace(0.0, 1.0, 101)
    tr = via(times, f(times), t)
    assert worst(tr.x[:, 0], f(t)) < 1e-15
    assert worst(tr.xd[:, 0], 6 * t - 6 * t**2) < 1e-14
    assert worst(tr.xdd[:, 0], 6 - 12 * t) < 1e-13


def test_via_inputs_are_checked():
    with pytest.raises(InputError, match="via needs at least 2 points"):
        via([0.0], [[1.0]], [0.0])
    with pytest.raises(InputError, match=r"via: 3 times need 3 points .*got shape \(2, 2\)"):
        via([0.0, 1.0, 2.0], [[0, 0], [1, 1]], [0.0])
    with pytest.raises(InputError, match=r"t\[2\] = 1 s repeats t\[1\] = 1 s"):
        via([0.0, 1.0, 1.0], [0, 1, 2], [0.0])
    with pytest.raises(InputError, match=r"t\[1\] = 0\.5 s comes before t\[0\] = 1 s"):
        via([1.0, 0.5], [0, 1], [0.0])
    with pytest.raises(InputError, match="via point 1 must be finite"):
        via([0.0, 1.0], [0.0, np.inf], [0.0])
    with pytest.raises(InputError, match=r"time t = 2\.5 s \(sample 0\) is outside the via "
                                         r"points' span \[0, 2\] s"):
        via(VIA_T, VIA_X, [2.5])


# -- tables ------------------------------------------------------------------------------------

def test_table_converges_at_the_stated_order_on_a_quintic():
    """A table sampled from the quintic 0 -> 1 in 1 s (peak rate 1.875 /s, peak acceleration
    5.77 /s^2), evaluated at 997 times. Measured errors (x, xd, xdd):
    51 rows: 1.6e-6, 5.0e-4, 0.098; 101 rows: 9.9e-8, 6.3e-5, 0.025; 201 rows: 6.2e-9,
    8.0e-6, 6.3e-3. Doubling the rows divides them by 16, 7.9, 3.9: orders h^4, h^3, h^2."""
    t = np.linspace(0.0, 1.0, 997)
    ref = quintic([0.0], [1.0], 1.0, t)
    errs = {}
    for rows in (51, 101, 201):
        times = np.linspace(0.0, 1.0, rows)
        tr = table(times, quintic([0.0], [1.0], 1.0, times).x, t)
        errs[rows] = np.array([worst(tr.x, ref.x), worst(tr.xd, ref.xd), worst(tr.xdd, ref.xdd)])
    assert np.all(errs[101] < [1.2e-7, 7e-5, 0.03])  # the stated figures with 101 rows
    for coarse, fine in ((51, 101), (101, 201)):
        order = np.log2(errs[coarse] / errs[fine])
        assert np.all(np.abs(order - [4, 3, 2]) < 0.1), order
    # the table's own rows are passed exactly
    times = np.linspace(0.0, 1.0, 101)
    rows = quintic([0.0], [1.0], 1.0, times).x
    assert worst(table(times, rows, times).x, rows) < 1e-15


def test_table_reproduces_cubics_and_short_tables():
    """Not-a-knot ends reproduce any cubic exactly; 2 rows: a straight line, 3: a parabola."""
    f = lambda t: 1 - 2 * t + 0.5 * t**2 + 0.25 * t**3
    times = np.array([0.0, 0.3, 1.1, 1.5, 2.0])
    t = np.linspace(0.0, 2.0, 41)
    tr = table(times, f(times), t)
    assert worst(tr.x[:, 0], f(t)) < 1e-14
    assert worst(tr.xd[:, 0], -2 + t + 0.75 * t**2) < 1e-13
    assert worst(tr.xdd[:, 0], 1 + 1.5 * t) < 1e-12
    line = table([0.0, 2.0], [[1.0, 0.0], [2.0, -4.0]], [0.0, 0.5, 2.0])
    assert worst(line.x, [[1, 0], [1.25, -1], [2, -4]]) < 1e-15
    assert worst(line.xd, [[0.5, -2]] * 3) < 1e-15 and worst(line.xdd, 0.0) < 1e-15
    par = table([0.0, 1.0, 3.0], [0.0, 1.0, 9.0], [2.0])
    assert par.x[0, 0] == pytest.approx(4.0, rel=1e-15) and par.xdd[0, 0] == pytest.approx(2.0)
    with pytest.raises(InputError, match=r"outside the table's span \[0\.5, 2\] s"):
        table([0.5, 2.0], [0.0, 1.0], [0.0])


# -- CSV tables --------------------------------------------------------------------------------

def write(tmp_path, text, name="motion.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_read_table_converts_units_by_suffix(tmp_path):
    path = write(tmp_path, "t_s,x_mm,phi_deg,y_m,q1_rad,tau1_n_m\n"
                           "0,100,90,0.5,1.5,2\n\n0.5,200,180,0.25,-1,3\n")
    times, v = read_table(path, [["x_m", "x_mm"], "phi_deg", "y_m", "q1_rad", "tau1_n_m"])
    assert np.array_equal(times, [0.0, 0.5])
    np.testing.assert_allclose(v, [[0.1, np.pi / 2, 0.5, 1.5, 2.0],
                                   [0.2, np.pi, 0.25, -1.0, 3.0]], rtol=1e-15)
    assert to_si("x_mm") == 1e-3 and to_si("q_deg") == np.pi / 180 and to_si("t_s") == 1.0
    with pytest.raises(InputError, match=r"column 'x' has no unit suffix \(_s, _mm, _m, _deg"):
        to_si("x")
    # a byte-order mark (Excel's UTF-8) does not hide t_s
    bom = tmp_path / "bom.csv"
    bom.write_bytes(b"\xef\xbb\xbft_s,x_m\n0,1\n1,2\n")
    assert np.array_equal(read_table(bom, ["x_m"])[1], [[1.0], [2.0]])


def test_read_table_names_every_problem_at_once(tmp_path):
    """One file with a missing column, a non-number, an empty cell, an infinite value, a
    repeated and a backward time: all six reported together, each with file, line, column;
    line numbers count the blank line 3."""
    path = write(tmp_path, "t_s,x_mm,q1_deg\n0,1,2\n\n1,abc,3\n1,3,\n0.5,inf,4\n2,5,6\n")
    with pytest.raises(InputError) as exc:
        read_table(path, ["x_mm", "q1_deg", ["y_mm", "y_m"]])
    assert str(exc.value).splitlines() == [
        "invalid table (6 problems):",
        f"  {path}: missing column y_mm or y_m (the header has t_s, x_mm, q1_deg)",
        f"  {path}: line 4, column x_mm: not a number ('abc')",
        f"  {path}: line 5, column q1_deg: empty",
        f"  {path}: line 6, column x_mm: must be finite ('inf')",
        f"  {path}: line 5: time 1 s repeated (line 4 has 1 s)",
        f"  {path}: line 6: time 0.5 s not increasing (line 4 has 1 s)"]


@pytest.mark.parametrize("text, columns, message", [
    ("x_mm\n1\n2\n", ["x_mm"], "{p}: missing column t_s (the header has x_mm)"),
    ("t_s,x_mm\n0,1\n", ["x_mm"], "{p}: needs at least 2 rows of numbers (has 1)"),
    ("t_s,x_mm\n0,1\n0,2\n", ["x_mm"], "{p}: line 3: time 0 s repeated (line 2 has 0 s)"),
    ("t_s,x_mm\n0,1\n2,2\n1,3\n", ["x_mm"],
     "{p}: line 4: time 1 s not increasing (line 3 has 2 s)"),
    ("t_s,x_mm\n0,1\nnan,2\n", ["x_mm"], "{p}: line 3, column t_s: must be finite ('nan')"),
    ("t_s,x_mm\n0,1\n1,2 m\n", ["x_mm"], "{p}: line 3, column x_mm: not a number ('2 m')"),
    ("t_s,x_mm\n0,1\n1\n", ["x_mm"], "{p}: line 3, column x_mm: empty"),
    ("t_s,x\n0,1\n1,2\n", ["x"], ("{p}: line 1: column 'x' has no unit suffix "
                                  "(_s, _mm, _m, _deg, _rad, _n_m, _n)")),
    ("t_s,x_mm,x_mm\n0,1,1\n1,2,2\n", ["x_mm"],
     "{p}: line 1: column x_mm appears 2 times in the header"),
    ("t_s,x_mm\n0,1,7\n1,2\n", ["x_mm"],
     "{p}: line 2: 3 cells, but the header names 2 columns (extra: 7)"),
    ("\n\n", ["x_mm"], "{p}: empty: a header row (t_s, ...) and at least 2 rows of numbers"),
])
def test_read_table_each_bad_input(tmp_path, text, columns, message):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as exc:
        read_table(path, columns)
    assert str(exc.value) == message.format(p=path)


def test_read_table_lists_twenty_problems_and_counts_the_rest(tmp_path):
    path = write(tmp_path, "t_s,x_mm\n" + "".join(f"{k},x{k}\n" for k in range(30)))
    with pytest.raises(InputError) as exc:
        read_table(path, ["x_mm"])
    lines = str(exc.value).splitlines()
    assert lines[0] == "invalid table (30 problems):" and len(lines) == 22
    assert lines[1] == f"  {path}: line 2, column x_mm: not a number ('x0')"
    assert lines[20] == f"  {path}: line 21, column x_mm: not a number ('x19')"
    assert lines[21] == "  ... and 10 more"


def test_read_table_unreadable_files(tmp_path):
    with pytest.raises(InputError, match=r"nothing\.csv: cannot read \(No such file"):
        read_table(tmp_path / "nothing.csv", ["x_mm"])
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"t_s,x_mm\n\xff\xfe\x00\n")
    with pytest.raises(InputError, match=r"b\.csv: not a text \(CSV\) file"):
        read_table(binary, ["x_mm"])


def test_a_csv_table_drives_a_profile(tmp_path):
    """A quintic written to CSV in mm and read back: the profile through it matches the
    quintic to the spline's accuracy (101 rows: rates within 6.3e-5 m/s per m moved)."""
    times = np.linspace(0.0, 1.0, 101)
    q = quintic([0.0], [0.2], 1.0, times).x[:, 0]
    body = "".join(f"{float(a)!r},{float(b) * 1e3!r}\n" for a, b in zip(times, q))
    path = write(tmp_path, "t_s,x_mm\n" + body)
    t_read, x = read_table(path, ["x_mm"])
    t = np.linspace(0.0, 1.0, 333)
    tr = make_profile("table", table_times=t_read, table_values=x, t_s=t)
    ref = quintic([0.0], [0.2], 1.0, t)
    assert worst(tr.x, ref.x) < 0.2 * 1.2e-7 and worst(tr.xd, ref.xd) < 0.2 * 7e-5


# -- one entry point ---------------------------------------------------------------------------

def test_make_profile_is_each_profile_by_name():
    t = np.linspace(0.0, 2.0, 21)
    start, end = np.array([0.1, 0.2]), np.array([0.4, -0.1])
    assert np.array_equal(make_profile("cubic", start=start, by=end - start, duration_s=2.0,
                                       t_s=t).x, cubic(start, end - start, 2.0, t).x)
    assert np.array_equal(make_profile("quintic", start=start, end=end, duration_s=2.0,
                                       t_s=t).xd, quintic(start, end - start, 2.0, t).xd)
    T = profile_span("trapezoid", start=start, end=end, v_max=0.3, a_max=1.0)[1]
    assert T == pytest.approx(0.3 / 0.3 + 0.3 / 1.0, rel=1e-15)
    tr = make_profile("trapezoid", start=start, end=end, v_max=0.3, a_max=1.0,
                      t_s=np.linspace(0.0, T, 11))
    assert worst(tr.x[-1], end) < 1e-16
    assert profile_span("cubic", start=start, end=end, duration_s=2.0) == (0.0, 2.0)
    assert profile_span("via", via_times=VIA_T, via_points=VIA_X) == (0.0, 2.0)
    assert profile_span("table", table_times=[0.5, 1.0], table_values=[1, 2]) == (0.5, 1.0)
    assert np.array_equal(make_profile("via", via_times=VIA_T, via_points=VIA_X, t_s=t).xdd,
                          via(VIA_T, VIA_X, t).xdd)
    assert KINDS == ("cubic", "quintic", "trapezoid", "via", "table")


def test_make_profile_refuses_unknown_kinds_and_stray_arguments():
    with pytest.raises(InputError) as exc:
        make_profile("zigzag", t_s=[0.0])
    assert str(exc.value) == ("unknown motion profile 'zigzag': the known ones are cubic, "
                              "quintic, trapezoid, via, table")
    with pytest.raises(InputError, match=r"a cubic profile does not take a_max, v_max \(it "
                                         r"takes by, duration_s, end, start\)"):
        make_profile("cubic", start=[0], end=[1], duration_s=1.0, v_max=1, a_max=1, t_s=[0.0])
    with pytest.raises(InputError, match="a quintic profile needs duration_s"):
        make_profile("quintic", start=[0], end=[1], t_s=[0.0])
    with pytest.raises(InputError, match=r"needs end or by \(exactly one\)"):
        make_profile("cubic", start=[0], end=[1], by=[1], duration_s=1.0, t_s=[0.0])
    with pytest.raises(InputError, match="a via profile does not take duration_s"):
        make_profile("via", via_times=VIA_T, via_points=VIA_X, duration_s=2.0, t_s=[0.0])
    with pytest.raises(InputError, match="a table profile needs table_values"):
        profile_span("table", table_times=[0, 1])
    with pytest.raises(InputError, match=r"start and end must have the same length"):
        make_profile("quintic", start=[0, 0], end=[1], duration_s=1.0, t_s=[0.0])


def test_the_motion_modules_load_without_scipy():
    """SciPy loads on the first spline, not on import (``import planar_sym`` stays light)."""
    import subprocess
    import sys

    code = ("import sys, planar_sym, planar_sym.motion.profiles_by_name, "
            "planar_sym.motion.tables\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('scipy', 'sympy')))\n"
            "planar_sym.motion.profiles_by_name.make_profile('via', via_times=[0, 1], "
            "via_points=[0, 1], t_s=[0.5])\n"
            "print('scipy' in sys.modules)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split("\n")[:2] == ["[]", "True"]
