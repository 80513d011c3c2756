"""The motion inputs by value: CSV tables read back against known unit conversions (mm -> m,
deg -> rad) with exact messages naming the file, line and column; the seed's cubic coefficients
with end rates against the Hermite conditions solved as a linear system; profiles by name
against closed forms (the rest-to-rest quintic, the trapezoid's durations from its textbook
formulas), and each refusal's exact message."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planar_sym.errors import InputError
from planar_sym.motion.profiles import coeff_3rd, cubic
from planar_sym.motion.profiles_by_name import make_profile, profile_span
from planar_sym.motion.tables import read_table, to_si


def _message(fn, *args, **kwargs) -> str:
    with pytest.raises(InputError) as info:
        fn(*args, **kwargs)
    return str(info.value)


def _csv(tmp_path, text: str | bytes, name: str = "t.csv"):
    path = tmp_path / name
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_bytes(text.encode("utf-8"))
    return path


# --- tables.py: to_si ---------------------------------------------------------------------------

def test_to_si_factors_of_every_suffix():
    assert to_si("x_mm") == 1e-3
    assert to_si("x_m") == 1.0
    assert to_si("q_deg") == math.pi / 180.0
    assert to_si("q_rad") == 1.0
    assert to_si("tau_n_m") == 1.0
    assert to_si("f_n") == 1.0
    assert to_si("t_s") == 1.0


@pytest.mark.parametrize("bare", ["_s", "_m", "_mm", "_deg", "_rad", "_n", "_n_m"])
def test_to_si_refuses_a_bare_suffix_without_a_name(bare):
    # "_n_m" is not a suffix alone, and its "_m" part has the name "_n": a known column.
    if bare == "_n_m":
        assert to_si(bare) == 1.0
        return
    assert _message(to_si, bare) == (
        f"column {bare!r} has no unit suffix (_s, _mm, _m, _deg, _rad, _n_m, _n)")


# --- tables.py: read_table ----------------------------------------------------------------------

def test_read_table_converts_mm_and_deg_to_si(tmp_path):
    path = _csv(tmp_path, "t_s,x_mm,q_deg\n0,100,30\n0.5,120,-45\n2,0,180\n")
    t, v = read_table(path, ["x_mm", "q_deg"])
    assert t.tolist() == [0.0, 0.5, 2.0]
    assert t.dtype == np.float64 and v.dtype == np.float64
    np.testing.assert_allclose(v, [[0.1, math.pi / 6], [0.12, -math.pi / 4], [0.0, math.pi]],
                               rtol=1e-15, atol=0)


def test_read_table_with_only_the_times(tmp_path):
    t, v = read_table(_csv(tmp_path, "t_s,x_m\n0,5\n1,5\n"), [])
    assert t.tolist() == [0.0, 1.0] and v.shape == (2, 0)


def test_read_table_a_quoted_name_keeps_its_crlf(tmp_path):
    # newline="" hands the csv module the file's own line ends, so a quoted cell keeps "\r\n"
    path = _csv(tmp_path, b't_s,"x\r\ny_m"\r\n0,1\r\n1,2\r\n')
    t, v = read_table(path, ["x\r\ny_m"])
    assert t.tolist() == [0.0, 1.0] and v.tolist() == [[1.0], [2.0]]
    assert _message(read_table, path, ["z_m"]) == (
        f"{path}: missing column z_m (the header has t_s, x\r\ny_m)")


def test_read_table_a_quoted_cell_with_crlf_is_named_as_it_is(tmp_path):
    path = _csv(tmp_path, b't_s,x_m\r\n0,1\r\n1,"2\r\n5"\r\n2,3\r\n')
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: line 3, column x_m: not a number ('2\\r\\n5')")


def test_read_table_a_field_too_large_is_not_a_csv_file(tmp_path):
    path = _csv(tmp_path, "t_s,x_m\n0," + "1" * 200_000 + "\n1,2\n")
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: not a CSV file (field larger than field limit (131072))")


def test_read_table_byte_order_mark_is_ignored(tmp_path):
    path = _csv(tmp_path, b"\xef\xbb\xbft_s,x_mm\n0,1\n1,2\n")
    t, v = read_table(path, ["x_mm"])
    assert t.tolist() == [0.0, 1.0] and v.tolist() == [[1e-3], [2e-3]]


def test_read_table_a_missing_column_does_not_stop_the_next_columns_checks(tmp_path):
    path = _csv(tmp_path, "t_s,x_m\n0,1\n1,abc\n")
    assert _message(read_table, path, ["y_m", "x_m"]) == (
        "invalid table (2 problems):\n"
        f"  {path}: missing column y_m (the header has t_s, x_m)\n"
        f"  {path}: line 3, column x_m: not a number ('abc')")


def test_read_table_without_times_checks_every_other_column(tmp_path):
    path = _csv(tmp_path, "time,x_m\n0,1\n1,zz\n")
    assert _message(read_table, path, ["x_m"]) == (
        "invalid table (2 problems):\n"
        f"  {path}: missing column t_s (the header has time, x_m)\n"
        f"  {path}: line 3, column x_m: not a number ('zz')")


def test_read_table_without_times_does_not_order_another_column(tmp_path):
    # x_m repeats and goes back, but it is not the time: only the missing t_s is reported
    path = _csv(tmp_path, "time,x_m\n0,1\n1,1\n2,0\n")
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: missing column t_s (the header has time, x_m)")


def test_read_table_keeps_ordering_the_times_after_a_bad_one(tmp_path):
    path = _csv(tmp_path, "t_s,x_m\n0,1\nabc,2\n1,3\n1,4\n")
    assert _message(read_table, path, ["x_m"]) == (
        "invalid table (2 problems):\n"
        f"  {path}: line 3, column t_s: not a number ('abc')\n"
        f"  {path}: line 5: time 1 s repeated (line 4 has 1 s)")


@pytest.mark.parametrize("cell, what", [("abc", "not a number ('abc')"),
                                        ("", "empty"),
                                        ("inf", "must be finite ('inf')"),
                                        ("nan", "must be finite ('nan')")])
def test_read_table_a_bad_time_is_one_problem(tmp_path, cell, what):
    path = _csv(tmp_path, f"t_s,x_m\n0,1\n{cell},2\n3,4\n")
    assert _message(read_table, path, ["x_m"]) == f"{path}: line 3, column t_s: {what}"


def test_read_table_a_bad_time_then_a_time_going_back(tmp_path):
    path = _csv(tmp_path, "t_s,x_m\n0,1\ninf,2\n2,3\n1,4\n")
    assert _message(read_table, path, ["x_m"]) == (
        "invalid table (2 problems):\n"
        f"  {path}: line 3, column t_s: must be finite ('inf')\n"
        f"  {path}: line 5: time 1 s not increasing (line 4 has 2 s)")


def test_read_table_rows_in_reverse_order_are_one_message(tmp_path):
    """A file written newest first listed 800 near-identical lines (a user trial): more than
    MAX_LISTED rows out of order are one problem, counted, the first named."""
    from planar_sym.motion.tables import MAX_LISTED

    n = MAX_LISTED + 5
    rows = "".join(f"{n - k},{k}\n" for k in range(n))
    path = _csv(tmp_path, "t_s,x_m\n" + rows)
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: column t_s: {n - 1} of {n} rows are not later than the rows before them "
        f"(line 3: time {n - 1} s not increasing (line 2 has {n} s)): sort the rows by time")
    few = _csv(tmp_path, "t_s,x_m\n0,1\n2,2\n1,3\n3,4\n")  # a few: each is named
    assert _message(read_table, few, ["x_m"]) == (
        f"{few}: line 4: time 1 s not increasing (line 3 has 2 s)")


def test_read_table_one_trailing_empty_header_cell(tmp_path):
    # Excel often writes "t_s,x_m," : the header names 2 columns, a third cell may be blank
    path = _csv(tmp_path, "t_s,x_m,\n0,1,\n1,2, \n")
    t, v = read_table(path, ["x_m"])
    assert t.tolist() == [0.0, 1.0] and v.tolist() == [[1.0], [2.0]]


def test_read_table_two_trailing_empty_header_cells(tmp_path):
    path = _csv(tmp_path, "t_s,x_m,,\n0,1,,\n1,2,,\n")
    t, v = read_table(path, ["x_m"])
    assert t.tolist() == [0.0, 1.0] and v.tolist() == [[1.0], [2.0]]


def test_read_table_a_cell_under_a_trailing_empty_header_cell_is_extra(tmp_path):
    path = _csv(tmp_path, "t_s,x_m,\n0,1,5\n1,2\n")
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: line 2: 3 cells, but the header names 2 columns (extra: 5)")


def test_read_table_extra_cells_are_all_listed(tmp_path):
    path = _csv(tmp_path, "t_s,x_m\n0,1\n1,2,5, ,6\n")
    assert _message(read_table, path, ["x_m"]) == (
        f"{path}: line 3: 5 cells, but the header names 2 columns (extra: 5, 6)")


def _bad_rows(n: int) -> str:
    return "t_s,x_m\n" + "".join(f"{k},bad{k}\n" for k in range(n))


def test_read_table_exactly_max_listed_problems_has_no_count_line(tmp_path):
    path = _csv(tmp_path, _bad_rows(20))
    expected = [f"{path}: line {k + 2}, column x_m: not a number ('bad{k}')" for k in range(20)]
    assert _message(read_table, path, ["x_m"]) == (
        "invalid table (20 problems):\n  " + "\n  ".join(expected))


def test_read_table_one_problem_more_than_listed(tmp_path):
    path = _csv(tmp_path, _bad_rows(21))
    expected = [f"{path}: line {k + 2}, column x_m: not a number ('bad{k}')" for k in range(20)]
    assert _message(read_table, path, ["x_m"]) == (
        "invalid table (21 problems):\n  " + "\n  ".join(expected) + "\n  ... and 1 more")


def test_read_table_two_problems_more_than_listed(tmp_path):
    path = _csv(tmp_path, _bad_rows(22))
    text = _message(read_table, path, ["x_m"])
    assert text.startswith("invalid table (22 problems):\n  ")
    assert text.endswith("line 21, column x_m: not a number ('bad19')\n  ... and 2 more")


# --- profiles.py --------------------------------------------------------------------------------

def _hermite(sp, sv, ep, ev, T):
    """Cubic coefficients from x(0) = sp, x'(0) = sv, x(T) = ep, x'(T) = ev, by linear solve."""
    m = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [1.0, T, T**2, T**3],
                  [0.0, 1.0, 2 * T, 3 * T**2]])
    return np.array([np.linalg.solve(m, [a, b, c, d]) for a, b, c, d in zip(sp, sv, ep, ev)])


def test_coeff_3rd_with_end_rates_meets_the_hermite_conditions():
    sp, sv, ep, ev, T = [0.3, -1.0], [0.7, -0.2], [1.1, 2.5], [-0.4, 1.3], 2.5
    c = coeff_3rd(sp, sv, ep, ev, T)
    np.testing.assert_allclose(c, _hermite(sp, sv, ep, ev, T), rtol=1e-12, atol=1e-14)
    # and the polynomial itself passes its four conditions
    for k in range(2):
        p = np.polynomial.Polynomial(c[k])
        assert p(0.0) == pytest.approx(sp[k], abs=1e-14)
        assert p(T) == pytest.approx(ep[k], abs=1e-12)
        assert p.deriv()(0.0) == pytest.approx(sv[k], abs=1e-14)
        assert p.deriv()(T) == pytest.approx(ev[k], abs=1e-12)


def test_cubic_values_against_the_closed_form():
    x0, dx, T = np.array([0.2, -1.0]), np.array([0.6, 3.0]), 1.6
    t = np.array([0.0, 0.4, 0.8, 1.3, 1.6])
    tr = cubic(x0, dx, T, t)
    u = t[:, None] / T
    np.testing.assert_allclose(tr.x, x0 + dx * (3 * u**2 - 2 * u**3), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(tr.xd, dx * 6 * u * (1 - u) / T, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(tr.xdd, dx * 6 * (1 - 2 * u) / T**2, rtol=1e-13, atol=1e-14)


def test_cubic_names_start_and_times():
    assert _message(cubic, "abc", [1.0], 1.0, [0.0]) == (
        "trajectory start must be numbers (got 'abc': could not convert string to float: "
        "'abc')")
    assert _message(cubic, [0.0], [1.0], 1.0, "abc") == (
        "trajectory times must be numbers (got 'abc': could not convert string to float: "
        "'abc')")


# --- profiles_by_name.py ------------------------------------------------------------------------

def test_quintic_by_name_against_the_closed_form():
    T, x0, x1 = 2.0, np.array([0.1, -0.5]), np.array([0.4, 0.5])
    t = np.array([0.0, 0.5, 1.0, 1.7, 2.0])
    tr = make_profile("quintic", t_s=t, start=x0, end=x1, duration_s=T)
    u = t[:, None] / T
    dx = x1 - x0
    np.testing.assert_allclose(tr.x, x0 + dx * (10 * u**3 - 15 * u**4 + 6 * u**5),
                               rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(tr.xd, dx * 30 * u**2 * (1 - u) ** 2 / T, rtol=1e-13, atol=1e-15)


def test_cubic_by_name_with_by():
    tr = make_profile("cubic", t_s=[0.0, 1.0, 2.0], start=[1.0], by=[2.0], duration_s=2.0)
    assert tr.x[:, 0].tolist() == pytest.approx([1.0, 2.0, 3.0], abs=1e-15)


@pytest.mark.parametrize("kind, extra", [("cubic", {"duration_s": 1.0}),
                                         ("quintic", {"duration_s": 1.0}),
                                         ("trapezoid", {"v_max": 1.0, "a_max": 1.0})])
def test_point_to_point_profiles_need_exactly_one_of_end_and_by(kind, extra):
    need = f"a {kind} profile needs end or by (exactly one)"
    assert _message(make_profile, kind, t_s=[0.0], start=[0.0], **extra) == need
    assert _message(make_profile, kind, t_s=[0.0], start=[0.0], end=[1.0], by=[1.0],
                    **extra) == need
    assert _message(profile_span, kind, start=[0.0], **extra) == need
    assert _message(profile_span, kind, start=[0.0], end=[1.0], by=[1.0], **extra) == need


def test_every_missing_argument_is_listed():
    assert _message(make_profile, "cubic", t_s=[0.0]) == (
        "a cubic profile needs start, duration_s, end or by (exactly one)")
    assert _message(profile_span, "trapezoid", start=[0.0], end=[1.0]) == (
        "a trapezoid profile needs v_max, a_max")


def test_step_names_start_and_end():
    assert _message(make_profile, "cubic", t_s=[0.0], start="abc", end=[1.0],
                    duration_s=1.0) == (
        "trajectory start must be numbers (got 'abc': could not convert string to float: "
        "'abc')")
    assert _message(make_profile, "quintic", t_s=[0.0], start=[0.0], end="xyz",
                    duration_s=1.0) == (
        "trajectory end must be numbers (got 'xyz': could not convert string to float: "
        "'xyz')")
    assert _message(profile_span, "trapezoid", start=[0.0], end="xyz", v_max=1.0,
                    a_max=1.0) == (
        "trajectory end must be numbers (got 'xyz': could not convert string to float: "
        "'xyz')")


# trapezoid of dx = 1 under v_max = 0.5, a_max = 1: the cruise speed is reached (v^2 < a):
# T_min = dx / v_max + v_max / a_max = 2 + 0.5 = 2.5 s.
# With T = 4 s the cruise speed vc solves vc (T - vc / a) = dx: vc^2 - 4 vc + 1 = 0, the slower
# root vc = 2 - sqrt(3), reached after ta = vc / a.
_TRAP = {"start": [0.0], "end": [1.0], "v_max": 0.5, "a_max": 1.0}


def test_trapezoid_span_is_its_textbook_minimum_time():
    assert profile_span("trapezoid", **_TRAP) == (0.0, pytest.approx(2.5, rel=1e-15))
    # triangular: dx = 2, v_max = 3, a_max = 2: T = 2 sqrt(dx / a_max) = 2 s
    assert profile_span("trapezoid", start=[1.0], by=[2.0], v_max=3.0, a_max=2.0) == (
        0.0, pytest.approx(2.0, rel=1e-15))


def test_trapezoid_span_with_a_duration_is_that_duration():
    assert profile_span("trapezoid", duration_s=4.0, **_TRAP) == (0.0, 4.0)
    assert profile_span("cubic", start=[0.0], end=[1.0], duration_s=3.0) == (0.0, 3.0)


def test_trapezoid_by_name_takes_the_duration_given():
    vc = 2.0 - math.sqrt(3.0)
    ta = vc  # a = 1
    t = np.array([0.1, 1.0, 2.0, 4.0])
    tr = make_profile("trapezoid", t_s=t, duration_s=4.0, **_TRAP)
    s_expected = [0.5 * 0.1**2, vc * (1.0 - ta / 2), 0.5, 1.0]
    np.testing.assert_allclose(tr.x[:, 0], s_expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tr.xd[:, 0], [0.1, vc, vc, 0.0], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tr.xdd[:, 0], [1.0, 0.0, 0.0, -1.0], rtol=0, atol=0)


def test_trapezoid_by_name_without_a_duration_takes_the_minimum():
    tr = make_profile("trapezoid", t_s=[0.25, 1.25, 2.5], **_TRAP)
    # ta = v_max / a_max = 0.5 s
    np.testing.assert_allclose(tr.x[:, 0], [0.5 * 0.25**2, 0.125 + 0.5 * 0.75, 1.0],
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tr.xd[:, 0], [0.25, 0.5, 0.0], rtol=1e-12, atol=1e-15)


def test_span_of_via_points_names_its_kind():
    assert profile_span("via", via_times=[0.5, 2.0], via_points=[0.0, 1.0]) == (0.5, 2.0)
    assert _message(profile_span, "via", via_times=[0.0, 0.0], via_points=[0.0, 1.0]) == (
        "via times must increase strictly: t[1] = 0 s repeats t[0] = 0 s")
    assert _message(profile_span, "table", table_times=[1.0, 0.5],
                    table_values=[0.0, 1.0]) == (
        "table times must increase strictly: t[1] = 0.5 s comes before t[0] = 1 s")
