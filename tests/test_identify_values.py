"""identify/base.py and identify/standard.py at their edges (mutation testing, issue 30's habit):
made-up stacks whose dependencies are known by construction, the thresholds at their exact
values, the printed forms, and the refusal of code generated before the regressors."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import LibraryError
from planar_sym.identify.base import CLEAN_TOL, base_parameters, from_stacked
from planar_sym.identify.standard import StandardParameters, columns, standard_parameters


def _std(*names, values=None):
    return StandardParameters(names, ("",) * len(names), ("",) * len(names),
                              np.arange(1.0, len(names) + 1) if values is None
                              else np.asarray(values, float))


def _basis(rows=12, k=3, seed=0):
    return np.random.default_rng(seed).normal(size=(rows, k))


def test_zero_column_threshold_is_inclusive_and_relative_to_the_largest():
    """A column of norm exactly 1e-12 times the largest (2) is no column at all."""
    w = np.zeros((4, 3))
    w[0, 0], w[1, 1], w[2, 2] = 2.0, 1.0, 2e-12
    base = from_stacked(w, _std("izo_b", "mcx_b", "mcy_b"))
    assert base.unidentifiable == ("mcy_b",)
    assert base.kept == (0, 1)


def test_a_small_stack_keeps_a_small_column():
    """All columns small (largest 2e-3): a column of 5e-13 is 2.5e-10 of the largest, a real
    column, not rounding (the floor is relative, not 1e-12 absolute)."""
    w = np.zeros((4, 3))
    w[0, 0], w[1, 1], w[2, 2] = 2e-3, 1e-3, 5e-13
    base = from_stacked(w, _std("izo_b", "mcx_b", "mcy_b"))
    assert base.unidentifiable == ()
    assert base.kept == (0, 1, 2)


def test_preference_not_column_order_picks_the_kept_one():
    """Two equal columns, the mass listed first: the inertia about the origin is kept (the
    preference order izo, mcx, mcy, m), the mass regrouped into it."""
    a = _basis(k=1)[:, 0]
    base = from_stacked(np.column_stack([a, a]), _std("m_b", "izo_b"))
    assert base.kept == (1,)
    assert base.names == ("izo_bR",)
    np.testing.assert_allclose(base.regrouping, [[1.0, 1.0]], atol=1e-14)


def test_small_regrouping_coefficients_are_kept_or_cleaned_relative_to_the_largest():
    """K's entries below CLEAN_TOL times its largest are rounding: with largest 4, 3e-10 goes
    (below 4e-10); with largest 0.5, 7e-11 stays (above 5e-11)."""
    a, b = _basis(k=2).T
    for big, small, kept in ((4.0, 3e-10, False), (0.5, 7e-11, True)):
        w = np.column_stack([a, b, big * a + small * b])
        base = from_stacked(w, _std("izo_b", "mcx_b", "m_b"))
        k = base.regrouping[:, 2]
        assert k[0] == pytest.approx(big, rel=1e-12)
        assert bool(k[1] != 0.0) is kept
        if kept:
            assert k[1] == pytest.approx(small, rel=1e-4)
    assert CLEAN_TOL == 1e-10


def test_margin_reports_both_sides_of_the_gap():
    """A column dependent up to 1e-10 noise is dropped; the margin names its distance (about
    1e-10, not 0) and the smallest kept one's (of order 1)."""
    a, b, noise = _basis(k=3).T
    w = np.column_stack([a, b, a + b + 1e-10 * noise])
    base = from_stacked(w, _std("izo_b", "mcx_b", "m_b"))
    assert base.kept == (0, 1)
    kept_side, dropped_side = base.margin
    assert kept_side > 0.1
    assert 1e-12 < dropped_side < 1e-8


def test_an_all_zero_stack_has_no_base_parameters():
    base = from_stacked(np.zeros((5, 2)), _std("izo_b", "m_b"))
    assert base.kept == () and base.unidentifiable == ("izo_b", "m_b")
    assert base.margin == (0.0, 0.0)
    assert base.values().shape == (0,)


def test_values_of_given_standard_parameters():
    a, b = _basis(k=2).T
    base = from_stacked(np.column_stack([a, b, 2 * a - b]), _std("izo_b", "mcx_b", "m_b"))
    assert base.values().tolist() == pytest.approx([1 + 2 * 3, 2 - 3])
    assert base.values([1, 1, 1]).tolist() == pytest.approx([3.0, 0.0])  # a list, ints
    assert base.values(np.array([0.5, 0.25, 2.0])).tolist() == pytest.approx([4.5, -1.75])


def test_expressions_signs_digits_and_unit_coefficients():
    """A mass regrouped into three kept columns with -0.1, 0.1234567 and 1 + 1e-6: a minus sign,
    six significant digits by default, and 1 + 1e-6 written out (only 1 to 1e-12 is left
    bare); a row whose first term is negative starts with "-"."""
    a, b, c = _basis(k=3).T
    w = np.column_stack([a, b, c, -0.1 * a + 0.1234567 * b + 1.000001 * c])
    base = from_stacked(w, _std("izo_a", "mcx_a", "mcy_a", "m_a"))
    assert base.expressions() == ["izo_aR = izo_a - 0.1 m_a", "mcx_aR = mcx_a + 0.123457 m_a",
                                  "mcy_aR = mcy_a + 1 m_a"]
    assert base.expressions(3)[1] == "mcx_aR = mcx_a + 0.123 m_a"
    w2 = np.column_stack([-0.1 * a, a])  # the mass listed first, regrouped with -0.1
    assert from_stacked(w2, _std("m_a", "mcx_a")).expressions() == \
        ["mcx_aR = -0.1 m_a + mcx_a"]
    w3 = np.column_stack([0.5 * a, a])
    assert from_stacked(w3, _std("m_a", "mcx_a")).expressions() == \
        ["mcx_aR = 0.5 m_a + mcx_a"]


def test_regrouped_names_where_each_dropped_parameter_went():
    base = base_parameters(ps.load("serial_2dof"))
    assert base.regrouped() == {
        "m_motor2": "mcx_link1R, izo_link1R", "mcx_motor2": "mcx_link1R, izo_link1R",
        "mcy_motor2": "mcy_link1R", "izo_motor2": "izo_link1R",
        "m_link2": "mcx_link1R, izo_link1R"}


def test_standard_parameters_carry_units_and_meanings():
    std = standard_parameters(ps.load("serial_2dof"))
    assert std.units[std.index("izo_link1")] == "kg*m^2"
    assert std.units[std.index("mcx_link2")] == "kg*m"
    assert std.units[std.index("fv_joint1")] == "N*m*s/rad"
    assert std.meanings[std.index("izo_link2")] == ("inertia of link2 about its frame's origin "
                                                    "(Izz + m |c|^2)")
    d = std.as_dict()
    assert list(d) == list(std.names)
    assert d["m_link2"] == 0.075 and d["mcx_link2"] == pytest.approx(0.075 * 0.04168)


def test_code_without_regressors_is_refused_by_name():
    old = SimpleNamespace(name="old_arm", library=SimpleNamespace(manifest={}))
    with pytest.raises(LibraryError) as err:
        columns(old)
    assert str(err.value) == ("old_arm: its generated code has no regressor (derived before "
                              "identification was added): run `make derive` (or load its TOML "
                              "again, which re-derives it)")
