"""Piecewise-polynomial signals (planar_sym.motion.signals) by value, against independent
references.

- ``"linear"`` and ``"hold"`` tables against values worked out by hand (slopes 2, -6, 3, 0;
  the end segments extend before the first row and after the last);
- ``"cubic"`` (not-a-knot) reproduces a cubic exactly, ``"pchip"`` equals SciPy's
  ``PchipInterpolator`` and ``"cubic"`` SciPy's ``CubicSpline`` (values and derivatives);
- ``from_motion`` reproduces a quintic exactly (value and derivatives 1 to 5, zero above),
  equals SciPy's ``BPoly.from_derivatives`` on random data, and its derivatives match finite
  differences of its values;
- ``hold_until`` (value held, one segment appended, nothing for an end at or before the last
  knot), ``covers`` at its tolerance boundaries (1e-12 s, relative for long runs);
- integer times and values are read as numbers (an int8 -100 to 100 does not wrap around),
  values come back as float64, and a scalar SciPy ``PPoly`` becomes one channel;
- every refusal word for word: too few times, a non-finite time, times not increasing (the
  first offending row), a non-finite table cell or reference entry, an unknown interpolation.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import BPoly, CubicSpline, PchipInterpolator, PPoly

from planar_sym.errors import InputError
from planar_sym.motion.signals import Signal, _from_ppoly, _times, from_motion, from_table

TOL = 1e-12

# a two-channel table: rows at 0, 1, 3 s
T3 = [0.0, 1.0, 3.0]
V3 = [[0.0, 10.0], [2.0, 4.0], [8.0, 4.0]]


# -- linear and hold by hand --------------------------------------------------------------------

def test_linear_by_hand():
    s = from_table(T3, V3, "linear")
    assert s.channels == 2 and s.degree == 1 and s.span_s == (0.0, 3.0)
    assert s.coefficients.shape == (2, 2, 2)
    np.testing.assert_allclose(s([0.5, 1.0, 2.0, 3.0]),
                               [[1.0, 7.0], [2.0, 4.0], [5.0, 4.0], [8.0, 4.0]], rtol=0, atol=TOL)
    np.testing.assert_allclose(s([0.5, 2.0], derivative=1), [[2.0, -6.0], [3.0, 0.0]],
                               rtol=0, atol=TOL)
    # the end segments extend: before 0 s along the first one, after 3 s along the last
    np.testing.assert_allclose(s(-1.0), [[-2.0, 16.0]], rtol=0, atol=TOL)
    np.testing.assert_allclose(s(4.0), [[11.0, 4.0]], rtol=0, atol=TOL)
    np.testing.assert_allclose(s(-1.0, derivative=1), [[2.0, -6.0]], rtol=0, atol=TOL)


def test_hold_by_hand():
    s = from_table(T3, V3, "hold")
    assert s.degree == 0 and s.coefficients.shape == (2, 2, 1)
    np.testing.assert_array_equal(s([-1.0, 0.0, 0.5, 0.999, 1.0, 2.9, 3.0, 5.0]),
                                  [[0, 10], [0, 10], [0, 10], [0, 10], [2, 4], [2, 4], [2, 4],
                                   [2, 4]])
    np.testing.assert_array_equal(s([0.5, 2.0], derivative=1), np.zeros((2, 2)))


def test_one_channel_from_a_flat_column():
    s = from_table([0.0, 2.0], [1.0, 5.0], "linear")
    assert s.channels == 1
    np.testing.assert_allclose(s([0.5, 1.0]), [[2.0], [3.0]], rtol=0, atol=TOL)


# -- cubic and pchip against closed forms and SciPy ---------------------------------------------

def _cubic(t):
    return 1.0 - 2.0 * t + 0.5 * t ** 2 + 0.25 * t ** 3


def test_cubic_reproduces_a_cubic():
    t = np.array([0.0, 0.4, 1.1, 1.5, 2.7, 3.0])
    s = from_table(t, np.column_stack([_cubic(t), -3.0 * _cubic(t)]), "cubic")
    assert s.degree == 3 and s.channels == 2 and s.coefficients.shape == (5, 2, 4)
    x = np.array([0.1, 0.77, 1.3, 2.0, 2.95])
    exact = [_cubic(x), -2.0 + x + 0.75 * x ** 2, 1.0 + 1.5 * x, np.full_like(x, 1.5)]
    for d, ref in enumerate(exact):
        np.testing.assert_allclose(s(x, derivative=d), np.column_stack([ref, -3.0 * ref]),
                                   rtol=1e-11, atol=1e-11)


def test_cubic_and_pchip_equal_scipy():
    t = np.array([0.0, 0.3, 0.9, 1.0, 1.8, 2.5])
    v = np.column_stack([np.sin(3 * t), [0.0, 1.0, 1.0, 3.0, -1.0, 0.5]])
    x = np.linspace(-0.2, 2.7, 37)
    for name, ref in (("cubic", CubicSpline(t, v)), ("pchip", PchipInterpolator(t, v))):
        s = from_table(t, v, name)
        assert s.degree == 3
        for d in range(4):
            np.testing.assert_allclose(s(x, derivative=d), ref(x, nu=d), rtol=1e-12, atol=1e-12)
    # pchip does not overshoot: between two equal rows it stays flat
    flat = from_table(t, v, "pchip")(np.linspace(0.3, 0.9, 7))[:, 1]
    np.testing.assert_allclose(flat, 1.0, rtol=0, atol=TOL)


def test_scalar_ppoly_becomes_one_channel():
    t = np.array([0.0, 1.0, 2.5, 3.0])
    y = np.array([1.0, -1.0, 2.0, 0.0])
    ref = CubicSpline(t, y)
    s = _from_ppoly(PPoly(ref.c, ref.x))  # c is (4, 3): one channel
    assert s.channels == 1 and s.degree == 3 and s.coefficients.shape == (3, 1, 4)
    x = np.linspace(0.0, 3.0, 13)
    np.testing.assert_allclose(s(x)[:, 0], ref(x), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s(x, derivative=2)[:, 0], ref(x, nu=2), rtol=1e-12, atol=1e-12)


# -- from_motion: quintic Hermite ---------------------------------------------------------------

A = [0.3, -1.0, 2.0, 0.5, -0.7, 0.2]  # a quintic, ascending powers


def _quintic(t, d=0):
    t = np.asarray(t, dtype=float)
    out = np.zeros_like(t)
    for j, a in enumerate(A):
        if j >= d:
            out += a * np.prod(np.arange(j - d + 1, j + 1)) * t ** (j - d)
    return out


def test_from_motion_reproduces_a_quintic():
    t = np.array([0.0, 0.5, 1.25, 2.0])
    s = from_motion(t, _quintic(t), _quintic(t, 1), _quintic(t, 2))
    assert s.degree == 5 and s.channels == 1 and s.coefficients.shape == (3, 1, 6)
    # on the first segment (knot 0) the coefficients are the quintic's own
    np.testing.assert_allclose(s.coefficients[0, 0], A, rtol=1e-12, atol=1e-12)
    x = np.array([-0.3, 0.1, 0.5, 0.9, 1.6, 2.0, 2.4])
    for d in range(6):
        np.testing.assert_allclose(s(x, derivative=d)[:, 0], _quintic(x, d), rtol=1e-10,
                                   atol=1e-10)
    np.testing.assert_array_equal(s(x, derivative=6), np.zeros((len(x), 1)))
    # 5th derivative: 120 * a5 everywhere
    np.testing.assert_allclose(s(x, derivative=5)[:, 0], 120 * A[5], rtol=1e-9)


def test_from_motion_equals_bpoly_and_finite_differences():
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.2, 0.8, 6))
    q, qd, qdd = (rng.normal(size=(6, 2)) for _ in range(3))
    s = from_motion(t, q, qd, qdd)
    x = np.linspace(t[0] - 0.1, t[-1] + 0.1, 41)
    for ch in range(2):
        ref = BPoly.from_derivatives(t, np.stack([q[:, ch], qd[:, ch], qdd[:, ch]], axis=1))
        for d in range(4):
            np.testing.assert_allclose(s(x, derivative=d)[:, ch], ref(x, nu=d), rtol=1e-9,
                                       atol=1e-9)
    # the rows themselves: position, rate, acceleration as given
    for d, ref in enumerate((q, qd, qdd)):
        np.testing.assert_allclose(s(t, derivative=d), ref, rtol=1e-10, atol=1e-10)
    # derivatives against central differences of the values
    xm = (t[:-1] + t[1:]) / 2
    h = 1e-5
    for d in range(3):
        fd = (s(xm + h, derivative=d) - s(xm - h, derivative=d)) / (2 * h)
        np.testing.assert_allclose(s(xm, derivative=d + 1), fd, rtol=1e-6, atol=1e-5)


# -- hold_until and covers ----------------------------------------------------------------------

def test_hold_until():
    s = from_table(T3, V3, "linear")
    held = s.hold_until(5.0)
    np.testing.assert_array_equal(held.knots_s, [0.0, 1.0, 3.0, 5.0])
    assert held.coefficients.shape == (3, 2, 2)
    np.testing.assert_allclose(held([0.5, 2.0, 3.0, 4.0, 5.0, 6.0]),
                               [[1, 7], [5, 4], [8, 4], [8, 4], [8, 4], [8, 4]], rtol=0, atol=TOL)
    np.testing.assert_array_equal(held([3.5, 4.5], derivative=1), np.zeros((2, 2)))
    # an end at or before the last knot changes nothing
    for t_end in (3.0, 2.0):
        same = s.hold_until(t_end)
        np.testing.assert_array_equal(same.knots_s, s.knots_s)
        np.testing.assert_array_equal(same.coefficients, s.coefficients)


def test_covers_boundaries():
    s = from_table([1e-12, 1.0 - 1e-12], [[0.0], [1.0]])
    s.covers(0.0, 1.0, "the table")  # both ends exactly at the 1e-12 s tolerance
    with pytest.raises(InputError) as e:
        from_table([2e-12, 1.0], [[0.0], [1.0]]).covers(0.0, 1.0, "the table")
    assert str(e.value) == ("the table covers 2e-12 to 1 s, but the run goes from 0 to 1 s: "
                            "extend the table, or shorten the run")
    with pytest.raises(InputError) as e:
        from_table([0.0, 1.0 - 1.5e-12], [[0.0], [1.0]]).covers(0.0, 1.0, "the torque table")
    assert str(e.value) == ("the torque table covers 0 to 1 s, but the run goes from 0 to 1 s: "
                            "extend the table, or shorten the run")
    # the tolerance is relative for a long run: 1e-9 s at 1000 s
    from_table([0.0, 1000.0 - 5e-10], [[0.0], [1.0]]).covers(0.0, 1000.0, "x")
    with pytest.raises(InputError):
        from_table([0.0, 1000.0 - 2e-9], [[0.0], [1.0]]).covers(0.0, 1000.0, "x")
    with pytest.raises(InputError) as e:
        from_table([0.0, 2.0], [[0.0], [1.0]]).covers(0.0, 3.0, "the reference")
    assert str(e.value) == ("the reference covers 0 to 2 s, but the run goes from 0 to 3 s: "
                            "extend the table, or shorten the run")


# -- number types ------------------------------------------------------------------------------

def test_small_integer_arrays_are_numbers():
    # int8 times -100 and 100 s: their difference 200 does not fit an int8
    t8 = np.array([-100, 100], dtype=np.int8)
    np.testing.assert_array_equal(_times(t8), [-100.0, 100.0])
    assert _times([0, 1, 2]).dtype == np.float64
    s = from_table(t8, [[0.0], [4.0]], "linear")
    np.testing.assert_allclose(s([0.0, 50.0]), [[2.0], [3.0]], rtol=0, atol=TOL)
    # int8 values 100 and -100
    v8 = np.array([[100], [-100]], dtype=np.int8)
    for name in ("linear", "cubic", "pchip"):
        np.testing.assert_allclose(from_table([0.0, 1.0], v8, name)([0.0, 0.5, 1.0]),
                                   [[100.0], [0.0], [-100.0]], rtol=0, atol=1e-9)
    z8 = np.zeros((2, 1), dtype=np.int8)
    s = from_motion([0.0, 1.0], v8, z8, z8)
    np.testing.assert_allclose(s([0.0, 0.5, 1.0]), [[100.0], [0.0], [-100.0]], rtol=0, atol=1e-9)
    np.testing.assert_allclose(s(1.0, derivative=1), [[0.0]], rtol=0, atol=1e-9)
    # whole-second int times of a long segment: h^5 = 1e20 does not fit an int64
    s = from_motion(np.array([0, 10000]), [0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    np.testing.assert_allclose(s([5000.0, 10000.0])[:, 0], [0.5, 1.0], rtol=1e-12)


def test_values_are_float64_whatever_the_times():
    s = from_table(T3, V3, "linear")
    ref = s(0.1)
    for t in (np.longdouble("0.1"), np.float64(0.1), [0.1]):
        out = s(t)
        assert out.dtype == np.float64 and out.shape == (1, 2)
        np.testing.assert_array_equal(out, ref)
    np.testing.assert_array_equal(s(2), [[5.0, 4.0]])


# -- refusals, word for word --------------------------------------------------------------------

def _message(fn, *args) -> str:
    with pytest.raises(InputError) as e:
        fn(*args)
    return str(e.value)


def test_too_few_times():
    assert _message(from_table, [0.0], [[1.0]]) == "a signal needs at least 2 times (got shape (1,))"
    assert _message(from_motion, [0.0], [1.0], [0.0], [0.0]) == (
        "a signal needs at least 2 times (got shape (1,))")
    assert _message(_times, [[0.0, 1.0], [2.0, 3.0]]) == (
        "a signal needs at least 2 times (got shape (2, 2))")
    assert _message(_times, 1.0) == "a signal needs at least 2 times (got shape ())"


def test_non_finite_times():
    assert _message(from_table, [0.0, np.inf, np.nan, 3.0], np.zeros(4)) == (
        "time 1 is inf: times must be finite")
    assert _message(_times, [0.0, 1.0, np.nan]) == "time 2 is nan: times must be finite"


def test_times_must_increase():
    assert _message(from_table, [0.0, 1.0, 2.0, 1.5, 3.0], np.zeros(5)) == (
        "times must increase: row 3 has t = 1.5 s after 2 s")
    # a repeated time is not an increase
    assert _message(_times, [0.0, 1.0, 1.0, 2.0]) == (
        "times must increase: row 2 has t = 1 s after 1 s")
    assert _message(_times, [5.0, 4.0]) == "times must increase: row 1 has t = 4 s after 5 s"


def test_non_finite_table_cell():
    v = [[0.0, 1.0], [2.0, np.inf], [3.0, 4.0]]
    assert _message(from_table, [0.0, 0.5, 1.0], v, "cubic") == (
        "row 1 (t = 0.5 s), column 1: inf is not finite")
    v = [[0.0, 1.0], [2.0, 3.0], [np.nan, -np.inf]]
    assert _message(from_table, [0.0, 0.5, 1.0], v) == (
        "row 2 (t = 1 s), column 0: nan is not finite")


def test_non_finite_reference():
    t = [0.0, 0.5, 1.0]
    ok = np.zeros((3, 2))
    for name, at in (("position", 0), ("rate", 1), ("acceleration", 2)):
        args = [ok.copy(), ok.copy(), ok.copy()]
        args[at][1, 1] = np.nan
        assert _message(from_motion, t, *args) == (
            f"reference {name} at t = 0.5 s, channel 1: nan is not finite")
    q = ok.copy()
    q[2, 0], q[2, 1] = np.inf, np.nan
    assert _message(from_motion, t, q, ok, ok) == (
        "reference position at t = 1 s, channel 0: inf is not finite")


def test_unknown_interpolation():
    assert _message(from_table, [0.0, 1.0], [0.0, 1.0], "spline") == (
        "interpolation must be one of hold, linear, cubic, pchip (got 'spline')")


def test_signal_by_hand_coefficients():
    # 1 + 2 x - x^2 on [0, 2] from knot 0, then 3 - 4 (t - 2) on [2, 4]
    s = Signal(np.array([0.0, 2.0, 4.0]),
               np.array([[[1.0, 2.0, -1.0]], [[3.0, -4.0, 0.0]]]))
    assert s.channels == 1 and s.degree == 2 and s.span_s == (0.0, 4.0)
    np.testing.assert_allclose(s([1.0, 2.0, 3.0])[:, 0], [2.0, 3.0, -1.0], rtol=0, atol=TOL)
    np.testing.assert_allclose(s([1.0, 3.0], derivative=1)[:, 0], [0.0, -4.0], rtol=0, atol=TOL)
    np.testing.assert_allclose(s([1.0, 3.0], derivative=2)[:, 0], [-2.0, 0.0], rtol=0, atol=TOL)
